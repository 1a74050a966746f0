//! Stage `report` of `diff`: the report as markdown (a terminal, a pull request), one
//! self-contained HTML file (images embedded as data URIs) or JSON (CI).

use super::{ImageDiff, Report};
use crate::error::{Error, Result};
use lightbench_compiler::plan::{mib_text, Change};
use std::fmt::Write;
use std::path::Path;

fn opt(v: Option<&String>) -> &str {
    v.map(String::as_str).unwrap_or("—")
}

fn num(v: Option<f64>, digits: usize) -> String {
    v.map(|x| format!("{x:.digits$}")).unwrap_or_else(|| "—".into())
}

/// A table cell: no pipes or line breaks.
fn cell(s: &str) -> String {
    s.replace('|', "\\|").replace('\n', "<br>")
}

fn header(r: &Report, s: &mut String) {
    let _ = writeln!(s, "# lightbench diff\n");
    let _ = writeln!(s, "- **A**: `{}`\n- **B**: `{}`", r.a.label, r.b.label);
    let _ = writeln!(s, "- scene `{}` at {}×{}", r.scene, r.size.0, r.size.1);
    for (side, rep) in [("A", &r.a), ("B", &r.b)] {
        for (v, o, why) in &rep.variants {
            if let Some(why) = why {
                let _ = writeln!(s, "- {side}: variant {v} = {o} ({why})");
            }
        }
    }
}

fn changes(s: &mut String, title: &str, list: &[Change]) {
    if list.is_empty() {
        return;
    }
    let _ = writeln!(s, "\n### {title}\n\n| name | A | B |\n|---|---|---|");
    for c in list {
        let _ = writeln!(s, "| {} | {} | {} |", c.name, cell(opt(c.a.as_ref())), cell(opt(c.b.as_ref())));
    }
}

fn structure(r: &Report, s: &mut String) {
    let d = &r.structure;
    let _ = writeln!(s, "\n## Structure\n");
    let (ma, mb) = d.memory;
    let _ = writeln!(
        s,
        "memory: A {} · B {} · difference {}{}",
        mib_text(ma),
        mib_text(mb),
        if mb >= ma { "+" } else { "−" },
        mib_text(ma.abs_diff(mb))
    );
    if d.is_empty() {
        let _ = writeln!(s, "\nThe Plans have the same structure.");
        return;
    }
    changes(s, "Variants", &d.variants);
    changes(s, "Parameters", &d.params);
    changes(s, "Passes only in A", &d.passes_removed);
    changes(s, "Passes only in B", &d.passes_added);
    if !d.passes_changed.is_empty() {
        let _ = writeln!(s, "\n### Passes changed\n\n| pass | only in A | only in B |\n|---|---|---|");
        for p in &d.passes_changed {
            let _ = writeln!(
                s,
                "| {} | {} | {} |",
                p.name,
                cell(&p.only_a.join("\n")),
                cell(&p.only_b.join("\n"))
            );
        }
    }
    if d.order_changed {
        let _ = writeln!(s, "\nThe passes both keep run in another order.");
    }
    changes(s, "Culled (reason)", &d.culled);
    changes(s, "Resources", &d.resources);
}

/// `resource [instance/layer]`, with `mip k` past level 0.
fn slice_name(i: &ImageDiff) -> String {
    match i.mip {
        0 => format!("{} [{}/{}]", i.resource, i.instance, i.layer),
        k => format!("{} [{}/{}] mip {k}", i.resource, i.instance, i.layer),
    }
}

fn pixels(r: &Report, s: &mut String) {
    if r.images.is_empty() && r.not_compared.is_empty() {
        return;
    }
    let _ = writeln!(s, "\n## Pixels\n");
    let _ = writeln!(
        s,
        "| resource [light/layer] | format | RMSE | max abs | PSNR dB | FLIP | SSIM | B/A 8×8 blocks p10–p90 (min–max) | images |\n|---|---|---|---|---|---|---|---|---|"
    );
    for i in &r.images {
        let m = &i.metrics;
        let psnr = m.psnr_db.map(|p| format!("{p:.1}")).unwrap_or_else(|| "equal".into());
        let files = i
            .side_by_side
            .as_deref()
            .map(|f| format!("[side by side]({f})"))
            .unwrap_or_default();
        let _ = writeln!(
            s,
            "| {} | {} | {:.3e} | {:.3e} | {psnr} | {} | {} | {} | {files} |",
            slice_name(i),
            i.format,
            m.rmse,
            m.max_abs,
            num(m.flip_mean, 4),
            num(m.ssim, 4),
            m.blocks
                .as_ref()
                .map(|b| format!("{:.2}–{:.2} ({:.2}–{:.2})", b.p10, b.p90, b.min, b.max))
                .unwrap_or_else(|| "—".into())
        );
    }
    for (n, why) in &r.not_compared {
        let _ = writeln!(s, "\nnot compared: `{n}`: {why}");
    }
}

fn stat(v: Option<super::timing::Stats>, digits: usize) -> String {
    v.map(|s| format!("{:.digits$} ({:.digits$}–{:.digits$})", s.median, s.min, s.max))
        .unwrap_or_else(|| "—".into())
}

fn time(r: &Report, s: &mut String) {
    let Some(t) = &r.timing else { return };
    let _ = writeln!(
        s,
        "\n## Time\n\nmedian (min–max) over {} frames each, interleaved, after a warm-up\n",
        t.frames
    );
    let _ = writeln!(
        s,
        "| pass | A GPU ms | B GPU ms | B/A | A encode µs | B encode µs |\n|---|---|---|---|---|---|"
    );
    for p in &t.passes {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} |",
            p.pass,
            stat(p.a_gpu_ms, 3),
            stat(p.b_gpu_ms, 3),
            num(p.ratio, 2),
            stat(p.a_encode_us, 1),
            stat(p.b_encode_us, 1)
        );
    }
    let _ = writeln!(
        s,
        "| **frame (GPU)** | {} | {} | {} | | |\n| frame (wall) | {} | {} | | | |",
        stat(t.a_gpu_ms, 3),
        stat(t.b_gpu_ms, 3),
        num(t.frame_ratio, 2),
        stat(t.a_frame_ms, 3),
        stat(t.b_frame_ms, 3)
    );
}

fn gates(r: &Report, s: &mut String) {
    if r.thresholds.is_empty() {
        return;
    }
    let _ = writeln!(s, "\n## Thresholds\n");
    for t in &r.thresholds {
        let verdict = if t.crossed { "**crossed**" } else { "ok" };
        let _ = writeln!(s, "- {} = {} (limit {}): {verdict}", t.metric.name(), num(t.value, 5), t.limit);
    }
}

pub fn markdown(r: &Report) -> String {
    let mut s = String::new();
    header(r, &mut s);
    structure(r, &mut s);
    pixels(r, &mut s);
    time(r, &mut s);
    gates(r, &mut s);
    s
}

pub fn json(r: &Report) -> String {
    serde_json::to_string_pretty(r).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Markdown tables as HTML tables, other lines as paragraphs (the report's own subset).
fn md_to_html(md: &str, images: &dyn Fn(&str) -> Option<String>) -> String {
    let mut out = String::new();
    let mut in_table = false;
    for line in md.lines() {
        let is_row = line.starts_with('|');
        if in_table && !is_row {
            out += "</table>\n";
            in_table = false;
        }
        if is_row {
            if line.starts_with("|---") {
                continue;
            }
            if !in_table {
                out += "<table>\n";
                in_table = true;
            }
            let cells: Vec<String> = line.trim_matches('|').split(" | ").map(|c| inline(c.trim(), images)).collect();
            out += &format!("<tr><td>{}</td></tr>\n", cells.join("</td><td>"));
        } else if let Some(h) = line.strip_prefix("### ") {
            out += &format!("<h3>{}</h3>\n", inline(h, images));
        } else if let Some(h) = line.strip_prefix("## ") {
            out += &format!("<h2>{}</h2>\n", inline(h, images));
        } else if let Some(h) = line.strip_prefix("# ") {
            out += &format!("<h1>{}</h1>\n", inline(h, images));
        } else if !line.trim().is_empty() {
            out += &format!("<p>{}</p>\n", inline(line.trim_start_matches("- "), images));
        }
    }
    if in_table {
        out += "</table>\n";
    }
    out
}

/// A cell's text: `[label](file.png)` becomes the embedded image, `<br>` stays a break.
fn inline(text: &str, images: &dyn Fn(&str) -> Option<String>) -> String {
    if let Some(rest) = text.strip_prefix("[side by side](") {
        let file = rest.trim_end_matches(')');
        return match images(file) {
            Some(uri) => format!("<img alt=\"{}\" src=\"{uri}\">", escape(file)),
            None => escape(file),
        };
    }
    let html = escape(text).replace("&lt;br&gt;", "<br>").replace("\\|", "|");
    spans(&spans(&html, "**", "strong"), "`", "code")
}

/// Markdown's paired `mark`s (`**`, `` ` ``) as `<tag>` elements; an unpaired mark stays text.
fn spans(text: &str, mark: &str, tag: &str) -> String {
    let parts: Vec<&str> = text.split(mark).collect();
    let pairs = (parts.len() - 1) / 2;
    let mut out = String::from(parts[0]);
    for (i, part) in parts.iter().enumerate().skip(1) {
        match i {
            _ if i > 2 * pairs => out.push_str(mark),
            _ if i % 2 == 1 => out.push_str(&format!("<{tag}>")),
            _ => out.push_str(&format!("</{tag}>")),
        }
        out.push_str(part);
    }
    out
}

/// One HTML file: the markdown report's content with every side-by-side image embedded.
pub fn html(r: &Report, dir: &Path) -> Result<String> {
    use base64::Engine;
    let mut embedded = std::collections::BTreeMap::new();
    for file in r.images.iter().filter_map(|i| i.side_by_side.as_ref()) {
        let bytes = std::fs::read(dir.join(file)).map_err(|e| Error::io(dir.join(file), e))?;
        let b64 = base64::engine::general_purpose::STANDARD.encode(bytes);
        embedded.insert(file.clone(), format!("data:image/png;base64,{b64}"));
    }
    let body = md_to_html(&markdown(r), &|f| embedded.get(f).cloned());
    Ok(format!(
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>lightbench diff</title>\n<style>\
         body{{font-family:sans-serif;margin:2em}} table{{border-collapse:collapse;margin:1em 0}} \
         td{{border:1px solid #ccc;padding:3px 6px;vertical-align:top;font-size:13px}} \
         img{{image-rendering:pixelated;height:128px}}</style></head>\n<body>\n{body}</body></html>\n"
    ))
}
