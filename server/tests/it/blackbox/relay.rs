//! Controller streams relayed between nodes (issue 23 item 2; docs/cluster.md, "Streams across
//! nodes"), on a real PostgreSQL and a real `nats-server -js`: several websocket clients of one
//! controller through one relaying node share one NATS subscription (`fivex_relay_subscriptions`)
//! and each gets what a websocket on the owner gives (the snapshot, the position, frames at its
//! own rate, a variable written through a third node, byte for byte as the owner's own
//! websocket); the owner stops publishing once they leave (a raw NATS subscriber hears
//! nothing more) and when a relaying node is killed; a relayed websocket stays open when its controller's node is killed (SIGKILL)
//! or stops (SIGTERM), gets a fresh snapshot from the controller's new node and its frames
//! there, and closes with 4404 when the controller is deleted.

use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use futures_util::{SinkExt, StreamExt};
use hyper::{Method, StatusCode};
use serde_json::{json, Value};
use tokio_tungstenite::tungstenite::Message;

use super::nats::NatsServer;
use super::nodes::{eventually, hosted, members_seen, node};
use super::postgres::Postgres;
use super::served::Served;

const C: &str = "/api/v1/controllers";
const PROGRAM: &str = "O0001\nWHILE[1EQ1]DO1\nG91 G01 X1. F600\nX-1.\nEND1\nM30\n";

/// A metric's value on `served` (`sample`: its name and labels as the text format writes them).
async fn metric(served: &Served, sample: &str) -> f64 {
    let reply = served.get("/metrics").await;
    let text = String::from_utf8_lossy(&reply.body).into_owned();
    text.lines()
        .find_map(|l| l.strip_prefix(sample)?.strip_prefix(' ')?.trim().parse().ok())
        .unwrap_or_else(|| panic!("no {sample} in /metrics: {text}"))
}

type Sink = futures_util::stream::SplitSink<super::nodes::Socket, Message>;

/// A websocket client whose messages a task of its own reads as they come (so no client is
/// ever slow while the test looks at another), each kept with when it came, raw and parsed.
struct Watcher {
    sink: Sink,
    log: Arc<Mutex<Vec<(Instant, String, Value)>>>,
    /// The close frame's code and reason, once closed.
    closed: Arc<Mutex<Option<(u16, String)>>>,
}

impl Watcher {
    async fn connect(served: &Served, id: &str, rate: u32) -> Watcher {
        let url = format!("ws://{}{C}/{id}/stream?rate={rate}", served.addr);
        let (ws, _) = tokio_tungstenite::connect_async(url).await.expect("relayed websocket");
        let (sink, mut stream) = ws.split();
        let (log, closed) = (Arc::new(Mutex::new(Vec::new())), Arc::new(Mutex::new(None)));
        let (l, c) = (log.clone(), closed.clone());
        tokio::spawn(async move {
            while let Some(message) = stream.next().await {
                match message {
                    Ok(Message::Text(text)) => {
                        let value = serde_json::from_str(text.as_str()).expect("a JSON message");
                        l.lock().unwrap().push((Instant::now(), text.as_str().to_owned(), value));
                    }
                    Ok(Message::Close(frame)) => {
                        let frame = frame.map_or((0, String::new()), |f| (u16::from(f.code), f.reason.to_string()));
                        *c.lock().unwrap() = Some(frame);
                        break;
                    }
                    Ok(_) => {}
                    Err(e) => {
                        *c.lock().unwrap() = Some((0, format!("error: {e}")));
                        break;
                    }
                }
            }
        });
        Watcher { sink, log, closed }
    }

    fn messages(&self) -> Vec<(Instant, String, Value)> {
        self.log.lock().unwrap().clone()
    }

    fn len(&self) -> usize {
        self.log.lock().unwrap().len()
    }

    fn closed(&self) -> Option<(u16, String)> {
        self.closed.lock().unwrap().clone()
    }

    /// Waits (60 s at most) for a message after the first `from` that `want` accepts; its index.
    /// The websocket must stay open meanwhile.
    async fn wait_for(&self, what: &str, from: usize, want: impl Fn(&Value) -> bool) -> usize {
        let deadline = Instant::now() + Duration::from_secs(60);
        loop {
            if let Some(at) = self.messages().iter().skip(from).position(|(_, _, v)| want(v)) {
                return from + at;
            }
            assert!(self.closed().is_none(), "{what}: the websocket closed: {:?}", self.closed());
            assert!(Instant::now() < deadline, "{what}: not within 60 s; got {}", self.tail(from));
            tokio::time::sleep(Duration::from_millis(50)).await;
        }
    }

    /// Waits (60 s at most) for the close frame.
    async fn wait_closed(&self, what: &str) -> (u16, String) {
        let deadline = Instant::now() + Duration::from_secs(60);
        loop {
            if let Some(closed) = self.closed() {
                return closed;
            }
            assert!(Instant::now() < deadline, "{what}: not closed within 60 s");
            tokio::time::sleep(Duration::from_millis(50)).await;
        }
    }

    /// What came after the first `from`: the types in order (runs of one type counted), then the
    /// last five messages.
    fn tail(&self, from: usize) -> String {
        let messages = self.messages();
        let mut types: Vec<(String, usize)> = Vec::new();
        for (_, _, v) in messages.iter().skip(from) {
            let kind = v["type"].as_str().unwrap_or("?").to_owned();
            match types.last_mut() {
                Some((last, n)) if *last == kind => *n += 1,
                _ => types.push((kind, 1)),
            }
        }
        let last: Vec<String> =
            messages.iter().skip(from).rev().take(5).map(|(_, text, _)| text.chars().take(160).collect()).collect();
        format!("{types:?}; last: {last:?}")
    }

    async fn leave(mut self) {
        let _ = self.sink.send(Message::Close(None)).await;
        let _ = self.sink.close().await;
    }
}

/// The subjects of the messages `raw` gets within `within`.
async fn drain(raw: &mut async_nats::Subscriber, within: Duration) -> Vec<String> {
    let until = tokio::time::Instant::now() + within;
    let mut subjects = Vec::new();
    while let Ok(Some(message)) = tokio::time::timeout_at(until, raw.next()).await {
        subjects.push(message.subject.to_string());
    }
    subjects
}

/// Prints the nodes' logs when the test fails (a cluster test's failure needs them).
struct LogsOnPanic(Vec<(&'static str, Arc<Mutex<Vec<String>>>)>);

impl Drop for LogsOnPanic {
    fn drop(&mut self) {
        if std::thread::panicking() {
            for (name, log) in &self.0 {
                eprintln!("--- node {name}:\n{}", log.lock().unwrap().join("\n"));
            }
        }
    }
}

fn is(kind: &'static str) -> impl Fn(&Value) -> bool {
    move |v| v["type"] == kind
}

/// Retries `request` while the controller is between nodes (503), until it succeeds.
async fn until_hosted(served: &Served, method: Method, path: &str, body: &Value) {
    let deadline = Instant::now() + Duration::from_secs(60);
    loop {
        let reply = served.send_json(method.clone(), path, body).await;
        if reply.status.is_success() {
            return;
        }
        assert_eq!(reply.status, StatusCode::SERVICE_UNAVAILABLE, "{path}: {:?}", reply.body);
        assert!(Instant::now() < deadline, "{path}: still 503 after 60 s");
        tokio::time::sleep(Duration::from_millis(200)).await;
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn relayed_streams_share_one_subscription_and_follow_their_controller() {
    let (pg, nats) = (Postgres::start(), NatsServer::start());
    let mut one = node(&pg, &nats, "one");
    let two = node(&pg, &nats, "two");
    let three = node(&pg, &nats, "three");
    let mut logs =
        LogsOnPanic(vec![("one", one.log_handle()), ("two", two.log_handle()), ("three", three.log_handle())]);
    members_seen(&[&one, &two, &three], &["one", "three", "two"]).await;
    let created = one.send_json(Method::POST, C, &json!({"name": "relayed", "preset": "head-bc"})).await;
    assert_eq!(created.status, StatusCode::CREATED, "{:?}", created.body);
    let id = created.json()["id"].as_str().unwrap().to_owned();
    assert_eq!(hosted(&one).await, vec![id.clone()]);
    let stored =
        three.request(Method::PUT, &format!("{C}/{id}/programs/1"), &[("content-type", "text/plain")], PROGRAM).await;
    assert_eq!(stored.status, StatusCode::CREATED, "{:?}", stored.body);
    let started = three.send_json(Method::POST, &format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
    assert!(started.status.is_success(), "{:?}", started.body);

    // A raw NATS subscriber on the controller's stream subjects.
    let raw_client = async_nats::connect(nats.url()).await.expect("NATS");
    let mut raw = raw_client.subscribe(format!("fivex.controllers.{id}.stream.>")).await.unwrap();
    raw_client.flush().await.unwrap();

    // Three clients through node two, at three rates, and one on the owner itself.
    let rates = [5, 20, 50];
    let mut clients = Vec::new();
    for rate in rates {
        clients.push(Watcher::connect(&two, &id, rate).await);
    }
    let local = Watcher::connect(&one, &id, 20).await;
    for (client, rate) in clients.iter().zip(rates) {
        client.wait_for("the snapshot", 0, is("snapshot")).await;
        let first = client.messages();
        assert_eq!(first[0].2["type"], "snapshot", "rate {rate}: {}", first[0].1);
        assert_eq!(first[0].2["controller"]["id"], json!(id));
        client.wait_for("the position after the snapshot", 1, |_| true).await;
        assert_eq!(client.messages()[1].2["type"], "position", "rate {rate}: {}", client.messages()[1].1);
    }
    // One subscription on node two for its three clients; one publisher on node one.
    assert_eq!(metric(&two, "fivex_relay_subscriptions").await, 1.0);
    assert_eq!(metric(&two, "fivex_websocket_subscribers{stream=\"controller\"}").await, 3.0);
    assert_eq!(metric(&one, "fivex_relay_publishers").await, 1.0);
    assert_eq!(metric(&one, "fivex_websocket_subscribers{stream=\"controller\"}").await, 1.0);

    // Each client's frames at its own rate (paced at node two from the owner's full-rate feed).
    let window = Instant::now();
    for client in &clients {
        client.wait_for("position frames", 2, is("position")).await;
    }
    while window.elapsed() < Duration::from_secs(3) {
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
    let published = drain(&mut raw, Duration::from_secs(1)).await.iter().filter(|s| s.ends_with(".position")).count();
    for (client, rate) in clients.iter().zip(rates) {
        let frames: Vec<Instant> = client
            .messages()
            .iter()
            .skip(2)
            .filter(|(_, _, v)| v["type"] == "position")
            .map(|(at, _, _)| *at)
            .collect();
        assert!(frames.len() >= 3, "rate {rate}: only {} frames", frames.len());
        let span = frames.last().unwrap().duration_since(frames[0]).as_secs_f64();
        let most = (span + 0.5) * f64::from(rate) + 2.0;
        assert!((frames.len() - 1) as f64 <= most, "rate {rate}: {} frames in {span:.2} s", frames.len());
    }
    assert!(published > 3 * 5, "the owner published {published} position frames");

    // A variable written through node three: every client gets the owner's message, byte for byte.
    let put = three.send_json(Method::PUT, &format!("{C}/{id}/variables/600"), &json!({"value": 6.25})).await;
    assert_eq!(put.status, StatusCode::OK, "{:?}", put.body);
    let written = |v: &Value| v["type"] == "variables" && v["changes"]["#600"] == json!(6.25);
    let at = local.wait_for("the variable on the owner", 0, written).await;
    let expected = local.messages()[at].1.clone();
    for client in &clients {
        let at = client.wait_for("the variable through node two", 0, written).await;
        assert_eq!(client.messages()[at].1, expected);
    }

    // The clients leave: node two unsubscribes, node one stops publishing, NATS hears nothing
    // more while the program still runs.
    let left = Instant::now();
    for client in clients {
        client.leave().await;
    }
    local.leave().await;
    eventually("node two unsubscribed", || async {
        let n = metric(&two, "fivex_relay_subscriptions").await;
        (n != 0.0).then(|| format!("{n}"))
    })
    .await;
    eventually("node one stopped publishing", || async {
        let n = metric(&one, "fivex_relay_publishers").await;
        (n != 0.0).then(|| format!("{n}"))
    })
    .await;
    assert!(left.elapsed() < Duration::from_secs(10), "publishing stopped {:?} after the clients left", left.elapsed());
    // What was on its way before it stopped (a second of quiet ends it; never more than 10 s).
    let drained = Instant::now();
    while let Ok(Some(_)) = tokio::time::timeout(Duration::from_secs(1), raw.next()).await {
        assert!(drained.elapsed() < Duration::from_secs(10), "node one goes on publishing");
    }
    let status = three.get(&format!("{C}/{id}")).await.json();
    assert_eq!(status["run_state"], "running", "{status}");
    if let Ok(Some(message)) = tokio::time::timeout(Duration::from_secs(3), raw.next()).await {
        panic!("published after the clients left: {} {:?}", message.subject, message.payload);
    }

    // A relaying node killed with its client: the owner stops publishing for it within seconds.
    let mut four = node(&pg, &nats, "four");
    logs.0.push(("four", four.log_handle()));
    let far = Watcher::connect(&four, &id, 20).await;
    far.wait_for("a snapshot through node four", 0, is("snapshot")).await;
    assert_eq!(metric(&one, "fivex_relay_publishers").await, 1.0);
    four.kill();
    let killed = Instant::now();
    eventually("node one stopped publishing for the killed node", || async {
        let n = metric(&one, "fivex_relay_publishers").await;
        (n != 0.0).then(|| format!("{n}"))
    })
    .await;
    assert!(killed.elapsed() < Duration::from_secs(15), "publishing stopped {:?} after the kill", killed.elapsed());

    // The owner killed: relayed websockets through node two and node three stay open and get a
    // fresh snapshot (reset state) from the controller's new node, then its frames there.
    let through_two = Watcher::connect(&two, &id, 20).await;
    let through_three = Watcher::connect(&three, &id, 20).await;
    for watcher in [&through_two, &through_three] {
        watcher.wait_for("a position before the kill", 2, is("position")).await;
    }
    let (from_two, from_three) = (through_two.len(), through_three.len());
    one.kill();
    let killed = Instant::now();
    for (watcher, from) in [(&through_two, from_two), (&through_three, from_three)] {
        let at = watcher.wait_for("a fresh snapshot after the kill", from, is("snapshot")).await;
        let snapshot = watcher.messages()[at].2.clone();
        assert_eq!(snapshot["controller"]["id"], json!(id), "{snapshot}");
        assert_ne!(snapshot["controller"]["run_state"], json!("running"), "{snapshot}");
        assert_eq!(snapshot["variables"]["#600"], json!(6.25), "{snapshot}");
    }
    let followed = killed.elapsed();
    assert!(followed < Duration::from_secs(30), "followed in {followed:?}");
    let (from_two, from_three) = (through_two.len(), through_three.len());
    until_hosted(&three, Method::POST, &format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
    for (watcher, from) in [(&through_two, from_two), (&through_three, from_three)] {
        // (A `state` message, or a fresh snapshot saying so: one may replace the events.)
        let running = |v: &Value| {
            (v["type"] == "state" && v["run_state"] == "running")
                || (v["type"] == "snapshot" && v["controller"]["run_state"] == "running")
        };
        watcher.wait_for("running on the new node", from, running).await;
        let at = watcher.wait_for("frames from the new node", from, is("position")).await;
        watcher.wait_for("more frames from the new node", at + 1, is("position")).await;
    }

    // Its new node stops cleanly (SIGTERM): the websocket through the other node follows the
    // controller there (relayed by that node to itself) and closes with 4404 when it is deleted.
    let on_two = hosted(&two).await.contains(&id);
    let (mut owner, survivor, watcher, gone) =
        if on_two { (two, three, through_three, through_two) } else { (three, two, through_two, through_three) };
    let from = watcher.len();
    let (status, _) = owner.terminate(Duration::from_secs(30));
    assert!(status.success(), "{status}; log: {}", owner.log());
    let (code, reason) = gone.wait_closed("the websocket on the stopped node").await;
    assert_eq!((code, reason.as_str()), (1001, "server shutting down"));
    let at = watcher.wait_for("a fresh snapshot after the clean stop", from, is("snapshot")).await;
    assert_eq!(watcher.messages()[at].2["controller"]["id"], json!(id));
    eventually("the controller on the survivor", || async {
        let hosted = hosted(&survivor).await;
        (!hosted.contains(&id)).then(|| format!("{hosted:?}"))
    })
    .await;
    let from = watcher.len();
    until_hosted(&survivor, Method::POST, &format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
    watcher.wait_for("frames after the clean stop", from, is("position")).await;
    let deleted = survivor.request(Method::DELETE, &format!("{C}/{id}"), &[], "").await;
    assert_eq!(deleted.status, StatusCode::NO_CONTENT, "{:?}", deleted.body);
    let (code, reason) = watcher.wait_closed("the websocket of the deleted controller").await;
    assert_eq!((code, reason.as_str()), (4404, "controller deleted"));
    assert_eq!(metric(&survivor, "fivex_relay_publishers").await, 0.0);
}
