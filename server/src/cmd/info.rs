//! `trackd info` (not built yet).

/// Flags of `trackd info`.
#[derive(clap::Args)]
pub struct Args {}

/// Runs `trackd info`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("trackd info: not built yet")
}
