//! `check` ok ⇒ `render` ok: the bundled pipelines' values mutated one at a time (numbers
//! and formats, where the compiler must know what wgpu would refuse) — every mutant the
//! compiler accepts renders a frame on a scene with every effect and the light kinds the
//! pipelines repeat passes for, without a wgpu error or a non-finite pixel; every one it
//! refuses is refused with a location.

use crate::gpu_common;

use gpu_common::*;
use lightbench::gpu::Executor;
use lightbench_compiler::ir::Effect;
use lightbench_compiler::workspace::Workspace;
use std::path::Path;

/// Values wgpu validates near: nothing, one, not a power of two, negative, fractional, past
/// a 4096 texture limit, past 16 bits, absurd.
const NUMBERS: [&str; 8] = ["0", "1", "3", "-1", "0.5", "4097", "65536", "1e9"];

/// Formats of every kind: colour (blendable or not, sRGB), integer, depth, packed.
const FORMATS: [&str; 8] = [
    "Rgba8UnormSrgb",
    "R32Uint",
    "Rgba32Float",
    "Depth32Float",
    "Depth24PlusStencil8",
    "Rg11b10Ufloat",
    "R8Unorm",
    "Bgra8Unorm",
];

/// Byte ranges of the numbers and format names that are values (not inside a comment or a
/// quoted string).
fn sites(text: &str) -> Vec<(usize, usize, bool)> {
    let mut out = vec![];
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        let code = line.split("//").next().unwrap_or("");
        let b = code.as_bytes();
        let (mut i, mut quoted) = (0, false);
        while i < b.len() {
            let word = |c: u8| c.is_ascii_alphanumeric() || c == b'_' || c == b'.';
            if b[i] == b'"' {
                quoted = !quoted;
                i += 1;
            } else if !quoted && word(b[i]) && (i == 0 || !word(b[i - 1])) {
                let s = i;
                while i < b.len() && word(b[i]) {
                    i += 1;
                }
                let w = &code[s..i];
                let number = w.as_bytes()[0].is_ascii_digit();
                let format = FORMATS
                    .iter()
                    .chain(["Rgba8Unorm", "Rgba16Float", "R16Float", "R32Float", "Rg16Float"].iter())
                    .any(|f| *f == w);
                if number || format {
                    out.push((offset + s, offset + i, number));
                }
            } else {
                i += 1;
            }
        }
        offset += line.len();
    }
    out
}

/// The Cornell box with a spot and a sun besides its point light, calling for every effect.
fn everything() -> lightbench::scene::Scene {
    let mut s = lightbench::scene::builtin::cornell();
    // (16×16 would leave bloom's 8×8 chain too small for its mip levels.)
    s.size = (32, 32);
    s.effects.extend(Effect::ALL);
    let (one, down) = (glam::Vec3::ONE, glam::Vec3::new(0.2, -1.0, -0.3).normalize());
    s.lights.push(lightbench::scene::Light::spot(
        glam::Vec3::new(0.0, 1.8, 0.5),
        down,
        20.0,
        30.0,
        one,
        4.0,
        10.0,
    ));
    s.lights.push(lightbench::scene::Light::directional(down, one, 1.0));
    s
}

/// Mutate `file` (under `mem/pipelines/`) at every `stride`th site and render what compiles;
/// (accepted, refused).
fn mutants(file: &str, stride: usize) -> (usize, usize) {
    let g = gpu();
    let vfs = memory_project();
    let ws = Workspace::new(vfs.clone());
    let path = Path::new("mem/pipelines").join(file);
    let text = std::fs::read_to_string(root().join("pipelines").join(file)).unwrap();
    let scene = everything();
    let (mut accepted, mut refused) = (0, 0);
    // Two values at each site, by turns through the lists.
    let each = sites(&text).into_iter().enumerate().step_by(stride);
    for (k, (s, e, number)) in each.flat_map(|(k, site)| [(2 * k, site), (2 * k + 3, site)]) {
        let by = if number {
            NUMBERS[k % NUMBERS.len()]
        } else {
            FORMATS[k % FORMATS.len()]
        };
        if by == &text[s..e] {
            continue;
        }
        let mutated = format!("{}{by}{}", &text[..s], &text[e..]);
        let line = text[..s].lines().count().max(1);
        let what = format!("{file}:{line}: `{}` → `{by}`", &text[s..e]);
        vfs.write(&path, mutated);
        match lightbench::render::compile_in(&ws, &g, &path, None, &scene, &[]) {
            Err(e) => {
                let e = e.to_string();
                assert!(
                    e.contains(".lbp:") || e.contains(".wgsl:"),
                    "{what}: refused without a location: {e}"
                );
                refused += 1;
            }
            Ok((exe, _)) => {
                let mut ex = Executor::new(&g, &exe, &scene).unwrap_or_else(|e| panic!("{what}: accepted, but {e}"));
                let inputs = ex.inputs(0.0);
                ex.render_frame(&g, &inputs).unwrap_or_else(|e| panic!("{what}: accepted, but {e}"));
                let out = output(&g, &ex);
                assert_eq!(out.non_finite(), 0, "{what}: NaN or Inf in the output");
                accepted += 1;
            }
        }
    }
    vfs.write(&path, text);
    eprintln!("{file}: {accepted} mutants accepted and rendered, {refused} refused");
    (accepted, refused)
}

#[test]
fn every_accepted_mutant_of_deferred_renders() {
    let (accepted, refused) = mutants("deferred.lbp", 1);
    assert!(
        accepted > 20 && refused > 20,
        "both outcomes exercised: {accepted} accepted, {refused} refused"
    );
}

#[test]
fn every_accepted_mutant_of_deferred_gi_renders() {
    let (accepted, refused) = mutants("deferred_gi.lbp", 3);
    assert!(
        accepted > 10 && refused > 10,
        "both outcomes exercised: {accepted} accepted, {refused} refused"
    );
}
