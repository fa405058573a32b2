//! The OPC UA server (being built: `--opcua` refuses to start until it is).

use std::sync::Arc;

use tokio::sync::watch;

use super::observe::Round;
use crate::http::AppState;

#[derive(Debug)]
pub struct Server;

impl Server {
    pub async fn start(_addr: &str, _rounds: watch::Receiver<Arc<Round>>, _state: &AppState) -> Result<Server, String> {
        Err("--opcua: the OPC UA server is not built yet".to_string())
    }

    pub async fn stop(self) {}
}
