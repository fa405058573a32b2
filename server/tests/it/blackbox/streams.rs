//! Streams that scale (issue 18): position frames only when something in them changed, the
//! fleet stream as a snapshot then deltas, and one frame shared by every subscriber; a workpiece
//! change told to every subscriber of its controller.

use std::collections::HashMap;
use std::time::Duration;

use futures_util::StreamExt;
use hyper::Method;
use serde_json::{json, Value};
use tokio::time::{timeout, Instant};
use tokio_tungstenite::tungstenite::Message;

use super::served::Served;

type Socket = tokio_tungstenite::WebSocketStream<tokio_tungstenite::MaybeTlsStream<tokio::net::TcpStream>>;

async fn connect(served: &Served, path: &str) -> Socket {
    let (ws, _) = tokio_tungstenite::connect_async(format!("ws://{}{path}", served.addr)).await.expect("websocket");
    ws
}

/// The next text message as text, or `None` when nothing came within `within`.
async fn next_text(ws: &mut Socket, within: Duration) -> Option<String> {
    let deadline = Instant::now() + within;
    loop {
        let left = deadline.saturating_duration_since(Instant::now());
        match timeout(left, ws.next()).await {
            Err(_) => return None,
            Ok(Some(Ok(Message::Text(text)))) => return Some(text.as_str().to_owned()),
            Ok(Some(Ok(Message::Close(_)))) | Ok(None) => panic!("the stream closed"),
            Ok(Some(Ok(_))) => continue,
            Ok(Some(Err(e))) => panic!("websocket error: {e}"),
        }
    }
}

async fn next_json(ws: &mut Socket, within: Duration) -> Option<Value> {
    next_text(ws, within).await.map(|t| serde_json::from_str(&t).expect("a JSON message"))
}

/// Every message that arrives within `span`.
async fn collect(ws: &mut Socket, span: Duration) -> Vec<String> {
    let end = Instant::now() + span;
    let mut out = Vec::new();
    while let Some(text) = next_text(ws, end.saturating_duration_since(Instant::now())).await {
        out.push(text);
    }
    out
}

fn kind(text: &str) -> String {
    serde_json::from_str::<Value>(text).expect("a JSON message")["type"].as_str().unwrap_or_default().to_owned()
}

async fn create(served: &Served, name: &str) -> String {
    let reply = served.send_json(Method::POST, "/api/v1/controllers", &json!({"name": name, "preset": "mill3"})).await;
    assert_eq!(reply.status, 201, "{:?}", String::from_utf8_lossy(&reply.body));
    reply.json()["id"].as_str().expect("an id").to_owned()
}

async fn mdi(served: &Served, id: &str, text: &str) {
    let reply = served.send_json(Method::POST, &format!("/api/v1/controllers/{id}/mdi"), &json!({"text": text})).await;
    assert_eq!(reply.status, 200, "{:?}", String::from_utf8_lossy(&reply.body));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_idle_controller_sends_no_position_frame_after_its_first() {
    let served = Served::start(&[]);
    let id = create(&served, "idle").await;
    let mut ws = connect(&served, &format!("/api/v1/controllers/{id}/stream?rate=30")).await;
    let first = next_json(&mut ws, Duration::from_secs(10)).await.expect("a snapshot");
    assert_eq!(first["type"], "snapshot");
    let position = next_json(&mut ws, Duration::from_secs(10)).await.expect("the position now");
    assert_eq!(position["type"], "position", "{position}");

    // Idle: 1.2 s at 30 frames a second would have been 36 identical frames before.
    let quiet = collect(&mut ws, Duration::from_millis(1200)).await;
    let frames: Vec<&String> = quiet.iter().filter(|m| kind(m) == "position").collect();
    assert!(frames.is_empty(), "an idle controller sent {} position frames: {:?}", frames.len(), frames.first());

    // The same socket does carry frames once the machine moves.
    mdi(&served, &id, "G91 G01 X20. F600").await;
    let moving = collect(&mut ws, Duration::from_millis(1500)).await;
    let frames = moving.iter().filter(|m| kind(m) == "position").count();
    assert!(frames >= 3, "a moving controller sent {frames} position frames in 1.5 s: {moving:?}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_fleet_stream_sends_a_snapshot_then_only_what_changed() {
    let served = Served::start(&[]);
    let ids = [create(&served, "a").await, create(&served, "b").await, create(&served, "c").await];
    let mut ws = connect(&served, "/api/v1/stream?rate=20").await;
    let snapshot = next_json(&mut ws, Duration::from_secs(10)).await.expect("a snapshot");
    assert_eq!(snapshot["type"], "fleet");
    let listed: Vec<&str> =
        snapshot["controllers"].as_array().unwrap().iter().map(|c| c["id"].as_str().unwrap()).collect();
    assert_eq!(listed, ids.iter().map(String::as_str).collect::<Vec<_>>());

    // Nothing changes: nothing is sent.
    assert_eq!(next_text(&mut ws, Duration::from_millis(600)).await, None);

    // One controller changes mode: a delta with that controller only.
    let reply =
        served.send_json(Method::PUT, &format!("/api/v1/controllers/{}/mode", ids[1]), &json!({"mode": "mdi"})).await;
    assert_eq!(reply.status, 200, "{:?}", String::from_utf8_lossy(&reply.body));
    let delta = next_json(&mut ws, Duration::from_secs(10)).await.expect("a delta");
    assert_eq!(delta["type"], "fleet_delta", "{delta}");
    let changed = delta["controllers"].as_array().unwrap();
    assert_eq!(changed.len(), 1, "{delta}");
    assert_eq!(changed[0]["id"], ids[1].as_str());
    assert_eq!(changed[0]["mode"], "mdi");
    assert_eq!(delta["removed"], json!([]));

    // A removal: its id, no entries.
    let reply = served.request(Method::DELETE, &format!("/api/v1/controllers/{}", ids[0]), &[], "").await;
    assert!(reply.status.is_success(), "{}", reply.status);
    let delta = next_json(&mut ws, Duration::from_secs(10)).await.expect("a delta");
    assert_eq!(delta, json!({"type": "fleet_delta", "controllers": [], "removed": [ids[0]]}));

    // A new controller: that one only.
    let added = create(&served, "d").await;
    let delta = next_json(&mut ws, Duration::from_secs(10)).await.expect("a delta");
    let changed = delta["controllers"].as_array().unwrap();
    assert_eq!((changed.len(), changed[0]["id"].as_str()), (1, Some(added.as_str())), "{delta}");

    // `deltas=false` keeps the whole fleet in every message.
    let mut whole = connect(&served, "/api/v1/stream?rate=20&deltas=false").await;
    let first = next_json(&mut whole, Duration::from_secs(10)).await.expect("a snapshot");
    assert_eq!(first["controllers"].as_array().unwrap().len(), 3);
    let reply =
        served.send_json(Method::PUT, &format!("/api/v1/controllers/{}/mode", ids[2]), &json!({"mode": "mdi"})).await;
    assert_eq!(reply.status, 200);
    let next = next_json(&mut whole, Duration::from_secs(10)).await.expect("the fleet again");
    assert_eq!(next["type"], "fleet");
    assert_eq!(next["controllers"].as_array().unwrap().len(), 3, "{next}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn subscribers_of_one_controller_receive_identical_frames() {
    let served = Served::start(&[]);
    let id = create(&served, "shared").await;
    let mut sockets = Vec::new();
    for _ in 0..3 {
        let mut ws = connect(&served, &format!("/api/v1/controllers/{id}/stream?rate=1000")).await;
        assert_eq!(next_json(&mut ws, Duration::from_secs(10)).await.expect("a snapshot")["type"], "snapshot");
        assert_eq!(next_json(&mut ws, Duration::from_secs(10)).await.expect("a position")["type"], "position");
        sockets.push(ws);
    }
    mdi(&served, &id, "G91 G01 X100. Y50. F3000").await;
    let mut seen: Vec<HashMap<u64, String>> = Vec::new();
    for ws in &mut sockets {
        let frames = collect(ws, Duration::from_millis(1000)).await;
        let by_t = frames
            .into_iter()
            .filter(|m| kind(m) == "position")
            .map(|m| (serde_json::from_str::<Value>(&m).unwrap()["t"].as_f64().unwrap().to_bits(), m))
            .collect();
        seen.push(by_t);
    }
    // Frames of the same instant are the same bytes for every subscriber (one encoding).
    let common: Vec<&u64> = seen[0].keys().filter(|t| seen[1..].iter().all(|s| s.contains_key(t))).collect();
    assert!(
        common.len() >= 10,
        "only {} frames in common: {:?}",
        common.len(),
        seen.iter().map(HashMap::len).collect::<Vec<_>>()
    );
    for t in common {
        assert_eq!(seen[0][t], seen[1][t]);
        assert_eq!(seen[0][t], seen[2][t]);
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_chain_switch_sends_a_frame_that_names_the_new_chain() {
    // Syntec G10 L5000 on the library's exchangeable-head machine, its A/C head given the B/C
    // head's nose: at zero angles both put the tip at the same place, so a switch changes nothing
    // in the frame but its chain — and the 3D view must still learn it.
    let served = Served::start(&[]);
    let mut machine: Value =
        serde_json::from_str(include_str!("../../../../machines/head-exchange-bc-ac.json")).unwrap();
    machine["chains"][0]["nose"] = machine["nose"].clone();
    let body = json!({"name": "heads", "dialect": "syntec", "machine": machine});
    let reply = served.send_json(Method::POST, "/api/v1/controllers", &body).await;
    assert_eq!(reply.status, 201, "{:?}", String::from_utf8_lossy(&reply.body));
    let id = reply.json()["id"].as_str().expect("an id").to_owned();
    let mut ws = connect(&served, &format!("/api/v1/controllers/{id}/stream?rate=30")).await;
    assert_eq!(next_json(&mut ws, Duration::from_secs(10)).await.expect("a snapshot")["type"], "snapshot");
    let now = next_json(&mut ws, Duration::from_secs(10)).await.expect("the position now");
    assert_eq!(now["chain"], json!({"set": 1, "sub": 1}), "{now}");

    for (text, set) in [("G10 L5000 P2", 2), ("G10 L5000 P1", 1)] {
        mdi(&served, &id, text).await;
        let frames: Vec<Value> = collect(&mut ws, Duration::from_millis(1500))
            .await
            .iter()
            .filter(|m| kind(m) == "position")
            .map(|m| serde_json::from_str(m).unwrap())
            .collect();
        let last = frames.last().unwrap_or_else(|| panic!("{text}: no position frame"));
        assert_eq!(last["chain"], json!({"set": set, "sub": 1}), "{text}: {last}");
        assert_eq!((&last["machine"], &last["tip"]), (&now["machine"], &now["tip"]), "{text}: {last}");
    }
}

/// The next message of kind `kind` (others, position frames among them, passed over), or `None`
/// when none came within `within`.
async fn next_of(ws: &mut Socket, kind_: &str, within: Duration) -> Option<Value> {
    let end = Instant::now() + within;
    while let Some(text) = next_text(ws, end.saturating_duration_since(Instant::now())).await {
        if kind(&text) == kind_ {
            return Some(serde_json::from_str(&text).expect("a JSON message"));
        }
    }
    None
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_workpiece_put_reaches_every_subscriber_of_its_controller() {
    let served = Served::start(&[]);
    let id = create(&served, "clamped").await;
    let other = create(&served, "elsewhere").await;
    let stream = format!("/api/v1/controllers/{id}/stream?rate=30");
    // Two dashboards on the controller, one on another controller.
    let (mut first, mut second) = (connect(&served, &stream).await, connect(&served, &stream).await);
    let mut bystander = connect(&served, &format!("/api/v1/controllers/{other}/stream?rate=30")).await;
    for ws in [&mut first, &mut second, &mut bystander] {
        let snapshot = next_of(ws, "snapshot", Duration::from_secs(10)).await.expect("a snapshot");
        assert_eq!(snapshot["workpiece"], json!({"boxes": []}), "nothing on the table at first");
    }

    // The first client puts two boxes; both subscribers are told, with the boxes.
    let boxes = json!([
        {"min": [-60.0, -40.0, 0.0], "max": [60.0, 40.0, 30.0]},
        {"min": [-20.0, -20.0, 30.0], "max": [20.0, 20.0, 50.0]}
    ]);
    let uri = format!("/api/v1/controllers/{id}/workpiece");
    let put = served.send_json(Method::PUT, &uri, &json!({"boxes": boxes})).await;
    assert_eq!(put.status, 200, "{:?}", String::from_utf8_lossy(&put.body));
    for ws in [&mut first, &mut second] {
        let told = next_of(ws, "workpiece", Duration::from_secs(10)).await.expect("a workpiece message");
        assert_eq!(told, json!({"type": "workpiece", "boxes": boxes}));
    }
    // A refused workpiece tells nothing; clearing the table does.
    let refused = served.send_json(Method::PUT, &uri, &json!({"boxes": [{"min": [0, 0, 0], "max": [0, 1, 1]}]})).await;
    assert_eq!(refused.status, 422);
    let cleared = served.send_json(Method::PUT, &uri, &json!({"boxes": []})).await;
    assert_eq!(cleared.status, 200);
    let told = next_of(&mut second, "workpiece", Duration::from_secs(10)).await.expect("the clearing");
    assert_eq!(told, json!({"type": "workpiece", "boxes": []}), "the refused one was not told");
    // The other controller's subscriber heard of neither.
    let heard = collect(&mut bystander, Duration::from_millis(500)).await;
    assert!(heard.iter().all(|m| kind(m) != "workpiece"), "{heard:?}");

    // A dashboard that connects later has the boxes in its snapshot.
    served.send_json(Method::PUT, &uri, &json!({"boxes": boxes})).await;
    let mut late = connect(&served, &stream).await;
    let snapshot = next_of(&mut late, "snapshot", Duration::from_secs(10)).await.expect("a snapshot");
    assert_eq!(snapshot["workpiece"], json!({"boxes": boxes}));
}
