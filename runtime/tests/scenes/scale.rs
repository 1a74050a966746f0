//! `cargo bench --bench scale` runs: its smallest points (a two-triangle grid, 10 k triangles
//! in one mesh, 40 k in four), each through `plan`, `render` and `reference` as child
//! processes (its figures are the bench's to print, not asserted here).

#[path = "../../benches/scale.rs"]
mod scale_bench;

#[test]
fn the_scale_bench_runs() {
    scale_bench::run(scale_bench::Size::Smoke);
}
