//! Stage `rows` of `sweep`: one row per measured point, kept in `rows.jsonl` (a JSON object
//! a line). Each finished point rewrites the file atomically with its row added, so a sweep
//! killed at any moment loses at most the point it was measuring, and a rerun skips what is
//! there. Shards write their own folders; `merge` joins them.

use super::measure::ErrorMetrics;
use crate::diff::timing::Stats;
use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};
use std::path::Path;

pub const FILE: &str = "rows.jsonl";

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Row {
    /// Fingerprint of the sweep spec the row belongs to.
    pub spec: String,
    pub sweep: String,
    /// Position in the spec's point order, and how many points the spec has.
    pub index: usize,
    pub points: usize,
    pub id: String,
    pub scene: String,
    pub size: (u32, u32),
    /// The settings that vary between points, in the spec's order.
    pub settings: Vec<(String, String)>,
    /// Every variant's option as planned (fallbacks taken where the adapter lacks a feature).
    pub variants: Vec<(String, String)>,
    /// GPU ms of the effect's passes per frame (`None` without GPU timestamps).
    pub effect_ms: Option<Stats>,
    /// GPU ms of the whole frame (wall-clock ms without GPU timestamps; see `timing`).
    pub frame_ms: Option<Stats>,
    /// "gpu" or "wall".
    pub timing: String,
    pub error: ErrorMetrics,
    /// The reference's cache key and samples per pixel.
    pub reference: String,
    pub reference_spp: u32,
}

impl Row {
    /// The cost axis: the effect's time, else the frame's.
    pub fn cost_ms(&self) -> Option<f64> {
        self.effect_ms.or(self.frame_ms).map(|s| s.median)
    }
    /// The point's settings as a label: the values, comma-separated, where every point of its
    /// plot has the same keys (`uniform`: the plot's title names them); else variant options
    /// as they are (they name themselves) and numbers and booleans as `last.segment=value`.
    pub fn label(&self, uniform: bool) -> String {
        let part = |(k, v): &(String, String)| {
            let named = v.parse::<f64>().is_ok() || v == "true" || v == "false";
            match k.split_once('.') {
                _ if uniform || !named => v.clone(),
                Some((_, rest)) => format!("{rest}={v}"),
                None => format!("{k}={v}"),
            }
        };
        self.settings.iter().map(part).collect::<Vec<_>>().join(", ")
    }
}

/// The rows in `dir` (none yet: empty). A line that does not parse — the tail of a write cut
/// short by something other than this program — is an error naming the line.
pub fn load(dir: &Path) -> Result<Vec<Row>> {
    let path = dir.join(FILE);
    // The guarded reader (rows.jsonl replaced by a FIFO or a device is refused, not read);
    // its cap is generous: a row is a few hundred bytes.
    let text = match lightbench_compiler::vfs::read_bytes(&path, 1 << 30).and_then(lightbench_compiler::vfs::utf8) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(vec![]),
        Err(e) => return Err(Error::io(&path, e)),
    };
    text.lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(i, l)| serde_json::from_str(l).map_err(|e| Error::io(&path, format!("line {}: {e}", i + 1))))
        .collect()
}

/// Write `rows` (sorted by index) as `dir/rows.jsonl`, atomically.
pub fn save(dir: &Path, rows: &[Row]) -> Result<()> {
    let mut sorted: Vec<&Row> = rows.iter().collect();
    sorted.sort_by_key(|r| r.index);
    let mut text = String::new();
    for r in sorted {
        text.push_str(&serde_json::to_string(r).map_err(|e| Error::io(dir, e))?);
        text.push('\n');
    }
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    Ok(crate::io::write_atomic(&dir.join(FILE), text.as_bytes())?)
}

/// Add `row` to the rows in `dir` under the folder's lock, re-reading them first: runs that
/// write into one folder at once (shards) keep every row. A row of the same point replaces
/// the one on file. Returns the rows now on file.
pub fn add(dir: &Path, row: Row) -> Result<Vec<Row>> {
    let _lock = crate::files::lock_dir(dir)?;
    let mut rows = load(dir)?;
    rows.retain(|r| r.id != row.id);
    rows.push(row);
    save(dir, &rows)?;
    Ok(rows)
}

/// The rows of several folders (shards) as one sweep: the same spec throughout, each point
/// once. Returns the rows and how many points the spec has.
pub fn merge(dirs: &[&Path]) -> Result<(Vec<Row>, usize)> {
    let mut out: Vec<Row> = vec![];
    for dir in dirs {
        let rows = load(dir)?;
        if rows.is_empty() {
            return Err(Error::Usage(format!("{}: no {FILE} with rows in it", dir.display())));
        }
        for r in rows {
            if let Some(first) = out.first() {
                if first.spec != r.spec {
                    return Err(Error::Usage(format!(
                        "{}: rows of another sweep spec ({} `{}`, not {} `{}`)",
                        dir.display(),
                        r.sweep,
                        r.spec,
                        first.sweep,
                        first.spec
                    )));
                }
            }
            if !out.iter().any(|o| o.id == r.id) {
                out.push(r);
            }
        }
    }
    out.sort_by_key(|r| r.index);
    let points = out.first().map_or(0, |r| r.points);
    Ok((out, points))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_name_numbers_where_points_differ_in_keys() {
        let row = Row {
            spec: String::new(),
            sweep: "s".into(),
            index: 0,
            points: 1,
            id: "x".into(),
            scene: "cornell".into(),
            size: (8, 8),
            settings: vec![
                ("indirect_diffuse".into(), "temporal".into()),
                ("gi.temporal.samples".into(), "4".into()),
                ("gi.area_weights".into(), "true".into()),
            ],
            variants: vec![],
            effect_ms: None,
            frame_ms: None,
            timing: "gpu".into(),
            error: ErrorMetrics {
                rmse: 0.0,
                rmse_raw: 0.0,
                bias: 0.0,
                flip: None,
                non_finite: 0,
                blocks: None,
                surfaces: vec![],
            },
            reference: String::new(),
            reference_spp: 1,
        };
        assert_eq!(row.label(true), "temporal, 4, true");
        assert_eq!(row.label(false), "temporal, temporal.samples=4, area_weights=true");
    }
}
