//! One module per subcommand.

mod bench;
mod diff;
pub mod frames;
pub mod info;
pub mod intermediates;
mod path_render;
pub mod render;

use crate::cli::Command;

/// A render stopped by Ctrl-C after writing what it had: `main` exits with 130, the shell's
/// code for SIGINT, so scripts can tell it from a finished render.
#[derive(Debug)]
pub struct Interrupted {
    pub passes: u32,
}

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "interrupted after {} passes; the image so far was written",
            self.passes
        )
    }
}

impl std::error::Error for Interrupted {}

pub fn run(command: Command) -> anyhow::Result<()> {
    match command {
        Command::Info(args) => info::run(&args),
        Command::Render(args) => render::run(&args),
        Command::Bench(args) => bench::run(&args.command),
        Command::Diff(args) => diff::run(&args),
        Command::View(args) => crate::view::run(&args),
    }
}
