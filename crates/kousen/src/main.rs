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
    quiet_mesa_device_select_without_session();
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

/// Mesa's Vulkan device-select layer, loaded implicitly with Mesa's drivers, asks Wayland for
/// the session's display to order the devices, and where there is no user session (a server, a
/// container, CI: no `XDG_RUNTIME_DIR`) libwayland prints two "error:" lines on every run that
/// are no error of kousen's. kousen orders the adapters itself (`--adapter` picks one), so
/// without a session the layer is turned off, unless the user set either of its variables.
fn quiet_mesa_device_select_without_session() {
    let set = |name| std::env::var_os(name).is_some();
    if set("XDG_RUNTIME_DIR") || set("NODEVICE_SELECT") || set("MESA_VK_DEVICE_SELECT") {
        return;
    }
    // SAFETY: called first thing in main, before any thread exists that could read the
    // environment at the same time.
    unsafe {
        std::env::set_var("NODEVICE_SELECT", "1");
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
