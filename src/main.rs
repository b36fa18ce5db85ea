use clap::Parser;
use glare_pipeline::cli::{run, Cli};

fn main() {
    let cli = Cli::parse();
    // Every refusal starts with the command it refuses (`render --scene fig7:`).
    let label = cli.command.label();
    if let Err(e) = run(cli) {
        eprintln!("error: {label}: {e}");
        std::process::exit(2);
    }
}
