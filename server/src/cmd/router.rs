//! `trackd router`: a Zenoh router (zenoh's own router mode) for fleets that outgrow
//! peer-to-peer: services connect to it with `--connect tcp/<router>:7447`.

use trackd_service::settings::zenoh_config;

/// Flags of `trackd router`.
#[derive(clap::Args)]
pub struct Args {
    /// Endpoint to listen on (repeatable).
    #[arg(
        long,
        env = "TRACKD_ROUTER_LISTEN",
        value_delimiter = ',',
        default_value = "tcp/127.0.0.1:7447"
    )]
    listen: Vec<String>,
    /// Other routers to connect to (repeatable).
    #[arg(long, env = "TRACKD_ROUTER_CONNECT", value_delimiter = ',')]
    connect: Vec<String>,
}

/// Runs the router until Ctrl-C or SIGTERM.
pub fn run(args: Args) -> anyhow::Result<()> {
    let runtime = tokio::runtime::Runtime::new()?;
    runtime.block_on(async move {
        let config = zenoh_config("router", &args.listen, &args.connect, false)?;
        let session = zenoh::open(config)
            .await
            .map_err(|e| anyhow::anyhow!("starting the Zenoh router: {e}"))?;
        eprintln!(
            "trackd router: listening on {} (Ctrl-C to stop)",
            args.listen.join(", ")
        );
        super::serve::shutdown_signal().await;
        session
            .close()
            .await
            .map_err(|e| anyhow::anyhow!("closing the router: {e}"))
    })
}
