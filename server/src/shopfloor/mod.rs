//! The shop-floor interfaces an integrator's own clients speak: an MTConnect agent
//! (`mtconnect`, read-only monitoring over HTTP) and an OPC UA server with the Machine Tools
//! companion specification (`opcua`). Both are off by default (`fivex serve --mtconnect ADDR`,
//! `--opcua ADDR`), listen on their own addresses, and show the controllers this process hosts
//! as one [`observe::Observer`] reads them (docs/shopfloor.md).

pub mod mtconnect;
pub mod observe;
pub mod opcua;

use std::time::Duration;

use crate::http::AppState;

/// What `fivex serve` switches on.
#[derive(Debug, Clone)]
pub struct Options {
    /// `--mtconnect ADDR`: the agent's listening address.
    pub mtconnect: Option<String>,
    /// `--mtconnect-buffer N`: observations the agent keeps for `/sample`.
    pub mtconnect_buffer: usize,
    /// `--opcua ADDR`: the OPC UA server's `host:port` (`opc.tcp://host:port/`).
    pub opcua: Option<String>,
    /// `--shopfloor-period-ms`: how often every controller is read.
    pub period: Duration,
}

impl Default for Options {
    fn default() -> Options {
        Options {
            mtconnect: None,
            mtconnect_buffer: mtconnect::DEFAULT_BUFFER,
            opcua: None,
            period: observe::DEFAULT_PERIOD,
        }
    }
}

impl Options {
    pub fn any(&self) -> bool {
        self.mtconnect.is_some() || self.opcua.is_some()
    }
}

/// The interfaces running; they stop when this is dropped (or [`Running::stop`]).
#[derive(Debug)]
pub struct Running {
    mtconnect: Option<mtconnect::Agent>,
    opcua: Option<opcua::Server>,
    /// Dropped last: the interfaces read its rounds.
    _observer: observe::Observer,
}

impl Running {
    /// Stops the interfaces (closing their connections) and the observer.
    pub async fn stop(mut self) {
        if let Some(agent) = self.mtconnect.take() {
            agent.stop().await;
        }
        if let Some(server) = self.opcua.take() {
            server.stop().await;
        }
    }
}

/// Starts what `options` switches on for `state`'s controllers (nothing: `None`); an address
/// that cannot be bound is an error for the user.
pub async fn start(options: &Options, state: &AppState) -> Result<Option<Running>, String> {
    if !options.any() {
        return Ok(None);
    }
    let observer = observe::Observer::start(state.host.clone(), options.period);
    let mtconnect = match &options.mtconnect {
        Some(addr) => Some(mtconnect::Agent::start(addr, options.mtconnect_buffer, observer.rounds(), state).await?),
        None => None,
    };
    let opcua = match &options.opcua {
        Some(addr) => Some(opcua::Server::start(addr, observer.rounds(), state).await?),
        None => None,
    };
    Ok(Some(Running { mtconnect, opcua, _observer: observer }))
}
