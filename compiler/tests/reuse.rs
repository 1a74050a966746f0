//! The reuse rule of a Plan (`plan::reuse`), GPU-free: small pipelines planned as `plan`
//! would, frames described by what changed, and which repetitions run asserted.

mod common;

use common::*;
use lightbench_compiler::plan::reuse::{FrameKeys, Graph, PassInputs, Reuse};
use lightbench_compiler::plan::Plan;
use lightbench_compiler::profile::Profile;
use lightbench_compiler::scene::SceneFeatures;
use lightbench_compiler::Session;

const FILL: &str = "@fragment\nfn fs_main() -> @location(0) vec4<f32> {\n    return vec4<f32>(0.25);\n}\n";
const CAMERA: &str =
    "#include \"lib/frame.wgsl\"\n@fragment\nfn fs_main() -> @location(0) vec4<f32> {\n    return frame.camera_pos * 0.01;\n}\n";
const COPY: &str = "@group(2) @binding(0) var input: texture_2d<f32>;\n@fragment\nfn fs_main(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {\n    return textureLoad(input, vec2<i32>(p.xy), 0);\n}\n";

/// `make` fills `a` once; `cam` adds to it what the camera sees (a `load` chain on `a`);
/// `mid` copies `a` into `b`; `show` copies `b` into `out`; `late` writes `b` again after
/// `mid`, from nothing that changes.
const PIPELINE: &str = "pipeline r\n\ntexture a: Rgba8Unorm 8x8\ntexture b: Rgba8Unorm 8x8\ntexture out: Rgba8Unorm 8x8\n\n\
fullscreen make \"fill.wgsl\" {\n    color a\n}\n\n\
fullscreen cam \"camera.wgsl\" {\n    color a load blend Add\n}\n\n\
fullscreen mid \"copy.wgsl\" {\n    reads a\n    bind input = a\n    color b\n}\n\n\
fullscreen late \"fill.wgsl\" {\n    color b load blend Add\n}\n\n\
fullscreen show \"copy.wgsl\" {\n    reads b\n    bind input = b\n    color out\n}\n\noutput out\n";

fn plan_of(text: &str) -> Plan {
    let lib = std::fs::read_to_string(repo_root().join("shaders/lib/frame.wgsl")).unwrap();
    let dir = write_project(
        "reuse",
        &[
            ("pipelines/r.lbp", text),
            ("shaders/fill.wgsl", FILL),
            ("shaders/camera.wgsl", CAMERA),
            ("shaders/copy.wgsl", COPY),
            ("shaders/lib/frame.wgsl", &lib),
        ],
    );
    let mut s = Session::new();
    let profile = Profile::offline("vulkan").unwrap();
    let plan = s.plan_file(&dir.join("pipelines/r.lbp"), None, &profile, &SceneFeatures::everything(), &[]);
    plan.unwrap_or_else(|| panic!("{}", s.render()))
}

/// The names of the passes that run (any repetition) with these keys.
fn frame(plan: &Plan, graph: &Graph, reuse: &mut Reuse, keys: &FrameKeys) -> Vec<String> {
    let inputs: Vec<PassInputs> = plan
        .passes
        .iter()
        .map(|p| PassInputs {
            plan: p,
            params: 0,
            rep_lights: vec![None; p.repetitions as usize],
        })
        .collect();
    let run = reuse.decide(graph, keys, &inputs);
    plan.passes
        .iter()
        .zip(run)
        .filter(|(_, r)| r.iter().any(|x| *x))
        .map(|(p, _)| p.name.clone())
        .collect()
}

#[test]
fn unchanged_work_is_reused_and_a_change_reruns_what_depends_on_it() {
    let plan = plan_of(PIPELINE);
    let graph = Graph::of(&plan);
    let mut reuse = Reuse::new(true);
    let still = FrameKeys::default();
    let all = ["make", "cam", "mid", "late", "show"];
    assert_eq!(frame(&plan, &graph, &mut reuse, &still), all, "the first frame runs everything");
    assert!(frame(&plan, &graph, &mut reuse, &still).is_empty(), "nothing changed");
    // The camera moved: `cam` adds to `a`, whose chain starts at `make` (rebuilt from its
    // start), and all that reads `a` after it runs again, with `late`, which writes `b` after
    // `mid` does.
    let moved = FrameKeys {
        camera: 1,
        ..FrameKeys::default()
    };
    assert_eq!(frame(&plan, &graph, &mut reuse, &moved), all);
    assert!(frame(&plan, &graph, &mut reuse, &moved).is_empty());
    // Reuse off: everything, every frame.
    let mut off = Reuse::new(false);
    assert_eq!(frame(&plan, &graph, &mut off, &moved), all);
    assert_eq!(frame(&plan, &graph, &mut off, &moved), all);
}

#[test]
fn a_change_late_in_a_load_chain_reruns_the_chain_from_its_start_and_what_reads_it() {
    // `late` follows the camera instead (and `cam` does not).
    let text = PIPELINE
        .replace("fullscreen cam \"camera.wgsl\"", "fullscreen cam \"fill.wgsl\"")
        .replace("fullscreen late \"fill.wgsl\"", "fullscreen late \"camera.wgsl\"");
    let plan = plan_of(&text);
    let graph = Graph::of(&plan);
    let mut reuse = Reuse::new(true);
    frame(&plan, &graph, &mut reuse, &FrameKeys::default());
    let moved = FrameKeys {
        camera: 1,
        ..FrameKeys::default()
    };
    // `late` loads `b`: its chain starts at `mid`, which runs again, and `mid` reads `a`,
    // whose last writer (`cam`) left it in place.
    assert_eq!(frame(&plan, &graph, &mut reuse, &moved), ["mid", "late", "show"]);
}

/// What a pass reads of the frame block is found by the bytes it reads, not the members'
/// names: a shader declaring the block with its own names (time as `seconds`, the rest
/// skipped over) depends on the time, and the Plan says `time`.
#[test]
fn a_frame_block_with_other_member_names_is_read_by_offset() {
    const OWN: &str = "struct Own {\n    skipped: array<vec4<f32>, 27>,\n    seconds: f32,\n    rest: vec3<u32>,\n};\n\
@group(0) @binding(0) var<uniform> frame: Own;\n\
@fragment\nfn fs_main() -> @location(0) vec4<f32> {\n    return vec4<f32>(fract(frame.seconds));\n}\n";
    let pipeline = "pipeline own\n\ntexture out: Rgba8Unorm 8x8\n\nfullscreen clock \"own.wgsl\" {\n    color out\n}\n\noutput out\n";
    let dir = write_project("reuse-own-frame", &[("pipelines/own.lbp", pipeline), ("shaders/own.wgsl", OWN)]);
    let mut s = Session::new();
    let profile = Profile::offline("vulkan").unwrap();
    let plan = s.plan_file(&dir.join("pipelines/own.lbp"), None, &profile, &SceneFeatures::everything(), &[]);
    let plan = plan.unwrap_or_else(|| panic!("{}", s.render()));
    let d = &plan.passes[0].depends;
    assert!(d.time && !d.camera && !d.frame_index, "{d:?}");
    assert_eq!(d.frame_fields, [lightbench_compiler::abi::FrameField::Time]);
    let json = serde_json::to_string(d).unwrap();
    assert!(json.contains(r#""frame_fields":["time"]"#), "{json}");
}
