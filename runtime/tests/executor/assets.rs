//! `cargo bench --bench assets` runs at its smallest: a textured grid loaded and rendered by
//! the copying and the taking executor, its textures decoded against read from the cache once
//! (its figures are the bench's to print, not asserted here).

use crate::gpu_common;

#[path = "../../benches/assets.rs"]
mod assets_bench;

#[test]
fn the_assets_bench_runs() {
    let _g = gpu_common::gpu();
    assets_bench::run(assets_bench::Size::Smoke);
}
