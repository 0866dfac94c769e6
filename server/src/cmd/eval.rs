//! `trackd eval` (not built yet).

/// Flags of `trackd eval`.
#[derive(clap::Args)]
pub struct Args {}

/// Runs `trackd eval`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("trackd eval: not built yet")
}
