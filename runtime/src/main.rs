//! The `lightbench` binary: parse the command line and run the command (see `cli`).

use clap::Parser;

fn main() {
    let cli = lightbench::cli::Cli::parse();
    std::process::exit(lightbench::cli::run(cli));
}
