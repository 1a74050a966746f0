//! The `lightbench` binary: parse the command line and run the command (see `cli`).

use clap::Parser;

fn main() {
    // A closed pipe (`lightbench check . 2>&1 | head -1`) ends the process quietly, as it
    // does other command-line tools, instead of panicking in the next print.
    #[cfg(unix)]
    // SAFETY: called first, before any thread starts; SIG_DFL is a valid disposition.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    let cli = lightbench::cli::Cli::parse();
    lightbench::cli::progress::show_texture_progress();
    std::process::exit(lightbench::cli::run(cli));
}
