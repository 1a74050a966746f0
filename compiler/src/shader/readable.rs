//! Sub-stage of `shaders`: naga's validation errors made readable — types in WGSL syntax
//! instead of naga's Debug form, expression handles (`[3]`) as the source text they came
//! from, and operations a stage forbids located at the operation, not at line 1.

use naga::{Handle, Module, Span};

/// A message with naga's Debug types (`Vector { size: Tri, scalar: Scalar { kind: Float,
/// width: 4 } }`) written as WGSL (`vec3<f32>`).
pub fn types(msg: &str, m: &Module) -> String {
    let mut out = String::new();
    let mut rest = msg;
    while !rest.is_empty() {
        if let Some((ty, len)) = parse_type(rest, m) {
            out.push_str(&ty);
            rest = &rest[len..];
        } else {
            let c = rest.chars().next().unwrap_or(' ');
            out.push(c);
            rest = &rest[c.len_utf8()..];
        }
    }
    out
}

/// A type in Debug form at the start of `s`: its WGSL name and the length it spans.
fn parse_type(s: &str, m: &Module) -> Option<(String, usize)> {
    // A type by handle, as naga names it in headlines: `Type [2] ''` (no name), `type [1]`.
    for prefix in ["Type [", "type ["] {
        if let Some(r) = s.strip_prefix(prefix) {
            let (index, after) = r.split_once(']')?;
            let (h, _) = m.types.iter().nth(index.parse().ok()?)?;
            let quoted = after.strip_prefix(" '").and_then(|q| q.find('\'')).map_or(0, |end| 2 + end + 1);
            let len = prefix.len() + index.len() + 1 + quoted;
            return Some((format!("{}ype `{}`", &prefix[..1], crate::shader::reflect::type_name(m, h)), len));
        }
    }
    if let Some(r) = s.strip_prefix("Scalar(") {
        let (name, n) = scalar(r)?;
        return r[n..].starts_with(')').then(|| (name, "Scalar(".len() + n + 1));
    }
    if s.starts_with("Scalar {") {
        return scalar(s);
    }
    if let Some(r) = s.strip_prefix("Vector { size: ") {
        let (size, r2) = r.split_once(", scalar: ")?;
        let n = match size {
            "Bi" => 2,
            "Tri" => 3,
            "Quad" => 4,
            _ => return None,
        };
        let (sc, len) = scalar(r2)?;
        r2[len..]
            .starts_with(" }")
            .then(|| (format!("vec{n}<{sc}>"), s.len() - r2.len() + len + 2))
    } else if let Some(r) = s.strip_prefix("Matrix { columns: ") {
        let (cols, r2) = r.split_once(", rows: ")?;
        let (rows, r3) = r2.split_once(", scalar: ")?;
        let (sc, len) = scalar(r3)?;
        let (c, r) = (vector_size(cols)?, vector_size(rows)?);
        r3[len..]
            .starts_with(" }")
            .then(|| (format!("mat{c}x{r}<{sc}>"), s.len() - r3.len() + len + 2))
    } else if let Some(r) = s.strip_prefix("Pointer { base: [") {
        let (index, r2) = r.split_once("], space: ")?;
        let end = r2.find(" }")?;
        let ty = m
            .types
            .iter()
            .nth(index.parse().ok()?)
            .map(|(h, _)| crate::shader::reflect::type_name(m, h))?;
        let space = r2[..end].split([' ', '{']).next()?.to_lowercase();
        Some((format!("ptr<{space}, {ty}>"), s.len() - r2.len() + end + 2))
    } else {
        None
    }
}

fn vector_size(s: &str) -> Option<u8> {
    Some(match s {
        "Bi" => 2,
        "Tri" => 3,
        "Quad" => 4,
        _ => return None,
    })
}

/// `Scalar { kind: Float, width: 4 }` at the start of `s`.
fn scalar(s: &str) -> Option<(String, usize)> {
    let r = s.strip_prefix("Scalar { kind: ")?;
    let (kind, r2) = r.split_once(", width: ")?;
    let end = r2.find(" }")?;
    let width: u8 = r2[..end].parse().ok()?;
    let name = match (kind, width) {
        ("Float", 2) => "f16",
        ("Float", 4) => "f32",
        ("Float", 8) => "f64",
        ("Sint", 4) => "i32",
        ("Sint", 8) => "i64",
        ("Uint", 4) => "u32",
        ("Uint", 8) => "u64",
        ("Bool", _) => "bool",
        ("AbstractInt", _) => "abstract-int",
        ("AbstractFloat", _) => "abstract-float",
        _ => return None,
    };
    Some((name.to_string(), s.len() - r2.len() + end + 2))
}

/// The words naga puts before a handle that is not an expression's.
const OTHER_HANDLES: [&str; 10] = [
    "Function ",
    "function ",
    "Type ",
    "type ",
    "Constant ",
    "Override ",
    "Global variable ",
    "global variable ",
    "Local variable ",
    "local variable ",
];

/// Expression handles (`[3]`, `Expression [3]`) as the source text of the expression in
/// `f`, quoted; handles naga gives no span for stay as they are.
pub fn expressions(msg: &str, f: &naga::Function, text: &str) -> String {
    let snippet = |i: usize| -> Option<String> {
        let (h, _) = f.expressions.iter().nth(i)?;
        let r = f.expressions.get_span(h).to_range()?;
        let s = text.get(r)?.trim();
        (!s.is_empty() && s.len() <= 60 && !s.contains('\n')).then(|| format!("`{s}`"))
    };
    let msg = msg.replace("naga::ir::Expression ", "").replace("Expression [", "[");
    let mut out = String::new();
    let mut rest = msg.as_str();
    while let Some(open) = rest.find('[') {
        out.push_str(&rest[..open]);
        let after = &rest[open + 1..];
        // Handles into other arenas (functions, types, constants, globals...) are not
        // expressions: their numbers index something else and stay as naga wrote them.
        let other_arena = OTHER_HANDLES.iter().any(|k| out.ends_with(k));
        let close = after
            .find(']')
            .filter(|&c| c > 0 && !other_arena && after[..c].bytes().all(|b| b.is_ascii_digit()));
        match close.and_then(|c| Some((c, snippet(after[..c].parse().ok()?)?))) {
            Some((c, s)) => {
                out.push_str(&s);
                rest = &after[c + 1..];
            }
            None => {
                out.push('[');
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

/// What each naga capability lets a shader write: its `enable` extension (if any) and words
/// only it allows, to find where a shader asks for a capability naga names without a span.
const CAPABILITY_USES: &[(&str, &str, &[&str])] = &[
    ("RAY_QUERY", "wgpu_ray_query", &["ray_query", "acceleration_structure"]),
    ("FLOAT64", "", &["f64"]),
    ("SHADER_INT64_ATOMIC", "", &["atomic<u64>", "atomic<i64>"]),
    ("SHADER_INT64", "", &["i64", "u64"]),
    ("SHADER_INT16", "", &["i16", "u16"]),
    ("FLOAT16", "f16", &["f16"]),
    ("SHADER_FLOAT32_ATOMIC", "", &["atomic<f32>"]),
    ("TEXTURE_ATOMIC", "", &["textureAtomic"]),
    ("PRIMITIVE_INDEX", "primitive_index", &["primitive_index"]),
    ("IMMEDIATES", "", &["var<immediate>"]),
    ("MULTIVIEW", "", &["view_index"]),
    ("CLIP_DISTANCES", "clip_distances", &["clip_distances"]),
    ("DUAL_SOURCE_BLENDING", "dual_source_blending", &["blend_src"]),
    ("SUBGROUP", "", &["subgroup"]),
    ("BINDING_ARRAY", "wgpu_binding_array", &["binding_array"]),
    ("CUBE_ARRAY_TEXTURES", "", &["texture_cube_array", "texture_depth_cube_array"]),
    ("EARLY_DEPTH_TEST", "", &["early_depth_test"]),
    ("SHADER_BARYCENTRICS", "", &["barycentric"]),
];

/// Where a shader asks for a capability that `messages` (naga's error chain) say is missing:
/// its `enable` directive, else the first use of a word only that capability allows. naga
/// gives such errors no span (a ray-query type is "Type \[0\]").
pub fn capability_span(messages: &[String], text: &str) -> Option<(std::ops::Range<usize>, String)> {
    let (key, enable, words) = CAPABILITY_USES
        .iter()
        .find(|(cap, ..)| messages.iter().any(|m| m.contains("apabilit") && m.contains(cap)))?;
    // The capability's full name as naga wrote it (`SHADER_INT64_ATOMIC_ALL_OPS` for the key
    // `SHADER_INT64_ATOMIC`).
    let named = messages.iter().find_map(|m| {
        let at = m.find(key)?;
        Some(
            m[at..]
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect::<String>(),
        )
    });
    let cap = named.as_deref().unwrap_or(key);
    let code = |i: usize| !text[..i].rsplit('\n').next().unwrap_or("").contains("//");
    if !enable.is_empty() {
        let directive = format!("enable {enable}");
        if let Some(i) = text.match_indices(&directive).map(|(i, _)| i).find(|&i| code(i)) {
            return Some((i..i + directive.len(), format!("needs {cap}")));
        }
    }
    let word_at = |w: &str| {
        text.match_indices(w).map(|(i, _)| i).find(|&i| {
            let before = text[..i].chars().next_back().is_none_or(|c| !(c.is_alphanumeric() || c == '_'));
            let after = text[i + w.len()..]
                .chars()
                .next()
                .is_none_or(|c| !(c.is_alphanumeric() || c == '_'));
            (before && after || w.contains('<')) && code(i)
        })
    };
    let (i, w) = words.iter().filter_map(|w| word_at(w).map(|i| (i, *w))).min()?;
    Some((i..i + w.len(), format!("`{w}` needs {cap}")))
}

/// Where in the source a span-less error about a function or entry point belongs: the
/// argument (`Argument N`) or result it names, else the `fn NAME` it is about; with a label.
pub fn signature_span(e: &naga::valid::ValidationError, text: &str) -> Option<(std::ops::Range<usize>, String)> {
    use naga::valid::{EntryPointError as EP, ValidationError as V};
    let (name, detail) = match e {
        V::EntryPoint { name, source, .. } => (name.as_str(), Some(source)),
        V::Function { name, .. } => (name.as_str(), None),
        _ => return None,
    };
    let fn_at = declaration(text, name)?;
    let open = fn_at.end + text[fn_at.end..].find('(')?;
    let args = top_level_args(text, open)?;
    // Each arm may find nothing (a GLSL entry point has no `->`): then the function's name.
    let specific = || match detail {
        Some(EP::Argument(i, _)) => args.get(*i as usize).map(|r| (r.clone(), format!("argument {i}"))),
        Some(EP::Result(v)) => {
            let close = args.last().map_or(open + 1, |r| r.end);
            let after = close + text[close..].find(')')? + 1;
            match text[after..].find("->") {
                Some(a) => {
                    let arrow = after + a;
                    let end = arrow + text[arrow..].find('{')?;
                    Some((arrow..text[..end].trim_end().len(), "the result".into()))
                }
                None => glsl_output(text, v),
            }
        }
        _ => None,
    };
    specific().or(Some((fn_at, format!("`{name}`"))))
}

/// A GLSL entry point's result is its `out` globals: the one a varying error is about (the
/// second at a location two share), else the first.
fn glsl_output(text: &str, e: &naga::valid::VaryingError) -> Option<(std::ops::Range<usize>, String)> {
    let outs: Vec<(usize, &str)> = (text.match_indices('\n').map(|(i, _)| i + 1))
        .chain([0])
        .filter_map(|i| {
            let line = text[i..].lines().next()?;
            (line.trim_start().starts_with("layout") && line.contains(") out ")).then_some((i, line))
        })
        .collect();
    let location = |l: &str| {
        let at = l.find("location")?;
        let digits: String = l[at..]
            .chars()
            .skip_while(|c| !c.is_ascii_digit())
            .take_while(char::is_ascii_digit)
            .collect();
        digits.parse::<u32>().ok()
    };
    let (i, line) = match e {
        naga::valid::VaryingError::BindingCollision { location: at } => *outs.iter().filter(|(_, l)| location(l) == Some(*at)).nth(1)?,
        _ => *outs.iter().min()?,
    };
    let start = i + (line.len() - line.trim_start().len());
    Some((start..i + line.trim_end().len(), "an output of the entry point".into()))
}

/// Where an invalid type naga gives no span is written: the type's arena span, else its first
/// spelling in the source (`array<array<f32>, 2>`).
pub fn type_span(e: &naga::valid::ValidationError, m: &Module, text: &str) -> Option<(std::ops::Range<usize>, String)> {
    let naga::valid::ValidationError::Type { handle, .. } = e else {
        return None;
    };
    if let Some(r) = m.types.get_span(*handle).to_range().filter(|r| !r.is_empty()) {
        return Some((r, "this type".into()));
    }
    let written = crate::shader::reflect::type_name(m, *handle);
    let at = text.find(&written)?;
    Some((at..at + written.len(), "this type".into()))
}

/// The span of `fn NAME` (WGSL) or `void NAME` (GLSL) in `text` (the expanded source).
pub fn declaration(text: &str, name: &str) -> Option<std::ops::Range<usize>> {
    ["fn ", "void "].iter().find_map(|kw| {
        let pat = format!("{kw}{name}");
        text.match_indices(&pat)
            .find(|(i, _)| {
                let after = text[i + pat.len()..].trim_start();
                after.starts_with('(') && (*i == 0 || !text.as_bytes()[i - 1].is_ascii_alphanumeric())
            })
            .map(|(i, _)| i..i + pat.len())
    })
}

/// The spans of the arguments between the parenthesis at `open` and its match (commas inside
/// `<>`, `()` and `[]` do not split).
fn top_level_args(text: &str, open: usize) -> Option<Vec<std::ops::Range<usize>>> {
    let (mut depth, mut start, mut out) = (0i32, open + 1, vec![]);
    for (i, c) in text[open + 1..].char_indices().map(|(i, c)| (i + open + 1, c)) {
        match c {
            '(' | '<' | '[' => depth += 1,
            ')' if depth == 0 => {
                let arg = text[start..i].trim();
                if !arg.is_empty() {
                    let s = start + (text[start..i].len() - text[start..i].trim_start().len());
                    out.push(s..s + arg.len());
                }
                return Some(out);
            }
            ')' | '>' | ']' => depth -= 1,
            ',' if depth == 0 => {
                let s = start + (text[start..i].len() - text[start..i].trim_start().len());
                out.push(s..s + text[start..i].trim().len());
                start = i + 1;
            }
            _ => {}
        }
    }
    None
}

/// The function a validation error is about, if it names one.
pub fn function_of<'m>(e: &naga::valid::ValidationError, m: &'m Module) -> Option<&'m naga::Function> {
    use naga::valid::ValidationError as V;
    match e {
        V::Function { handle, .. } => m.functions.try_get(*handle).ok(),
        V::EntryPoint { stage, name, .. } => m
            .entry_points
            .iter()
            .find(|ep| ep.stage == *stage && ep.name == *name)
            .map(|ep| &ep.function),
        _ => None,
    }
}

/// Where an entry point (or a function it calls) uses an operation only fragment shaders
/// may: implicit-derivative sampling and derivatives, and `discard`; each with what it is.
pub fn forbidden_operations(m: &Module, ep: &naga::EntryPoint) -> Vec<(Span, &'static str)> {
    const DERIVATIVES: &str = "needs implicit derivatives, which only fragment shaders have (use `textureSampleLevel`)";
    let mut spans = vec![];
    let mut todo = vec![&ep.function];
    let mut seen = std::collections::BTreeSet::<Handle<naga::Function>>::new();
    while let Some(f) = todo.pop() {
        for (h, e) in f.expressions.iter() {
            let implicit = match e {
                naga::Expression::ImageSample { level, .. } => matches!(level, naga::SampleLevel::Auto | naga::SampleLevel::Bias(_)),
                naga::Expression::Derivative { .. } => true,
                _ => false,
            };
            if implicit {
                spans.push((f.expressions.get_span(h), DERIVATIVES));
            }
        }
        crate::shader::reflect::statements(&f.body, &mut |s, span| {
            if let naga::Statement::Kill = s {
                spans.push((*span, "`discard` ends a fragment; other stages cannot use it"));
            }
        });
        let mut called = vec![];
        crate::shader::reflect::called(&f.body, &mut called);
        for h in called {
            if seen.insert(h) {
                todo.push(&m.functions[h]);
            }
        }
    }
    spans
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Only expression handles become source text: `Function [1]` and `Type [2]` index
    /// other arenas, and rewriting them with expression 1's or 2's text named the wrong thing.
    #[test]
    fn only_expression_handles_become_source_text() {
        let src = "fn f() -> f32 {\n    let v = 2u;\n    return 1.0;\n}\n";
        let m = naga::front::wgsl::parse_str(src).unwrap();
        let f = &m.functions.iter().next().unwrap().1;
        let first = f.expressions.iter().next().map(|(h, _)| h.index()).unwrap();
        let msg = format!("Function [{first}] 'helper' is invalid: Type [{first}] of Expression [{first}]");
        let out = expressions(&msg, f, src);
        assert!(
            out.starts_with(&format!("Function [{first}] 'helper' is invalid: Type [{first}] of `")),
            "{out}"
        );
    }

    #[test]
    fn debug_types_become_wgsl() {
        let m = Module::default();
        let msg = "with [0] (of type Matrix { columns: Quad, rows: Quad, scalar: Scalar { kind: Float, width: 4 } }) and [2] (of type Vector { size: Tri, scalar: Scalar { kind: Float, width: 4 } }), Scalar(Scalar { kind: Uint, width: 4 })";
        assert_eq!(types(msg, &m), "with [0] (of type mat4x4<f32>) and [2] (of type vec3<f32>), u32");
    }
}
