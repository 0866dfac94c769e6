//! `trackctl`: the command-line client of a trackd service.

mod table;
mod upload;

use std::path::PathBuf;

use clap::{Parser, Subcommand};
use trackd_client::Client;

/// Talk to a trackd vehicle service.
#[derive(Parser)]
#[command(name = "trackctl", version, about)]
struct Cli {
    /// The service's base URL.
    #[arg(
        long,
        env = "TRACKD_URL",
        default_value = "http://127.0.0.1:8080",
        global = true
    )]
    url: String,
    /// Bearer token for writes.
    #[arg(long, env = "TRACKD_TOKEN", global = true)]
    token: Option<String>,
    /// Print JSON instead of tables.
    #[arg(long, global = true)]
    json: bool,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Upload a scan file (.bin, .pcd), a folder of scans, or a KITTI raw drive with its OXTS.
    Upload {
        /// File or folder.
        path: PathBuf,
        /// Scans per second (0: as fast as the service takes them).
        #[arg(long, default_value_t = 10.0)]
        rate: f64,
        /// Queue only (202) instead of waiting for each result.
        #[arg(long = "async")]
        queue_only: bool,
    },
    /// The tracks after the latest frame.
    Tracks,
    /// One track and its history.
    Track {
        /// Track id.
        id: u64,
    },
    /// The vehicles the service knows of.
    Fleet,
    /// The fused world view of the fleet.
    Objects,
    /// A live table of the tracks, from the SSE stream (Ctrl-C to stop).
    Watch,
    /// Download the occupancy map.
    Occupancy {
        /// Where to write the OctoMap `.bt` file.
        #[arg(long, default_value = "map.bt")]
        out: PathBuf,
    },
}

fn print_json<T: serde::Serialize>(value: &T) -> anyhow::Result<()> {
    println!("{}", serde_json::to_string_pretty(value)?);
    Ok(())
}

async fn run(cli: Cli) -> anyhow::Result<()> {
    let client = Client::new(&cli.url, cli.token.clone());
    match cli.command {
        Command::Upload {
            path,
            rate,
            queue_only,
        } => upload::run(&client, &path, rate, queue_only, cli.json).await,
        Command::Tracks => {
            let t = client.tracks().await?;
            if cli.json {
                print_json(&t)
            } else {
                table::tracks(&t);
                Ok(())
            }
        }
        Command::Track { id } => {
            let t = client.track(id).await?;
            if cli.json {
                print_json(&t)
            } else {
                table::track(&t);
                Ok(())
            }
        }
        Command::Fleet => {
            let f = client.fleet().await?;
            if cli.json {
                print_json(&f)
            } else {
                table::fleet(&f);
                Ok(())
            }
        }
        Command::Objects => {
            let o = client.objects().await?;
            if cli.json {
                print_json(&o)
            } else {
                table::objects(&o);
                Ok(())
            }
        }
        Command::Watch => {
            let json = cli.json;
            client
                .watch(|t| {
                    if json {
                        if let Ok(line) = serde_json::to_string(&t) {
                            println!("{line}");
                        }
                    } else {
                        // Clear the screen and redraw.
                        print!("\x1b[2J\x1b[H");
                        table::tracks(&t);
                    }
                    true
                })
                .await?;
            Ok(())
        }
        Command::Occupancy { out } => {
            let bytes = client.occupancy_bt().await?;
            std::fs::write(&out, &bytes)?;
            eprintln!("wrote {} ({} bytes)", out.display(), bytes.len());
            Ok(())
        }
    }
}

fn main() -> anyhow::Result<()> {
    let cli = Cli::parse();
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()?;
    runtime.block_on(run(cli))
}
