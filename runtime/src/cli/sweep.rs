//! `lightbench sweep SPEC` and `lightbench sweep merge DIR...`: parse the options, run or
//! merge, and say where the results are.

use super::{failed, EXIT_ERRORS, EXIT_OK};
use crate::error::{Error, Result};
use crate::gpu::{DeviceOptions, Gpu};
use crate::sweep::{self, report, rows, spec};
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct Args {
    #[command(subcommand)]
    pub merge: Option<MergeCommand>,
    /// The sweep spec (RON; see `sweeps/`).
    #[arg(required = true)]
    pub spec: Option<PathBuf>,
    /// Results folder (default: `sweep-NAME`). Rerunning into it skips finished points.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Measure only points K, K+N, K+2N… (`K/N`), for a job array; join with `sweep merge`.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,
    /// Reference cache folder (default: OUT/references); share it between shards on one disk.
    #[arg(long)]
    pub references: Option<PathBuf>,
    #[command(flatten)]
    pub effects: super::EffectArgs,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    #[arg(long, value_enum)]
    pub backend: Option<crate::gpu::device::BackendChoice>,
    #[arg(long)]
    pub adapter: Option<String>,
}

#[derive(clap::Subcommand, Debug)]
pub enum MergeCommand {
    /// Join the result folders of a sweep's shards into one (rows, CSV, JSON, report, plots).
    Merge {
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        #[arg(long)]
        out: PathBuf,
    },
}

fn execute(a: &Args) -> Result<()> {
    let path = a.spec.as_ref().ok_or_else(|| Error::Usage("name a sweep spec".into()))?;
    let mut loaded = spec::load(path)?;
    loaded.add_effects(&a.effects.effects);
    let shard = a.shard.as_deref().map(spec::parse_shard).transpose()?.unwrap_or((0, 1));
    let out = a.out.clone().unwrap_or_else(|| PathBuf::from(format!("sweep-{}", loaded.name)));
    let gpu = Gpu::new(&DeviceOptions {
        backend: a.backend,
        adapter: a.adapter.clone(),
    })?;
    eprintln!("{}", gpu.describe());
    let opts = sweep::Options {
        out: out.clone(),
        shard,
        references: a.references.clone(),
        progress: !a.quiet,
    };
    let s = sweep::run(&gpu, &loaded, &opts)?;
    eprintln!(
        "sweep {}: {} point(s) measured, {} already done, {} of {} in {}",
        loaded.name,
        s.measured,
        s.skipped,
        s.rows.len(),
        s.points,
        out.display()
    );
    print!("{}", report::markdown(&s.rows, s.points));
    Ok(())
}

fn merge(dirs: &[PathBuf], out: &std::path::Path) -> Result<()> {
    let refs: Vec<&std::path::Path> = dirs.iter().map(|d| d.as_path()).collect();
    let (rows, points) = rows::merge(&refs)?;
    rows::save(out, &rows)?;
    report::write_all(out, &rows, points)?;
    if rows.len() < points {
        eprintln!("warning: {} of {points} points are in the merged folders", rows.len());
    }
    eprintln!("merged {} point(s) into {}", rows.len(), out.display());
    Ok(())
}

pub fn run(a: Args) -> i32 {
    let result = match &a.merge {
        Some(MergeCommand::Merge { dirs, out }) => merge(dirs, out),
        None => execute(&a),
    };
    match result {
        Ok(()) => EXIT_OK,
        Err(Error::Executor(crate::gpu::Error::Compile(report))) => {
            eprint!("{report}");
            EXIT_ERRORS
        }
        Err(Error::Scene(crate::scene::Error::Scene(_))) => EXIT_ERRORS,
        Err(e) => failed(e),
    }
}
