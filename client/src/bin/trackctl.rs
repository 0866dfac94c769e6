//! `trackctl`: the command-line client of a trackd service.

fn main() -> anyhow::Result<()> {
    anyhow::bail!("trackctl: not built yet")
}
