//! `kousen bench ...`: speed measured side by side in one run, with the machine and adapter.

mod host;
mod traversal;

use crate::cli::BenchCommand;

pub fn run(command: &BenchCommand) -> anyhow::Result<()> {
    match command {
        BenchCommand::Traversal(args) => traversal::run(args),
    }
}
