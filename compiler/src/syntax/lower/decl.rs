//! Lowering of declarations: parameters, samplers, resources.

use super::{Lowerer, Obj, Res};
use crate::diag::Diagnostic;
use crate::format::TextureFormat;
use crate::ir::*;
use crate::span::Spanned;
use crate::tree::{Node, Value};

impl Lowerer<'_> {
    pub(super) fn params(&mut self, node: &Node) -> Res<Vec<Param>> {
        let entries = self.string_map(node)?;
        Some(entries.into_iter().filter_map(|(name, v)| self.param(name, &v)).collect())
    }

    fn param(&mut self, name: Spanned<String>, node: &Node) -> Res<Param> {
        let mut o = self.obj(node, &ParamType::NAMES, "parameter")?;
        o.what = format!("parameter `{}`", name.value);
        let ty = match ParamType::from_name(&o.kind) {
            Some(t) => t,
            None => {
                let opts = self.required(&mut o, "options")?;
                ParamType::Enum(self.string_list(&opts)?.into_iter().map(|s| s.value).collect())
            }
        };
        let default = self.required(&mut o, "default").and_then(|n| self.param_value(&ty, &n));
        let min = o.take("min").and_then(|n| self.param_value(&ty, &n));
        let max = o.take("max").and_then(|n| self.param_value(&ty, &n));
        let doc = o.take("doc").and_then(|n| self.string(&n)).map(|s| s.value);
        let (span, head) = (o.span, o.head);
        self.finish(o, &["default", "min", "max", "doc", "options"], &[]);
        Some(Param {
            name,
            ty: Spanned::new(ty, head),
            default: default?,
            min,
            max,
            doc,
            span,
        })
    }

    /// A literal as written, its type still open (a number, bool, text or tuple of numbers).
    pub(super) fn literal(&mut self, node: &Node) -> Res<Literal> {
        Some(match &*node.value {
            Value::Int(i) => Literal::Int(*i),
            Value::Float(_) => Literal::Float(self.f64(node)?),
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
        })
    }

    fn param_value(&mut self, ty: &ParamType, node: &Node) -> Res<Spanned<ParamValue>> {
        let lit = self.literal(node)?;
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

    pub(super) fn samplers(&mut self, node: &Node) -> Res<Vec<SamplerDecl>> {
        let entries = self.string_map(node)?;
        Some(entries.into_iter().filter_map(|(name, v)| self.sampler(name, &v)).collect())
    }

    fn sampler(&mut self, name: Spanned<String>, node: &Node) -> Res<SamplerDecl> {
        let mut o = self.obj(node, &["Sampler"], "sampler")?;
        o.what = format!("sampler `{}`", name.value);
        let filter = o
            .get("filter")
            .and_then(|n| self.ident(&n, "filter mode", &FilterMode::NAMES, FilterMode::from_name));
        let mipmap = o
            .get("mipmap")
            .and_then(|n| self.ident(&n, "filter mode", &FilterMode::NAMES, FilterMode::from_name));
        let address = o
            .get("address")
            .and_then(|n| self.ident(&n, "address mode", &AddressMode::NAMES, AddressMode::from_name));
        let compare = match o.take("compare") {
            Some(n) => Some(self.ident(&n, "compare function", &CompareFn::NAMES, CompareFn::from_name)?),
            None => None,
        };
        let span = o.span;
        self.finish(o, &["filter", "mipmap", "address", "compare"], &[]);
        Some(SamplerDecl {
            name,
            filter: filter?,
            mipmap: mipmap?,
            address: address?,
            compare,
            span,
        })
    }

    pub(super) fn resources(&mut self, node: &Node) -> Res<Vec<Resource>> {
        let entries = self.string_map(node)?;
        Some(entries.into_iter().filter_map(|(name, v)| self.resource(name, &v)).collect())
    }

    fn resource(&mut self, name: Spanned<String>, node: &Node) -> Res<Resource> {
        let mut o = self.obj(node, &["Texture", "Buffer", "AccelerationStructure"], "resource")?;
        o.what = format!("resource `{}`", name.value);
        if o.kind == "AccelerationStructure" {
            // The scene supplies it whole: nothing about it is declared.
            let span = o.span;
            self.finish(o, &[], &[]);
            let kind = ResourceKind::AccelerationStructure;
            return Some(Resource {
                name,
                kind,
                valid: None,
                span,
            });
        }
        let per_light = match o.take("per_light") {
            Some(n) => Some(self.light_kinds(&n)?),
            None => None,
        };
        let history = o.get("history").and_then(|n| self.bool(&n));
        let external = o.get("external").and_then(|n| self.bool(&n));
        let data = match o.take("data") {
            Some(n) => Some(self.data(&n)?),
            None => None,
        };
        let valid = match o.take("valid") {
            Some(n) => Some(Spanned::new(
                self.floats::<2>(&n, "a range `(min, max)`").map(|[a, b]| (a, b))?,
                n.span,
            )),
            None => None,
        };
        let span = o.span;
        let kind = if o.kind == "Buffer" {
            let size = self.required(&mut o, "size").and_then(|n| self.u64(&n));
            let per_pixel = o.get("per_pixel").and_then(|n| self.bool(&n));
            self.finish(o, &["size", "per_pixel", "per_light", "history", "external", "data", "valid"], &[]);
            ResourceKind::Buffer(BufferDesc {
                size: size?,
                per_pixel: per_pixel?,
                per_light,
                history: history?,
                external: external?,
                data,
            })
        } else {
            let mut t = self.texture(o, per_light, history?, external?)?;
            t.data = data;
            ResourceKind::Texture(t)
        };
        Some(Resource { name, kind, valid, span })
    }

    fn texture(&mut self, mut o: Obj, per_light: Option<Spanned<Vec<LightKind>>>, history: bool, external: bool) -> Res<TextureDesc> {
        let format = self.required(&mut o, "format").and_then(|n| {
            self.ident(&n, "texture format", TextureFormat::NAMES, TextureFormat::from_name)
                .map(|f| Spanned::new(f, n.span))
        });
        let size = o.get("size").and_then(|n| self.size(&n));
        let layers = o.get("layers").and_then(|n| self.u32(&n));
        let view = o.get("view").and_then(|n| {
            self.ident(&n, "view dimension", &ViewDim::NAMES, ViewDim::from_name)
                .map(|v| Spanned::new(v, n.span))
        });
        let mips = o.get("mips").and_then(|n| self.u32(&n));
        self.finish(
            o,
            &[
                "format",
                "size",
                "layers",
                "view",
                "mips",
                "per_light",
                "history",
                "external",
                "data",
                "valid",
            ],
            &[],
        );
        Some(TextureDesc {
            format: format?,
            size: size?,
            layers: layers?,
            view: view?,
            mips: mips?,
            per_light,
            history,
            external,
            data: None,
        })
    }

    /// `File("noise.png")`, `F32([..])` or `U32([..])`.
    fn data(&mut self, n: &Node) -> Res<Spanned<DataSource>> {
        let expected = "`File(\"path\")`, `F32([numbers])` or `U32([whole numbers])`";
        let d = match (&*n.value, n.name()) {
            (Value::Tuple { items, .. }, Some("File")) if items.len() == 1 => DataSource::File(self.string(&items[0])?.value),
            (Value::Tuple { items, .. }, Some("F32")) if items.len() == 1 => {
                let list = self.list(&items[0])?.to_vec();
                DataSource::F32(list.iter().map(|x| self.f64(x)).collect::<Option<_>>()?)
            }
            (Value::Tuple { items, .. }, Some("U32")) if items.len() == 1 => {
                let list = self.list(&items[0])?.to_vec();
                DataSource::U32(list.iter().map(|x| self.u32(x).map(|v| v.value as u64)).collect::<Option<_>>()?)
            }
            _ => return self.type_err(expected, n),
        };
        Some(Spanned::new(d, n.span))
    }

    fn size(&mut self, n: &Node) -> Res<Spanned<SizeSpec>> {
        let s = match (&*n.value, n.name()) {
            (Value::Ident(_), Some("Viewport")) => SizeSpec::Viewport { scale: 1.0 },
            (Value::Tuple { items, .. }, Some("Viewport")) if items.len() == 1 && items[0].name() == Some("Param") => {
                match &*items[0].value {
                    Value::Tuple { items: inner, .. } if inner.len() == 1 => SizeSpec::ViewportParam(self.string(&inner[0])?.value),
                    _ => return self.type_err("`Viewport(Param(\"name\"))`", &items[0]),
                }
            }
            (Value::Tuple { items, .. }, Some("Viewport")) if items.len() == 1 => SizeSpec::Viewport {
                scale: self.f64(&items[0])?,
            },
            (Value::Tuple { items, .. }, Some("Fixed")) if items.len() == 2 => SizeSpec::Fixed {
                width: self.u32(&items[0])?.value,
                height: self.u32(&items[1])?.value,
            },
            (Value::Tuple { items, .. }, Some("Param")) if items.len() == 1 => SizeSpec::Param(self.string(&items[0])?.value),
            _ => {
                return self.type_err(
                    "`Viewport`, `Viewport(scale)`, `Viewport(Param(\"name\"))`, `Fixed(width, height)` or `Param(\"name\")`",
                    n,
                )
            }
        };
        Some(Spanned::new(s, n.span))
    }
}
