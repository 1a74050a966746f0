//! Lowering of passes: the keys every pass has, then each kind's own (raster, fullscreen,
//! compute), shader references and targets.

use super::{Lowerer, Obj, Res};
use crate::diag::{Code, Diagnostic};
use crate::ir::*;
use crate::span::{Span, Spanned};
use crate::tree::{Node, Value};

const COMMON: [&str; 16] = [
    "name",
    "shader",
    "reads",
    "writes",
    "params",
    "values",
    "constants",
    "param_block",
    "bind",
    "when",
    "per_light",
    "per_face",
    "shadow_casters",
    "per_mip",
    "repeat",
    "always",
];
const RASTER: [&str; 8] = ["vertex", "fragment", "color", "depth", "draw", "cull", "instances", "multiview"];
const FULLSCREEN: [&str; 3] = ["fragment", "color", "depth"];
const COMPUTE: [&str; 2] = ["entry", "dispatch"];

/// The keys a pass of a kind (`Raster`, `Fullscreen`, `Compute`) may have, as the syntax
/// tree names them (editors complete them).
pub fn pass_keys(kind: &str) -> Vec<&'static str> {
    keys(kind).0
}

/// The keys of a pass kind, and those that belong to the other kinds only.
fn keys(kind: &str) -> (Vec<&'static str>, Vec<&'static str>) {
    let own: &[&str] = match kind {
        "Raster" => &RASTER,
        "Fullscreen" => &FULLSCREEN,
        _ => &COMPUTE,
    };
    let allowed: Vec<&str> = COMMON.iter().chain(own).copied().collect();
    let mut elsewhere: Vec<&str> = RASTER.iter().chain(&FULLSCREEN).chain(&COMPUTE).copied().collect();
    elsewhere.retain(|k| !allowed.contains(k));
    (allowed, elsewhere)
}

impl Lowerer<'_> {
    pub(super) fn passes(&mut self, node: &Node, variants: &[Variant]) -> Res<Vec<Pass>> {
        let items = self.list(node)?.to_vec();
        let written = items.iter().enumerate();
        Some(written.flat_map(|(i, it)| self.pass_with_choices(it, variants, i as u32)).collect())
    }

    pub(super) fn pass(&mut self, node: &Node) -> Res<Pass> {
        let mut o = self.obj(node, &["Raster", "Fullscreen", "Compute"], "pass")?;
        let name = self.required(&mut o, "name").and_then(|n| self.string(&n));
        if let Some(n) = &name {
            o.what = format!("pass `{}`", n.value);
        }
        let shader = o.take("shader").and_then(|n| self.string(&n));
        let kind = match o.kind.as_str() {
            "Raster" => self.raster(&mut o, &shader).map(PassKind::Raster),
            "Fullscreen" => self.fullscreen(&mut o, &shader).map(PassKind::Fullscreen),
            _ => self.compute(&mut o, &shader).map(PassKind::Compute),
        };
        let pass = self.pass_common(&mut o, name, kind);
        let (allowed, elsewhere) = keys(&o.kind);
        self.finish(o, &allowed, &elsewhere);
        pass
    }

    fn pass_common(&mut self, o: &mut Obj, name: Option<Spanned<String>>, kind: Option<PassKind>) -> Res<Pass> {
        let reads = o.get("reads").and_then(|n| self.reads(&n));
        let writes = o.get("writes").and_then(|n| self.string_list(&n));
        let params = o.get("params").and_then(|n| self.string_list(&n));
        let param_block = o.get("param_block").and_then(|n| self.string(&n));
        let bind = o.get("bind").and_then(|n| self.string_pairs(&n));
        let when = match o.take("when") {
            Some(n) => Some(self.condition(&n)?),
            None => None,
        };
        let per_light = match o.take("per_light") {
            Some(n) => Some(self.light_kinds(&n)?),
            None => None,
        };
        let per_face = o.get("per_face").and_then(|n| self.bool(&n));
        let shadow_casters = o.get("shadow_casters").and_then(|n| self.bool(&n));
        let values = o.get("values").and_then(|n| self.values(&n));
        let constants = o.get("constants").and_then(|n| self.constants(&n));
        let per_mip = match o.take("per_mip") {
            Some(n) => Some(self.mip_range(&n)?),
            None => None,
        };
        let repeat = match o.take("repeat") {
            Some(n) => Some(self.repeat(&n)?),
            None => None,
        };
        let always = o.get("always").and_then(|n| self.bool(&n));
        Some(Pass {
            name: name?,
            kind: kind?,
            reads: reads?,
            writes: writes?,
            params: params?,
            param_block: param_block?,
            bind: bind?,
            when,
            per_light,
            per_face: per_face?,
            shadow_casters: shadow_casters?,
            values: values?,
            constants: constants?,
            per_mip,
            repeat,
            always: always?,
            from: None,
            origin: None,
            choice: None,
            span: o.span,
        })
    }

    /// `values: {"field": literal}`: numbers (whole or not: the field's type decides),
    /// bools, tuples of numbers.
    fn values(&mut self, n: &Node) -> Res<Vec<(Spanned<String>, Spanned<ParamValue>)>> {
        let entries = self.string_map(n)?;
        let mut out = vec![];
        for (k, v) in entries {
            let value = match &*v.value {
                Value::Int(_) | Value::Float(_) => ParamValue::Float(self.f64(&v)?),
                Value::Bool(b) => ParamValue::Bool(*b),
                Value::Tuple { name: None, items } if (2..=4).contains(&items.len()) => {
                    ParamValue::Vec(items.iter().map(|x| self.f64(x)).collect::<Option<_>>()?)
                }
                _ => return self.type_err("a number, `true`/`false` or a tuple of 2 to 4 numbers", &v),
            };
            out.push((k, Spanned::new(value, v.span)));
        }
        Some(out)
    }

    /// `constants: {"NAME": value}`: a number, `true`/`false`, `Param("name")` or
    /// `Variant("variant", "option")`.
    fn constants(&mut self, n: &Node) -> Res<Vec<(Spanned<String>, Spanned<Constant>)>> {
        let entries = self.string_map(n)?;
        let mut out = vec![];
        for (k, v) in entries {
            let c = match (&*v.value, v.name()) {
                (Value::Int(_) | Value::Float(_), _) => Constant::Number(self.f64(&v)?),
                (Value::Bool(b), _) => Constant::Bool(*b),
                (Value::Tuple { items, .. }, Some("Param")) if items.len() == 1 => Constant::Param(self.string(&items[0])?.value),
                (Value::Tuple { items, .. }, Some("Variant")) if items.len() == 2 => {
                    Constant::Variant(self.string(&items[0])?.value, self.string(&items[1])?.value)
                }
                _ => {
                    return self.type_err(
                        "a number, `true`/`false`, `Param(\"name\")` or `Variant(\"variant\", \"option\")`",
                        &v,
                    )
                }
            };
            out.push((k, Spanned::new(c, v.span)));
        }
        Some(out)
    }

    /// The layer a `Layer(name, ..)` read binds: `n` or `Rep(offset)`.
    fn layer_read(&mut self, n: &Node) -> Res<Spanned<LayerSel>> {
        let sel = match (&*n.value, n.name()) {
            (Value::Int(_), _) => LayerSel::Index(self.u32(n)?.value),
            (Value::Tuple { items, .. }, Some("Rep")) if items.len() == 1 => LayerSel::Rep(self.rep_offset(&items[0])?),
            _ => return self.type_err("a layer `n` or `Rep(offset)`", n),
        };
        Some(Spanned::new(sel, n.span))
    }

    fn rep_offset(&mut self, n: &Node) -> Res<i32> {
        match &*n.value {
            Value::Int(i) if i32::try_from(*i).is_ok() => Some(*i as i32),
            _ => self.type_err("a whole-number offset", n),
        }
    }

    /// `repeat: N` or `repeat: Param("name")`.
    fn repeat(&mut self, n: &Node) -> Res<Spanned<Repeat>> {
        let r = match (&*n.value, n.name()) {
            (Value::Int(_), _) => Repeat::Times(self.u32(n)?.value),
            (Value::Tuple { items, .. }, Some("Param")) if items.len() == 1 => Repeat::Param(self.string(&items[0])?.value),
            _ => return self.type_err("a number of times or `Param(\"name\")`", n),
        };
        Some(Spanned::new(r, n.span))
    }

    /// `per_mip: (from, to)`.
    fn mip_range(&mut self, n: &Node) -> Res<Spanned<MipRange>> {
        match &*n.value {
            Value::Tuple { name: None, items } if items.len() == 2 => {
                let (from, to) = (self.u32(&items[0])?.value, self.u32(&items[1])?.value);
                Some(Spanned::new(MipRange { from, to }, n.span))
            }
            _ => self.type_err("a range of mip levels `(from, to)`", n),
        }
    }

    /// `Level(n)` or `Rep(offset)`.
    fn mip_sel(&mut self, n: &Node) -> Res<Spanned<MipSel>> {
        let m = match (&*n.value, n.name()) {
            (Value::Tuple { items, .. }, Some("Level")) if items.len() == 1 => MipSel::Level(self.u32(&items[0])?.value),
            (Value::Tuple { items, .. }, Some("Rep")) if items.len() == 1 => match &*items[0].value {
                Value::Int(i) if i32::try_from(*i).is_ok() => MipSel::Rep(*i as i32),
                _ => return self.type_err("a whole-number offset", &items[0]),
            },
            _ => return self.type_err("`Level(n)` or `Rep(offset)`", n),
        };
        Some(Spanned::new(m, n.span))
    }

    fn raster(&mut self, o: &mut Obj, shader: &Option<Spanned<String>>) -> Res<Raster> {
        let draw = o.get("draw").and_then(|n| match (&*n.value, n.name()) {
            (Value::Ident(_), Some("Scene")) => Some(Draw::Scene),
            (Value::Ident(_), Some("Transparent")) => Some(Draw::Transparent),
            (Value::Ident(_), Some("LightVolume")) => Some(Draw::LightVolume),
            (Value::Tuple { items, .. }, Some("Vertices")) if items.len() == 1 => Some(Draw::Vertices(self.u32(&items[0])?.value)),
            (Value::Tuple { items, .. }, Some("Triangles")) if items.len() == 1 => Some(Draw::Triangles(self.u32(&items[0])?.value)),
            _ => self.type_err("`Scene`, `Transparent`, `LightVolume`, `Vertices(count)` or `Triangles(count)`", &n),
        });
        let cull = o
            .get("cull")
            .and_then(|n| self.ident(&n, "cull mode", &CullMode::NAMES, CullMode::from_name));
        let instances = o.get("instances").and_then(|n| self.u32(&n));
        let multiview = match o.take("multiview") {
            Some(n) => Some(self.u32(&n)?),
            None => None,
        };
        let vertex = self.shader_ref(shader, o.take("vertex"), Stage::Vertex, o.span);
        // Without color targets a raster pass is depth-only unless it names a fragment stage.
        let fragment = match o.take("fragment") {
            None if !o.has("color") => Some(None),
            given => self.optional_stage(shader, given, o.span),
        };
        let targets = self.targets(o);
        Some(Raster {
            vertex: vertex?,
            fragment: fragment?,
            targets: targets?,
            draw: draw?,
            cull: cull?,
            instances: instances?,
            multiview,
        })
    }

    fn fullscreen(&mut self, o: &mut Obj, shader: &Option<Spanned<String>>) -> Res<Fullscreen> {
        let fragment = self.shader_ref(shader, o.take("fragment"), Stage::Fragment, o.span);
        let targets = self.targets(o);
        Some(Fullscreen {
            fragment: fragment?,
            targets: targets?,
        })
    }

    fn compute(&mut self, o: &mut Obj, shader: &Option<Spanned<String>>) -> Res<Compute> {
        let entry = self.shader_ref(shader, o.take("entry"), Stage::Compute, o.span);
        let dispatch = self.required(o, "dispatch").and_then(|n| {
            let d = match (&*n.value, n.name()) {
                (Value::Tuple { items, .. }, Some("Size")) if items.len() == 1 => Dispatch::Size(self.string(&items[0])?),
                (Value::Tuple { items, .. }, Some("Groups")) if items.len() == 3 => {
                    Dispatch::Groups(self.u32(&items[0])?.value, self.u32(&items[1])?.value, self.u32(&items[2])?.value)
                }
                _ => return self.type_err("`Size(\"resource\")` or `Groups(x, y, z)`", &n),
            };
            Some(Spanned::new(d, n.span))
        });
        Some(Compute {
            entry: entry?,
            dispatch: dispatch?,
        })
    }

    /// `fragment: None` (no fragment stage) or a stage reference.
    fn optional_stage(&mut self, shader: &Option<Spanned<String>>, given: Option<Node>, span: Span) -> Res<Option<ShaderRef>> {
        if let Some(n) = &given {
            if matches!(&*n.value, Value::Ident(i) if i == "None") {
                return Some(None);
            }
        }
        self.shader_ref(shader, given, Stage::Fragment, span).map(Some)
    }

    /// A stage's shader: `file#entry` names another file; a given entry is used as written;
    /// with none, the stage's default entry of the pass's shader (`main` for GLSL).
    fn shader_ref(&mut self, shader: &Option<Spanned<String>>, given: Option<Node>, stage: Stage, pass_span: Span) -> Res<ShaderRef> {
        let (text, span) = match given {
            Some(n) => {
                let s = self.string(&n)?;
                (Some(s.value), s.span)
            }
            None => (None, shader.as_ref().map(|f| f.span).unwrap_or(pass_span)),
        };
        if let Some((file, entry)) = text.as_deref().and_then(|t| t.split_once('#')) {
            return Some(ShaderRef {
                file: Spanned::new(file.to_string(), span),
                entry: Spanned::new(entry.to_string(), span),
            });
        }
        let Some(file) = shader.clone() else {
            self.err(Diagnostic::error(
                Code::MissingKey,
                format!("pass has no `shader` for its {} stage", stage.word()),
                pass_span,
            ));
            return None;
        };
        let entry = text.unwrap_or_else(|| default_entry(stage, &file.value).to_string());
        Some(ShaderRef {
            file,
            entry: Spanned::new(entry, span),
        })
    }

    fn reads(&mut self, n: &Node) -> Res<Vec<Read>> {
        let items = self.list(n)?.to_vec();
        let mut out = vec![];
        for it in &items {
            match (&*it.value, it.name()) {
                (Value::Str(s), _) => out.push(Read::Current(Spanned::new(s.clone(), it.span))),
                (Value::Tuple { items, .. }, Some("Prev")) if items.len() == 1 => out.push(Read::Prev(self.string(&items[0])?)),
                (Value::Tuple { items, .. }, Some("Mip")) if items.len() == 2 => {
                    out.push(Read::Mip(self.string(&items[0])?, self.mip_sel(&items[1])?))
                }
                (Value::Tuple { items, .. }, Some("Layer")) if items.len() == 2 => {
                    out.push(Read::Layer(self.string(&items[0])?, self.layer_read(&items[1])?))
                }
                _ => {
                    return self.type_err(
                        "a resource name, `Prev(\"name\")`, `Mip(\"name\", level)` or `Layer(\"name\", n)`",
                        it,
                    )
                }
            }
        }
        Some(out)
    }

    fn targets(&mut self, o: &mut Obj) -> Res<Targets> {
        let color = o.get("color").and_then(|n| {
            let items = self.list(&n)?.to_vec();
            items.iter().map(|it| self.color_target(it)).collect::<Option<Vec<_>>>()
        });
        let depth = match o.take("depth") {
            Some(n) => Some(self.depth_target(&n)?),
            None => None,
        };
        Some(Targets { color: color?, depth })
    }

    /// A target given as a bare name is the target struct with every key at its default.
    fn target_obj(&mut self, n: &Node, kind: &str, what: &str) -> Res<(Spanned<String>, Obj)> {
        if let Value::Str(s) = &*n.value {
            let bare = Node::structure(
                kind,
                n.span,
                vec![("resource".into(), n.span, Node::str(s.clone(), n.span))],
                n.span,
            );
            return self.target_obj(&bare, kind, what);
        }
        let mut o = self.obj(n, &[kind], what)?;
        let resource = self.required(&mut o, "resource").and_then(|r| self.string(&r))?;
        Some((resource, o))
    }

    fn color_target(&mut self, n: &Node) -> Res<ColorTarget> {
        let (resource, mut o) = self.target_obj(n, "Target", "color target")?;
        let load = self.load(&mut o, |l, n| l.floats::<4>(n, "an RGBA tuple `(r, g, b, a)`"));
        let blend = match o.take("blend") {
            Some(b) => Some(Spanned::new(self.ident(&b, "blend mode", &Blend::NAMES, Blend::from_name)?, b.span)),
            None => None,
        };
        let layer = o.get("layer").and_then(|l| self.layer(&l));
        let mip = o.get("mip").and_then(|m| self.mip_sel(&m));
        let span = o.span;
        self.finish(o, &["resource", "clear", "load", "blend", "layer", "mip"], &["compare", "write"]);
        Some(ColorTarget {
            resource,
            load: load?,
            blend,
            layer: layer?,
            mip: mip?,
            span,
        })
    }

    fn depth_target(&mut self, n: &Node) -> Res<DepthTarget> {
        let (resource, mut o) = self.target_obj(n, "Depth", "depth target")?;
        let load = self.load(&mut o, Self::depth_clear);
        let compare = o
            .get("compare")
            .and_then(|c| self.ident(&c, "compare function", &CompareFn::NAMES, CompareFn::from_name));
        let write = o.get("write").and_then(|w| self.bool(&w));
        let layer = o.get("layer").and_then(|l| self.layer(&l));
        let mip = o.get("mip").and_then(|m| self.mip_sel(&m));
        let span = o.span;
        self.finish(o, &["resource", "clear", "load", "compare", "write", "layer", "mip"], &["blend"]);
        Some(DepthTarget {
            resource,
            load: load?,
            compare: compare?,
            write: write?,
            layer: layer?,
            mip: mip?,
            span,
        })
    }

    /// A depth target's clear value: depth lies in 0..1, and wgpu refuses any other (at
    /// render time, and only where the pass runs), so it is refused here, where it is written.
    fn depth_clear(&mut self, n: &Node) -> Res<f64> {
        let v = self.f64(n)?;
        if (0.0..=1.0).contains(&v) {
            return Some(v);
        }
        self.err(
            Diagnostic::error(Code::ValueOutOfRange, format!("depth clear value `{v}` is outside 0..1"), n.span)
                .with_note("depth lies in 0..1: clear to 1 (the far plane), or 0 with reversed depth"),
        );
        None
    }

    /// `clear: value` or `load: Load` (`load: Clear` means the default clear value).
    fn load<T>(&mut self, o: &mut Obj, value: impl Fn(&mut Self, &Node) -> Res<T>) -> Res<Load<T>> {
        match (o.take("clear"), o.take("load")) {
            (Some(c), Some(_)) => {
                self.err(Diagnostic::error(
                    Code::ConflictingKeys,
                    "give either `clear` or `load`, not both",
                    c.span,
                ));
                None
            }
            (None, Some(l)) => match &*l.value {
                Value::Ident(i) if i == "Load" => Some(Load::Load),
                Value::Ident(i) if i == "Clear" => Some(Load::Clear(value(self, &o.get("clear")?)?)),
                _ => self.type_err("`Load` or `Clear`", &l),
            },
            (c, None) => {
                let c = c.or_else(|| o.get("clear"))?;
                Some(Load::Clear(value(self, &c)?))
            }
        }
    }

    fn layer(&mut self, n: &Node) -> Res<LayerSel> {
        match (&*n.value, n.name()) {
            (Value::Ident(_), Some("Base")) => Some(LayerSel::Base),
            (Value::Ident(_), Some("Face")) => Some(LayerSel::Face),
            (Value::Ident(_), Some("All")) => Some(LayerSel::All),
            (Value::Tuple { items, .. }, Some("Index")) if items.len() == 1 => Some(LayerSel::Index(self.u32(&items[0])?.value)),
            (Value::Tuple { items, .. }, Some("Rep")) if items.len() == 1 => Some(LayerSel::Rep(self.rep_offset(&items[0])?)),
            _ => self.type_err("`Base`, `Face`, `All`, `Index(n)` or `Rep(offset)`", n),
        }
    }
}
