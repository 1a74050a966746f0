use clap::Parser;

fn main() {
    let cli = lightbench::cli::Cli::parse();
    std::process::exit(lightbench::cli::run(cli));
}
