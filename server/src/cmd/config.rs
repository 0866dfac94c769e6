//! `trackd config` (not built yet).

/// Flags of `trackd config`.
#[derive(clap::Args)]
pub struct Args {}

/// Runs `trackd config`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("trackd config: not built yet")
}
