//! Timeouts and limits (issue 18, item 4; `docs/api.md` "Connections and limits"): connections
//! that never finish their request head are closed, the connection and websocket caps refuse
//! the excess, fleet runs queue and can be cancelled, and SIGTERM ends the service within
//! seconds while everything is busy.

use std::net::SocketAddr;
use std::time::{Duration, Instant};

use futures_util::StreamExt;
use hyper::Method;
use serde_json::{json, Value};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::{TcpSocket, TcpStream};
use tokio_tungstenite::tungstenite;

use super::served::Served;

/// A program that never ends and never moves: one block after another, as fast as the
/// interpreter goes (without a cancel, only the 50-million-block guard would stop it).
const ENDLESS: &str = "O1\n#1=0\nWHILE[#1 GE 0]DO1\n#1=#1+1\nEND1\nM30\n";

/// A connection from `source` (any 127.x.y.z: all of them are loopback on Linux, so a test can
/// be several clients).
async fn connect_from(served: &Served, source: &str) -> TcpStream {
    let socket = TcpSocket::new_v4().unwrap();
    socket.bind(format!("{source}:0").parse().unwrap()).unwrap();
    let addr: SocketAddr = served.addr.parse().unwrap();
    socket.connect(addr).await.unwrap()
}

/// What the server does with a connection within `limit`: `Some(bytes)` when it answered
/// something, `None` when it closed it without a byte (end of stream or reset).
async fn read_or_close(stream: &mut TcpStream, limit: Duration) -> Option<Vec<u8>> {
    let mut buf = vec![0u8; 4096];
    match tokio::time::timeout(limit, stream.read(&mut buf)).await {
        Ok(Ok(0)) | Ok(Err(_)) => None,
        Ok(Ok(n)) => Some(buf[..n].to_vec()),
        Err(_) => panic!("the server neither answered nor closed the connection within {limit:?}"),
    }
}

/// A kept-alive connection that asked `/healthz` and got its 200: it stays open.
async fn held_connection(served: &Served, source: &str) -> TcpStream {
    let mut stream = connect_from(served, source).await;
    stream.write_all(b"GET /healthz HTTP/1.1\r\nHost: localhost\r\n\r\n").await.unwrap();
    let answer = read_or_close(&mut stream, Duration::from_secs(20)).await.expect("an answer");
    let text = String::from_utf8_lossy(&answer);
    assert!(text.starts_with("HTTP/1.1 200"), "{text}");
    stream
}

/// A connection the server closed without answering (beyond a connection cap).
async fn assert_refused(served: &Served, source: &str) {
    let mut stream = connect_from(served, source).await;
    // Whether the request is still written or the reset came first does not matter.
    let _ = stream.write_all(b"GET /healthz HTTP/1.1\r\nHost: localhost\r\n\r\n").await;
    let answer = read_or_close(&mut stream, Duration::from_secs(20)).await;
    assert!(
        answer.is_none(),
        "answered beyond the cap: {:?}",
        answer.map(|a| String::from_utf8_lossy(&a).into_owned())
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn half_open_connections_are_closed_after_the_header_timeout_while_healthz_answers() {
    let served = Served::start(&["--header-timeout", "2"]);
    let mut half_open = Vec::new();
    for _ in 0..200 {
        let mut stream = connect_from(&served, "127.0.0.1").await;
        stream.write_all(b"GET / HTTP/1.1\r\n").await.unwrap();
        half_open.push(stream);
    }
    let started = Instant::now();
    let health = served.get("/healthz").await;
    assert_eq!(health.status, 200, "/healthz while 200 connections hang");
    for (i, stream) in half_open.iter_mut().enumerate() {
        let left = Duration::from_secs(30).saturating_sub(started.elapsed());
        let answer = read_or_close(stream, left).await;
        assert!(
            answer.is_none(),
            "connection {i} was answered: {:?}",
            answer.map(|a| String::from_utf8_lossy(&a).into_owned())
        );
    }
    // The bound is generous (a loaded 2-core machine); the header timeout is 2 s.
    assert!(started.elapsed() < Duration::from_secs(30), "{:?}", started.elapsed());
    assert_eq!(served.get("/healthz").await.status, 200);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_connection_that_says_nothing_and_a_kept_alive_idle_one_are_closed() {
    let served = Served::start(&["--header-timeout", "1", "--idle-timeout", "2"]);
    let mut silent = connect_from(&served, "127.0.0.1").await;
    let mut kept = held_connection(&served, "127.0.0.1").await;
    assert!(read_or_close(&mut silent, Duration::from_secs(20)).await.is_none());
    assert!(read_or_close(&mut kept, Duration::from_secs(20)).await.is_none());
}

/// The head of a `POST /api/v1/controllers` whose JSON body is `length` bytes long.
fn create_head(length: usize) -> String {
    format!("POST /api/v1/controllers HTTP/1.1\r\nHost: localhost\r\ncontent-type: application/json\r\ncontent-length: {length}\r\n\r\n")
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_request_body_that_stops_coming_is_cut_but_a_slow_steady_one_is_not() {
    let served = Served::start(&["--body-timeout", "2"]);
    let body = json!({"name": "slow but steady", "preset": "mill3"}).to_string();
    // Stalled: a tenth of the body, then nothing.
    let mut stalled = connect_from(&served, "127.0.0.1").await;
    stalled.write_all(format!("{}{}", create_head(body.len()), &body[..4]).as_bytes()).await.unwrap();
    // Steady: a piece every 0.25 s, 5 s in all, far longer than the body timeout.
    let mut steady = connect_from(&served, "127.0.0.1").await;
    steady.write_all(create_head(body.len()).as_bytes()).await.unwrap();
    let pieces: Vec<&[u8]> = body.as_bytes().chunks(body.len().div_ceil(20)).collect();
    for piece in pieces {
        tokio::time::sleep(Duration::from_millis(250)).await;
        steady.write_all(piece).await.unwrap();
    }
    let answer = read_or_close(&mut steady, Duration::from_secs(20)).await.expect("the steady body was answered");
    let text = String::from_utf8_lossy(&answer);
    assert!(text.starts_with("HTTP/1.1 201"), "{text}");
    let answer = read_or_close(&mut stalled, Duration::from_secs(20)).await;
    assert!(
        answer.is_none(),
        "the stalled body was answered: {:?}",
        answer.map(|a| String::from_utf8_lossy(&a).into_owned())
    );
    let listed = served.get("/api/v1/controllers").await.json();
    assert_eq!(listed.as_array().unwrap().len(), 1, "{listed}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_client_that_takes_nothing_of_its_answers_is_cut() {
    let served = Served::start(&["--body-timeout", "1"]);
    // 20 pipelined requests for a 1.4 MB file: far more than the socket buffers hold.
    let path = "/swagger-ui/swagger-ui-bundle.js";
    let one = served.get(path).await;
    assert_eq!(one.status, 200);
    let asked = 20 * one.body.len();
    let mut stream = connect_from(&served, "127.0.0.1").await;
    let request = format!("GET {path} HTTP/1.1\r\nHost: localhost\r\n\r\n");
    stream.write_all(request.repeat(20).as_bytes()).await.unwrap();
    // Take nothing for a while (the server's writes stall once the buffers are full) …
    tokio::time::sleep(Duration::from_secs(5)).await;
    // … then everything there is: what was buffered, then the end.
    let mut got = 0;
    let mut buf = vec![0u8; 1 << 16];
    let read_all = async {
        loop {
            match stream.read(&mut buf).await {
                Ok(0) | Err(_) => break,
                Ok(n) => got += n,
            }
        }
    };
    tokio::time::timeout(Duration::from_secs(30), read_all).await.expect("the connection was never closed");
    assert!(got < asked, "all {got} bytes were sent: the connection was never cut");
    assert_eq!(served.get("/healthz").await.status, 200);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_connection_caps_refuse_the_excess_per_client_and_in_all() {
    let served = Served::start(&["--max-connections", "6", "--max-connections-per-client", "4"]);
    let mut first = Vec::new();
    for _ in 0..4 {
        first.push(held_connection(&served, "127.0.0.1").await);
    }
    assert_refused(&served, "127.0.0.1").await;
    // Another client still gets in, up to the total.
    let second = vec![held_connection(&served, "127.0.0.2").await, held_connection(&served, "127.0.0.2").await];
    assert_refused(&served, "127.0.0.3").await;
    // Closed connections give their places back.
    drop(first);
    drop(second);
    let deadline = Instant::now() + Duration::from_secs(20);
    loop {
        let mut stream = connect_from(&served, "127.0.0.1").await;
        let _ = stream.write_all(b"GET /healthz HTTP/1.1\r\nHost: localhost\r\n\r\n").await;
        if let Some(answer) = read_or_close(&mut stream, Duration::from_secs(20)).await {
            assert!(String::from_utf8_lossy(&answer).starts_with("HTTP/1.1 200"));
            break;
        }
        assert!(Instant::now() < deadline, "the places were never given back");
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
}

/// A websocket upgrade of `/api/v1/stream` from `source`: `Ok` with the socket, or the refusal's
/// status and JSON body.
async fn websocket_from(
    served: &Served,
    source: &str,
) -> Result<tokio_tungstenite::WebSocketStream<TcpStream>, (u16, Value)> {
    let stream = connect_from(served, source).await;
    let url = format!("ws://{}/api/v1/stream", served.addr);
    match tokio_tungstenite::client_async(url, stream).await {
        Ok((socket, _)) => Ok(socket),
        Err(tungstenite::Error::Http(response)) => {
            let body = response.body().clone().unwrap_or_default();
            let json = serde_json::from_slice(&body).unwrap_or_else(|e| panic!("not JSON ({e}): {body:?}"));
            Err((response.status().as_u16(), json))
        }
        Err(e) => panic!("websocket: {e}"),
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_websocket_caps_refuse_with_429_per_client_and_503_in_all() {
    let served = Served::start(&["--max-websockets", "3", "--max-websockets-per-client", "2"]);
    let mut open = Vec::new();
    for _ in 0..2 {
        open.push(websocket_from(&served, "127.0.0.1").await.expect("within the caps"));
    }
    let (status, body) = websocket_from(&served, "127.0.0.1").await.expect_err("refused");
    assert_eq!(status, 429);
    assert!(body["error"].as_str().unwrap().contains("websockets"), "{body}");
    open.push(websocket_from(&served, "127.0.0.2").await.expect("another client"));
    let (status, body) = websocket_from(&served, "127.0.0.3").await.expect_err("refused");
    assert_eq!(status, 503);
    assert!(body["error"].is_string(), "{body}");
    // The open ones work: each got the fleet snapshot.
    for socket in &mut open {
        let first = tokio::time::timeout(Duration::from_secs(20), socket.next()).await.unwrap().unwrap().unwrap();
        assert!(first.to_text().unwrap().contains("\"fleet\""), "{first:?}");
    }
    // A closed websocket gives its place back.
    drop(open);
    let deadline = Instant::now() + Duration::from_secs(20);
    while websocket_from(&served, "127.0.0.1").await.is_err() {
        assert!(Instant::now() < deadline, "the websocket places were never given back");
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
}

/// Posts a fleet run without waiting; its id.
async fn start_run(served: &Served, program: &str) -> String {
    let reply = served
        .send_json(Method::POST, "/api/v1/fleet/runs?wait=false", &json!({"program": program, "presets": ["mill3"]}))
        .await;
    assert_eq!(reply.status, 202, "{:?}", reply.json());
    reply.json()["id"].as_str().unwrap().to_string()
}

async fn run_status(served: &Served, id: &str) -> Value {
    let reply = served.get(&format!("/api/v1/fleet/runs/{id}")).await;
    assert_eq!(reply.status, 200);
    reply.json()
}

/// Waits (at most 30 s) until the run's status is `status`.
async fn wait_for_status(served: &Served, id: &str, status: &str) -> Value {
    let deadline = Instant::now() + Duration::from_secs(30);
    loop {
        let run = run_status(served, id).await;
        if run["status"] == status {
            return run;
        }
        assert!(Instant::now() < deadline, "run {id} never became {status}: {run}");
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_endless_fleet_run_is_cancelled_within_seconds() {
    let served = Served::start(&[]);
    let id = start_run(&served, ENDLESS).await;
    wait_for_status(&served, &id, "running").await;
    let asked = Instant::now();
    let reply = served.request(Method::POST, &format!("/api/v1/fleet/runs/{id}/cancel"), &[], "").await;
    let took = asked.elapsed();
    assert_eq!(reply.status, 200, "{:?}", reply.json());
    assert_eq!(reply.json()["status"], "cancelled");
    // Promptly: the engine looks at the flag before every block. Generous for a loaded machine.
    assert!(took < Duration::from_secs(5), "{took:?}");
    let run = run_status(&served, &id).await;
    assert_eq!(run["status"], "cancelled");
    assert!(run["finished_at"].is_string(), "{run}");
    assert_eq!(run["results"], json!([null]), "the machine did not finish");
    // Its stream tells the same, by the machine's name.
    let url = format!("ws://{}/api/v1/fleet/runs/{id}/stream", served.addr);
    let (mut socket, _) = tokio_tungstenite::connect_async(url).await.expect("the run's stream");
    let message = tokio::time::timeout(Duration::from_secs(20), socket.next()).await.unwrap().unwrap().unwrap();
    let progress: Value = serde_json::from_str(message.to_text().unwrap()).unwrap();
    assert_eq!(progress["status"], "cancelled", "{progress}");
    assert_eq!(progress["finished"], true);
    assert_eq!(progress["machines"], json!([{"machine": "mill3", "state": "cancelled", "cycle_time_s": null}]));
    // Cancelling it again, or a run that does not exist.
    let again = served.request(Method::POST, &format!("/api/v1/fleet/runs/{id}/cancel"), &[], "").await;
    assert_eq!(again.status, 409);
    assert!(again.json()["error"].as_str().unwrap().contains("already over"));
    let none = served.request(Method::POST, "/api/v1/fleet/runs/nope/cancel", &[], "").await;
    assert_eq!(none.status, 404);
    assert!(none.json()["error"].is_string());
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn with_one_fleet_job_a_second_run_waits_queued_until_the_first_ends() {
    let served = Served::start(&["--fleet-jobs", "1"]);
    let first = start_run(&served, ENDLESS).await;
    wait_for_status(&served, &first, "running").await;
    let second = start_run(&served, "O2\nG91 G01 X10. F1000\nM30\n").await;
    let third = start_run(&served, "O3\nG91 G01 X10. F1000\nM30\n").await;
    // However long we look, they wait: the first never ends by itself.
    for _ in 0..10 {
        assert_eq!(run_status(&served, &second).await["status"], "queued");
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    // A queued run cancelled never runs.
    let reply = served.request(Method::POST, &format!("/api/v1/fleet/runs/{third}/cancel"), &[], "").await;
    assert_eq!(reply.status, 200);
    assert_eq!(reply.json()["status"], "cancelled");
    assert_eq!(run_status(&served, &first).await["status"], "running");
    assert_eq!(run_status(&served, &second).await["status"], "queued");
    // The first ends: the second runs and completes.
    let reply = served.request(Method::POST, &format!("/api/v1/fleet/runs/{first}/cancel"), &[], "").await;
    assert_eq!(reply.status, 200);
    let done = wait_for_status(&served, &second, "done").await;
    assert_eq!(done["completed"], 1);
    assert_eq!(done["results"][0]["status"], "completed");
    let third = run_status(&served, &third).await;
    assert_eq!(third["status"], "cancelled");
    assert_eq!(third["results"], json!([null]));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn sigterm_under_load_exits_0_within_seconds_and_records_the_fleet_run_interrupted() {
    let mut served = Served::start(&[]);
    let cycling = "O1\nWHILE[1 EQ 1]DO1\nG91 G01 X10. F3000\nX-10.\nEND1\nM30\n";
    let mut ids = Vec::new();
    for i in 0..20 {
        let reply = served
            .send_json(Method::POST, "/api/v1/controllers", &json!({"name": format!("cell {i}"), "preset": "mill3"}))
            .await;
        assert_eq!(reply.status, 201, "{:?}", reply.json());
        let id = reply.json()["id"].as_str().unwrap().to_string();
        let stored = served
            .request(
                Method::PUT,
                &format!("/api/v1/controllers/{id}/programs/1"),
                &[("content-type", "text/plain")],
                cycling,
            )
            .await;
        assert_eq!(stored.status, 201, "{:?}", stored.json());
        let started = served
            .send_json(Method::POST, &format!("/api/v1/controllers/{id}/cycle-start"), &json!({"program": 1}))
            .await;
        assert_eq!(started.status, 200, "{:?}", started.json());
        assert_eq!(started.json()["run_state"], "running");
        ids.push(id);
    }
    let mut sockets = Vec::new();
    for id in &ids[..3] {
        let url = format!("ws://{}/api/v1/controllers/{id}/stream", served.addr);
        sockets.push(tokio_tungstenite::connect_async(url).await.expect("controller stream").0);
    }
    sockets.push(tokio_tungstenite::connect_async(format!("ws://{}/api/v1/stream", served.addr)).await.unwrap().0);
    let run = start_run(&served, ENDLESS).await;
    wait_for_status(&served, &run, "running").await;
    // And a request that waits for a fleet run (queued behind the endless one).
    let waiting = served.url("/api/v1/fleet/runs");
    let waiter = tokio::spawn(async move {
        let client = hyper_util::client::legacy::Client::builder(hyper_util::rt::TokioExecutor::new()).build_http();
        let body = json!({"program": ENDLESS, "presets": ["mill3"]}).to_string();
        let request = hyper::Request::post(waiting)
            .header("content-type", "application/json")
            .body(http_body_util::Full::new(bytes::Bytes::from(body)))
            .unwrap();
        client.request(request).await.map(|r| r.status().as_u16())
    });
    // The waiting request's run is stored, queued behind the endless one.
    let deadline = Instant::now() + Duration::from_secs(30);
    while served.get("/api/v1/fleet/runs").await.json().as_array().unwrap().len() < 2 {
        assert!(Instant::now() < deadline, "the waiting request's run was never stored");
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    // Everything is busy: the sockets receive.
    for socket in &mut sockets {
        let first = tokio::time::timeout(Duration::from_secs(20), socket.next()).await.unwrap().unwrap().unwrap();
        assert!(first.is_text());
    }
    let (status, took) = served.terminate(Duration::from_secs(10));
    assert!(status.success(), "{status} after {took:?}; log: {}", served.log());
    // The waiting request was answered: the run it waited for was interrupted.
    let waited =
        tokio::time::timeout(Duration::from_secs(10), waiter).await.expect("the waiting request ended").unwrap();
    assert_eq!(waited.expect("an answer before the exit"), 503);
    // Every websocket ended (a close frame, or the end of the stream).
    for mut socket in sockets {
        let ended = tokio::time::timeout(Duration::from_secs(10), async {
            while let Some(Ok(message)) = socket.next().await {
                if message.is_close() {
                    break;
                }
            }
        })
        .await;
        assert!(ended.is_ok(), "a websocket stayed open after the exit");
    }
    // Recorded as interrupted by the shutdown itself, before any restart.
    let dir = std::mem::replace(&mut served.dir, tempfile::tempdir().unwrap());
    drop(served);
    let served = Served::start_in(dir, &[]);
    let stored = run_status(&served, &run).await;
    assert_eq!(stored["status"], "interrupted", "{stored}");
    assert!(stored["finished_at"].is_string(), "recorded at the shutdown, not at the restart: {stored}");
    let listed = served.get("/api/v1/fleet/runs").await.json();
    let statuses: Vec<&str> = listed.as_array().unwrap().iter().map(|r| r["status"].as_str().unwrap()).collect();
    assert_eq!(statuses, ["interrupted", "interrupted"], "{listed}");
}

#[test]
fn limits_out_of_range_are_usage_errors() {
    for args in
        [["--header-timeout", "0"], ["--body-timeout", "soon"], ["--fleet-jobs", "0"], ["--max-connections", "0"]]
    {
        let dir = tempfile::tempdir().unwrap();
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_fivex"))
            .arg("serve")
            .arg("--db")
            .arg(dir.path().join("fivex.db"))
            .args(["--addr", "127.0.0.1:0"])
            .args(args)
            .output()
            .expect("run fivex serve");
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains(args[0]), "{args:?}: {stderr}");
        assert!(!dir.path().join("fivex.db").exists(), "{args:?}: nothing is created");
    }
}
