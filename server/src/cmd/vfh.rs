//! `trackd vfh` (not built yet).

/// Flags of `trackd vfh`.
#[derive(clap::Args)]
pub struct Args {}

/// Runs `trackd vfh`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("trackd vfh: not built yet")
}
