//! Stage `report` of `sweep`: the rows as CSV, JSON and a markdown table, and per scene and
//! size an SVG plot (plotters) of error against cost with the Pareto front marked (★) and
//! every point labelled with its settings.

use super::pareto;
use super::rows::Row;
use crate::diff::timing::Stats;
use crate::error::{Error, Result};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The rows of one scene at one size: the points a front is drawn through.
pub struct Group<'a> {
    pub scene: &'a str,
    pub size: (u32, u32),
    pub rows: Vec<&'a Row>,
    pub front: Vec<bool>,
}

impl Group<'_> {
    pub fn plot_name(&self) -> String {
        let scene: String = self
            .scene
            .chars()
            .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
            .collect();
        format!("pareto_{scene}_{}x{}.svg", self.size.0, self.size.1)
    }
}

pub fn groups(rows: &[Row]) -> Vec<Group<'_>> {
    let mut keys: Vec<(&str, (u32, u32))> = vec![];
    for r in rows {
        if !keys.contains(&(r.scene.as_str(), r.size)) {
            keys.push((&r.scene, r.size));
        }
    }
    keys.into_iter()
        .map(|(scene, size)| {
            let rows: Vec<&Row> = rows.iter().filter(|r| r.scene == scene && r.size == size).collect();
            let front = pareto::front(&rows.iter().map(|r| (r.cost_ms(), r.error.rmse)).collect::<Vec<_>>());
            Group { scene, size, rows, front }
        })
        .collect()
}

fn on_front(groups: &[Group], row: &Row) -> bool {
    groups
        .iter()
        .flat_map(|g| g.rows.iter().zip(&g.front))
        .any(|(r, &f)| r.id == row.id && f)
}

/// Every setting key, in the order rows first use them.
fn keys(rows: &[Row]) -> Vec<String> {
    let mut out: Vec<String> = vec![];
    for r in rows {
        for (k, _) in &r.settings {
            if !out.contains(k) {
                out.push(k.clone());
            }
        }
    }
    out
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

fn num(v: Option<f64>) -> String {
    v.map(|x| format!("{x}")).unwrap_or_default()
}

fn stats_cols(s: Option<Stats>) -> [String; 3] {
    [num(s.map(|s| s.median)), num(s.map(|s| s.min)), num(s.map(|s| s.max))]
}

pub fn csv(rows: &[Row]) -> String {
    let groups = groups(rows);
    let keys = keys(rows);
    let mut head: Vec<String> = ["index", "scene", "width", "height"].map(String::from).to_vec();
    head.extend(keys.iter().cloned());
    head.extend(
        [
            "effect_ms",
            "effect_ms_min",
            "effect_ms_max",
            "frame_ms",
            "frame_ms_min",
            "frame_ms_max",
            "timing",
            "rmse",
            "rmse_raw",
            "bias",
            "flip",
            "block_p10",
            "block_p90",
            "block_min",
            "block_max",
            "surface_min",
            "surface_min_name",
            "surface_max",
            "surface_max_name",
            "non_finite",
            "pareto",
            "variants",
        ]
        .map(String::from),
    );
    let mut out = head.iter().map(|h| csv_field(h)).collect::<Vec<_>>().join(",") + "\n";
    for r in rows {
        let mut f = vec![r.index.to_string(), r.scene.clone(), r.size.0.to_string(), r.size.1.to_string()];
        for k in &keys {
            f.push(r.settings.iter().find(|(n, _)| n == k).map(|(_, v)| v.clone()).unwrap_or_default());
        }
        f.extend(stats_cols(r.effect_ms));
        f.extend(stats_cols(r.frame_ms));
        f.push(r.timing.clone());
        f.extend([
            num(Some(r.error.rmse)),
            num(Some(r.error.rmse_raw)),
            num(Some(r.error.bias)),
            num(r.error.flip),
        ]);
        let b = r.error.blocks.as_ref();
        f.extend([b.map(|b| b.p10), b.map(|b| b.p90), b.map(|b| b.min), b.map(|b| b.max)].map(num));
        let (low, high) = r.error.surface_extremes().unzip();
        for s in [low, high] {
            f.extend([num(s.map(|s| s.ratio)), s.map(|s| s.name.clone()).unwrap_or_default()]);
        }
        f.push(r.error.non_finite.to_string());
        f.push(on_front(&groups, r).to_string());
        f.push(r.variants.iter().map(|(k, v)| format!("{k}={v}")).collect::<Vec<_>>().join(" "));
        out.push_str(&f.iter().map(|x| csv_field(x)).collect::<Vec<_>>().join(","));
        out.push('\n');
    }
    out
}

#[derive(Serialize)]
struct JsonRow<'a> {
    #[serde(flatten)]
    row: &'a Row,
    pareto: bool,
}

pub fn json(rows: &[Row]) -> String {
    let groups = groups(rows);
    let out: Vec<JsonRow> = rows
        .iter()
        .map(|row| JsonRow {
            row,
            pareto: on_front(&groups, row),
        })
        .collect();
    serde_json::to_string_pretty(&out).unwrap_or_default()
}

fn ms(s: Option<Stats>) -> String {
    s.map(|s| format!("{:.3} ({:.3}–{:.3})", s.median, s.min, s.max))
        .unwrap_or_else(|| "–".into())
}

pub fn markdown(rows: &[Row], points: usize) -> String {
    let keys = keys(rows);
    let name = rows.first().map_or("sweep", |r| r.sweep.as_str());
    let mut out = format!("# Sweep `{name}`: {} of {points} points\n", rows.len());
    for g in groups(rows) {
        out.push_str(&format!(
            "\n## {} at {}x{} (plot: {})\n\n",
            g.scene,
            g.size.0,
            g.size.1,
            g.plot_name()
        ));
        out.push_str(&format!(
            "| {} | effect GPU ms (min–max) | frame ms (min–max) | RMSE | bias | FLIP | 8×8 blocks p10–p90 (min–max) | surfaces (lowest–highest) | front |\n",
            keys.join(" | ")
        ));
        out.push_str(&format!("|{}---|---|---|---|---|---|---|---|\n", "---|".repeat(keys.len())));
        for (r, &front) in g.rows.iter().zip(&g.front) {
            let vals: Vec<String> = keys
                .iter()
                .map(|k| r.settings.iter().find(|(n, _)| n == k).map(|(_, v)| v.clone()).unwrap_or_default())
                .collect();
            out.push_str(&format!(
                "| {} | {} | {} | {:.5} | {:+.5} | {} | {} | {} | {} |\n",
                vals.join(" | "),
                ms(r.effect_ms),
                ms(r.frame_ms),
                r.error.rmse,
                r.error.bias,
                r.error.flip.map(|f| format!("{f:.4}")).unwrap_or_else(|| "–".into()),
                r.error
                    .blocks
                    .map(|b| format!("{:.2}–{:.2} ({:.2}–{:.2})", b.p10, b.p90, b.min, b.max))
                    .unwrap_or_else(|| "–".into()),
                r.error
                    .surface_extremes()
                    .map(|(lo, hi)| format!("{:.2} {} – {:.2} {}", lo.ratio, lo.name, hi.ratio, hi.name))
                    .unwrap_or_else(|| "–".into()),
                if front { "★" } else { "" }
            ));
        }
    }
    out
}

fn plot_error(e: impl std::fmt::Display) -> Error {
    Error::Usage(format!("drawing the Pareto plot: {e}"))
}

/// Error against cost for one group, front points filled and joined, every point labelled.
pub fn svg(g: &Group, keys: &[String]) -> Result<String> {
    use plotters::prelude::*;
    let key_list = |r: &Row| r.settings.iter().map(|(k, _)| k.clone()).collect::<Vec<_>>();
    let uniform = g.rows.iter().all(|r| key_list(r) == keys);
    let pts: Vec<(f64, f64, bool, String)> = g
        .rows
        .iter()
        .zip(&g.front)
        .filter_map(|(r, &f)| r.cost_ms().map(|c| (c, r.error.rmse, f, r.label(uniform))))
        .collect();
    // Room on the right for the longest label (about 6.5 px a character on an 850 px axis).
    let longest = pts.iter().map(|p| p.3.chars().count()).max().unwrap_or(0) as f64;
    let room = ((longest * 6.5 + 30.0) / 850.0).clamp(0.2, 0.6);
    let xmax = pts.iter().map(|p| p.0).fold(0.0, f64::max).max(1e-6) / (1.0 - room);
    let ymax = pts.iter().map(|p| p.1).fold(0.0, f64::max).max(1e-9) * 1.15;
    let effect = g.rows.first().is_some_and(|r| r.effect_ms.is_some());
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, (960, 640)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        let title = if uniform {
            format!("{} at {}x{}: error vs time ({})", g.scene, g.size.0, g.size.1, keys.join(", "))
        } else {
            format!("{} at {}x{}: error vs time", g.scene, g.size.0, g.size.1)
        };
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 18))
            .margin(20)
            .x_label_area_size(45)
            .y_label_area_size(70)
            .build_cartesian_2d(0.0..xmax, 0.0..ymax)
            .map_err(plot_error)?;
        chart
            .configure_mesh()
            .x_desc(if effect {
                "effect GPU ms per frame (median)"
            } else {
                "frame ms (median)"
            })
            .y_desc("RMSE against the reference (noise-corrected)")
            .draw()
            .map_err(plot_error)?;
        let mut front: Vec<(f64, f64)> = pts.iter().filter(|p| p.2).map(|p| (p.0, p.1)).collect();
        front.sort_by(|a, b| a.0.total_cmp(&b.0));
        chart.draw_series(LineSeries::new(front, RED.stroke_width(2))).map_err(plot_error)?;
        for (x, y, on, label) in &pts {
            let (style, text) = if *on {
                (RED.filled(), format!("★ {label}"))
            } else {
                (BLACK.stroke_width(1), label.clone())
            };
            // The marker at the point, its label just right of it.
            let marker =
                EmptyElement::at((*x, *y)) + Circle::new((0, 0), 4, style) + Text::new(text, (7, -5), ("sans-serif", 11).into_font());
            chart.draw_series([marker]).map_err(plot_error)?;
        }
        root.present().map_err(plot_error)?;
    }
    Ok(text)
}

/// Write rows.csv, rows.json, report.md and the plots into `dir`; the files written.
pub fn write_all(dir: &Path, rows: &[Row], points: usize) -> Result<Vec<PathBuf>> {
    let mut written = vec![];
    let mut put = |name: &str, text: &str| -> Result<()> {
        let p = dir.join(name);
        crate::io::write_atomic(&p, text.as_bytes())?;
        written.push(p);
        Ok(())
    };
    put("results.csv", &csv(rows))?;
    put("results.json", &json(rows))?;
    put("report.md", &markdown(rows, points))?;
    let keys = keys(rows);
    for g in groups(rows) {
        put(&g.plot_name(), &svg(&g, &keys)?)?;
    }
    Ok(written)
}
