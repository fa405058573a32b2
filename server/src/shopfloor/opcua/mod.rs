//! The OPC UA server (`fivex serve --opcua HOST:PORT`, docs/shopfloor.md): async-opcua's server
//! on `opc.tcp://HOST:PORT/` with the Machine Tools companion specification (OPC 40501-1) on top
//! of Machinery, DI and IA. Every controller this process hosts is a `MachineToolType` object
//! under `Objects/Machines`, updated from the observer's rounds; its alarms are events; its
//! `Panel` methods run the operator panel as the REST API does.
//!
//! - `nodesets`: the four NodeSet2 files, imported at start;
//! - `manager`: the node manager holding them and fivex's namespace, and the method calls;
//! - `instance`: instances of the loaded types (their mandatory members, and the optional ones
//!   named);
//! - `machine`: one controller as a machine: its nodes and how its values map;
//! - `follow`: the rounds into the address space;
//! - `events`: an alarm as an event;
//! - `access`: anonymous and user-name sessions, the token for the methods;
//! - `pki`: the certificate store and its self-signed certificate.

mod access;
mod events;
mod follow;
mod instance;
mod machine;
mod manager;
mod nodesets;
mod pki;

use std::net::IpAddr;
use std::sync::Arc;

use opcua::crypto::SecurityPolicy;
use opcua::server::node_manager::memory::CoreNodeManager;
use opcua::server::{ServerBuilder, ServerEndpoint, ServerHandle, ANONYMOUS_USER_TOKEN_ID};
use opcua::types::{ApplicationDescription, ApplicationType, BuildInfo, DateTime, LocalizedText};
use tokio::net::TcpListener;
use tokio::sync::watch;
use tokio::task::JoinHandle;

use super::observe::Round;
use crate::http::AppState;

/// fivex's own namespace: its event type, and the machines' nodes and fivex's extensions.
pub const FIVEX: &str = "urn:fivex:opcua";

/// The server as an application (its certificate names it); not a namespace of nodes (the
/// diagnostics' node manager takes the application URI as its namespace).
const APPLICATION_URI: &str = "urn:fivex:server";

/// The endpoints' path: `opc.tcp://HOST:PORT/`.
const PATH: &str = "/";

pub struct Server {
    handle: ServerHandle,
    server: JoinHandle<Result<(), String>>,
    follower: JoinHandle<()>,
    pki: pki::Pki,
}

impl std::fmt::Debug for Server {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Server").field("pki", &self.pki).finish_non_exhaustive()
    }
}

impl Server {
    /// Listens on `addr` (`HOST:PORT`; port 0 picks a free one) and serves `state`'s
    /// controllers as `rounds` shows them.
    pub async fn start(addr: &str, rounds: watch::Receiver<Arc<Round>>, state: &AppState) -> Result<Server, String> {
        let listener = TcpListener::bind(addr).await.map_err(|e| format!("--opcua: cannot listen on {addr}: {e}"))?;
        let local = listener.local_addr().map_err(|e| format!("--opcua: cannot listen on {addr}: {e}"))?;
        // The endpoints name the host clients reach: a wildcard address is none, the machine's
        // name is.
        let host = match local.ip() {
            ip if ip.is_unspecified() => opcua::crypto::hostname().unwrap_or_else(|_| "localhost".to_string()),
            IpAddr::V6(ip) => format!("[{ip}]"),
            ip => ip.to_string(),
        };
        let url = format!("opc.tcp://{host}:{}{PATH}", local.port());
        let pki = pki::Pki::beside(state.db.sqlite_file().as_deref());
        let addresses = vec![host.trim_matches(['[', ']']).to_string(), local.ip().to_string()];
        let (dir, port, hosted, token) =
            (pki.dir.clone(), local.port(), state.host.clone(), state.token().map(str::to_string));
        let (started, started_rx) = watch::channel(false);
        // Key generation and the nodesets' import take seconds: not on the runtime's threads.
        let built = tokio::task::spawn_blocking(move || {
            pki::ensure_certificate(&dir, application(), addresses)?;
            let imports = nodesets::imports()?;
            builder(&host, port, &dir, token.as_deref())
                .with_node_manager(manager::builder(imports, hosted, started))
                .build()
                .map_err(|e| format!("--opcua: {e}"))
        })
        .await
        .map_err(|e| format!("--opcua: the server's start failed: {e}"))?;
        let (server, handle) = match built {
            Ok(built) => built,
            Err(e) => {
                pki.close();
                return Err(e);
            }
        };
        let managers = handle.node_managers();
        let (Some(manager), Some(core), Some(fivex)) = (
            managers.get_of_type::<manager::Manager>(),
            managers.get_of_type::<CoreNodeManager>(),
            handle.get_namespace_index(FIVEX),
        ) else {
            pki.close();
            return Err("--opcua: the server's node managers are missing".to_string());
        };
        let follower = match follow::Follower::new(handle.clone(), manager, core, fivex) {
            Ok(follower) => follower,
            Err(e) => {
                pki.close();
                return Err(e);
            }
        };
        let server = tokio::spawn(server.run_with(listener));
        let follower = tokio::spawn(follower.run(started_rx, rounds));
        tracing::info!(pki = %pki.dir.display(), token = state.token().is_some(), "OPC UA server at {url}");
        Ok(Server { handle, server, follower, pki })
    }

    /// Closes the sessions and stops listening.
    pub async fn stop(self) {
        self.follower.abort();
        self.handle.cancel();
        match self.server.await {
            Ok(Err(e)) => tracing::warn!("OPC UA server: {e}"),
            Err(e) => tracing::warn!("OPC UA server: {e}"),
            Ok(Ok(())) => {}
        }
        self.pki.close();
    }
}

fn application() -> ApplicationDescription {
    ApplicationDescription {
        application_uri: APPLICATION_URI.into(),
        product_uri: "urn:fivex".into(),
        application_name: LocalizedText::new("", "fivex"),
        application_type: ApplicationType::Server,
        ..Default::default()
    }
}

/// The server's configuration: its endpoints (security None, and signed and encrypted with
/// Basic256Sha256 or Aes256_Sha256_RsaPss), its certificate store, who may do what (`token`:
/// the service's).
fn builder(host: &str, port: u16, pki: &std::path::Path, token: Option<&str>) -> ServerBuilder {
    let mut builder = configured(host, port, pki, token);
    // One subscription may watch every value of every controller (1,000 controllers of ~15
    // values); async-opcua's default is 1,000 items.
    builder.limits_mut().subscriptions.max_monitored_items_per_sub = MONITORED_ITEMS_PER_SUBSCRIPTION;
    // A client may as well watch each machine by a subscription of its own (a dashboard of a
    // fleet); async-opcua's default is 10 per session.
    builder.limits_mut().subscriptions.max_subscriptions_per_session = SUBSCRIPTIONS_PER_SESSION;
    builder
}

/// How many subscriptions one session may hold.
const SUBSCRIPTIONS_PER_SESSION: usize = 1_000;

/// How many values one subscription may monitor.
const MONITORED_ITEMS_PER_SUBSCRIPTION: usize = 100_000;

fn configured(host: &str, port: u16, pki: &std::path::Path, token: Option<&str>) -> ServerBuilder {
    let anonymous = [ANONYMOUS_USER_TOKEN_ID.to_string()];
    let none = ServerEndpoint {
        // A user-name token's password is encrypted all the same (`access`).
        password_security_policy: Some(SecurityPolicy::Basic256Sha256.to_str().to_string()),
        ..ServerEndpoint::new_none(PATH, &anonymous)
    };
    ServerBuilder::new()
        .application_name("fivex")
        .application_uri(APPLICATION_URI)
        .product_uri("urn:fivex")
        .build_info(BuildInfo {
            product_uri: "urn:fivex".into(),
            manufacturer_name: "fivex".into(),
            product_name: "fivex".into(),
            software_version: env!("CARGO_PKG_VERSION").into(),
            build_number: env!("CARGO_PKG_VERSION").into(),
            build_date: DateTime::now(),
        })
        .host(host)
        .port(port)
        .pki_dir(pki)
        .create_sample_keypair(false)
        // Any client certificate is accepted (there is no one to move it to `trusted/`): the
        // channel is encrypted, and who may act is the user-name token's business.
        .trust_client_certs(true)
        .discovery_urls(vec![PATH.to_string()])
        .add_endpoint("none", none)
        .add_endpoint("basic256sha256_sign_encrypt", ServerEndpoint::new_basic256sha256_sign_encrypt(PATH, &anonymous))
        .add_endpoint(
            "aes256_sha256_rsapss_sign_encrypt",
            ServerEndpoint::new_aes256_sha256_rsapss_sign_encrypt(PATH, &anonymous),
        )
        .with_authenticator(Arc::new(access::Access::new(token)))
}
