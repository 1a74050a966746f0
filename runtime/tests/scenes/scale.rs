//! `cargo bench --bench scale` and `--bench assets` run at their smallest: scale's points (a
//! two-triangle grid, 10 k triangles in one mesh, 40 k in four), each through `plan`,
//! `render` and `reference` as child processes; assets' textured grid loaded, rendered and its
//! textures decoded against cached once (their figures are the benches' to print, not
//! asserted here).

#[path = "../../benches/scale.rs"]
mod scale_bench;

#[test]
fn the_scale_bench_runs() {
    scale_bench::run(scale_bench::Size::Smoke);
}

#[path = "../../benches/assets.rs"]
mod assets_bench;

#[test]
fn the_assets_bench_runs() {
    let _g = crate::gpu_common::gpu();
    assets_bench::run(assets_bench::Size::Smoke);
}
