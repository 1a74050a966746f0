//! The one lowering: syntax tree -> IR. Both front ends parse into the tree; this is where
//! names become IR values and absent keys take their defaults (from `syntax::defaults`).
//! Range, duplicate and cross-reference checks are not here: the IR can hold such
//! values and `check::declarations` reports them.

mod choice;
mod cond;
mod decl;
mod fix;
mod obj;
mod pass;
mod scene;
mod variant;

use crate::diag::{suggestion_note, Code, Diagnostic, Diagnostics};
use crate::ir::{LightKind, Pipeline};
use crate::span::Spanned;
use crate::tree::{Node, Value};
pub(crate) use choice::{find_match, is_match};
pub(crate) use obj::Obj;
pub use pass::pass_keys;
pub use scene::scene;

type Res<T> = Option<T>;

/// Lower a pipeline tree. Problems go to `diags`; `None` when the tree cannot become IR.
pub fn pipeline(root: &Node, diags: &mut Diagnostics) -> Option<Pipeline> {
    let before = diags.error_count();
    let p = Lowerer::new(diags).pipeline(root);
    if diags.error_count() > before {
        return None;
    }
    p
}

/// Lower what lowers: items with errors are left out (the errors are in `diags`). For
/// checks that do not depend on the left-out items (each pass's shaders), so that one bad
/// value does not hide every other problem of the file.
pub fn pipeline_partial(root: &Node, diags: &mut Diagnostics) -> Option<Pipeline> {
    Lowerer::new(diags).pipeline(root)
}

pub(crate) struct Lowerer<'d> {
    pub diags: &'d mut Diagnostics,
    /// The pipeline's named conditions (`lets`), as written, and the names being lowered
    /// (a name among them used again is a cycle).
    lets: Lets,
}

/// Named conditions as written, by name; the names being lowered, in order; each one lowered
/// (once: its problems are reported once), by name.
#[derive(Default)]
struct Lets {
    written: Vec<(Spanned<String>, Node)>,
    open: Vec<String>,
    lowered: std::collections::BTreeMap<String, Option<crate::span::Spanned<crate::ir::Condition>>>,
}

impl<'d> Lowerer<'d> {
    pub(crate) fn new(diags: &'d mut Diagnostics) -> Self {
        Lowerer {
            diags,
            lets: Lets::default(),
        }
    }
}

impl Lowerer<'_> {
    fn err(&mut self, d: Diagnostic) {
        self.diags.push(d);
    }

    fn type_err<T>(&mut self, expected: &str, node: &Node) -> Res<T> {
        let mut d = Diagnostic::error(
            Code::TypeMismatch,
            format!("expected {expected}, found {}", node.value.kind_word()),
            node.span,
        )
        .with_label_text(format!("expected {expected}"));
        if choice::is_match(node) {
            d = d.with_note("a choice (`Match`) stands only for a pass field or an element of a pass's list field");
        }
        self.err(d);
        None
    }

    fn pipeline(&mut self, root: &Node) -> Res<Pipeline> {
        let mut o = self.obj(root, &["Pipeline"], "pipeline")?;
        let name = self.required(&mut o, "name").and_then(|n| self.string(&n));
        let params = o.take("params").and_then(|n| self.params(&n)).unwrap_or_default();
        let samplers = o.take("samplers").and_then(|n| self.samplers(&n)).unwrap_or_default();
        let resources = o.take("resources").and_then(|n| self.resources(&n)).unwrap_or_default();
        // Variants first: choices inside passes are checked against them.
        let variants = o.take("variants").and_then(|n| self.variants(&n)).unwrap_or_default();
        // Named conditions before the passes that use them.
        if let Some(n) = o.take("lets") {
            self.lets.written = self.string_map(&n).unwrap_or_default();
        }
        let passes = self
            .required(&mut o, "passes")
            .and_then(|n| self.passes(&n, &variants))
            .unwrap_or_default();
        let output = self.required(&mut o, "output").and_then(|n| self.string(&n));
        let hdr_output = match o.take("hdr_output") {
            Some(n) => Some(self.string(&n)?),
            None => None,
        };
        let fixes = match o.take("fix") {
            Some(n) => self.string_pairs(&n).unwrap_or_default(),
            None => vec![],
        };
        let always = o.get("always").and_then(|n| self.bool(&n));
        let jitter = o.get("jitter").and_then(|n| self.bool(&n));
        let span = o.span;
        let keys = [
            "name",
            "params",
            "samplers",
            "resources",
            "passes",
            "variants",
            "output",
            "hdr_output",
            "always",
            "jitter",
            "fix",
            "lets",
        ];
        self.finish(o, &keys, &[]);
        let lets = self.lets_declared();
        let mut p = Pipeline {
            name: name?,
            params,
            samplers,
            resources,
            passes,
            variants,
            lets,
            output: output?,
            hdr_output,
            always: always?,
            jitter: jitter?,
            written: None,
            span,
        };
        self.fix(&mut p, fixes);
        Some(p)
    }

    fn string(&mut self, node: &Node) -> Res<Spanned<String>> {
        match &*node.value {
            Value::Str(s) => Some(Spanned::new(s.clone(), node.span)),
            _ => self.type_err("a string", node),
        }
    }

    fn bool(&mut self, node: &Node) -> Res<bool> {
        match &*node.value {
            Value::Bool(b) => Some(*b),
            _ => self.type_err("`true` or `false`", node),
        }
    }

    fn u32(&mut self, node: &Node) -> Res<Spanned<u32>> {
        match &*node.value {
            Value::Int(i) => match u32::try_from(*i) {
                Ok(v) => Some(Spanned::new(v, node.span)),
                Err(_) => {
                    self.err(Diagnostic::error(
                        Code::BadNumber,
                        format!("`{i}` is not a 32-bit whole number (0 to {})", u32::MAX),
                        node.span,
                    ));
                    None
                }
            },
            _ => self.type_err("an integer", node),
        }
    }

    fn u64(&mut self, node: &Node) -> Res<Spanned<u64>> {
        match &*node.value {
            Value::Int(i) if *i >= 0 => Some(Spanned::new(*i as u64, node.span)),
            Value::Int(i) => {
                self.err(Diagnostic::error(Code::BadNumber, format!("`{i}` is negative"), node.span));
                None
            }
            _ => self.type_err("an integer", node),
        }
    }

    /// A number as written, finite or not (scene values are range-checked later, by name).
    fn number(&mut self, node: &Node) -> Res<f64> {
        match &*node.value {
            Value::Int(i) => Some(*i as f64),
            Value::Float(f) => Some(*f),
            _ => self.type_err("a number", node),
        }
    }

    /// A finite number. Pipelines have no use for `inf`/`NaN`, and LBP cannot spell them,
    /// so rejecting them here keeps every RON <-> LBP conversion parseable. Every pipeline
    /// number becomes an f32 on the GPU: one beyond its range (1e39) is infinite there too.
    fn f64(&mut self, node: &Node) -> Res<f64> {
        let v = self.number(node)?;
        let why = if !v.is_finite() {
            format!("`{v}` is not a finite number")
        } else if !(v as f32).is_finite() {
            format!("`{v:e}` is not a finite 32-bit float (largest ±3.4e38): it would be infinite on the GPU")
        } else {
            return Some(v);
        };
        self.err(Diagnostic::error(Code::NonFinite, why, node.span));
        None
    }

    /// An anonymous tuple of exactly `N` numbers.
    fn floats<const N: usize>(&mut self, node: &Node, expected: &str) -> Res<[f64; N]> {
        match &*node.value {
            Value::Tuple { name: None, items } if items.len() == N => {
                let mut out = [0.0; N];
                for (o, it) in out.iter_mut().zip(items) {
                    *o = self.f64(it)?;
                }
                Some(out)
            }
            _ => self.type_err(expected, node),
        }
    }

    fn list<'n>(&mut self, node: &'n Node) -> Res<&'n [Node]> {
        match &*node.value {
            Value::List(items) => Some(items),
            _ => self.type_err("a list `[...]`", node),
        }
    }

    fn string_list(&mut self, n: &Node) -> Res<Vec<Spanned<String>>> {
        let items = self.list(n)?.to_vec();
        Some(items.iter().filter_map(|i| self.string(i)).collect())
    }

    /// A map with string keys, in file order (duplicates are kept for the checks to report).
    fn string_map(&mut self, node: &Node) -> Res<Vec<(Spanned<String>, Node)>> {
        let Value::Map(entries) = &*node.value else {
            return self.type_err("a map `{...}`", node);
        };
        Some(entries.iter().filter_map(|(k, v)| Some((self.string(k)?, v.clone()))).collect())
    }

    /// A map from strings to strings (`bind`, shader substitutions).
    fn string_pairs(&mut self, node: &Node) -> Res<Vec<(Spanned<String>, Spanned<String>)>> {
        let entries = self.string_map(node)?;
        Some(entries.into_iter().filter_map(|(k, v)| self.string(&v).map(|v| (k, v))).collect())
    }

    /// A unit enum value (`Linear`) checked against its names.
    fn ident<T>(&mut self, node: &Node, what: &str, names: &[&str], parse: impl Fn(&str) -> Option<T>) -> Res<T> {
        match &*node.value {
            Value::Ident(i) => match parse(i) {
                Some(v) => Some(v),
                None => {
                    self.err(
                        Diagnostic::error(Code::UnknownValue, format!("unknown {what} `{i}`"), node.span)
                            .with_note(suggestion_note(i, names)),
                    );
                    None
                }
            },
            _ => self.type_err(&format!("a {what} name"), node),
        }
    }

    fn light_kinds(&mut self, node: &Node) -> Res<Spanned<Vec<LightKind>>> {
        let items = self.list(node)?.to_vec();
        let mut kinds = vec![];
        for it in &items {
            let k = self.ident(it, "light kind", &LightKind::NAMES, LightKind::from_name)?;
            if !kinds.contains(&k) {
                kinds.push(k);
            }
        }
        Some(Spanned::new(kinds, node.span))
    }
}
