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
    end_quietly_on_closed_pipes();
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

/// Output piped into a reader that stops early (`kousen info X | head -1`) ends kousen the way
/// it ends any Unix tool, by SIGPIPE, instead of a panic in `println!`. Rust ignores SIGPIPE by
/// default, turning the closed pipe into an error every print would have to handle.
fn end_quietly_on_closed_pipes() {
    #[cfg(unix)]
    // SAFETY: called first thing in main, before any thread exists; SIG_DFL is a valid handler.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}
