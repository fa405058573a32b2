//! The MTConnect agent (being built).

use std::sync::Arc;

use tokio::sync::watch;

use super::observe::Round;
use crate::http::AppState;

/// Observations kept for `/sample` by default (the reference agent's 2^17).
pub const DEFAULT_BUFFER: usize = 131_072;

#[derive(Debug)]
pub struct Agent;

impl Agent {
    pub async fn start(
        _addr: &str,
        _buffer: usize,
        _rounds: watch::Receiver<Arc<Round>>,
        _state: &AppState,
    ) -> Result<Agent, String> {
        Err("--mtconnect: the MTConnect agent is not built yet".to_string())
    }

    pub async fn stop(self) {}
}
