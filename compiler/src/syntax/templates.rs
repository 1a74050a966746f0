//! Stage `templates`: attributes written once and given to several passes or groups — LBP
//! `template lit(entry) like per_light_all { fragment $entry … }` and `raster a like lit(fs_a)`,
//! RON `templates: {"lit": Template(parameters: ["entry"], like: Like("per_light_all"), fragment:
//! Arg("entry"), …)}` and `like: Like("lit", "fs_a")`. A pass or group `like` a template takes
//! the template's attributes, each `$PARAM` (`Arg`) replaced by the instance's argument, as
//! from a group around it: its own attributes win, `when`s hold together, the template's
//! `reads` come first. A template may build on another. Runs on each file's tree before its
//! groups, so both front ends share it and every attribute keeps the span it was written at
//! (an argument's value points at the instance that gave it).

use crate::diag::{suggestion_note, Code, Diagnostic, Diagnostics};
use crate::tree::{Field, Node, Value};
use std::collections::{HashMap, HashSet};

/// Does the tree declare or use a template, or name a parameter (then this stage runs, and
/// `fmt` and `convert` print the file as written)?
pub fn has_templates(root: &Node) -> bool {
    let Value::Struct { fields, .. } = &*root.value else { return false };
    fields.iter().any(|f| f.0 == "templates") || fields.iter().any(|f| f.0 == "passes" && mentions(&f.2))
}

/// Does `n` hold a `Like(..)` or an `Arg(..)`?
fn mentions(n: &Node) -> bool {
    match &*n.value {
        Value::Tuple { name: Some((k, _)), .. } if k == "Like" || k == "Arg" => true,
        Value::Struct { fields, .. } => fields.iter().any(|f| f.0 == "like" || mentions(&f.2)),
        Value::List(items) | Value::Tuple { items, .. } => items.iter().any(mentions),
        Value::Map(entries) => entries.iter().any(|(k, v)| mentions(k) || mentions(v)),
        _ => false,
    }
}

/// One declared template: its parameters and attributes (`like` among them) as written.
struct Template {
    name: Node,
    params: Vec<Node>,
    fields: Vec<Field>,
}

/// The tree without `templates`, every pass and group `like` one given its attributes.
pub fn expand(root: &Node, diags: &mut Diagnostics) -> Node {
    if !has_templates(root) {
        return root.clone();
    }
    let Value::Struct { name, fields } = &*root.value else {
        return root.clone();
    };
    let templates = read(fields, diags);
    let by_name = templates.iter().enumerate().map(|(i, t)| (text(&t.name).to_string(), i)).collect();
    let mut table = Table {
        templates,
        by_name,
        used: HashSet::new(),
        resolved: HashMap::new(),
        diags,
    };
    let fields: Vec<Field> = fields
        .iter()
        .filter(|f| f.0 != "templates")
        .map(|(k, span, v)| match (k.as_str(), &*v.value) {
            ("passes", Value::List(items)) => {
                let items = items.iter().filter_map(|i| table.apply(i)).collect();
                (k.clone(), *span, Node::list(items, v.span))
            }
            _ => (k.clone(), *span, v.clone()),
        })
        .collect();
    // Where a `$NAME` outside a template is likely: in a pass (elsewhere the lowering says
    // the value is of the wrong kind).
    for (_, _, v) in fields.iter().filter(|f| f.0 == "passes") {
        stray_args(v, table.diags);
    }
    for t in table.templates.iter().filter(|t| !table.used.contains(text(&t.name))) {
        let d = Diagnostic::warning(
            Code::UnusedTemplate,
            format!("no pass or group is like `{}`", text(&t.name)),
            t.name.span,
        );
        table.diags.push(d);
    }
    let value = Value::Struct {
        name: name.clone(),
        fields,
    };
    Node::new(value, root.span)
}

fn text(n: &Node) -> &str {
    n.text().unwrap_or("")
}

/// The template a `Like("T", ..)` names.
fn text_of(like: &Node) -> &str {
    match &*like.value {
        Value::Tuple { items, .. } => items.first().map(text).unwrap_or(""),
        _ => "",
    }
}

/// The declared templates, each checked once: its parameters distinct, every `$PARAM` in it
/// one of them, no pass inside it.
fn read(root: &[Field], diags: &mut Diagnostics) -> Vec<Template> {
    let Some((_, _, map)) = root.iter().find(|f| f.0 == "templates") else {
        return vec![];
    };
    let Value::Map(entries) = &*map.value else {
        diags.push(Diagnostic::error(
            Code::TypeMismatch,
            "`templates` is a map of names to `Template(..)`",
            map.span,
        ));
        return vec![];
    };
    let mut out: Vec<Template> = vec![];
    let mut seen: HashMap<&str, usize> = HashMap::new();
    for (k, v) in entries {
        if let Some(&first) = seen.get(text(k)) {
            let d = Diagnostic::error(Code::DuplicateName, format!("template `{}` is declared twice", text(k)), k.span)
                .with_secondary(out[first].name.span, "first declared here");
            diags.push(d);
            continue;
        }
        if let Some(t) = template(k, v, diags) {
            seen.insert(text(k), out.len());
            out.push(t);
        }
    }
    out
}

/// One `Template(parameters: [..], ..)` entry, or none (reported) when it is not one.
fn template(k: &Node, v: &Node, diags: &mut Diagnostics) -> Option<Template> {
    let Value::Struct {
        name: Some((n, _)),
        fields,
    } = &*v.value
    else {
        diags.push(Diagnostic::error(
            Code::TypeMismatch,
            format!("expected `Template(..)`, found {}", v.value.kind_word()),
            v.span,
        ));
        return None;
    };
    if n != "Template" {
        diags.push(Diagnostic::error(
            Code::TypeMismatch,
            format!("expected `Template(..)`, found `{n}(..)`"),
            v.span,
        ));
        return None;
    }
    let params: Vec<Node> = match fields.iter().find(|f| f.0 == "parameters").map(|f| &*f.2.value) {
        Some(Value::List(ps)) => ps.clone(),
        _ => vec![],
    };
    for (i, p) in params.iter().enumerate() {
        if params[..i].iter().any(|q| text(q) == text(p)) {
            diags.push(Diagnostic::error(
                Code::DuplicateName,
                format!("parameter `{}` twice", text(p)),
                p.span,
            ));
        }
    }
    let fields: Vec<Field> = fields.iter().filter(|f| f.0 != "parameters").cloned().collect();
    if let Some((key, span, _)) = fields.iter().find(|f| matches!(f.0.as_str(), "name" | "passes" | "replace")) {
        let d = Diagnostic::error(
            Code::UnknownKey,
            format!("a template has no `{key}`: it gives attributes to the passes and groups like it"),
            *span,
        )
        .with_note("a pass or group names it: `raster NAME like TEMPLATE(ARGS)`");
        diags.push(d);
        return None;
    }
    let names: Vec<&str> = params.iter().map(text).collect();
    for (_, _, f) in &fields {
        unknown_args(f, k, &names, diags);
    }
    Some(Template {
        name: k.clone(),
        params,
        fields,
    })
}

/// Report each `$X` in `n` that is not a parameter of template `t`.
fn unknown_args(n: &Node, t: &Node, params: &[&str], diags: &mut Diagnostics) {
    if let Some(a) = arg(n) {
        if !params.contains(&text(a)) {
            let msg = format!("template `{}` has no parameter `{}`", text(t), text(a));
            diags.push(Diagnostic::error(Code::TemplateParam, msg, n.span).with_note(suggestion_note(text(a), params)));
        }
        return;
    }
    n.each_child(|c| unknown_args(c, t, params, diags));
}

/// Report each `$X` left where no template gives it a value.
fn stray_args(n: &Node, diags: &mut Diagnostics) {
    if let Some(a) = arg(n) {
        let msg = format!("`${}` outside a template: only a template's attributes take parameters", text(a));
        diags.push(Diagnostic::error(Code::TemplateParam, msg, n.span));
        return;
    }
    n.each_child(|c| stray_args(c, diags));
}

/// The name in `Arg("NAME")`.
fn arg(n: &Node) -> Option<&Node> {
    match &*n.value {
        Value::Tuple { name: Some((k, _)), items } if k == "Arg" && items.len() == 1 => Some(&items[0]),
        _ => None,
    }
}

/// `n` with each `Arg("P")` of `params` replaced by the matching argument; `None` when it
/// holds none (nothing is rebuilt then: most of a template is not a parameter).
fn substitute(n: &Node, params: &[Node], args: &[Node]) -> Option<Node> {
    if let Some(a) = arg(n) {
        let i = params.iter().position(|p| text(p) == text(a))?;
        return Some(args[i].clone());
    }
    // Each child substituted, the node rebuilt only when one of them changed.
    let changed = |items: &[Node]| -> Option<Vec<Node>> {
        let new: Vec<Option<Node>> = items.iter().map(|i| substitute(i, params, args)).collect();
        new.iter().any(Option::is_some).then(|| {
            new.into_iter()
                .zip(items)
                .map(|(n, old)| n.unwrap_or_else(|| old.clone()))
                .collect()
        })
    };
    let value = match &*n.value {
        Value::List(items) => Value::List(changed(items)?),
        Value::Tuple { name, items } => Value::Tuple {
            name: name.clone(),
            items: changed(items)?,
        },
        Value::Struct { name, fields } => {
            let values: Vec<Node> = fields.iter().map(|f| f.2.clone()).collect();
            let values = changed(&values)?;
            let fields = fields.iter().zip(values).map(|((k, s, _), v)| (k.clone(), *s, v)).collect();
            Value::Struct {
                name: name.clone(),
                fields,
            }
        }
        Value::Map(entries) => {
            let flat: Vec<Node> = entries.iter().flat_map(|(k, v)| [k.clone(), v.clone()]).collect();
            let flat = changed(&flat)?;
            Value::Map(flat.chunks(2).map(|kv| (kv[0].clone(), kv[1].clone())).collect())
        }
        _ => return None,
    };
    Some(Node::new(value, n.span))
}

/// How many templates deep `like` may lead (each a recursion of `resolve`).
const MAX_TEMPLATE_DEPTH: usize = 64;

struct Table<'d> {
    templates: Vec<Template>,
    /// Each template's index in `templates` by name.
    by_name: HashMap<String, usize>,
    used: HashSet<String>,
    /// The attributes of each template given without arguments, once resolved (most are).
    resolved: HashMap<String, Vec<Field>>,
    diags: &'d mut Diagnostics,
}

impl Table<'_> {
    /// A pass or group with the attributes of the template it is like (a group's passes
    /// likewise); none when the template cannot be had (reported: the item would only add
    /// errors about what it lacks).
    fn apply(&mut self, item: &Node) -> Option<Node> {
        let Value::Struct { name, fields } = &*item.value else {
            return Some(item.clone());
        };
        if !fields.iter().any(|f| f.0 == "like" || f.0 == "passes") {
            return Some(item.clone());
        }
        let mut own: Vec<Field> = fields.iter().filter(|f| f.0 != "like").cloned().collect();
        if let Some((_, _, like)) = fields.iter().find(|f| f.0 == "like") {
            own = super::groups::with_inherited(&own, &self.resolve_all(like, &mut vec![])?);
        }
        for f in own.iter_mut().filter(|f| f.0 == "passes") {
            if let Value::List(items) = &*f.2.value {
                f.2 = Node::list(items.iter().filter_map(|i| self.apply(i)).collect(), f.2.span);
            }
        }
        let value = Value::Struct {
            name: name.clone(),
            fields: own,
        };
        Some(Node::new(value, item.span))
    }

    /// The attributes a `like` gives: one template's, or (a list) several templates' together,
    /// `when`s joined and `reads` in the order written; any other attribute from one of them.
    fn resolve_all(&mut self, like: &Node, chain: &mut Vec<String>) -> Option<Vec<Field>> {
        let Value::List(likes) = &*like.value else {
            return self.resolve(like, chain);
        };
        if likes.is_empty() {
            let msg = "expected `Like(\"TEMPLATE\", ARGS...)` or a list of them, found an empty list";
            self.diags.push(Diagnostic::error(Code::TypeMismatch, msg, like.span));
            return None;
        }
        let mut all: Option<Vec<Field>> = None;
        let mut from: Vec<(String, &Node)> = vec![];
        for l in likes {
            let fields = self.resolve(l, chain)?;
            let name = text_of(l);
            for (k, _, _) in fields.iter().filter(|f| f.0 != "when" && f.0 != "reads") {
                if let Some((_, other)) = from.iter().find(|(key, _)| key == k) {
                    let msg = format!(
                        "`{k}` is given by two templates, `{}` and `{name}`: each attribute comes from one",
                        text_of(other)
                    );
                    self.diags.push(Diagnostic::error(Code::DuplicateKey, msg, l.span));
                    return None;
                }
            }
            from.extend(fields.iter().map(|f| (f.0.clone(), l)));
            all = Some(match all {
                None => fields,
                Some(before) => super::groups::with_inherited(&fields, &before),
            });
        }
        all
    }

    /// The attributes `Like("T", ARGS)` gives: T's, its parameters replaced by ARGS, over
    /// those of the template T is like. `chain`: the templates being resolved, for cycles.
    fn resolve(&mut self, like: &Node, chain: &mut Vec<String>) -> Option<Vec<Field>> {
        let items = match &*like.value {
            Value::Tuple { name: Some((k, _)), items } if k == "Like" && !items.is_empty() => items,
            _ => {
                let msg = format!("expected `Like(\"TEMPLATE\", ARGS...)`, found {}", like.value.kind_word());
                self.diags.push(Diagnostic::error(Code::TypeMismatch, msg, like.span));
                return None;
            }
        };
        let (name, args) = (&items[0], &items[1..]);
        if let Some(done) = self.resolved.get(text(name)).filter(|_| args.is_empty()) {
            return Some(done.clone());
        }
        let Some(&at) = self.by_name.get(text(name)) else {
            let names: Vec<&str> = self.templates.iter().map(|t| text(&t.name)).collect();
            let d = Diagnostic::error(Code::UnknownTemplate, format!("no template `{}`", text(name)), name.span)
                .with_note(suggestion_note(text(name), &names));
            self.diags.push(d);
            return None;
        };
        if chain.len() >= MAX_TEMPLATE_DEPTH {
            let msg = format!("templates are like others more than {MAX_TEMPLATE_DEPTH} deep");
            self.diags.push(Diagnostic::error(Code::NestingTooDeep, msg, name.span));
            return None;
        }
        if let Some(first) = chain.iter().position(|c| c == text(name)) {
            let mut names = chain[first..].to_vec();
            names.push(text(name).to_string());
            let msg = format!("templates are like each other: {}", names.join(" -> "));
            self.diags.push(Diagnostic::error(Code::TemplateCycle, msg, name.span));
            return None;
        }
        self.used.insert(text(name).to_string());
        let t = &self.templates[at];
        if args.len() != t.params.len() {
            let params: Vec<&str> = t.params.iter().map(text).collect();
            let msg = format!(
                "`{}` takes {} argument{} ({}), given {}",
                text(name),
                params.len(),
                if params.len() == 1 { "" } else { "s" },
                params.join(", "),
                args.len()
            );
            self.diags.push(Diagnostic::error(Code::TemplateArguments, msg, like.span));
            return None;
        }
        let fields: Vec<Field> = t
            .fields
            .iter()
            .map(|(k, s, v)| (k.clone(), *s, substitute(v, &t.params, args).unwrap_or_else(|| v.clone())))
            .collect();
        let all = match fields.iter().position(|f| f.0 == "like") {
            None => fields,
            Some(at) => {
                let mut own = fields;
                let (_, _, inner) = own.remove(at);
                chain.push(text(name).to_string());
                let inherited = self.resolve_all(&inner, chain);
                chain.pop();
                super::groups::with_inherited(&own, &inherited?)
            }
        };
        if args.is_empty() {
            self.resolved.insert(text(name).to_string(), all.clone());
        }
        Some(all)
    }
}
