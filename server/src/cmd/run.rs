//! `trackd run` (not built yet).

/// Flags of `trackd run`.
#[derive(clap::Args)]
pub struct Args {}

/// Runs `trackd run`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("trackd run: not built yet")
}
