//! `kousen`: stochastic progressive photon mapping on the GPU. See `kousen --help`.

mod checkpoint_file;
mod cli;
mod cmd;
mod image_io;
mod image_metrics;
mod output_file;
mod path_trace;
mod progress;
mod view;

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let cli = cli::Cli::parse();
    let level = match cli.verbose {
        0 => "warn",
        1 => "info",
        _ => "debug",
    };
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or(level))
        .format_timestamp(None)
        .init();
    match cmd::run(cli.command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) if error.is::<cmd::Interrupted>() => {
            eprintln!("kousen: {error}");
            ExitCode::from(130)
        }
        Err(error) => {
            // One line: the whole chain of causes, joined.
            eprintln!("kousen: error: {error:#}");
            ExitCode::FAILURE
        }
    }
}
