//! Controllers hosted across nodes (issue 23 item 2; docs/cluster.md): three `fivex serve --nats
//! URL --node NAME` nodes on one real PostgreSQL and one real `nats-server -js`. Controllers
//! created through one node are driven through another and read through a third (requests
//! forwarded to the owner); the owner killed (SIGKILL) while a program runs and variables are
//! written, every controller comes back on a survivor with every acknowledged write; a node
//! stopped cleanly hands its controllers over; the stream of a remote controller is relayed by
//! the node holding the websocket, and follows the controller when the owner dies (a fresh
//! snapshot from its new node; `relay.rs` tests the relaying itself).

use std::time::{Duration, Instant};

use futures_util::StreamExt;
use hyper::{Method, StatusCode};
use serde_json::{json, Value};
use tokio_tungstenite::tungstenite::Message;

use super::nats::NatsServer;
use super::postgres::Postgres;
use super::served::Served;

const C: &str = "/api/v1/controllers";

pub(super) fn node(pg: &Postgres, nats: &NatsServer, name: &str) -> Served {
    Served::start_on(&pg.url(), &["--nats", &nats.url(), "--node", name, "--workers", "1"])
}

/// The controller ids node `served` hosts, from `/readyz`, sorted.
pub(super) async fn hosted(served: &Served) -> Vec<String> {
    let ready = served.get("/readyz").await.json();
    let mut ids: Vec<String> =
        ready["cluster"]["controllers"].as_array().unwrap().iter().map(|v| v.as_str().unwrap().to_owned()).collect();
    ids.sort();
    ids
}

pub(super) type Socket = tokio_tungstenite::WebSocketStream<tokio_tungstenite::MaybeTlsStream<tokio::net::TcpStream>>;

/// The next text message as JSON (within 30 s).
pub(super) async fn next_json(ws: &mut Socket) -> Value {
    next_json_within(ws, Duration::from_secs(30)).await
}

/// The next text message as JSON, within `limit`.
pub(super) async fn next_json_within(ws: &mut Socket, limit: Duration) -> Value {
    loop {
        match tokio::time::timeout(limit, ws.next()).await.unwrap_or_else(|_| panic!("no message within {limit:?}")) {
            Some(Ok(Message::Text(text))) => return serde_json::from_str(text.as_str()).expect("a JSON message"),
            Some(Ok(Message::Close(frame))) => panic!("the stream closed: {frame:?}"),
            Some(Ok(_)) => continue,
            other => panic!("websocket: {other:?}"),
        }
    }
}

/// Waits (generously) until `check` holds, panicking with `what` after the deadline.
pub(super) async fn eventually<F, Fut>(what: &str, mut check: F)
where
    F: FnMut() -> Fut,
    Fut: std::future::Future<Output = Option<String>>,
{
    let deadline = Instant::now() + Duration::from_secs(30);
    loop {
        let Some(why_not) = check().await else { return };
        assert!(Instant::now() < deadline, "{what}: not within 30 s: {why_not}");
        tokio::time::sleep(Duration::from_millis(200)).await;
    }
}

/// Waits until every node of `nodes` sees exactly the members `names` (sorted).
pub(super) async fn members_seen(nodes: &[&Served], names: &[&str]) {
    eventually("every node sees the members", || async {
        for n in nodes {
            let members = n.get("/readyz").await.json()["cluster"]["members"].clone();
            if members != json!(names) {
                return Some(format!("{members}"));
            }
        }
        None
    })
    .await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn controllers_are_hosted_across_nodes_and_survive_a_killed_node() {
    let (pg, nats) = (Postgres::start(), NatsServer::start());
    let mut one = node(&pg, &nats, "one");
    let two = node(&pg, &nats, "two");
    let three = node(&pg, &nats, "three");
    members_seen(&[&one, &two, &three], &["one", "three", "two"]).await;

    // Created through node one: placed on it.
    let mut ids = Vec::new();
    for i in 0..3 {
        let reply = one.send_json(Method::POST, C, &json!({"name": format!("c{i}"), "preset": "head-bc"})).await;
        assert_eq!(reply.status, StatusCode::CREATED, "{:?}", reply.body);
        ids.push(reply.json()["id"].as_str().unwrap().to_owned());
    }
    let id = ids[0].clone();
    let mut on_one = hosted(&one).await;
    on_one.sort();
    let mut sorted = ids.clone();
    sorted.sort();
    assert_eq!(on_one, sorted);
    assert!(hosted(&two).await.is_empty() && hosted(&three).await.is_empty());

    // Driven through node three: a program stored and started, variables written.
    let program = "O0001\nWHILE[1EQ1]DO1\nG91 G01 X1. F600\nX-1.\nEND1\nM30\n";
    let stored =
        three.request(Method::PUT, &format!("{C}/{id}/programs/1"), &[("content-type", "text/plain")], program).await;
    assert_eq!(stored.status, StatusCode::CREATED, "{:?}", stored.body);
    let started = three.send_json(Method::POST, &format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
    assert!(started.status.is_success(), "{:?}", started.body);
    let put = three.send_json(Method::PUT, &format!("{C}/{id}/variables/500"), &json!({"value": 7.5})).await;
    assert_eq!(put.status, StatusCode::OK, "{:?}", put.body);
    assert_eq!(three.get(&format!("{C}/{id}/variables/500")).await.json()["value"], json!(7.5));
    // Read through node two: the owner's answer, the program running there.
    let status = two.get(&format!("{C}/{id}")).await;
    assert_eq!(status.status, StatusCode::OK, "{:?}", status.body);
    assert_eq!(status.json()["id"], json!(id));
    assert_eq!(String::from_utf8_lossy(&two.get(&format!("{C}/{id}/programs/1")).await.body), program);
    // The list through any node holds every controller.
    for n in [&one, &two, &three] {
        let list = n.get(C).await.json();
        let mut listed: Vec<String> =
            list.as_array().unwrap().iter().map(|c| c["id"].as_str().unwrap().to_owned()).collect();
        listed.sort();
        assert_eq!(listed, sorted, "{list}");
    }
    // No such controller: 404 on any node, as on one.
    for path in [format!("{C}/0123456789abcdef0123456789abcdef"), format!("{C}/no%20such")] {
        assert_eq!(two.get(&path).await.status, StatusCode::NOT_FOUND, "{path}");
    }
    // The stream of a controller on node one through node two: relayed (snapshot, positions of
    // the running program, a variable written through node three); a bad rate refused as on one.
    let bad = format!("ws://{}{C}/{id}/stream?rate=0", two.addr);
    match tokio_tungstenite::connect_async(bad).await {
        Err(tokio_tungstenite::tungstenite::Error::Http(response)) => assert_eq!(response.status(), 422),
        other => panic!("a bad rate opened a stream: {:?}", other.map(|_| ())),
    }
    let (mut ws, _) = tokio_tungstenite::connect_async(format!("ws://{}{C}/{id}/stream?rate=20", two.addr))
        .await
        .expect("relayed websocket");
    let snapshot = next_json(&mut ws).await;
    assert_eq!(snapshot["type"], "snapshot", "{snapshot}");
    assert_eq!(snapshot["controller"]["id"], json!(id));
    let mut positions = 0;
    while positions < 5 {
        if next_json(&mut ws).await["type"] == "position" {
            positions += 1;
        }
    }
    let put = three.send_json(Method::PUT, &format!("{C}/{id}/variables/600"), &json!({"value": 6.25})).await;
    assert_eq!(put.status, StatusCode::OK);
    loop {
        let message = next_json(&mut ws).await;
        if message.to_string().contains("6.25") {
            break;
        }
    }

    // Writes acknowledged while the program runs, then the owner killed.
    let mut acknowledged: Vec<(u32, f64)> = vec![(500, 7.5), (600, 6.25)];
    for k in 0..20u32 {
        let (number, value) = (501 + k, f64::from(k) * 1.5);
        let path = format!("{C}/{}/variables/{number}", ids[(k % 3) as usize]);
        let mut put = three.send_json(Method::PUT, &path, &json!({"value": value})).await;
        // An idle controller may be moving to a less loaded node (docs/cluster.md,
        // "Rebalancing"): 503 with Retry-After until its new node hosts it.
        let deadline = Instant::now() + Duration::from_secs(30);
        while put.status == StatusCode::SERVICE_UNAVAILABLE && put.headers.contains_key("retry-after") {
            assert!(Instant::now() < deadline, "{path}: still 503 after 30 s: {:?}", put.body);
            tokio::time::sleep(Duration::from_millis(200)).await;
            put = three.send_json(Method::PUT, &path, &json!({"value": value})).await;
        }
        if put.status.is_success() {
            acknowledged.push((number, value));
        }
    }
    assert_eq!(acknowledged.len(), 22);
    one.kill();
    // The relayed stream stays open and follows the controller: a fresh snapshot from its new
    // node, in reset state.
    loop {
        let message = next_json(&mut ws).await;
        if message["type"] == "snapshot" {
            assert_eq!(message["controller"]["id"], json!(id), "{message}");
            assert_ne!(message["controller"]["run_state"], json!("running"), "{message}");
            break;
        }
    }

    eventually("every controller hosted by a survivor", || async {
        let (a, b) = (hosted(&two).await, hosted(&three).await);
        let mut all: Vec<String> = a.iter().chain(&b).cloned().collect();
        all.sort();
        (all != sorted).then(|| format!("two {a:?}, three {b:?}"))
    })
    .await;
    assert!(!hosted(&two).await.is_empty() && !hosted(&three).await.is_empty(), "the survivors share the controllers");
    // In reset state, with every acknowledged write, through either survivor.
    let after = two.get(&format!("{C}/{id}")).await;
    assert_eq!(after.status, StatusCode::OK, "{:?}", after.body);
    assert_ne!(after.json()["run_state"], json!("running"), "{}", after.json());
    for (k, (number, value)) in acknowledged.iter().enumerate() {
        let target = if k < 2 { &ids[0] } else { &ids[(k - 2) % 3] };
        for n in [&two, &three] {
            let read = n.get(&format!("{C}/{target}/variables/{number}")).await;
            assert_eq!(read.json()["value"], json!(value), "#{number} of {target}: {:?}", read.body);
        }
    }

    // A node leaving cleanly hands its controllers over to the one left.
    let mut two = two;
    let (status, _) = two.terminate(Duration::from_secs(30));
    assert!(status.success(), "{status}; log: {}", two.log());
    eventually("every controller on node three", || async {
        let mut all = hosted(&three).await;
        all.sort();
        (all != sorted).then(|| format!("{all:?}"))
    })
    .await;
    let program_back = three.get(&format!("{C}/{id}/programs/1")).await;
    assert_eq!(String::from_utf8_lossy(&program_back.body), program);
    let members: Value = three.get("/readyz").await.json()["cluster"]["members"].clone();
    assert_eq!(members, json!(["three"]));
}

/// `--node` with a SQLite database is refused: controllers are shared through PostgreSQL.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn node_with_sqlite_is_refused() {
    let nats = NatsServer::start();
    let dir = tempfile::tempdir().unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_fivex"))
        .args(["serve", "--addr", "127.0.0.1:0", "--nats", &nats.url(), "--node", "n1", "--db"])
        .arg(dir.path().join("fivex.db"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("PostgreSQL"), "{}", String::from_utf8_lossy(&out.stderr));
}

/// A node that stops hosting a controller another node took over (as when it was cut off from
/// NATS for longer than its lease) closes the controller's websockets on it with 1012 "hosted
/// by another node now; reconnect", not 4404 "deleted": the controller is still stored and
/// answers through either node.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_stream_on_a_node_that_loses_its_controller_says_reconnect() {
    let (pg, nats) = (Postgres::start(), NatsServer::start());
    let one = node(&pg, &nats, "one");
    let two = node(&pg, &nats, "two");
    members_seen(&[&one, &two], &["one", "two"]).await;
    let created = one.send_json(Method::POST, C, &json!({"name": "m", "preset": "mill3"})).await;
    assert_eq!(created.status, StatusCode::CREATED, "{:?}", created.body);
    let id = created.json()["id"].as_str().unwrap().to_owned();
    let (mut ws, _) =
        tokio_tungstenite::connect_async(format!("ws://{}{C}/{id}/stream", one.addr)).await.expect("websocket");
    assert_eq!(next_json(&mut ws).await["type"], "snapshot");

    // Node two's takeover as the bucket sees it: the placement names node two.
    let client = async_nats::connect(nats.url()).await.expect("NATS");
    let placement = async_nats::jetstream::new(client).get_key_value("fivex_placement").await.expect("the bucket");
    placement.put(&id, "two".into()).await.expect("placement written");

    let frame = loop {
        match tokio::time::timeout(Duration::from_secs(30), ws.next()).await.expect("the stream closes") {
            Some(Ok(Message::Close(frame))) => break frame.expect("a close frame"),
            Some(Ok(_)) => continue,
            other => panic!("the stream ended without a close frame: {other:?}"),
        }
    };
    assert_eq!(u16::from(frame.code), 1012, "{frame:?}");
    assert!(frame.reason.contains("hosted by another node"), "{frame:?}");
    eventually("the controller hosted by node two", || async {
        let on_two = hosted(&two).await;
        (on_two != [id.clone()]).then(|| format!("{on_two:?}"))
    })
    .await;
    for n in [&one, &two] {
        let read = n.get(&format!("{C}/{id}")).await;
        assert_eq!(read.status, StatusCode::OK, "{:?}", read.body);
    }
}
