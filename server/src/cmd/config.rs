//! `trackd config`: print the commented default file, or check a file with its overrides.

use trackd_service::settings::{Settings, SettingsFlags};

/// Flags of `trackd config`.
#[derive(clap::Args)]
pub struct Args {
    /// Print the whole default `trackd.toml`, with comments.
    #[arg(long)]
    print_default: bool,
    /// Print the settings in force after the file, variables and flags (as TOML).
    #[arg(long)]
    print: bool,
    #[command(flatten)]
    settings: SettingsFlags,
}

/// Runs `trackd config`: with no option, checks the settings and says so.
pub fn run(args: Args) -> anyhow::Result<()> {
    if args.print_default {
        print!("{}", Settings::default_file());
        return Ok(());
    }
    let settings = Settings::load(&args.settings)?;
    if args.print {
        print!("{}", toml::to_string(&settings)?);
    } else {
        println!(
            "settings valid: vehicle {}, http {}, zenoh {} listen {:?} connect {:?}",
            settings.vehicle.id,
            settings.http.listen,
            settings.zenoh.mode.as_str(),
            settings.zenoh.listen,
            settings.zenoh.connect
        );
    }
    Ok(())
}
