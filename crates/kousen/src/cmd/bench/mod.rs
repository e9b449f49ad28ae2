//! `kousen bench ...`: speed measured side by side in one run, with the machine and adapter.

mod density;
mod host;
mod occupancy;
mod photons;
mod rng;
mod traversal;

use crate::cli::BenchCommand;

pub fn run(command: &BenchCommand) -> anyhow::Result<()> {
    match command {
        BenchCommand::Traversal(args) => traversal::run(args),
        BenchCommand::Photons(args) => photons::run(args),
        BenchCommand::Rng(args) => rng::run(args),
        BenchCommand::Density(args) => density::run(args),
    }
}
