//! Command-line flags (clap) and their dispatch to the library.

use clap::Parser;
use std::process::ExitCode;

/// articula: a terminal workbench for the dynamics of articulated avatars.
#[derive(Debug, Parser)]
#[command(name = "articula", version, about)]
pub struct Cli {}

pub fn run(_cli: Cli) -> anyhow::Result<ExitCode> {
    Ok(ExitCode::SUCCESS)
}
