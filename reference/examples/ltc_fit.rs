//! Fit the LTC table of the pipelines' area lights to the specular lobe of the project's
//! Blinn-Phong (`lightbench_reference::ltc`) and write it where the pipelines read it:
//!
//!     cargo run --release -p lightbench-reference --example ltc_fit [-- OUT.json]
//!
//! (default `pipelines/ltc_blinn_phong.json`). Deterministic: the same table every run. Prints
//! the fit's error (∫|D − f|, f the normalised lobe) by roughness.

use lightbench_reference::ltc;
use std::path::PathBuf;

fn main() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let out = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("pipelines/ltc_blinn_phong.json"));
    let start = std::time::Instant::now();
    let fits = ltc::fit_table();
    println!("fitted {0}×{0} cells in {1:.1} s", ltc::SIZE, start.elapsed().as_secs_f64());
    println!(
        "{:>10} {:>12} {:>12} {:>14}",
        "roughness", "mean error", "worst error", "albedo range"
    );
    for i in (0..ltc::SIZE).step_by(4).chain([ltc::SIZE - 1]) {
        let row = &fits[i * ltc::SIZE..(i + 1) * ltc::SIZE];
        let mean = row.iter().map(|f| f.error).sum::<f32>() / row.len() as f32;
        let worst = row.iter().map(|f| f.error).fold(0.0, f32::max);
        let (lo, hi) = row
            .iter()
            .fold((f32::MAX, 0.0f32), |(lo, hi), f| (lo.min(f.magnitude), hi.max(f.magnitude)));
        println!("{:>10.3} {mean:>12.4} {worst:>12.4} {lo:>6.3}..{hi:<6.3}", ltc::roughness_at(i));
    }
    let floats = ltc::table_floats(&fits);
    let text = serde_json::to_string(&floats.iter().map(|v| (*v as f64 * 1e6).round() / 1e6).collect::<Vec<f64>>()).unwrap();
    lightbench_scene::files::write_atomic(&out, text.as_bytes()).unwrap_or_else(|e| panic!("{e}"));
    println!("wrote {} ({} floats)", out.display(), floats.len());
}
