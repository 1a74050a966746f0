//! `cargo bench -p lightbench-compiler --bench memory` (and `cargo test`, as it is: it is
//! quick): memory of the bundled pipelines at
//! 1920×1080 with every effect called for and every light kind, each resource its own
//! (logical) against transient resources aliased (physical, stage `alias`); goal for
//! `deferred_gi`: ≤ 0.7×. A figure of the Plan, not a timing: the same on every machine.

use lightbench_compiler::plan::mib_text;
use lightbench_compiler::profile::Profile;
use lightbench_compiler::scene::SceneFeatures;
use lightbench_compiler::Session;
use std::path::Path;

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap().to_path_buf();
    let mut scene = SceneFeatures::everything();
    scene.size = (1920, 1080);
    for file in ["deferred.lbp", "deferred_gi.lbp"] {
        let mut s = Session::new();
        let plan = s.plan_file(&root.join("pipelines").join(file), None, &Profile::vulkan(), &scene, &[]);
        let plan = plan.unwrap_or_else(|| panic!("{}", s.render()));
        let shared = plan.resources.iter().filter(|r| r.shares.is_some()).count();
        println!(
            "{file:<16} 1920×1080, every effect: logical {:>10}, physical {:>10} ({:.2}×; {shared} of {} resources in another's memory)",
            mib_text(plan.memory_bytes),
            mib_text(plan.physical_bytes),
            plan.physical_bytes as f64 / plan.memory_bytes as f64,
            plan.resources.len()
        );
    }
}
