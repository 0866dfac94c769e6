//! `trackd router` (not built yet).

/// Flags of `trackd router`.
#[derive(clap::Args)]
pub struct Args {}

/// Runs `trackd router`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("trackd router: not built yet")
}
