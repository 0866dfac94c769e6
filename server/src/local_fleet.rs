//! A fleet on this machine's loopback: a Zenoh router and services connected to it, on free
//! ports. Used by `trackd demo`, the fleet benchmark and the integration tests.

use std::net::{Ipv4Addr, SocketAddr, TcpListener};

use crate::{
    service::{self, RunningService},
    settings::{Settings, zenoh_config},
};

/// A free TCP port on 127.0.0.1 (bound and released: another process could take it in
/// between, which loopback tests accept).
pub fn free_port() -> std::io::Result<u16> {
    Ok(TcpListener::bind((Ipv4Addr::LOCALHOST, 0))?
        .local_addr()?
        .port())
}

/// `tcp/127.0.0.1:<port>`.
pub fn loopback_endpoint(port: u16) -> String {
    format!("tcp/127.0.0.1:{port}")
}

/// A Zenoh router listening on `tcp/127.0.0.1:<port>` (multicast scouting off).
pub async fn start_router(port: u16) -> anyhow::Result<zenoh::Session> {
    let config = zenoh_config("router", &[loopback_endpoint(port)], &[], false)?;
    zenoh::open(config)
        .await
        .map_err(|e| anyhow::anyhow!("starting a Zenoh router on port {port}: {e}"))
}

/// Settings of a loopback service for `vehicle`: REST on a free port, a Zenoh peer listening
/// on a free port and connected to the router at `router_port`.
pub fn loopback_settings(
    vehicle: &str,
    router_port: u16,
    base: &Settings,
) -> anyhow::Result<Settings> {
    let mut settings = base.clone();
    settings.vehicle.id = vehicle.to_string();
    settings.http.listen = SocketAddr::from((Ipv4Addr::LOCALHOST, 0));
    settings.zenoh.listen = vec![loopback_endpoint(free_port()?)];
    settings.zenoh.connect = vec![loopback_endpoint(router_port)];
    settings.zenoh.multicast_scouting = false;
    Ok(settings)
}

/// A router and services on loopback.
pub struct LocalFleet {
    /// The router's port.
    pub router_port: u16,
    router: zenoh::Session,
    /// The services, in the order of the vehicle ids given.
    pub services: Vec<RunningService>,
}

impl LocalFleet {
    /// Starts a router and one service per vehicle id, each from `base` settings.
    pub async fn start(vehicles: &[String], base: &Settings) -> anyhow::Result<Self> {
        let router_port = free_port()?;
        let router = start_router(router_port).await?;
        let mut services = Vec::with_capacity(vehicles.len());
        for v in vehicles {
            services.push(service::start(loopback_settings(v, router_port, base)?).await?);
        }
        Ok(Self {
            router_port,
            router,
            services,
        })
    }

    /// Stops every service, then the router.
    pub async fn stop(self) -> anyhow::Result<()> {
        for s in self.services {
            s.stop().await?;
        }
        self.router
            .close()
            .await
            .map_err(|e| anyhow::anyhow!("closing the router: {e}"))
    }
}
