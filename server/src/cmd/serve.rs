//! `trackd serve`: the vehicle service (REST API, perception worker, Zenoh fleet link).

use trackd_service::settings::{Settings, SettingsFlags};

/// Flags of `trackd serve` (each also a `TRACKD_*` variable; flags win over variables, both
/// over the file).
#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    settings: SettingsFlags,
}

/// Runs `trackd serve` until Ctrl-C or SIGTERM.
pub fn run(args: Args) -> anyhow::Result<()> {
    let settings = Settings::load(&args.settings)?;
    let runtime = tokio::runtime::Runtime::new()?;
    runtime.block_on(async move {
        let service = trackd_service::service::start(settings).await?;
        eprintln!(
            "trackd serve: vehicle {} on {} (Ctrl-C to stop)",
            service.vehicle(),
            service.url()
        );
        service.run_until(shutdown_signal()).await
    })
}

/// Resolves on Ctrl-C, or SIGTERM (as `docker stop` sends).
pub async fn shutdown_signal() {
    let ctrl_c = async {
        let _ = tokio::signal::ctrl_c().await;
    };
    #[cfg(unix)]
    let term = async {
        match tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate()) {
            Ok(mut s) => {
                s.recv().await;
            }
            Err(_) => std::future::pending::<()>().await,
        }
    };
    #[cfg(not(unix))]
    let term = std::future::pending::<()>();
    tokio::select! {
        _ = ctrl_c => {},
        _ = term => {},
    }
}
