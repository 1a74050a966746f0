//! Stage `script` of the viewer: a `--script` file as steps, each line's syntax checked
//! before any window opens, and one step run against the viewer — the same actions keys and
//! widgets give. Every error names `FILE:LINE`.

use super::state::{parse_action, Viewer};
use crate::error::{Error, Result};
use crate::gpu::Gpu;

/// A script step: an action line (see `state::parse_action`) and where it was written
/// (`FILE:LINE`, which its errors name), or frames to render before the next one.
pub enum Step {
    Line(String, String),
    Frames(u32),
}

/// The steps of a script's text (`file` names it in errors); blank lines and `#` comments
/// are skipped.
pub fn parse(text: &str, file: &str) -> Result<Vec<Step>> {
    let mut steps = vec![];
    for (n, line) in text.lines().enumerate().map(|(n, l)| (n + 1, l.trim())) {
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let at = format!("{file}:{n}");
        match line.strip_prefix("frames ") {
            Some(k) => {
                steps.push(Step::Frames(k.trim().parse().map_err(|_| {
                    Error::Usage(format!("{at}: script line `{line}`: `frames` takes a whole number"))
                })?))
            }
            None => {
                parse_action(line, None).map_err(|e| e.at(&at))?;
                steps.push(Step::Line(line.to_string(), at));
            }
        }
    }
    Ok(steps)
}

/// Run one action line against the viewer: its values checked against the running Plan, then
/// applied. A failing line's error is said at its place.
pub fn run_line(viewer: &mut Viewer, gpu: &Gpu, line: &str, at: &str) -> Result<()> {
    let a = parse_action(line, Some(viewer.ex.plan())).map_err(|e| e.at(at))?;
    viewer.apply(gpu, a).map_err(|e| e.at(at))
}
