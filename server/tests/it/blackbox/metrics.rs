//! `/metrics` and `/readyz` of the real service (docs/api.md, "Readiness and metrics"): three
//! controllers, one running a program with a stream subscriber; the metrics agree with what the
//! REST API says, and the frames counter grows between two scrapes while frames arrive.

use std::time::Duration;

use futures_util::StreamExt;
use hyper::{Method, StatusCode};
use serde_json::{json, Value};
use tokio::time::timeout;
use tokio_tungstenite::tungstenite::Message;

use super::served::Served;
use crate::common::exposition::{parse_both, Exposition};

const C: &str = "/api/v1/controllers";

/// A program that runs for minutes: a long move at a slow feed.
const LONG: &str = "O0001\nG91 G01 X400. F60\nM30\n";

async fn scrape(served: &Served) -> Exposition {
    let reply = served.get("/metrics").await;
    assert_eq!(reply.status, StatusCode::OK, "{:?}", reply.body);
    assert_eq!(reply.content_type(), "text/plain; version=0.0.4; charset=utf-8");
    parse_both(std::str::from_utf8(&reply.body).expect("UTF-8"))
}

type Socket = tokio_tungstenite::WebSocketStream<tokio_tungstenite::MaybeTlsStream<tokio::net::TcpStream>>;

/// Reads messages until `count` position frames came (each within 10 s).
async fn positions(ws: &mut Socket, count: usize) {
    let mut seen = 0;
    while seen < count {
        let message = timeout(Duration::from_secs(10), ws.next()).await.expect("a message within 10 s");
        if let Some(Ok(Message::Text(text))) = message {
            let value: Value = serde_json::from_str(text.as_str()).expect("JSON");
            if value["type"] == "position" {
                seen += 1;
            }
        } else {
            panic!("the stream ended: {message:?}");
        }
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn metrics_agree_with_the_api_while_a_program_runs_and_a_client_watches() {
    // With a token: the scrape and the readiness check do without it, the API does not.
    let served = Served::start(&["--token", "s3cret"]);
    let auth = [("authorization", "Bearer s3cret")];
    let mut ids = Vec::new();
    for name in ["a", "b", "c"] {
        let body = json!({"name": name, "preset": "mill3"}).to_string();
        let reply = served.request(Method::POST, C, &[auth[0], ("content-type", "application/json")], body).await;
        assert_eq!(reply.status, StatusCode::CREATED, "{:?}", reply.body);
        ids.push(reply.json()["id"].as_str().expect("an id").to_owned());
    }
    let running = &ids[1];
    let stored = served
        .request(Method::PUT, &format!("{C}/{running}/programs/1"), &[auth[0], ("content-type", "text/plain")], LONG)
        .await;
    assert_eq!(stored.status, StatusCode::CREATED, "{:?}", stored.body);
    let started = served
        .request(
            Method::POST,
            &format!("{C}/{running}/cycle-start"),
            &[auth[0], ("content-type", "application/json")],
            json!({"program": 1}).to_string(),
        )
        .await;
    assert_eq!(started.json()["run_state"], "running");
    let url = format!("ws://{}{C}/{running}/stream?token=s3cret", served.addr);
    let (mut ws, _) = tokio_tungstenite::connect_async(url).await.expect("websocket");
    positions(&mut ws, 2).await;

    let ready = served.get("/readyz").await;
    assert_eq!(ready.status, StatusCode::OK);
    assert_eq!(ready.json()["node"]["controllers"], 3);
    assert_eq!(ready.json()["cluster"], Value::Null);
    super::wire::assert_valid(&super::wire::document(), "Readiness", &ready.json(), "/readyz");

    let first = scrape(&served).await;
    // What the API says, state by state.
    let list = served.request(Method::GET, C, &auth, "").await.json();
    for state in ["idle", "running", "hold", "alarm"] {
        let listed = list.as_array().unwrap().iter().filter(|c| c["run_state"] == state).count();
        assert_eq!(first.value("fivex_controllers", &[("state", state)]), listed as f64, "{state}");
    }
    assert_eq!(first.sum("fivex_controllers"), 3.0);
    assert_eq!(first.value("fivex_controllers", &[("state", "running")]), 1.0);
    assert!(first.value("fivex_websocket_subscribers", &[("stream", "controller")]) >= 1.0);
    assert_eq!(first.value("fivex_http_requests_total", &[("class", "1xx")]), 1.0, "the upgrade");
    let frames = first.value("fivex_position_frames_sent_total", &[]);
    assert!(frames >= 1.0, "{frames}");
    assert!(first.value("fivex_position_frame_lag_seconds_count", &[]) >= 1.0);

    // Two more frames: the first of them was counted before the second was sent.
    positions(&mut ws, 2).await;
    let second = scrape(&served).await;
    assert!(second.value("fivex_position_frames_sent_total", &[]) > frames);
    assert_eq!(second.value("fivex_controllers", &[("state", "running")]), 1.0);

    // The subscriber gone, the count follows (the session ends once it sees the close).
    ws.close(None).await.expect("close");
    let mut left = f64::NAN;
    for _ in 0..100 {
        left = scrape(&served).await.value("fivex_websocket_subscribers", &[("stream", "controller")]);
        if left == 0.0 {
            break;
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    assert_eq!(left, 0.0);
}
