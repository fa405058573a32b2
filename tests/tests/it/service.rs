//! `fivex serve` as a user runs it: the real binary on a loopback port, driven over HTTP and a
//! websocket. A program runs and its positions, state changes and variables arrive on the
//! stream; the service stops gracefully (closing the stream) or is killed, and after a restart
//! everything that was acknowledged is still there.

use crate::common;

use std::io::{BufRead, BufReader};
use std::net::TcpStream;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use common::{fivex, fivex_bin, stdout};
use serde_json::{json, Value};
use tungstenite::stream::MaybeTlsStream;
use tungstenite::{Message, WebSocket};

/// A running `fivex serve`, stopped (SIGKILL) when dropped.
struct Server {
    child: Child,
    base: String,
    addr: String,
}

impl Server {
    /// Start on `db`, port 0; wait for the address it announces.
    fn start(db: &Path) -> Server {
        let mut child = Command::new(fivex_bin())
            .args(["serve", "--db"])
            .arg(db)
            .args(["--addr", "127.0.0.1:0"])
            .env("RUST_LOG", "info")
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start fivex serve");
        let stderr = child.stderr.take().unwrap();
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let mut sent = false;
            for line in BufReader::new(stderr).lines().map_while(Result::ok) {
                if !sent {
                    if let Some(at) = line.find("listening on http://") {
                        let _ = tx.send(line[at + "listening on http://".len()..].trim().to_string());
                        sent = true;
                    }
                }
            }
        });
        let addr = rx.recv_timeout(Duration::from_secs(30)).expect("the server announces its address");
        Server { child, base: format!("http://{addr}/api/v1"), addr }
    }

    fn signal(&mut self, signal: i32) {
        unsafe {
            libc::kill(self.child.id() as i32, signal);
        }
    }

    /// SIGTERM, and the exit status.
    fn stop(mut self) -> std::process::ExitStatus {
        self.signal(libc::SIGTERM);
        let deadline = Instant::now() + Duration::from_secs(20);
        loop {
            if let Some(status) = self.child.try_wait().unwrap() {
                return status;
            }
            assert!(Instant::now() < deadline, "the server did not stop after SIGTERM");
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    fn kill(mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }

    fn get(&self, path: &str) -> Value {
        let mut reply = ureq::get(&format!("{}{path}", self.base)).call().unwrap_or_else(|e| panic!("GET {path}: {e}"));
        reply.body_mut().read_json().unwrap()
    }

    fn send(&self, method: &str, path: &str, body: &Value) -> Value {
        let url = format!("{}{path}", self.base);
        let agent = ureq::Agent::new_with_defaults();
        let request = match method {
            "POST" => agent.post(&url),
            "PUT" => agent.put(&url),
            other => panic!("{other}"),
        };
        let mut reply = request.send_json(body).unwrap_or_else(|e| panic!("{method} {path}: {e}"));
        reply.body_mut().read_json().unwrap()
    }

    fn put_text(&self, path: &str, text: &str) {
        ureq::put(&format!("{}{path}", self.base))
            .header("content-type", "text/plain")
            .send(text)
            .unwrap_or_else(|e| panic!("PUT {path}: {e}"));
    }

    fn stream(&self, id: &str) -> WebSocket<MaybeTlsStream<TcpStream>> {
        let (socket, _) = tungstenite::connect(format!("ws://{}/api/v1/controllers/{id}/stream?rate=50", self.addr))
            .expect("websocket");
        if let MaybeTlsStream::Plain(s) = socket.get_ref() {
            s.set_read_timeout(Some(Duration::from_secs(20))).unwrap();
        }
        socket
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn next_json(ws: &mut WebSocket<MaybeTlsStream<TcpStream>>) -> Option<Value> {
    loop {
        match ws.read() {
            Ok(Message::Text(t)) => return Some(serde_json::from_str(t.as_str()).unwrap()),
            // Why the stream ended, for a test that fails on it (a stream closed under load was
            // seen twice and not reproduced: the close frame or the error says which side).
            Ok(Message::Close(frame)) => {
                eprintln!("the stream closed: {frame:?}");
                return None;
            }
            Err(e) => {
                eprintln!("the stream failed: {e}");
                return None;
            }
            Ok(_) => {}
        }
    }
}

#[test]
fn a_program_runs_over_the_api_the_stream_shows_it_and_a_restart_keeps_everything() {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("fivex.db");
    let server = Server::start(&db);
    let created = server.send("POST", "/controllers", &json!({"name": "cell", "preset": "table-ac", "speed": 4}));
    let id = created["id"].as_str().unwrap().to_string();
    let program = "G90 G01 X50. Y20. Z10. A10. C30. F3000\n#500=42\n#101=#500+1\nG01 X0 Y0 Z0 A0 C0\nM30\n";
    server.put_text(&format!("/controllers/{id}/programs/1"), program);

    let (mut fleet, _) = tungstenite::connect(format!("ws://{}/api/v1/stream?rate=10", server.addr)).unwrap();
    let first = next_json(&mut fleet).expect("fleet message");
    assert_eq!((first["type"].as_str(), first["controllers"][0]["name"].as_str()), (Some("fleet"), Some("cell")));
    assert_eq!(first["controllers"][0]["run_state"], "idle");
    let mut ws = server.stream(&id);
    let snapshot = next_json(&mut ws).expect("snapshot");
    assert_eq!(snapshot["type"], "snapshot");
    assert_eq!(snapshot["controller"]["run_state"], "idle");
    let started = server.send("POST", &format!("/controllers/{id}/cycle-start"), &json!({"program": 1}));
    assert_eq!(started["run_state"], "running");

    let (mut positions, mut states, mut variables) = (Vec::new(), Vec::new(), json!({}));
    let deadline = Instant::now() + Duration::from_secs(30);
    while Instant::now() < deadline {
        let Some(m) = next_json(&mut ws) else { break };
        match m["type"].as_str().unwrap() {
            "position" => positions.push(m),
            "state" => {
                let done = m["run_state"] == "idle";
                states.push(m["run_state"].as_str().unwrap().to_string());
                if done {
                    break;
                }
            }
            "variables" => {
                for (k, v) in m["changes"].as_object().unwrap() {
                    variables[k] = v.clone();
                }
            }
            _ => {}
        }
    }
    assert_eq!(states, ["running", "idle"], "state messages");
    // The fleet stream saw it run.
    let mut fleet_states = Vec::new();
    while let Some(m) = next_json(&mut fleet) {
        let state = m["controllers"][0]["run_state"].as_str().unwrap().to_string();
        let done = state == "idle";
        fleet_states.push(state);
        if done {
            break;
        }
    }
    assert!(fleet_states.contains(&"running".to_string()), "{fleet_states:?}");
    assert!(positions.len() > 20, "{} position frames", positions.len());
    let moved = positions.iter().any(|p| p["machine"]["A"].as_f64().unwrap() > 5.0);
    assert!(moved, "the frames show A turning");
    // `tip` is where the machine puts the tip (zero work offset, no tool length: `fivex kin fk`
    // of the frame's axes); with A turning outside TCP it leaves the programmed point.
    let turned = positions.iter().find(|p| p["machine"]["A"].as_f64().unwrap() > 5.0).unwrap();
    let m = &turned["machine"];
    let axes = ["X", "Y", "Z", "A", "C"].map(|a| format!("{a}={}", m[a].as_f64().unwrap())).join(",");
    let fk: Value =
        serde_json::from_str(&stdout(&fivex(&["kin", "fk", "--preset", "table-ac", "--axes", &axes]))).unwrap();
    for k in 0..3 {
        let (tip, want) = (turned["tip"][k].as_f64().unwrap(), fk["tip"][k].as_f64().unwrap());
        assert!((tip - want).abs() < 1e-9, "{turned}\nfk {fk}");
    }
    assert_eq!(turned["programmed_in"], "workpiece");
    let apart = |p: &Value| {
        (0..3).map(|k| (p["tip"][k].as_f64().unwrap() - p["programmed"][k].as_f64().unwrap()).abs()).fold(0.0, f64::max)
    };
    assert!(positions.iter().any(|p| apart(p) > 1.0), "the tip leaves the programmed point while A turns");
    let times: Vec<f64> = positions.iter().map(|p| p["t"].as_f64().unwrap()).collect();
    assert!(times.windows(2).all(|w| w[1] > w[0]), "frames in time order");
    assert_eq!(variables, json!({"#500": 42.0, "#101": 43.0}), "variables streamed");
    assert_eq!(server.get(&format!("/controllers/{id}/variables/101"))["value"], 43.0);

    // A graceful stop closes the stream with a close frame and exits 0.
    let status = server.stop();
    assert!(status.success(), "{status:?}");
    assert_eq!(close_code(&mut ws), Some(1001), "the stream ends with 'going away'");

    // A restart finds the controller (reset state), its program and its retained variable.
    let server = Server::start(&db);
    let c = server.get(&format!("/controllers/{id}"));
    assert_eq!(
        (c["name"].as_str(), c["run_state"].as_str(), c["mode"].as_str()),
        (Some("cell"), Some("idle"), Some("auto"))
    );
    assert_eq!(server.get(&format!("/controllers/{id}/variables/500"))["value"], 42.0);
    assert_eq!(server.get(&format!("/controllers/{id}/variables/101"))["value"], Value::Null, "#101 is not retained");
    let text = ureq::get(&format!("{}/controllers/{id}/programs/1", server.base))
        .call()
        .unwrap()
        .body_mut()
        .read_to_string()
        .unwrap();
    assert_eq!(text, program);
    server.stop();
}

/// Under cutter compensation the stream's position frames carry `cutting`: the radius-5 tool
/// outside a square (G42) touches each side where it runs along it, and the frames of a block
/// without an offset value (before G42, the G40 block) have none.
#[test]
fn the_stream_shows_where_the_compensated_tool_touches_the_contour() {
    let dir = tempfile::tempdir().unwrap();
    let server = Server::start(&dir.path().join("fivex.db"));
    let created = server.send("POST", "/controllers", &json!({"name": "crc", "preset": "mill3", "speed": 4}));
    let id = created["id"].as_str().unwrap().to_string();
    server.send("PUT", &format!("/controllers/{id}/tool-offsets/1"), &json!({"radius": 5.0}));
    let program = "G90 G00 X0 Y-10. Z0\nG42 D1 G01 Y0 F600\nX20.\nY20.\nX0\nY0\nG40 Y-10.\nM30\n";
    server.put_text(&format!("/controllers/{id}/programs/1"), program);
    let mut ws = server.stream(&id);
    next_json(&mut ws).expect("snapshot");
    server.send("POST", &format!("/controllers/{id}/cycle-start"), &json!({"program": 1}));
    let mut positions = Vec::new();
    let deadline = Instant::now() + Duration::from_secs(30);
    while Instant::now() < deadline {
        let Some(m) = next_json(&mut ws) else { break };
        match m["type"].as_str().unwrap() {
            "position" => positions.push(m),
            "state" if m["run_state"] == "idle" => break,
            _ => {}
        }
    }
    let xyz = |v: &Value| [0, 1, 2].map(|k| v[k].as_f64().unwrap());
    let (mut on_side, mut worst) = (0, 0.0f64);
    for p in &positions {
        let line = p["line"].as_u64().unwrap();
        let cutting = p.get("cutting");
        if line == 1 || line == 7 {
            assert!(cutting.is_none(), "no cutting point without an offset value: {p}");
            continue;
        }
        // Along the sides X20 (line 3: y = 0) and Y20 (line 4: x = 20), inside their ends.
        let (tip, cut) = (xyz(&p["tip"]), cutting.map(xyz));
        let want = match line {
            3 if (1.0..19.0).contains(&tip[0]) => [tip[0], 0.0, 0.0],
            4 if (1.0..19.0).contains(&tip[1]) => [20.0, tip[1], 0.0],
            _ => continue,
        };
        let cut = cut.unwrap_or_else(|| panic!("a frame on a side without a cutting point: {p}"));
        worst = (0..3).map(|k| (cut[k] - want[k]).abs()).fold(worst, f64::max);
        on_side += 1;
    }
    assert!(on_side > 10, "{on_side} frames along the sides of {}", positions.len());
    assert!(worst < 1e-6, "the cutting point {worst} mm off the square's side");
    server.stop();
}

#[test]
fn what_was_acknowledged_survives_kill_9() {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("fivex.db");
    let server = Server::start(&db);
    let id = server.send("POST", "/controllers", &json!({"name": "k", "preset": "mill3"}))["id"]
        .as_str()
        .unwrap()
        .to_string();
    server.put_text(&format!("/controllers/{id}/programs/7"), "G01 X1. F100\nM30\n");
    server.send("PUT", &format!("/controllers/{id}/variables/999"), &json!({"value": 3.5}));
    server.kill();
    let server = Server::start(&db);
    assert_eq!(server.get(&format!("/controllers/{id}/variables/999"))["value"], 3.5);
    assert_eq!(server.get(&format!("/controllers/{id}/programs")), json!([{"number": 7, "size": 17}]));
    server.stop();
}

#[test]
fn a_client_that_never_reads_does_not_slow_anyone() {
    let dir = tempfile::tempdir().unwrap();
    let server = Server::start(&dir.path().join("fivex.db"));
    let id = server.send("POST", "/controllers", &json!({"name": "s", "preset": "mill3"}))["id"]
        .as_str()
        .unwrap()
        .to_string();
    server.put_text(&format!("/controllers/{id}/programs/1"), "G01 X300. F600\nM30\n");
    // A client that subscribes at the highest rate and never reads.
    let (stalled, _) =
        tungstenite::connect(format!("ws://{}/api/v1/controllers/{id}/stream?rate=1000", server.addr)).unwrap();
    server.send("POST", &format!("/controllers/{id}/cycle-start"), &json!({"program": 1}));
    let mut reader = server.stream(&id);
    next_json(&mut reader).expect("snapshot");
    // The reading client keeps getting fresh frames, and the controller keeps real time.
    let start = Instant::now();
    let mut last_t = 0.0;
    let mut frames = 0;
    while start.elapsed() < Duration::from_secs(3) {
        let m = next_json(&mut reader).expect("a message");
        if m["type"] == "position" {
            frames += 1;
            last_t = m["t"].as_f64().unwrap();
            let lag_ms = now_ms() - m["wall_ms"].as_f64().unwrap();
            assert!(lag_ms < 2000.0, "frame {lag_ms} ms old");
        }
    }
    assert!(frames > 50, "{frames} frames in 3 s at 50 Hz");
    let status = server.get(&format!("/controllers/{id}"));
    assert!(status["time_s"].as_f64().unwrap() >= last_t);
    drop(stalled);
    server.stop();
}

/// Read what is left on the stream; the close frame's code (None: the connection just broke).
fn close_code(ws: &mut WebSocket<MaybeTlsStream<TcpStream>>) -> Option<u16> {
    for _ in 0..100_000 {
        match ws.read() {
            Ok(Message::Close(frame)) => return frame.map(|f| f.code.into()),
            Ok(_) => {}
            Err(_) => return None,
        }
    }
    None
}

fn now_ms() -> f64 {
    std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).unwrap().as_secs_f64() * 1000.0
}
