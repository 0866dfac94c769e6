//! `trackd serve` (not built yet).

/// Flags of `trackd serve`.
#[derive(clap::Args)]
pub struct Args {}

/// Runs `trackd serve`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("trackd serve: not built yet")
}
