//! One module per subcommand.

mod bench;
mod diff;
pub mod info;
mod path_render;
pub mod render;

use crate::cli::Command;

pub fn run(command: Command) -> anyhow::Result<()> {
    match command {
        Command::Info(args) => info::run(&args),
        Command::Render(args) => render::run(&args),
        Command::Bench(args) => bench::run(&args.command),
        Command::Diff(args) => diff::run(&args),
        Command::View(args) => crate::view::run(&args),
    }
}
