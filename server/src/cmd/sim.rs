//! `trackd sim` (not built yet).

/// Flags of `trackd sim`.
#[derive(clap::Args)]
pub struct Args {}

/// Runs `trackd sim`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("trackd sim: not built yet")
}
