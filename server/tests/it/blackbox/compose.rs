//! The cluster of `docker-compose.yml` on loopback (issue 23, item 4; docs/cluster.md "With
//! Docker Compose"). Docker cannot run on these machines, so this runs what the compose file
//! runs, from the compose file itself: a real PostgreSQL and a real `nats-server -js`, the three
//! nodes with each service's `command` and `environment` (the service names `postgres` and
//! `nats` replaced by the loopback servers, `0.0.0.0:8080` by a free loopback port), and Debian's
//! nginx with `deploy/nginx.conf` (its `fivex-N:8080` upstreams replaced by the nodes'
//! addresses). Through the proxy's one address a client creates controllers, runs programs,
//! writes variables and watches a stream; a node killed with SIGKILL, the proxy keeps answering
//! (JSON, never the proxy's own error page), every controller comes back with every
//! acknowledged write, and a stream opened again gets its snapshot.

use std::net::TcpStream;
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use bytes::Bytes;
use http_body_util::{BodyExt, Full};
use hyper::{Method, Request, StatusCode};
use hyper_util::client::legacy::{connect::HttpConnector, Client};
use hyper_util::rt::TokioExecutor;
use serde_json::{json, Value};

use super::nats::NatsServer;
use super::nodes::{hosted, next_json, Socket};
use super::postgres::Postgres;
use super::served::{Reply, Served};

const C: &str = "/api/v1/controllers";
const NODES: [&str; 3] = ["fivex-1", "fivex-2", "fivex-3"];

fn workspace_file(relative: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..").join(relative)
}

/// `docker-compose.yml` as JSON, its merge keys (`<<: *node`) applied.
fn compose() -> Value {
    let text = std::fs::read_to_string(workspace_file("docker-compose.yml")).unwrap();
    let mut yaml: serde_norway::Value = serde_norway::from_str(&text).expect("docker-compose.yml is YAML");
    yaml.apply_merge().expect("merge keys");
    serde_json::to_value(yaml).unwrap()
}

/// Node `name` started as the compose file starts it, on the loopback servers.
fn start_node(compose: &Value, name: &str, pg: &Postgres, nats: &NatsServer) -> Served {
    let service = &compose["services"][name];
    let args: Vec<&str> = service["command"].as_array().unwrap().iter().map(|v| v.as_str().unwrap()).collect();
    let mut envs: Vec<(String, String)> = Vec::new();
    for (key, value) in service["environment"].as_object().expect("environment") {
        let value = value.as_str().unwrap_or_else(|| panic!("{name}: {key} is not a string"));
        let value = match key.as_str() {
            // The compose network's service names, here the loopback servers of this test.
            "FIVEX_DB" if value.contains("@postgres:5432/") => pg.url(),
            "FIVEX_NATS" if value == "nats://nats:4222" => nats.url(),
            "FIVEX_ADDR" if value == "0.0.0.0:8080" => "127.0.0.1:0".to_owned(),
            "FIVEX_DB" | "FIVEX_NATS" | "FIVEX_ADDR" => panic!("{name}: {key}={value} names no service of the file"),
            _ => value.to_owned(),
        };
        envs.push((key.clone(), value));
    }
    let envs: Vec<(&str, &str)> = envs.iter().map(|(k, v)| (k.as_str(), v.as_str())).collect();
    Served::start_as_given(&args, &envs)
}

/// Debian's nginx with the repository's `deploy/nginx.conf`, killed when dropped.
struct Proxy {
    child: Child,
    addr: String,
    dir: tempfile::TempDir,
    client: Client<HttpConnector, Full<Bytes>>,
}

impl Proxy {
    /// Starts it in front of `nodes` (in the order of [`NODES`]) on a free loopback port.
    fn start(nodes: &[&Served]) -> Proxy {
        let bin = ["/usr/sbin/nginx", "/usr/bin/nginx"]
            .into_iter()
            .map(PathBuf::from)
            .find(|p| p.exists())
            .unwrap_or_else(|| panic!("nginx not found: install Debian's `nginx` (scripts/test.sh does)"));
        let mut conf = std::fs::read_to_string(workspace_file("deploy/nginx.conf")).unwrap();
        for (name, node) in NODES.iter().zip(nodes) {
            let upstream = format!("server {name}:8080");
            assert!(conf.contains(&upstream), "deploy/nginx.conf has no `{upstream}`");
            conf = conf.replace(&upstream, &format!("server {}", node.addr));
        }
        let port = std::net::TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port();
        assert!(conf.contains("listen 8080;"), "deploy/nginx.conf does not listen on 8080");
        conf = conf.replace("listen 8080;", &format!("listen 127.0.0.1:{port};"));
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("nginx.conf");
        std::fs::write(&path, conf).unwrap();
        let child = Command::new(&bin)
            .arg("-c")
            .arg(&path)
            .arg("-p")
            .arg(dir.path())
            .arg("-g")
            .arg(format!("daemon off; pid {};", dir.path().join("nginx.pid").display()))
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap_or_else(|e| panic!("cannot start {}: {e}", bin.display()));
        let mut proxy = Proxy {
            child,
            addr: format!("127.0.0.1:{port}"),
            dir,
            client: Client::builder(TokioExecutor::new()).build_http(),
        };
        let deadline = Instant::now() + Duration::from_secs(30);
        while TcpStream::connect(("127.0.0.1", port)).is_err() {
            if let Ok(Some(status)) = proxy.child.try_wait() {
                panic!("nginx exited at start: {status} (config in {})", proxy.dir.path().display());
            }
            assert!(Instant::now() < deadline, "nginx did not listen on {port} within 30 s");
            std::thread::sleep(Duration::from_millis(20));
        }
        proxy
    }

    async fn request(&self, method: Method, path: &str, content_type: &str, body: impl Into<Bytes>) -> Reply {
        let request = Request::builder()
            .method(method)
            .uri(format!("http://{}{path}", self.addr))
            .header("content-type", content_type)
            .body(Full::new(body.into()))
            .unwrap();
        let response = self.client.request(request).await.expect("request sent");
        let (status, headers) = (response.status(), response.headers().clone());
        let body = response.into_body().collect().await.expect("response body").to_bytes();
        Reply { status, headers, body }
    }

    async fn get(&self, path: &str) -> Reply {
        self.request(Method::GET, path, "application/json", Bytes::new()).await
    }

    async fn send_json(&self, method: Method, path: &str, body: &Value) -> Reply {
        self.request(method, path, "application/json", body.to_string()).await
    }
}

impl Drop for Proxy {
    /// SIGTERM, so that the master stops its workers (killed, it would leave them serving).
    fn drop(&mut self) {
        let _ = Command::new("kill").args(["-TERM", &self.child.id().to_string()]).status();
        let deadline = Instant::now() + Duration::from_secs(10);
        while matches!(self.child.try_wait(), Ok(None)) && Instant::now() < deadline {
            std::thread::sleep(Duration::from_millis(20));
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Every node's log, for a failure's message.
fn logs(nodes: &[Served]) -> String {
    nodes.iter().zip(NODES).map(|(n, name)| format!("--- {name}\n{}\n", n.log())).collect()
}

/// A stream through the proxy: open, its snapshot names controller `id`.
async fn stream_through(proxy: &Proxy, id: &str) -> Socket {
    let (mut ws, _) = tokio_tungstenite::connect_async(format!("ws://{}{C}/{id}/stream?rate=20", proxy.addr))
        .await
        .expect("a websocket through the proxy");
    let snapshot = next_json(&mut ws).await;
    assert_eq!(snapshot["type"], "snapshot", "{snapshot}");
    assert_eq!(snapshot["controller"]["id"], json!(id));
    ws
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_compose_cluster_behind_its_proxy_survives_a_killed_node() {
    let compose = compose();
    let (pg, nats) = (Postgres::start(), NatsServer::start());
    let mut nodes: Vec<Served> = NODES.iter().map(|name| start_node(&compose, name, &pg, &nats)).collect();
    let proxy = Proxy::start(&nodes.iter().collect::<Vec<_>>());

    // As a client of the one address sees it: one node has seen all three join (the others
    // may not have yet: they forward to a member that joined since their last beat all the same).
    let deadline = Instant::now() + Duration::from_secs(30);
    loop {
        let members = proxy.get("/readyz").await.json()["cluster"]["members"].clone();
        if members == json!(NODES) {
            break;
        }
        assert!(Instant::now() < deadline, "the nodes did not all join within 30 s: {members}");
        tokio::time::sleep(Duration::from_millis(200)).await;
    }

    // Created through the one address: the proxy spreads them over the nodes.
    let mut ids = Vec::new();
    for i in 0..6 {
        let reply = proxy.send_json(Method::POST, C, &json!({"name": format!("c{i}"), "preset": "table-ac"})).await;
        assert_eq!(reply.status, StatusCode::CREATED, "{:?}", reply.body);
        ids.push(reply.json()["id"].as_str().unwrap().to_owned());
    }
    let mut sorted = ids.clone();
    sorted.sort();
    let mut placed = Vec::new();
    for node in &nodes {
        placed.push(hosted(node).await);
    }
    let mut all: Vec<String> = placed.concat();
    all.sort();
    assert_eq!(all, sorted, "every controller hosted by exactly one node: {placed:?}");
    assert!(placed.iter().filter(|p| !p.is_empty()).count() >= 2, "the proxy used one node only: {placed:?}");

    // Programs running on every controller, variables written, a stream watched: all through
    // the proxy, whichever node answers.
    let program = "O0001\nWHILE[1EQ1]DO1\nG91 G01 X10. F3000\nX-10.\nEND1\nM30\n";
    let mut acknowledged = Vec::new();
    for (k, id) in ids.iter().enumerate() {
        let stored = proxy.request(Method::PUT, &format!("{C}/{id}/programs/1"), "text/plain", program).await;
        assert_eq!(stored.status, StatusCode::CREATED, "{:?}; logs:\n{}", stored.body, logs(&nodes));
        let started = proxy.send_json(Method::POST, &format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
        assert!(started.status.is_success(), "{:?}", started.body);
        let value = 1.25 * k as f64;
        let put = proxy.send_json(Method::PUT, &format!("{C}/{id}/variables/500"), &json!({"value": value})).await;
        assert_eq!(put.status, StatusCode::OK, "{:?}", put.body);
        acknowledged.push((id.clone(), value));
    }
    let victim = ids[0].clone();
    let mut ws = stream_through(&proxy, &victim).await;
    let mut positions = 0;
    while positions < 3 {
        if next_json(&mut ws).await["type"] == "position" {
            positions += 1;
        }
    }
    drop(ws);

    // The node hosting the watched controller killed: no shutdown of any kind.
    let mut owner = None;
    for (i, node) in nodes.iter().enumerate() {
        if hosted(node).await.contains(&victim) {
            owner = Some(i);
        }
    }
    let owner = owner.expect("the watched controller is hosted");
    nodes[owner].kill();

    // The one address keeps answering: a JSON answer every time (503 with Retry-After while a
    // controller is between nodes), never the proxy's own error page, until every controller
    // is back.
    let deadline = Instant::now() + Duration::from_secs(40);
    loop {
        let list = proxy.get(C).await;
        assert!(
            list.status == StatusCode::OK || list.status == StatusCode::SERVICE_UNAVAILABLE,
            "{}: {:?}",
            list.status,
            list.body
        );
        let listed: Vec<String> = if list.status == StatusCode::OK {
            list.json().as_array().unwrap().iter().map(|c| c["id"].as_str().unwrap().to_owned()).collect()
        } else {
            assert!(list.json()["error"].is_string(), "{:?}", list.body);
            Vec::new()
        };
        let mut listed = listed;
        listed.sort();
        if listed == sorted {
            break;
        }
        assert!(Instant::now() < deadline, "not every controller back within 40 s: {listed:?}");
        tokio::time::sleep(Duration::from_millis(200)).await;
    }
    let members = proxy.get("/readyz").await.json()["cluster"]["members"].clone();
    assert_eq!(members.as_array().unwrap().len(), 2, "{members}");

    // Every acknowledged write reads back through the one address; the killed node's
    // controllers are in reset state.
    for (id, value) in &acknowledged {
        let read = proxy.get(&format!("{C}/{id}/variables/500")).await;
        assert_eq!(read.status, StatusCode::OK, "{id}: {:?}", read.body);
        assert_eq!(read.json()["value"], json!(value), "#500 of {id}; logs:\n{}", logs(&nodes));
    }
    let after = proxy.get(&format!("{C}/{victim}")).await;
    assert_eq!(after.status, StatusCode::OK, "{:?}", after.body);
    assert_ne!(after.json()["run_state"], json!("running"), "{}", after.json());
    let ws = stream_through(&proxy, &victim).await;
    drop(ws);
    // And it runs its program again when asked.
    let started = proxy.send_json(Method::POST, &format!("{C}/{victim}/cycle-start"), &json!({"program": 1})).await;
    assert!(started.status.is_success(), "{:?}", started.body);
}
