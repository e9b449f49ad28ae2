//! One module per subcommand.

mod bench;
pub mod info;
mod render;

use crate::cli::Command;

pub fn run(command: Command) -> anyhow::Result<()> {
    match command {
        Command::Info(args) => info::run(&args),
        Command::Render(args) => render::run(&args),
        Command::Bench(args) => bench::run(&args.command),
    }
}
