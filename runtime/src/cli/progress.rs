//! CLI: progress shown on a terminal while a model's textures are decoded (the first run of a
//! scene; later runs read them from the texture cache). Off a terminal nothing is drawn.

use lightbench_scene::texture_cache::{self, Progress};
use std::sync::Mutex;

/// Draw a bar for each model's texture decoding, on standard error when it is a terminal.
pub fn show_texture_progress() {
    let bar: Mutex<Option<indicatif::ProgressBar>> = Mutex::new(None);
    texture_cache::on_progress(move |p: Progress| {
        let mut bar = bar.lock().unwrap_or_else(|e| e.into_inner());
        if p.done == 0 {
            *bar = Some(new_bar(p.total));
        }
        // Reports come from the decoding threads, not necessarily in order: one that comes
        // after the last image's finds no bar.
        let Some(b) = bar.as_ref() else { return };
        let said = format!("{} decoded, {} from the cache", p.decoded, p.done.saturating_sub(p.decoded));
        if p.done == p.total {
            // The summary stays on its own line (printed only where the bar is drawn).
            b.println(format!(
                "textures: {}/{} ({said}) in {:.1} s",
                p.done,
                p.total,
                b.elapsed().as_secs_f64()
            ));
            b.finish_and_clear();
            *bar = None;
            return;
        }
        b.set_message(said);
        b.set_position(b.position().max(p.done as u64));
    });
}

fn new_bar(total: usize) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::new(total as u64).with_message("0 decoded, 0 from the cache");
    if let Ok(st) = indicatif::ProgressStyle::with_template("textures {bar:30} {pos}/{len} ({msg}), {elapsed}") {
        bar.set_style(st);
    }
    bar
}
