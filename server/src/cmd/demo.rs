//! `trackd demo` (not built yet).

/// Flags of `trackd demo`.
#[derive(clap::Args)]
pub struct Args {}

/// Runs `trackd demo`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("trackd demo: not built yet")
}
