//! The pipeline language's part 2, driven as a user writes it (LBP files and WGSL, no
//! Rust): per-pass values, data resources, mip chains, reuse of unchanged work, temporal
//! inputs. Small images, asserted on pixels.

use crate::cli_common;
use crate::gpu_common;

use gpu_common::*;
use lightbench::scene::builtin;
use std::path::{Path, PathBuf};

/// A scratch project: the bundled shaders (for `lib/`), and the given files.
fn project(tag: &str, files: &[(&str, &str)]) -> PathBuf {
    let d = cli_common::scratch(tag);
    std::fs::create_dir_all(d.join("shaders")).unwrap();
    std::fs::create_dir_all(d.join("pipelines")).unwrap();
    for e in std::fs::read_dir(root().join("shaders/lib")).unwrap() {
        let p = e.unwrap().path();
        std::fs::create_dir_all(d.join("shaders/lib")).unwrap();
        std::fs::copy(&p, d.join("shaders/lib").join(p.file_name().unwrap())).unwrap();
    }
    for (name, text) in files {
        std::fs::write(d.join(name), text).unwrap();
    }
    d
}

fn render_out(pipeline: &Path, frames: u32) -> (lightbench::io::Image, lightbench::gpu::Executor) {
    let g = gpu();
    let ex = render_with(&g, pipeline, &builtin::cornell(), &[], frames);
    (output(&g, &ex), ex)
}

/// A pattern with detail in both directions: impulses on a lattice, ramps in g and b.
const PATTERN: &str = "@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<u32>(pos.xy);
    let spike = select(0.0, 1.0, (p.x * 7u + p.y * 3u) % 5u == 0u);
    return vec4<f32>(spike, pos.x / 32.0, pos.y / 32.0, 1.0);
}
";

/// The bundled `blur.wgsl` written by hand for one direction and 3 taps: no parameter block.
fn hand_written_blur(dir: &str) -> String {
    let mut text = std::fs::read_to_string(root().join("shaders/blur.wgsl")).unwrap();
    let dir = format!("vec2<i32>({dir})");
    for (from, to) in [
        ("struct Params {\n    dir: vec2<f32>,\n    taps: u32,\n};\n", ""),
        ("@group(2) @binding(1) var<uniform> params: Params;\n", ""),
        ("vec2<i32>(params.dir)", dir.as_str()),
        ("i32(params.taps)", "3"),
    ] {
        assert!(text.contains(from), "blur.wgsl no longer has `{from}`");
        text = text.replace(from, to);
    }
    text
}

const BLUR_HEAD: &str = "pipeline blur
texture src: Rgba16Float 32x32
texture tmp: Rgba16Float 32x32
texture out: Rgba16Float 32x32

fullscreen pattern \"pattern.wgsl\" {
    color src
}
";

#[test]
fn one_blur_shader_serves_two_passes_through_per_pass_values() {
    let shared = format!(
        "{BLUR_HEAD}
fullscreen blur_h \"blur.wgsl\" {{
    reads src
    bind input = src
    set dir = (1, 0), taps = 3
    color tmp
}}

fullscreen blur_v \"blur.wgsl\" {{
    reads tmp
    bind input = tmp
    set dir = (0, 1), taps = 3
    color out
}}

output out
"
    );
    let separate = format!(
        "{BLUR_HEAD}
fullscreen blur_h \"blur_h.wgsl\" {{
    reads src
    bind input = src
    color tmp
}}

fullscreen blur_v \"blur_v.wgsl\" {{
    reads tmp
    bind input = tmp
    color out
}}

output out
"
    );
    let (h, v) = (hand_written_blur("1, 0"), hand_written_blur("0, 1"));
    let d = project(
        "values",
        &[
            ("shaders/pattern.wgsl", PATTERN),
            // The bundled blur, as the README and its header tell a user to use it.
            (
                "shaders/blur.wgsl",
                &std::fs::read_to_string(root().join("shaders/blur.wgsl")).unwrap(),
            ),
            ("shaders/blur_h.wgsl", &h),
            ("shaders/blur_v.wgsl", &v),
            ("pipelines/shared.lbp", &shared),
            ("pipelines/separate.lbp", &separate),
        ],
    );
    let (a, ex) = render_out(&d.join("pipelines/shared.lbp"), 1);
    let (b, _) = render_out(&d.join("pipelines/separate.lbp"), 1);
    assert_eq!(a.width, 32);
    assert_eq!(a.rgba, b.rgba, "per-pass values give what two hand-written shaders give");
    // Blurred both ways: the lattice's spikes (1 in 5 texels) spread to about their mean.
    let [r, ..] = a.pixel(16, 16);
    assert!((r - 0.2).abs() < 0.1, "{r}");
    // The value is the parameter `blur_v.dir`: a vec2 defaulting to what the pass wrote.
    let block = &ex.plan().pass("blur_v").unwrap().uniform_blocks[0];
    let dir = block.fields.iter().find(|f| f.name == "dir").unwrap();
    let lightbench_compiler::layout::FieldSource::Param(id) = dir.source else {
        panic!("{:?}", dir.source)
    };
    let p = ex.plan().param(id);
    assert_eq!((p.name.as_str(), p.pass.as_deref()), ("blur_v.dir", Some("blur_v")));
    assert_eq!(p.default, lightbench_compiler::ir::ParamValue::Vec(vec![0.0, 1.0]));
}

/// Shows a 4×4 noise texture (left half) and the first texel of a JSON buffer and of an
/// inline buffer (right half), as loaded: no pass writes either.
const SHOW: &str = "@group(2) @binding(0) var noise: texture_2d<f32>;
@group(2) @binding(1) var<storage, read> kernel: array<vec4<f32>>;
@group(2) @binding(2) var<storage, read> counts: array<u32>;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(pos.xy);
    if p.x < 4 {
        // Back to the stored bytes: equal only if every byte arrived unchanged.
        return round(textureLoad(noise, p, 0) * 255.0);
    }
    if p.y == 0 {
        return kernel[p.x - 4];
    }
    return vec4<f32>(f32(counts[0]), f32(counts[1]), 0.0, 1.0);
}
";

const DATA: &str = "pipeline data
texture noise: Rgba8Unorm 4x4 data \"noise.png\"
buffer kernel: 64 bytes data \"kernel.json\"
buffer counts: 8 bytes data u32(7, 4000000)
texture out: Rgba32Float 8x4

fullscreen show \"show.wgsl\" {
    reads noise, kernel, counts
    color out
}

output out
";

fn noise_png(path: &Path, w: u32, h: u32) -> Vec<u8> {
    let img = image::RgbaImage::from_fn(w, h, |x, y| {
        let v = (x * 61 + y * 17) as u8;
        image::Rgba([v, v.wrapping_mul(3), 255 - v, (x * 40 + 100) as u8])
    });
    img.save(path).unwrap();
    img.into_raw()
}

#[test]
fn data_resources_reach_the_shader_bit_exactly() {
    let kernel: Vec<f32> = (0..16).map(|i| (i as f32 * 0.37).sin() * 1e-3 + i as f32).collect();
    let json = serde_json::to_string(&kernel).unwrap();
    let d = project(
        "data",
        &[
            ("shaders/show.wgsl", SHOW),
            ("pipelines/data.lbp", DATA),
            ("pipelines/kernel.json", &json),
        ],
    );
    let texels = noise_png(&d.join("pipelines/noise.png"), 4, 4);
    let (img, ex) = render_out(&d.join("pipelines/data.lbp"), 1);
    for y in 0..4 {
        for x in 0..4 {
            let want: Vec<f32> = texels[((y * 4 + x) * 4) as usize..][..4].iter().map(|b| *b as f32).collect();
            assert_eq!(img.pixel(x, y).to_vec(), want, "texel ({x}, {y})");
        }
    }
    for i in 0..4u32 {
        assert_eq!(img.pixel(4 + i, 0).to_vec(), kernel[4 * i as usize..][..4].to_vec(), "kernel[{i}]");
    }
    assert_eq!(img.pixel(4, 1), [7.0, 4_000_000.0, 0.0, 1.0]);
    assert!(ex.plan().resource("noise").unwrap().data);
    // Dumps write words as the shaders declare them: `array<u32>` as whole numbers.
    let (p, dump, o) = (d.join("pipelines/data.lbp"), d.join("dump"), d.join("o.exr"));
    let args = ["render", "--pipeline", p.to_str().unwrap(), "--out", o.to_str().unwrap()];
    let (code, _, err) = cli_common::lightbench(&[&args[..], &["--dump", "counts,kernel", "--dump-dir", dump.to_str().unwrap()]].concat());
    assert_eq!(code, 0, "{err}");
    assert_eq!(std::fs::read_to_string(dump.join("counts.json")).unwrap(), "[7,4000000]");
    let k: Vec<f32> = serde_json::from_str(&std::fs::read_to_string(dump.join("kernel.json")).unwrap()).unwrap();
    assert_eq!(k, kernel);
}

#[test]
fn data_that_does_not_fit_is_a_located_check_error() {
    let d = project(
        "data-bad",
        &[
            ("shaders/show.wgsl", SHOW),
            ("pipelines/data.lbp", DATA),
            ("pipelines/kernel.json", "[1, 2, 3]"),
        ],
    );
    noise_png(&d.join("pipelines/noise.png"), 5, 4);
    let (code, _, err) = cli_common::lightbench(&["check", d.join("pipelines/data.lbp").to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("error[data-mismatch]: data of `noise`: `noise.png` is 5×4, the texture is 4×4"),
        "{err}"
    );
    assert!(err.contains("data.lbp:2:31"), "{err}");
    assert!(
        err.contains("data of `kernel`: the data has 12 bytes, the buffer is declared with 64"),
        "{err}"
    );
    std::fs::remove_file(d.join("pipelines/noise.png")).unwrap();
    let (code, _, err) = cli_common::lightbench(&["check", d.join("pipelines/data.lbp").to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("error[file-not-found]: data of `noise`: cannot read `noise.png`"),
        "{err}"
    );
    let escape = DATA.replace("data \"noise.png\"", "data \"../../noise.png\"");
    std::fs::write(d.join("pipelines/data.lbp"), escape).unwrap();
    let (code, _, err) = cli_common::lightbench(&["check", d.join("pipelines/data.lbp").to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("error[outside-root]"), "{err}");
}

/// A compute pass copies the frame block's matrices and jitter into a buffer.
const FRAME_PROBE: &str = "#include \"lib/frame.wgsl\"

@group(2) @binding(0) var<storage, read_write> probe: array<vec4<f32>>;

@compute @workgroup_size(1)
fn cs_main() {
    for (var i = 0; i < 4; i++) {
        probe[i] = frame.view_proj[i];
        probe[4 + i] = frame.prev_view_proj[i];
    }
    probe[8] = frame.jitter;
    probe[9] = vec4<f32>(f32(frame.frame_index), frame.time, 0.0, 0.0);
}
";

const PROBE_PIPELINE: &str = "pipeline probe
buffer probe: 160 bytes
texture out: Rgba8Unorm 4x4

compute probe \"probe.wgsl\" {
    writes probe
    dispatch groups(1, 1, 1)
}

fullscreen show \"show_probe.wgsl\" {
    reads probe
    color out
}

output out
";

const SHOW_PROBE: &str = "@group(2) @binding(0) var<storage, read> probe: array<vec4<f32>>;

@fragment
fn fs_main() -> @location(0) vec4<f32> {
    return fract(probe[9]);
}
";

/// A variant option that jitters the camera while it is chosen.
const JITTER_OPTION: &str = "variant aa = none {
    option none
    option taa jitter \"accumulates jittered frames\"
}
";

const ORBIT: &str = "Scene(
    name: \"orbit\",
    size: (64, 64),
    camera: (position: (0.0, 1.0, 3.6), fov: 40.0, animation: Orbit(center: (0.0, 1.0, 0.0), speed: 90.0)),
    builtin: \"cornell\",
)
";

#[test]
fn the_previous_view_projection_is_the_last_frames() {
    let d = project(
        "prev-vp",
        &[
            ("shaders/probe.wgsl", FRAME_PROBE),
            ("shaders/show_probe.wgsl", SHOW_PROBE),
            ("pipelines/probe.lbp", PROBE_PIPELINE),
            ("pipelines/jitter.lbp", &format!("{PROBE_PIPELINE}\njitter\n")),
            ("pipelines/option.lbp", &format!("{PROBE_PIPELINE}\n{JITTER_OPTION}")),
            ("orbit.ron", ORBIT),
        ],
    );
    let g = gpu();
    let scene = lightbench::scene::load(d.join("orbit.ron").to_str().unwrap()).unwrap();
    let taa = vec![("aa".to_string(), "taa".to_string())];
    for (file, variants, jitter) in [
        ("probe.lbp", vec![], false),
        ("jitter.lbp", vec![], true),
        ("option.lbp", vec![], false),
        ("option.lbp", taa, true),
    ] {
        let (exe, _) = lightbench::render::compile(&g, &d.join("pipelines").join(file), None, &scene, &variants).unwrap();
        let mut ex = lightbench::gpu::Executor::new(&g, &exe, &scene).unwrap();
        let mut last: Option<Vec<f32>> = None;
        for f in 0..3 {
            ex.render_frame(&g, &ex.inputs(f as f32 / 10.0)).unwrap();
            let probe = ex.read_buffer(&g, "probe", 0).unwrap();
            let (vp, prev) = (&probe[0..16], &probe[16..32]);
            assert_eq!(
                prev,
                last.as_deref().unwrap_or(vp),
                "{file} frame {f}: prev_view_proj is the last frame's"
            );
            if let Some(l) = &last {
                assert!(l.iter().zip(vp).any(|(a, b)| (a - b).abs() > 1e-3), "the orbiting camera moved");
            }
            assert_eq!(probe[36], f as f32, "frame_index");
            let j = &probe[32..34];
            if jitter {
                let want = lightbench::gpu::halton_jitter(f);
                assert_eq!(j, want, "frame {f}: jitter");
                assert!(j.iter().all(|v| v.abs() <= 0.5));
            } else {
                assert_eq!(j, [0.0, 0.0]);
            }
            last = Some(vp.to_vec());
        }
    }
}

#[test]
fn an_orbiting_camera_in_a_scene_file_moves_the_image() {
    let d = project(
        "orbit",
        &[
            ("orbit.ron", ORBIT),
            (
                "still.ron",
                &ORBIT.replace(", animation: Orbit(center: (0.0, 1.0, 0.0), speed: 90.0)", ""),
            ),
        ],
    );
    let mut means = vec![];
    for (scene, frames) in [("orbit.ron", "1"), ("orbit.ron", "20"), ("still.ron", "1"), ("still.ron", "20")] {
        let out = d.join(format!("{scene}-{frames}.png"));
        let s = d.join(scene);
        let (code, _, err) = cli_common::lightbench(&[
            "render",
            "--scene",
            s.to_str().unwrap(),
            "--frames",
            frames,
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{err}");
        means.push(lightbench::io::Image::load_png(&out).unwrap());
    }
    let diff = |a: &lightbench::io::Image, b: &lightbench::io::Image| {
        a.rgba.iter().zip(&b.rgba).map(|(x, y)| (x - y).abs()).sum::<f32>() / a.rgba.len() as f32
    };
    assert!(
        diff(&means[0], &means[1]) > 0.02,
        "the orbit moved the image: {}",
        diff(&means[0], &means[1])
    );
    assert_eq!(diff(&means[2], &means[3]), 0.0, "a still camera renders the same image");
    assert_eq!(diff(&means[0], &means[2]), 0.0, "at time 0 the orbit starts where the camera is");
}

fn timing_log(path: &Path) -> Vec<Vec<serde_json::Value>> {
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap();
    v.as_array().unwrap().iter().map(|f| f.as_array().unwrap().clone()).collect()
}

/// In which frames (0-based) a pass ran.
fn ran(log: &[Vec<serde_json::Value>], pass: &str) -> Vec<usize> {
    log.iter()
        .enumerate()
        .filter(|(_, f)| f.iter().any(|t| t["pass"] == pass && t["reused"] == false))
        .map(|(i, _)| i)
        .collect()
}

/// A spot light that is still, then one that sweeps (Rotate): its shadow map is rendered in
/// the first frame only while the light is still, every frame once it moves; the images are
/// those of a render that reuses nothing.
#[test]
fn static_shadow_maps_are_reused_and_moved_lights_rerender() {
    let still = "Scene(
    name: \"spot\",
    size: (64, 64),
    builtin: \"cornell\",
    lights: [Spot(position: (0.0, 1.9, 0.3), direction: (0.2, -1.0, 0.0), inner: 20.0, outer: 30.0, intensity: 4.0, range: 8.0)],
    effects: [Shadows],
)
";
    let moving = still.replace("range: 8.0)", "range: 8.0, animation: Rotate(speed: 120.0))");
    let d = project("reuse", &[("still.ron", still), ("moving.ron", &moving)]);
    for (scene, want) in [("still.ron", vec![0]), ("moving.ron", vec![0, 1, 2, 3])] {
        let mut images = vec![];
        for reuse in [true, false] {
            let (out, json) = (d.join(format!("{scene}-{reuse}.png")), d.join(format!("{scene}-{reuse}.json")));
            let s = d.join(scene);
            let mut args = vec![
                "render",
                "--scene",
                s.to_str().unwrap(),
                "--frames",
                "4",
                "--out",
                out.to_str().unwrap(),
            ];
            args.extend(["--timings-json", json.to_str().unwrap()]);
            if !reuse {
                args.push("--no-reuse");
            }
            let (code, _, err) = cli_common::lightbench(&args);
            assert_eq!(code, 0, "{err}");
            let log = timing_log(&json);
            assert_eq!(log.len(), 4);
            if reuse {
                assert_eq!(ran(&log, "shadow_map"), want, "{scene}: frames the shadow map was rendered in");
                // Nothing moves in the still scene: after the first frame every pass is reused.
                if scene == "still.ron" {
                    assert!(log[1..].iter().flatten().all(|t| t["reused"] == true), "{:?}", log[1]);
                }
            } else {
                assert_eq!(ran(&log, "shadow_map"), vec![0, 1, 2, 3]);
            }
            images.push(std::fs::read(&out).unwrap());
        }
        assert!(images[0] == images[1], "{scene}: the same image with and without reuse");
    }
}

/// An initialisation pass (a compute pass that depends on nothing that changes) runs once;
/// a pass marked `always` runs every frame.
#[test]
fn an_initialisation_pass_runs_exactly_once() {
    let init = "@group(2) @binding(0) var<storage, read_write> lut: array<f32>;

@compute @workgroup_size(4)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    lut[id.x] = f32(id.x) * 0.25;
}
";
    let show = "@group(2) @binding(0) var<storage, read> lut: array<f32>;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(lut[u32(pos.x)], 0.0, 0.0, 1.0);
}
";
    let pipeline = "pipeline init
buffer lut: 16 bytes
texture out: Rgba16Float 4x1

compute init \"init.wgsl\" {
    writes lut
    dispatch groups(1, 1, 1)
}

fullscreen show \"show.wgsl\" {
    reads lut
    color out
    always
}

output out
";
    let d = project(
        "init",
        &[
            ("shaders/init.wgsl", init),
            ("shaders/show.wgsl", show),
            ("pipelines/init.lbp", pipeline),
        ],
    );
    let (json, out) = (d.join("t.json"), d.join("out.exr"));
    let p = d.join("pipelines/init.lbp");
    let (code, _, err) = cli_common::lightbench(&[
        "render",
        "--pipeline",
        p.to_str().unwrap(),
        "--frames",
        "4",
        "--out",
        out.to_str().unwrap(),
        "--timings-json",
        json.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let log = timing_log(&json);
    assert_eq!(ran(&log, "init"), vec![0], "the initialisation pass runs once");
    assert_eq!(ran(&log, "show"), vec![0, 1, 2, 3], "`always` runs every frame");
    let img = image::open(&out).unwrap().to_rgba32f();
    assert_eq!(img.get_pixel(3, 0).0[0], 0.75, "the first frame's LUT is still there in the last");
    let (code, text, err) = cli_common::lightbench(&["plan", p.to_str().unwrap(), "--explain"]);
    assert_eq!(code, 0, "{err}");
    assert!(text.contains("runs once (depends on nothing that changes)"), "{text}");
    assert!(text.contains("runs every frame: `always: true`"), "{text}");
}

const COPY: &str = "@group(2) @binding(0) var input: texture_2d<f32>;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    return textureLoad(input, vec2<i32>(pos.xy), 0);
}
";

/// Half of the next smaller level, added by the target's blend.
const UP: &str = "@group(2) @binding(0) var input: texture_2d<f32>;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    return textureLoad(input, vec2<i32>(pos.xy) / 2, 0) * 0.5;
}
";

/// Bloom over a 5-level chain: three passes (bright, down per mip, up per mip) against the
/// same chain spelled with a texture per level and nine passes.
#[test]
fn a_mip_chain_in_three_passes_matches_separate_textures() {
    let chain = "pipeline chain
texture src: Rgba16Float 32x32
texture bloom: Rgba16Float 32x32 mips 5

fullscreen pattern \"pattern.wgsl\" {
    color src
}

fullscreen bright \"copy.wgsl\" {
    reads src
    bind input = src
    color bloom
}

fullscreen down \"down.wgsl\" {
    per_mip 1..4
    reads mip(bloom, rep-1)
    bind input = bloom
    color bloom mip rep
}

fullscreen up \"up.wgsl\" {
    per_mip 3..0
    reads mip(bloom, rep+1)
    bind input = bloom
    color bloom load blend Add mip rep
}

output bloom
";
    let mut separate = String::from("pipeline separate\ntexture src: Rgba16Float 32x32\n");
    for l in 0..5 {
        separate += &format!("texture b{l}: Rgba16Float {0}x{0}\n", 32 >> l);
    }
    separate += "\nfullscreen pattern \"pattern.wgsl\" {\n    color src\n}\n";
    separate += "\nfullscreen bright \"copy.wgsl\" {\n    reads src\n    bind input = src\n    color b0\n}\n";
    for l in 1..5 {
        separate += &format!(
            "\nfullscreen down{l} \"down.wgsl\" {{\n    reads b{0}\n    bind input = b{0}\n    color b{l}\n}}\n",
            l - 1
        );
    }
    for l in (0..4).rev() {
        separate += &format!(
            "\nfullscreen up{l} \"up.wgsl\" {{\n    reads b{0}\n    bind input = b{0}\n    color b{l} load blend Add\n}}\n",
            l + 1
        );
    }
    separate += "\noutput b0\n";
    let d = project(
        "mips",
        &[
            ("shaders/pattern.wgsl", PATTERN),
            ("shaders/copy.wgsl", COPY),
            // The bundled mip generator, as the README tells a user to use it.
            (
                "shaders/down.wgsl",
                &std::fs::read_to_string(root().join("shaders/mip_down.wgsl")).unwrap(),
            ),
            ("shaders/up.wgsl", UP),
            ("pipelines/chain.lbp", chain),
            ("pipelines/separate.lbp", &separate),
        ],
    );
    let (a, ex) = render_out(&d.join("pipelines/chain.lbp"), 1);
    let (b, _) = render_out(&d.join("pipelines/separate.lbp"), 1);
    assert_eq!(ex.plan().passes.len(), 4, "pattern + three chain passes");
    assert_eq!(ex.plan().pass("down").unwrap().repetitions, 4);
    let max_err = a.rgba.iter().zip(&b.rgba).map(|(x, y)| (x - y).abs()).fold(0.0f32, f32::max);
    assert!(max_err < 1e-3, "the mip chain matches separate textures: max error {max_err}");
    // The blur added something: a texel between spikes is no longer 0.
    let src_zero = (0..32).find(|x| (x * 7) % 5 != 0).unwrap();
    assert!(a.pixel(src_zero, 0)[0] > 0.01, "bloom spread light");
}

#[test]
fn reading_the_mip_a_pass_writes_is_an_error() {
    let bad = "pipeline bad
texture t: Rgba16Float 32x32 mips 3

fullscreen fill \"copy.wgsl\" {
    color t
    reads mip(t, 1)
    bind input = t
}

fullscreen down \"copy.wgsl\" {
    per_mip 1..2
    reads mip(t, rep)
    bind input = t
    color t mip rep
}

fullscreen out_of_range \"copy.wgsl\" {
    per_mip 1..2
    reads mip(t, rep+1)
    bind input = t
    color t mip rep
}

output t
";
    let d = project("mips-bad", &[("shaders/copy.wgsl", COPY), ("pipelines/bad.lbp", bad)]);
    let (code, _, err) = cli_common::lightbench(&["check", d.join("pipelines/bad.lbp").to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("error[mip-select]: pass `down` reads mip 1 of `t`, which it writes"),
        "{err}"
    );
    assert!(err.contains("bad.lbp:12:18"), "{err}");
    assert!(
        err.contains("error[mip-select]: mip 3 of `t` is out of range (at repetition level 2): it has 3 mip level(s)"),
        "{err}"
    );
}

/// The README's LBP example, as written: it checks, and renders an image supplied with
/// `--input` into a blurred level of its mip chain.
#[test]
fn the_readme_lbp_example_checks_and_renders() {
    let readme = cli_common::manual();
    let start = readme.find("```\npipeline chain_and_blur").expect("the manual shows the example") + 4;
    let text = &readme[start..][..readme[start..].find("```").unwrap()];
    let d = project("readme-lbp", &[("pipelines/example.lbp", text)]);
    for f in ["blur.wgsl", "mip_down.wgsl"] {
        std::fs::copy(root().join("shaders").join(f), d.join("shaders").join(f)).unwrap();
    }
    let p = d.join("pipelines/example.lbp");
    let (code, _, err) = cli_common::lightbench(&["check", p.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    image::RgbaImage::from_pixel(128, 128, image::Rgba([255, 128, 0, 255]))
        .save(d.join("src.png"))
        .unwrap();
    let (out, src) = (d.join("out.exr"), format!("src={}", d.join("src.png").display()));
    let args = [
        "render",
        "--pipeline",
        p.to_str().unwrap(),
        "--input",
        &src,
        "--out",
        out.to_str().unwrap(),
    ];
    let (code, _, err) = cli_common::lightbench(&args);
    assert_eq!(code, 0, "{err}");
    let img = image::open(&out).unwrap().to_rgba32f();
    assert_eq!(img.dimensions(), (32, 32));
    let px = img.get_pixel(16, 16).0;
    assert!(
        (px[0] - 1.0).abs() < 1e-3 && (px[1] - 128.0 / 255.0).abs() < 2e-3 && px[2] == 0.0,
        "{px:?}"
    );
}

/// The bundled pipeline's bloom (scenes with `effects: [Bloom]`): written with a mip chain
/// and per-pass values, it adds blurred light (manual exposure, so the exposure does not
/// compensate), runs its passes only when the scene calls for it, and reuses them when
/// nothing changes.
#[test]
fn the_bundled_bloom_adds_blurred_light() {
    let d = project(
        "bloom",
        &[("bloom.ron", "Scene(name: \"bloomy\", builtin: \"cornell\", effects: [Bloom])\n")],
    );
    let mut images = vec![];
    for scene in ["cornell".to_string(), d.join("bloom.ron").display().to_string()] {
        let (out, json) = (d.join(format!("{}.exr", images.len())), d.join(format!("{}.json", images.len())));
        let args = [
            "render",
            "--scene",
            &scene,
            "--param",
            "exposure.automatic=false",
            "--param",
            "bloom.threshold=0.2",
            "--frames",
            "2",
            "--out",
            out.to_str().unwrap(),
            "--timings-json",
            json.to_str().unwrap(),
        ];
        let (code, _, err) = cli_common::lightbench(&args);
        assert_eq!(code, 0, "{err}");
        let log = timing_log(&json);
        let bloom_ran = ran(&log, "bloom_up");
        images.push((image::open(&out).unwrap().to_rgba32f(), bloom_ran));
    }
    let ((plain, plain_ran), (bloom, bloom_ran)) = (&images[0], &images[1]);
    assert!(plain_ran.is_empty(), "no bloom passes without the effect");
    assert_eq!(*bloom_ran, vec![0], "bloom runs in the first frame and is reused in the second");
    assert!(bloom.pixels().all(|p| p.0.iter().all(|v| v.is_finite())), "no NaN or Inf");
    let mean = |img: &image::Rgba32FImage| img.pixels().map(|p| p.0[0] + p.0[1] + p.0[2]).sum::<f32>() / img.len() as f32;
    assert!(
        mean(bloom) > mean(plain) * 1.05,
        "bloom adds light: {} vs {}",
        mean(bloom),
        mean(plain)
    );
}

/// One layer of an array texture, read as a plain 2D texture (`layer(t, 1)`), while three
/// passes render the three layers.
#[test]
fn one_layer_of_an_array_is_read_as_a_2d_texture() {
    let fill = "struct Params { value: f32 };
@group(2) @binding(0) var<uniform> params: Params;

@fragment
fn fs_main() -> @location(0) vec4<f32> {
    return vec4<f32>(params.value, 0.0, 0.0, 1.0);
}
";
    let mut pipeline = String::from("pipeline layers\ntexture stack: Rgba16Float 4x4 layers 3 D2Array\ntexture out: Rgba16Float 4x4\n");
    for l in 0..3 {
        pipeline += &format!(
            "\nfullscreen fill{l} \"fill.wgsl\" {{\n    set value = {}\n    color stack layer {l}\n}}\n",
            0.25 * (l + 1) as f32
        );
    }
    pipeline += "\nfullscreen show \"copy.wgsl\" {\n    reads layer(stack, 1)\n    bind input = stack\n    color out\n}\n\noutput out\n";
    let d = project(
        "layers",
        &[
            ("shaders/fill.wgsl", fill),
            ("shaders/copy.wgsl", COPY),
            ("pipelines/layers.lbp", &pipeline),
        ],
    );
    let (img, _) = render_out(&d.join("pipelines/layers.lbp"), 1);
    assert_eq!(img.pixel(2, 2), [0.5, 0.0, 0.0, 1.0], "layer 1 holds 0.5");
    let bad = pipeline.replace("layer(stack, 1)", "layer(stack, 3)");
    std::fs::write(d.join("pipelines/layers.lbp"), bad).unwrap();
    let (code, _, err) = cli_common::lightbench(&["check", d.join("pipelines/layers.lbp").to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("error[layer-select]: layer 3 is out of range: `stack` has 3"), "{err}");
}

/// `blend: DualSource` as the README gives it: the target becomes `src + dst × src1` per
/// channel, the second source being the shader's `@blend_src(1)` output; the pair counts as one
/// target.
#[test]
fn dual_source_blending_multiplies_by_the_second_source() {
    let shader = "enable dual_source_blending;
struct Out {
    @location(0) @blend_src(0) color: vec4<f32>,
    @location(0) @blend_src(1) transmit: vec4<f32>,
};
@fragment
fn fs_main() -> Out {
    return Out(vec4<f32>(0.2, 0.0, 0.0, 0.0), vec4<f32>(0.5, 1.0, 0.0, 1.0));
}
";
    let pipeline = "pipeline p\ntexture out: Rgba8Unorm 8x8\nfullscreen f \"tint.wgsl\" {\n    color out clear(0.5, 0.5, 0.5, 1) blend DualSource\n}\noutput out\n";
    let d = project("dual-source", &[("shaders/tint.wgsl", shader), ("pipelines/p.lbp", pipeline)]);
    let (img, _) = render_out(&d.join("pipelines/p.lbp"), 1);
    let [r, g, b, a] = img.pixel(4, 4);
    let want = [0.2 + 0.5 * 0.5, 0.5 * 1.0, 0.0, 1.0];
    for (got, want) in [r, g, b, a].into_iter().zip(want) {
        assert!((got - want).abs() < 1.5 / 255.0, "{:?} vs {want:?}", img.pixel(4, 4));
    }
}
