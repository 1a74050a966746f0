//! `lightbench view`: an interactive window onto a running pipeline (seed 000 ch. 6.1, 8):
//! the output or any resource of the Plan, camera and light controls, parameter and variant
//! widgets, per-pass costs, screenshots. Sub-stages: `state` (what is shown and the actions
//! that change it: keys, widgets and `--script` alike), `script` (a script file as steps, one
//! step run), `display` (any format as an image), `traced` (the path-traced view beside the
//! raster one), `panels` (egui), `window` (winit, the wgpu surface).

pub mod display;
mod panels;
pub mod script;
pub mod state;
pub mod traced;
mod window;

use crate::error::{Error, Result};
use crate::scene::Scene;
use lightbench_compiler::Workspace;
use std::path::PathBuf;

pub use script::Step;

/// What to show.
pub struct Options {
    pub workspace: Workspace,
    pub pipeline: PathBuf,
    pub shaders: Option<PathBuf>,
    pub scene: Scene,
    /// The scene file the scene was loaded from, watched with the pipeline (none for a
    /// built-in scene).
    pub scene_file: Option<PathBuf>,
    /// Effects asked for besides the scene's own (`--effect`), kept when it reloads.
    pub effects: Vec<lightbench_compiler::ir::Effect>,
    /// The models the scene was loaded with (`ModelCache::keeping`): a reload parses again
    /// only those whose files changed.
    pub models: crate::scene::model_cache::ModelCache,
    pub variants: Vec<(String, String)>,
    /// Close the window when the script is over.
    pub scripted: bool,
}

/// Open the window and run until it is closed (or the script ends).
pub fn run(opts: Options, script: Vec<Step>) -> Result<()> {
    let el = winit::event_loop::EventLoop::new().map_err(|e| Error::Usage(format!("cannot open a window (no display?): {e}")))?;
    let mut app = window::App::new(opts, script);
    el.run_app(&mut app)
        .map_err(|e| Error::Usage(format!("the window's event loop failed: {e}")))?;
    app.result
}
