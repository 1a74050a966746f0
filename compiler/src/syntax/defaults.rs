//! The one table of defaults: what a key means when a pipeline file leaves it out. The
//! lowering fills absent keys from it and the raise leaves out values equal to it, so the
//! two front ends, both printers and the IR agree by construction.

use crate::span::Span;
use crate::tree::{same, Node, Value};

/// A default value, as the syntax tree would spell it.
#[derive(Clone, Copy, Debug)]
pub enum Def {
    Ident(&'static str),
    Str(&'static str),
    Int(i64),
    Float(f64),
    Bool(bool),
    Floats(&'static [f64]),
    EmptyList,
    EmptyMap,
    /// `Level(0)`: a target's mip.
    Level0,
}

/// (owner, key, default). Owners are item kinds as the tree names them; `Pass` holds the
/// keys every pass kind shares, `Light` those of every light kind.
pub const DEFAULTS: &[(&str, &str, Def)] = &[
    ("Texture", "size", Def::Ident("Viewport")),
    ("Texture", "layers", Def::Int(1)),
    ("Texture", "view", Def::Ident("D2")),
    ("Texture", "mips", Def::Int(1)),
    ("Texture", "history", Def::Bool(false)),
    ("Texture", "external", Def::Bool(false)),
    ("Buffer", "history", Def::Bool(false)),
    ("Buffer", "per_pixel", Def::Bool(false)),
    ("Buffer", "external", Def::Bool(false)),
    ("Sampler", "filter", Def::Ident("Linear")),
    ("Sampler", "mipmap", Def::Ident("Nearest")),
    ("Sampler", "address", Def::Ident("ClampToEdge")),
    ("Pass", "reads", Def::EmptyList),
    ("Pass", "writes", Def::EmptyList),
    ("Pass", "params", Def::EmptyList),
    ("Pass", "param_block", Def::Str("params")),
    ("Pass", "bind", Def::EmptyMap),
    ("Pass", "per_face", Def::Bool(false)),
    ("Pass", "shadow_casters", Def::Bool(false)),
    ("Pass", "values", Def::EmptyMap),
    ("Pass", "constants", Def::EmptyMap),
    ("Pass", "always", Def::Bool(false)),
    ("Pipeline", "always", Def::Bool(false)),
    ("Pipeline", "jitter", Def::Bool(false)),
    ("Pass", "color", Def::EmptyList),
    ("Raster", "draw", Def::Ident("Scene")),
    ("Raster", "cull", Def::Ident("Back")),
    ("Raster", "instances", Def::Int(1)),
    ("Target", "clear", Def::Floats(&[0.0, 0.0, 0.0, 0.0])),
    ("Target", "layer", Def::Ident("Base")),
    ("Target", "mip", Def::Level0),
    ("Depth", "clear", Def::Float(1.0)),
    ("Depth", "compare", Def::Ident("Less")),
    ("Depth", "write", Def::Bool(true)),
    ("Depth", "layer", Def::Ident("Base")),
    ("Depth", "mip", Def::Level0),
    ("Option", "requires", Def::EmptyList),
    ("Option", "jitter", Def::Bool(false)),
    ("Option", "limits", Def::EmptyMap),
    ("Option", "shaders", Def::EmptyMap),
    ("Option", "params", Def::EmptyMap),
    // Scene files.
    ("Camera", "yaw", Def::Float(0.0)),
    ("Camera", "pitch", Def::Float(0.0)),
    ("Camera", "fov", Def::Float(45.0)),
    ("Camera", "near", Def::Float(0.05)),
    ("Camera", "far", Def::Float(100.0)),
    ("Model", "translation", Def::Floats(&[0.0, 0.0, 0.0])),
    ("Model", "rotation", Def::Floats(&[0.0, 0.0, 0.0])),
    ("Model", "scale", Def::Float(1.0)),
    ("Model", "triangles", Def::Float(1.0)),
    ("Model", "reflective", Def::Bool(false)),
    ("Light", "on", Def::Bool(true)),
    ("Light", "color", Def::Floats(&[1.0, 1.0, 1.0])),
    ("Light", "intensity", Def::Float(1.0)),
    ("Light", "position", Def::Floats(&[0.0, 0.0, 0.0])),
    ("Light", "direction", Def::Floats(&[0.0, -1.0, 0.0])),
    ("Light", "inner", Def::Float(25.0)),
    ("Light", "outer", Def::Float(35.0)),
    ("Light", "range", Def::Float(10.0)),
    ("Light", "shadows", Def::Bool(true)),
];

/// The default of `key` in an item of kind `owner` (pass kinds fall back to `Pass`).
pub fn get(owner: &str, key: &str) -> Option<Def> {
    let find = |o: &str| DEFAULTS.iter().find(|(ow, k, _)| *ow == o && *k == key).map(|(_, _, d)| *d);
    let shared = match owner {
        "Raster" | "Fullscreen" | "Compute" => Some("Pass"),
        "Point" | "Spot" | "Directional" => Some("Light"),
        _ => None,
    };
    find(owner).or_else(|| shared.and_then(find))
}

impl Def {
    pub fn node(self, span: Span) -> Node {
        match self {
            Def::Ident(s) => Node::ident(s, span),
            Def::Str(s) => Node::str(s, span),
            Def::Int(i) => Node::int(i, span),
            Def::Float(f) => Node::float(f, span),
            Def::Bool(b) => Node::bool(b, span),
            Def::Floats(v) => Node::tuple(v.iter().map(|x| Node::float(*x, span)).collect(), span),
            Def::EmptyList => Node::list(vec![], span),
            Def::EmptyMap => Node::map(vec![], span),
            Def::Level0 => Node::call("Level", vec![Node::int(0, span)], span),
        }
    }
}

/// Is `node` what the table says `owner.key` defaults to? (The raise leaves such keys out.)
pub fn is_default(owner: &str, key: &str, node: &Node) -> bool {
    match get(owner, key) {
        Some(Def::EmptyMap) => matches!(&*node.value, Value::Map(m) if m.is_empty()),
        Some(d) => same(&d.node(node.span), node),
        None => false,
    }
}
