//! `trackd cluster` (not built yet).

/// Flags of `trackd cluster`.
#[derive(clap::Args)]
pub struct Args {}

/// Runs `trackd cluster`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("trackd cluster: not built yet")
}
