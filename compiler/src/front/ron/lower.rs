//! Lowers the spanned RON tree to the IR, reporting every problem with its location.

use super::value::{Node, Value};
use crate::diag::{suggestion_note, Diagnostic, Diagnostics};
use crate::format::TextureFormat;
use crate::ir::*;
use crate::profile::Feature;
use crate::span::{Span, Spanned};

pub struct Lowerer<'d> {
    pub diags: &'d mut Diagnostics,
}

/// The fields of a `Name(key: value, ...)` struct, taken one by one; `finish` reports the rest
/// as unknown keys with a did-you-mean.
pub struct Obj {
    pub what: String,
    pub span: Span,
    fields: Vec<(String, Span, Node, bool)>,
}

impl Obj {
    fn take(&mut self, key: &str) -> Option<(Span, Node)> {
        self.fields.iter_mut().find(|f| f.0 == key && !f.3).map(|f| {
            f.3 = true;
            (f.1, f.2.clone())
        })
    }
}

type Res<T> = Option<T>;

impl<'d> Lowerer<'d> {
    fn err(&mut self, d: Diagnostic) {
        self.diags.push(d);
    }

    fn type_err<T>(&mut self, expected: &str, node: &Node) -> Res<T> {
        self.err(
            Diagnostic::error(
                "type-mismatch",
                format!("expected {expected}, found {}", node.value.kind_word()),
                node.span,
            )
            .with_label_text(format!("expected {expected}")),
        );
        None
    }

    /// Open `Name(...)` (or an anonymous `(...)` when `name` allows it) as an object.
    fn obj(&mut self, node: &Node, expected_names: &[&str], what: &str) -> Res<(String, Obj)> {
        let (name, fields) = match &*node.value {
            Value::Struct { name, fields } => (name.clone(), fields.clone()),
            Value::Tuple { name, items } if items.is_empty() => (name.clone(), vec![]),
            Value::Ident(i) if expected_names.contains(&i.as_str()) => (Some((i.clone(), node.span)), vec![]),
            _ => return self.type_err(&format!("{what} `{}(...)`", expected_names.first().unwrap_or(&"")), node),
        };
        let name_str = match name {
            Some((n, nspan)) => {
                if !expected_names.is_empty() && !expected_names.contains(&n.as_str()) {
                    self.err(
                        Diagnostic::error("unknown-kind", format!("unknown {what} kind `{n}`"), nspan)
                            .with_note(suggestion_note(&n, expected_names)),
                    );
                    return None;
                }
                n
            }
            None => expected_names.first().copied().unwrap_or("").to_string(),
        };
        let mut seen: Vec<&str> = vec![];
        for (k, kspan, _) in &fields {
            if seen.contains(&k.as_str()) {
                self.err(Diagnostic::error(
                    "duplicate-key",
                    format!("key `{k}` is given twice in this {what}"),
                    *kspan,
                ));
            }
            seen.push(k);
        }
        let fields = fields.into_iter().map(|(k, s, n)| (k, s, n, false)).collect();
        Some((
            name_str,
            Obj {
                what: what.to_string(),
                span: node.span,
                fields,
            },
        ))
    }

    fn finish(&mut self, obj: Obj, allowed: &[&str]) {
        for (k, kspan, _, used) in obj.fields {
            if used {
                continue;
            }
            if allowed.contains(&k.as_str()) {
                continue; // taken conditionally elsewhere
            }
            if matches!(k.as_str(), "geometry" | "geometry_shader" | "gs") {
                self.err(geometry_error(kspan));
                continue;
            }
            self.err(
                Diagnostic::error("unknown-key", format!("unknown key `{k}` in {}", obj.what), kspan)
                    .with_note(suggestion_note(&k, allowed)),
            );
        }
    }

    fn required(&mut self, obj: &mut Obj, key: &str) -> Res<(Span, Node)> {
        let r = obj.take(key);
        if r.is_none() {
            self.err(
                Diagnostic::error("missing-key", format!("{} is missing required key `{key}`", obj.what), obj.span)
                    .with_label_text(format!("`{key}` is required here")),
            );
        }
        r
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
            Value::Int(i) if *i >= 0 && *i <= u32::MAX as i64 => Some(Spanned::new(*i as u32, node.span)),
            Value::Int(_) => {
                self.err(Diagnostic::error(
                    "value-out-of-range",
                    "expected a non-negative 32-bit integer",
                    node.span,
                ));
                None
            }
            _ => self.type_err("an integer", node),
        }
    }

    fn f64(&mut self, node: &Node) -> Res<f64> {
        match &*node.value {
            Value::Int(i) => Some(*i as f64),
            Value::Float(f) => Some(*f),
            _ => self.type_err("a number", node),
        }
    }

    fn list<'n>(&mut self, node: &'n Node) -> Res<&'n [Node]> {
        match &*node.value {
            Value::List(items) => Some(items),
            _ => self.type_err("a list `[...]`", node),
        }
    }

    /// A map with string keys, in file order; duplicate keys are reported.
    fn string_map(&mut self, node: &Node, what: &str) -> Res<Vec<(Spanned<String>, Node)>> {
        let Value::Map(entries) = &*node.value else {
            return self.type_err("a map `{...}`", node);
        };
        let mut out: Vec<(Spanned<String>, Node)> = vec![];
        for (k, v) in entries {
            let Some(key) = self.string(k) else { continue };
            if let Some((prev, _)) = out.iter().find(|(p, _)| p.value == key.value) {
                let prev_span = prev.span;
                self.err(
                    Diagnostic::error("duplicate-name", format!("{what} `{}` is declared twice", key.value), key.span)
                        .with_secondary(prev_span, "first declared here"),
                );
                continue;
            }
            out.push((key, v.clone()));
        }
        Some(out)
    }

    /// A unit enum value (`Linear`) checked against its names.
    fn ident<T>(&mut self, node: &Node, what: &str, names: &[&str], parse: impl Fn(&str) -> Option<T>) -> Res<T> {
        match &*node.value {
            Value::Ident(i) => match parse(i) {
                Some(v) => Some(v),
                None => {
                    self.err(
                        Diagnostic::error("unknown-value", format!("unknown {what} `{i}`"), node.span).with_note(suggestion_note(i, names)),
                    );
                    None
                }
            },
            _ => self.type_err(&format!("a {what} name"), node),
        }
    }

    fn light_kinds(&mut self, node: &Node) -> Res<Spanned<Vec<LightKind>>> {
        let items = self.list(node)?;
        let mut kinds = vec![];
        for it in items {
            if let Some(k) = self.ident(it, "light kind", &LightKind::NAMES, LightKind::from_name) {
                if !kinds.contains(&k) {
                    kinds.push(k);
                }
            }
        }
        if kinds.is_empty() {
            self.err(Diagnostic::error(
                "empty-light-kinds",
                "a per-light list needs at least one light kind",
                node.span,
            ));
            return None;
        }
        Some(Spanned::new(kinds, node.span))
    }

    pub fn pipeline(&mut self, root: &Node) -> Res<Pipeline> {
        let (_, mut o) = self.obj(root, &["Pipeline"], "pipeline")?;
        let name = self.required(&mut o, "name").and_then(|(_, n)| self.string(&n));
        let params = o.take("params").and_then(|(_, n)| self.params(&n)).unwrap_or_default();
        let samplers = o.take("samplers").and_then(|(_, n)| self.samplers(&n)).unwrap_or_default();
        let resources = o.take("resources").and_then(|(_, n)| self.resources(&n)).unwrap_or_default();
        let passes = self
            .required(&mut o, "passes")
            .and_then(|(_, n)| self.passes(&n))
            .unwrap_or_default();
        let variants = o.take("variants").and_then(|(_, n)| self.variants(&n)).unwrap_or_default();
        let output = self.required(&mut o, "output").and_then(|(_, n)| self.string(&n));
        let span = o.span;
        self.finish(o, &["name", "params", "samplers", "resources", "passes", "variants", "output"]);
        Some(Pipeline {
            name: name?,
            params,
            samplers,
            resources,
            passes,
            variants,
            output: output?,
            span,
        })
    }

    fn params(&mut self, node: &Node) -> Res<Vec<Param>> {
        let entries = self.string_map(node, "parameter")?;
        Some(entries.into_iter().filter_map(|(name, v)| self.param(name, &v)).collect())
    }

    fn param(&mut self, name: Spanned<String>, node: &Node) -> Res<Param> {
        let (kind, mut o) = self.obj(node, &ParamType::NAMES, "parameter")?;
        let kind_span = match &*node.value {
            Value::Struct { name: Some((_, s)), .. } | Value::Tuple { name: Some((_, s)), .. } => *s,
            _ => node.span,
        };
        let ty = match kind.as_str() {
            "Float" => ParamType::Float,
            "Int" => ParamType::Int,
            "Bool" => ParamType::Bool,
            "Vec2" => ParamType::Vec2,
            "Vec3" => ParamType::Vec3,
            "Vec4" => ParamType::Vec4,
            "Color" => ParamType::Color,
            _ => {
                let (_, opts) = self.required(&mut o, "options")?;
                let items = self.list(&opts)?.to_vec();
                let names: Vec<String> = items.iter().filter_map(|i| self.string(i).map(|s| s.value)).collect();
                if names.is_empty() {
                    self.err(Diagnostic::error(
                        "empty-enum",
                        "an Enum parameter needs at least one option",
                        opts.span,
                    ));
                    return None;
                }
                ParamType::Enum(names)
            }
        };
        let default = self.required(&mut o, "default").and_then(|(_, n)| self.param_value(&ty, &n));
        let min = o.take("min").and_then(|(_, n)| self.param_value(&ty, &n));
        let max = o.take("max").and_then(|(_, n)| self.param_value(&ty, &n));
        let doc = o.take("doc").and_then(|(_, n)| self.string(&n)).map(|s| s.value);
        let span = o.span;
        self.finish(o, &["default", "min", "max", "doc", "options"]);
        Some(Param {
            name,
            ty: Spanned::new(ty, kind_span),
            default: default?,
            min,
            max,
            doc,
            span,
        })
    }

    fn param_value(&mut self, ty: &ParamType, node: &Node) -> Res<Spanned<ParamValue>> {
        let lit = match &*node.value {
            Value::Int(i) => Literal::Int(*i),
            Value::Float(f) => Literal::Float(*f),
            Value::Bool(b) => Literal::Bool(*b),
            Value::Str(s) => Literal::Text(s.clone()),
            Value::Tuple { name: None, items } => {
                let mut v = vec![];
                for it in items {
                    v.push(self.f64(it)?);
                }
                Literal::Tuple(v)
            }
            other => Literal::Other(other.kind_word()),
        };
        match ty.value_of(lit) {
            Ok(v) => Some(Spanned::new(v, node.span)),
            Err(e) => {
                let mut d = Diagnostic::error(e.code, e.message, node.span);
                if let Some(n) = e.note {
                    d = d.with_note(n);
                }
                self.err(d);
                None
            }
        }
    }

    fn samplers(&mut self, node: &Node) -> Res<Vec<SamplerDecl>> {
        let entries = self.string_map(node, "sampler")?;
        let mut out = vec![];
        for (name, v) in entries {
            let Some((_, mut o)) = self.obj(&v, &["Sampler"], "sampler") else {
                continue;
            };
            let filter = o.take("filter").and_then(|(_, n)| self.filter(&n)).unwrap_or(FilterMode::Linear);
            let mipmap = o.take("mipmap").and_then(|(_, n)| self.filter(&n)).unwrap_or(FilterMode::Nearest);
            let address = o
                .take("address")
                .and_then(|(_, n)| {
                    self.ident(&n, "address mode", &["ClampToEdge", "Repeat", "MirrorRepeat"], |s| match s {
                        "ClampToEdge" => Some(AddressMode::ClampToEdge),
                        "Repeat" => Some(AddressMode::Repeat),
                        "MirrorRepeat" => Some(AddressMode::MirrorRepeat),
                        _ => None,
                    })
                })
                .unwrap_or(AddressMode::ClampToEdge);
            let compare = o.take("compare").and_then(|(_, n)| self.compare(&n));
            let span = o.span;
            self.finish(o, &["filter", "mipmap", "address", "compare"]);
            out.push(SamplerDecl {
                name,
                filter,
                mipmap,
                address,
                compare,
                span,
            });
        }
        Some(out)
    }

    fn filter(&mut self, n: &Node) -> Res<FilterMode> {
        self.ident(n, "filter mode", &["Nearest", "Linear"], |s| match s {
            "Nearest" => Some(FilterMode::Nearest),
            "Linear" => Some(FilterMode::Linear),
            _ => None,
        })
    }

    fn compare(&mut self, n: &Node) -> Res<CompareFn> {
        self.ident(n, "compare function", &CompareFn::NAMES, CompareFn::from_name)
    }

    fn resources(&mut self, node: &Node) -> Res<Vec<Resource>> {
        let entries = self.string_map(node, "resource")?;
        Some(entries.into_iter().filter_map(|(name, v)| self.resource(name, &v)).collect())
    }

    fn resource(&mut self, name: Spanned<String>, node: &Node) -> Res<Resource> {
        let (kind, mut o) = self.obj(node, &["Texture", "Buffer"], "resource")?;
        let per_light = o.take("per_light").and_then(|(_, n)| self.light_kinds(&n));
        let history = o.take("history").and_then(|(_, n)| self.bool(&n)).unwrap_or(false);
        let external = o.take("external").and_then(|(_, n)| self.bool(&n)).unwrap_or(false);
        let span = o.span;
        if kind == "Buffer" {
            let size = self.required(&mut o, "size").and_then(|(_, n)| match &*n.value {
                Value::Int(i) if *i > 0 => Some(Spanned::new(*i as u64, n.span)),
                _ => {
                    self.err(Diagnostic::error(
                        "value-out-of-range",
                        "buffer size must be a positive number of bytes",
                        n.span,
                    ));
                    None
                }
            });
            self.finish(o, &["size", "per_light", "history", "external"]);
            return Some(Resource {
                name,
                kind: ResourceKind::Buffer(BufferDesc {
                    size: size?,
                    per_light,
                    history,
                    external,
                }),
                span,
            });
        }
        let format = self.required(&mut o, "format").and_then(|(_, n)| {
            self.ident(&n, "texture format", TextureFormat::NAMES, TextureFormat::from_name)
                .map(|f| Spanned::new(f, n.span))
        });
        let size = match o.take("size") {
            Some((_, n)) => self.size(&n),
            None => Some(Spanned::new(SizeSpec::Viewport { scale: 1.0 }, span)),
        };
        let layers = match o.take("layers") {
            Some((_, n)) => self.u32(&n),
            None => Some(Spanned::new(1, span)),
        };
        let view = match o.take("view") {
            Some((_, n)) => self
                .ident(&n, "view dimension", &ViewDim::NAMES, |s| match s {
                    "D2" => Some(ViewDim::D2),
                    "D2Array" => Some(ViewDim::D2Array),
                    "Cube" => Some(ViewDim::Cube),
                    _ => None,
                })
                .map(|v| Spanned::new(v, n.span)),
            None => Some(Spanned::new(ViewDim::D2, span)),
        };
        let mips = match o.take("mips") {
            Some((_, n)) => self.u32(&n),
            None => Some(Spanned::new(1, span)),
        };
        self.finish(o, &["format", "size", "layers", "view", "mips", "per_light", "history", "external"]);
        let desc = TextureDesc {
            format: format?,
            size: size?,
            layers: layers?,
            view: view?,
            mips: mips?,
            per_light,
            history,
            external,
        };
        Some(Resource {
            name,
            kind: ResourceKind::Texture(desc),
            span,
        })
    }

    fn size(&mut self, n: &Node) -> Res<Spanned<SizeSpec>> {
        let s = match &*n.value {
            Value::Ident(i) if i == "Viewport" => SizeSpec::Viewport { scale: 1.0 },
            Value::Tuple {
                name: Some((nm, _)),
                items,
            } if nm == "Viewport" && items.len() == 1 => {
                let scale = self.f64(&items[0])?;
                if !(scale > 0.0 && scale <= 16.0) {
                    self.err(Diagnostic::error(
                        "value-out-of-range",
                        "viewport scale must be in (0, 16]",
                        items[0].span,
                    ));
                    return None;
                }
                SizeSpec::Viewport { scale }
            }
            Value::Tuple {
                name: Some((nm, _)),
                items,
            } if nm == "Fixed" && items.len() == 2 => {
                let w = self.u32(&items[0])?;
                let h = self.u32(&items[1])?;
                if w.value == 0 || h.value == 0 {
                    self.err(Diagnostic::error("value-out-of-range", "texture size must be at least 1×1", n.span));
                    return None;
                }
                SizeSpec::Fixed {
                    width: w.value,
                    height: h.value,
                }
            }
            _ => return self.type_err("`Viewport`, `Viewport(scale)` or `Fixed(width, height)`", n),
        };
        Some(Spanned::new(s, n.span))
    }

    fn passes(&mut self, node: &Node) -> Res<Vec<Pass>> {
        let items = self.list(node)?.to_vec();
        let mut out: Vec<Pass> = vec![];
        for it in &items {
            if let Some(p) = self.pass(it) {
                if let Some(prev) = out.iter().find(|q| q.name.value == p.name.value) {
                    let prev_span = prev.name.span;
                    self.err(
                        Diagnostic::error("duplicate-name", format!("pass `{}` is declared twice", p.name.value), p.name.span)
                            .with_secondary(prev_span, "first declared here"),
                    );
                    continue;
                }
                out.push(p);
            }
        }
        Some(out)
    }

    /// A stage's shader: `file#entry` names another file; a given entry is used as written;
    /// with none, the stage's default entry of the pass's shader (`main` for GLSL).
    fn shader_ref(
        &mut self,
        default_file: &Option<Spanned<String>>,
        node: Option<(Span, Node)>,
        stage: naga::ShaderStage,
        pass_span: Span,
    ) -> Res<Option<ShaderRef>> {
        let (given, span) = match node {
            Some((_, n)) => match &*n.value {
                Value::Ident(i) if i == "None" => return Some(None),
                _ => {
                    let s = self.string(&n)?;
                    (Some(s.value), s.span)
                }
            },
            None => (None, default_file.as_ref().map(|f| f.span).unwrap_or(pass_span)),
        };
        if let Some((file, entry)) = given.as_deref().and_then(|t| t.split_once('#')) {
            return Some(Some(ShaderRef {
                file: Spanned::new(file.to_string(), span),
                entry: Spanned::new(entry.to_string(), span),
            }));
        }
        let word = crate::check::entry::stage_word(stage);
        let Some(file) = default_file.clone() else {
            self.err(Diagnostic::error(
                "missing-key",
                format!("pass has no `shader` for its {word} stage"),
                pass_span,
            ));
            return None;
        };
        let entry = given.unwrap_or_else(|| default_entry(stage, &file.value).to_string());
        Some(Some(ShaderRef {
            file,
            entry: Spanned::new(entry, span),
        }))
    }

    fn pass(&mut self, node: &Node) -> Res<Pass> {
        let (kind_name, mut o) = self.obj(node, &["Raster", "Fullscreen", "Compute"], "pass")?;
        let name = self.required(&mut o, "name").and_then(|(_, n)| self.string(&n));
        o.what = match &name {
            Some(n) => format!("pass `{}`", n.value),
            None => "pass".into(),
        };
        let span = o.span;
        let shader = o.take("shader").and_then(|(_, n)| self.string(&n));
        let mut allowed: Vec<&str> = vec![
            "name",
            "shader",
            "reads",
            "writes",
            "params",
            "param_block",
            "bind",
            "when",
            "per_light",
            "per_face",
        ];
        let (kind, vertex, fragment, compute) = match kind_name.as_str() {
            "Raster" => {
                allowed.extend(["vertex", "fragment", "color", "depth", "draw", "cull", "instances", "multiview"]);
                let draw = match o.take("draw") {
                    Some((_, n)) => match &*n.value {
                        Value::Ident(i) if i == "Scene" => Draw::Scene,
                        Value::Tuple {
                            name: Some((nm, _)),
                            items,
                        } if nm == "Vertices" && items.len() == 1 => Draw::Vertices(self.u32(&items[0])?.value),
                        _ => return self.type_err("`Scene` or `Vertices(count)`", &n),
                    },
                    None => Draw::Scene,
                };
                let cull = match o.take("cull") {
                    Some((_, n)) => self.ident(&n, "cull mode", &["None", "Front", "Back"], |s| match s {
                        "None" => Some(CullMode::None),
                        "Front" => Some(CullMode::Front),
                        "Back" => Some(CullMode::Back),
                        _ => None,
                    })?,
                    None => CullMode::Back,
                };
                let instances = match o.take("instances") {
                    Some((_, n)) => self.u32(&n)?.value.max(1),
                    None => 1,
                };
                let multiview = match o.take("multiview") {
                    Some((_, n)) => Some(self.u32(&n)?),
                    None => None,
                };
                let has_color = o.fields.iter().any(|f| f.0 == "color");
                let v = self.shader_ref(&shader, o.take("vertex"), naga::ShaderStage::Vertex, span)?;
                let f_node = o.take("fragment");
                let f = if f_node.is_none() && !has_color {
                    None
                } else {
                    self.shader_ref(&shader, f_node, naga::ShaderStage::Fragment, span)?
                };
                (
                    PassKind::Raster {
                        draw,
                        cull,
                        instances,
                        multiview,
                    },
                    v,
                    f,
                    None,
                )
            }
            "Fullscreen" => {
                allowed.extend(["fragment"]);
                let v = Some(ShaderRef {
                    file: Spanned::new(crate::shader::FULLSCREEN_FILE.to_string(), span),
                    entry: Spanned::new(crate::shader::FULLSCREEN_ENTRY.to_string(), span),
                });
                let f = self.shader_ref(&shader, o.take("fragment"), naga::ShaderStage::Fragment, span)?;
                (PassKind::Fullscreen, v, f, None)
            }
            _ => {
                allowed.extend(["entry", "dispatch"]);
                let c = self.shader_ref(&shader, o.take("entry"), naga::ShaderStage::Compute, span)?;
                let dispatch = match self.required(&mut o, "dispatch") {
                    Some((_, n)) => match &*n.value {
                        Value::Tuple {
                            name: Some((nm, _)),
                            items,
                        } if nm == "Size" && items.len() == 1 => Dispatch::Size(self.string(&items[0])?),
                        Value::Tuple {
                            name: Some((nm, _)),
                            items,
                        } if nm == "Groups" && items.len() == 3 => {
                            Dispatch::Groups(self.u32(&items[0])?.value, self.u32(&items[1])?.value, self.u32(&items[2])?.value)
                        }
                        _ => return self.type_err("`Size(\"resource\")` or `Groups(x, y, z)`", &n),
                    },
                    None => return None,
                };
                (PassKind::Compute { dispatch }, None, None, c)
            }
        };
        let reads = o.take("reads").and_then(|(_, n)| self.reads(&n)).unwrap_or_default();
        let writes = o.take("writes").and_then(|(_, n)| self.string_list(&n)).unwrap_or_default();
        let color = o.take("color").and_then(|(_, n)| self.color_targets(&n)).unwrap_or_default();
        let depth = o.take("depth").and_then(|(_, n)| self.depth_target(&n));
        let params = o.take("params").and_then(|(_, n)| self.string_list(&n)).unwrap_or_default();
        let param_block = match o.take("param_block") {
            Some((_, n)) => self.string(&n)?,
            None => Spanned::new("params".to_string(), span),
        };
        let bind = match o.take("bind") {
            Some((_, n)) => self
                .string_map(&n, "binding")?
                .into_iter()
                .filter_map(|(k, v)| self.string(&v).map(|v| (k, v)))
                .collect(),
            None => vec![],
        };
        let when = o.take("when").and_then(|(_, n)| self.condition(&n));
        let per_light = o.take("per_light").and_then(|(_, n)| self.light_kinds(&n));
        let per_face = o.take("per_face").and_then(|(_, n)| self.bool(&n)).unwrap_or(false);
        self.finish(o, &allowed);
        Some(Pass {
            name: name?,
            kind,
            vertex,
            fragment,
            compute,
            reads,
            writes,
            color,
            depth,
            params,
            param_block,
            bind,
            when,
            per_light,
            per_face,
            span,
        })
    }

    fn string_list(&mut self, n: &Node) -> Res<Vec<Spanned<String>>> {
        let items = self.list(n)?.to_vec();
        Some(items.iter().filter_map(|i| self.string(i)).collect())
    }

    fn reads(&mut self, n: &Node) -> Res<Vec<Read>> {
        let items = self.list(n)?.to_vec();
        let mut out = vec![];
        for it in &items {
            match &*it.value {
                Value::Str(s) => out.push(Read::Current(Spanned::new(s.clone(), it.span))),
                Value::Tuple {
                    name: Some((nm, _)),
                    items,
                } if nm == "Prev" && items.len() == 1 => {
                    if let Some(s) = self.string(&items[0]) {
                        out.push(Read::Prev(s));
                    }
                }
                _ => {
                    let _: Option<()> = self.type_err("a resource name or `Prev(\"name\")`", it);
                }
            }
        }
        Some(out)
    }

    fn load(&mut self, o: &mut Obj, depth: bool) -> Res<LoadOp> {
        let clear = o.take("clear");
        let load = o.take("load");
        match (clear, load) {
            (Some((ks, _)), Some(_)) => {
                self.err(Diagnostic::error("conflicting-keys", "give either `clear` or `load`, not both", ks));
                None
            }
            (Some((_, n)), None) => match (&*n.value, depth) {
                (Value::Tuple { name: None, items }, false) if items.len() == 4 => {
                    let mut v = vec![];
                    for i in items {
                        v.push(self.f64(i)?);
                    }
                    Some(LoadOp::Clear(v))
                }
                (_, true) => Some(LoadOp::Clear(vec![self.f64(&n)?])),
                _ => self.type_err("an RGBA tuple `(r, g, b, a)`", &n),
            },
            (None, Some((_, n))) => match &*n.value {
                Value::Ident(i) if i == "Load" => Some(LoadOp::Load),
                Value::Ident(i) if i == "Clear" => Some(LoadOp::Clear(if depth { vec![1.0] } else { vec![0.0; 4] })),
                _ => self.type_err("`Load` or `Clear`", &n),
            },
            (None, None) => Some(LoadOp::Clear(if depth { vec![1.0] } else { vec![0.0; 4] })),
        }
    }

    fn layer(&mut self, o: &mut Obj) -> Res<LayerSel> {
        match o.take("layer") {
            None => Some(LayerSel::Base),
            Some((_, n)) => match &*n.value {
                Value::Ident(i) if i == "Base" => Some(LayerSel::Base),
                Value::Ident(i) if i == "Face" => Some(LayerSel::Face),
                Value::Ident(i) if i == "All" => Some(LayerSel::All),
                Value::Tuple {
                    name: Some((nm, _)),
                    items,
                } if nm == "Index" && items.len() == 1 => Some(LayerSel::Index(self.u32(&items[0])?.value)),
                _ => self.type_err("`Base`, `Face`, `All` or `Index(n)`", &n),
            },
        }
    }

    fn color_targets(&mut self, n: &Node) -> Res<Vec<ColorTarget>> {
        let items = self.list(n)?.to_vec();
        let mut out = vec![];
        for it in &items {
            if let Value::Str(s) = &*it.value {
                out.push(ColorTarget {
                    resource: Spanned::new(s.clone(), it.span),
                    load: LoadOp::Clear(vec![0.0; 4]),
                    blend: None,
                    layer: LayerSel::Base,
                    span: it.span,
                });
                continue;
            }
            let Some((_, mut o)) = self.obj(it, &["Target"], "color target") else {
                continue;
            };
            let resource = self.required(&mut o, "resource").and_then(|(_, n)| self.string(&n));
            let load = self.load(&mut o, false);
            let blend = o.take("blend").and_then(|(_, n)| {
                self.ident(&n, "blend mode", &["Add", "Alpha", "Multiply"], |s| match s {
                    "Add" => Some(Blend::Add),
                    "Alpha" => Some(Blend::Alpha),
                    "Multiply" => Some(Blend::Multiply),
                    _ => None,
                })
                .map(|b| Spanned::new(b, n.span))
            });
            let layer = self.layer(&mut o);
            let span = o.span;
            self.finish(o, &["resource", "clear", "load", "blend", "layer"]);
            if let (Some(resource), Some(load), Some(layer)) = (resource, load, layer) {
                out.push(ColorTarget {
                    resource,
                    load,
                    blend,
                    layer,
                    span,
                });
            }
        }
        Some(out)
    }

    fn depth_target(&mut self, n: &Node) -> Res<DepthTarget> {
        if let Value::Str(s) = &*n.value {
            return Some(DepthTarget {
                resource: Spanned::new(s.clone(), n.span),
                load: LoadOp::Clear(vec![1.0]),
                compare: CompareFn::Less,
                write: true,
                layer: LayerSel::Base,
                span: n.span,
            });
        }
        let (_, mut o) = self.obj(n, &["Depth"], "depth target")?;
        let resource = self.required(&mut o, "resource").and_then(|(_, n)| self.string(&n));
        let load = self.load(&mut o, true);
        let compare = match o.take("compare") {
            Some((_, n)) => self.compare(&n),
            None => Some(CompareFn::Less),
        };
        let write = match o.take("write") {
            Some((_, n)) => self.bool(&n),
            None => Some(true),
        };
        let layer = self.layer(&mut o);
        let span = o.span;
        self.finish(o, &["resource", "clear", "load", "compare", "write", "layer"]);
        Some(DepthTarget {
            resource: resource?,
            load: load?,
            compare: compare?,
            write: write?,
            layer: layer?,
            span,
        })
    }

    pub fn condition(&mut self, n: &Node) -> Res<Spanned<Condition>> {
        const KINDS: [&str; 8] = ["Light", "Effect", "Reflective", "Toggle", "Variant", "Not", "All", "Any"];
        let c = match &*n.value {
            Value::Ident(i) if i == "Reflective" => Condition::Reflective,
            Value::Tuple {
                name: Some((nm, nspan)),
                items,
            } => match (nm.as_str(), items.as_slice()) {
                ("Light", [k]) => Condition::Light(self.ident(k, "light kind", &LightKind::NAMES, LightKind::from_name)?),
                ("Effect", [e]) => match &*e.value {
                    Value::Ident(i) => match Effect::from_name(i) {
                        Some(e) => Condition::Effect(e),
                        None => {
                            self.err(
                                Diagnostic::error("unknown-effect", format!("unknown effect `{i}`"), e.span)
                                    .with_note(suggestion_note(i, &Effect::NAMES)),
                            );
                            return None;
                        }
                    },
                    _ => return self.type_err("an effect name", e),
                },
                ("Toggle", [p]) => Condition::Toggle(self.string(p)?),
                ("Variant", [v, o]) => Condition::Variant(self.string(v)?, self.string(o)?),
                ("Not", [c]) => Condition::Not(Box::new(self.condition(c)?)),
                ("All" | "Any", [l]) => {
                    let items = self.list(l)?.to_vec();
                    let mut cs = vec![];
                    for i in &items {
                        cs.push(self.condition(i)?);
                    }
                    if nm == "All" {
                        Condition::All(cs)
                    } else {
                        Condition::Any(cs)
                    }
                }
                (k, _) if KINDS.contains(&k) => {
                    self.err(Diagnostic::error("type-mismatch", format!("wrong arguments for condition `{k}`"), n.span).with_note(
                        "forms: Light(Point), Effect(Ssr), Reflective, Toggle(\"param\"), Variant(\"name\", \"option\"), Not(c), All([..]), Any([..])",
                    ));
                    return None;
                }
                (k, _) => {
                    self.err(
                        Diagnostic::error("unknown-kind", format!("unknown condition `{k}`"), *nspan).with_note(suggestion_note(k, &KINDS)),
                    );
                    return None;
                }
            },
            _ => return self.type_err("a condition such as `Effect(Ssr)`", n),
        };
        Some(Spanned::new(c, n.span))
    }

    fn variants(&mut self, n: &Node) -> Res<Vec<Variant>> {
        let entries = self.string_map(n, "variant")?;
        let mut out = vec![];
        for (name, v) in entries {
            let Some((_, mut o)) = self.obj(&v, &["Variant"], "variant") else {
                continue;
            };
            o.what = format!("variant `{}`", name.value);
            let default = self.required(&mut o, "default").and_then(|(_, n)| self.string(&n));
            let doc = o.take("doc").and_then(|(_, n)| self.string(&n)).map(|s| s.value);
            let options = self.required(&mut o, "options").and_then(|(_, n)| self.variant_options(&n));
            let span = o.span;
            self.finish(o, &["default", "doc", "options"]);
            if let (Some(default), Some(options)) = (default, options) {
                out.push(Variant {
                    name,
                    options,
                    default,
                    doc,
                    span,
                });
            }
        }
        Some(out)
    }

    fn variant_options(&mut self, n: &Node) -> Res<Vec<VariantOption>> {
        let entries = self.string_map(n, "variant option")?;
        let mut out = vec![];
        for (name, v) in entries {
            let Some((_, mut o)) = self.obj(&v, &["Option"], "variant option") else {
                continue;
            };
            let requires = match o.take("requires") {
                Some((_, n)) => {
                    let items = self.list(&n)?.to_vec();
                    items
                        .iter()
                        .filter_map(|i| {
                            self.ident(i, "feature", Feature::NAMES, Feature::from_name)
                                .map(|f| Spanned::new(f, i.span))
                        })
                        .collect()
                }
                None => vec![],
            };
            let limits = match o.take("limits") {
                Some((_, n)) => {
                    let entries = self.string_map(&n, "limit")?;
                    let mut ls = vec![];
                    for (k, v) in entries {
                        if !crate::profile::Limits::NAMES.contains(&k.value.as_str()) {
                            self.err(
                                Diagnostic::error("unknown-limit", format!("unknown limit `{}`", k.value), k.span)
                                    .with_note(suggestion_note(&k.value, crate::profile::Limits::NAMES)),
                            );
                            continue;
                        }
                        if let Some(val) = self.u32(&v) {
                            ls.push((k, Spanned::new(val.value as u64, val.span)));
                        }
                    }
                    ls
                }
                None => vec![],
            };
            let fallback = o.take("fallback").and_then(|(_, n)| self.string(&n));
            let shaders = match o.take("shaders") {
                Some((_, n)) => self
                    .string_map(&n, "shader substitution")?
                    .into_iter()
                    .filter_map(|(k, v)| self.string(&v).map(|v| (k, v)))
                    .collect(),
                None => vec![],
            };
            let doc = o.take("doc").and_then(|(_, n)| self.string(&n)).map(|s| s.value);
            let span = o.span;
            self.finish(o, &["requires", "limits", "fallback", "shaders", "doc"]);
            out.push(VariantOption {
                name,
                requires,
                limits,
                fallback,
                shaders,
                doc,
                span,
            });
        }
        Some(out)
    }
}

pub fn geometry_error(span: Span) -> Diagnostic {
    Diagnostic::error("geometry-shader", "geometry shaders are not supported: WGSL, naga and wgpu have no geometry stage", span)
        .with_label_text("geometry stage requested here")
        .with_note("for single-pass layered rendering (e.g. cube shadow maps) use `multiview` (Multiview feature, one pass writing 6 views) or an instanced atlas (`instances: 6` with clip distances into a 3×2 atlas)")
}
