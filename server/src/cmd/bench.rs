//! `trackd bench` (not built yet).

/// Flags of `trackd bench`.
#[derive(clap::Args)]
pub struct Args {}

/// Runs `trackd bench`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("trackd bench: not built yet")
}
