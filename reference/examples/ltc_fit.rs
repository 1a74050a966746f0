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
    let args: Vec<String> = std::env::args().skip(1).collect();
    let out = match args.as_slice() {
        [] => root.join("pipelines/ltc_blinn_phong.json"),
        [path] if !path.starts_with('-') => PathBuf::from(path),
        _ => {
            eprintln!("usage: ltc_fit [OUT.json]");
            std::process::exit(2);
        }
    };
    // Refused before the fit's half minute: a device, pipe, socket or directory.
    if let Err(why) = lightbench_scene::files::replaceable(&out) {
        eprintln!("error: {}: {why}", out.display());
        std::process::exit(1);
    }
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
    let rounded: Vec<f64> = floats.iter().map(|v| (*v as f64 * 1e6).round() / 1e6).collect();
    let text = serde_json::to_string(&rounded).expect("numbers serialise");
    // Written atomically through lightbench's guarded writer (no device, no half-written file).
    if let Err(e) = lightbench_scene::files::write_atomic(&out, text.as_bytes()) {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
    println!("wrote {} ({} floats)", out.display(), floats.len());
}
