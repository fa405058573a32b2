//! `fivex-load`: a bounded load test of `fivex serve` on loopback. It starts the service (the
//! `fivex` binary next to this one, or `--fivex PATH`) on a fresh database, creates N
//! controllers running an endless program, subscribes to each controller's stream, and after a
//! warm-up measures for a while:
//!
//! - position frame lag: the client's clock when a frame arrives minus the server's clock when
//!   the frame was made (`wall_ms`), p50 / p99 / max over every frame;
//! - real time: how far each controller's simulated time advanced against the wall clock over
//!   the measurement (a controller "behind" advanced less than 99 %);
//! - CPU: the service's user + system time over the measurement, in cores.
//!
//! It prints one JSON object and exits 0 if the goal holds (p99 lag under `--p99-ms`, no
//! controller behind), 1 otherwise. `docs/performance.md` has the command and the figures.

use std::path::PathBuf;
use std::process::Stdio;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use clap::Parser;
use futures_util::StreamExt;
use serde::Deserialize;
use serde_json::{json, Value};
use tokio::io::{AsyncBufReadExt, BufReader};

#[derive(Parser, Debug)]
#[command(name = "fivex-load", about = "Load test of fivex serve on loopback: N controllers, a stream each")]
struct Args {
    /// Controllers to run.
    #[arg(long, default_value_t = 100)]
    controllers: usize,
    /// Seconds to measure (after the warm-up).
    #[arg(long, default_value_t = 20.0)]
    seconds: f64,
    /// Seconds to let everything settle before measuring.
    #[arg(long, default_value_t = 5.0)]
    warmup: f64,
    /// Position frames per second each subscriber asks for.
    #[arg(long, default_value_t = 30.0)]
    rate: f64,
    /// Machine preset of every controller.
    #[arg(long, default_value = "table-ac")]
    preset: String,
    /// The goal: p99 lag below this many milliseconds.
    #[arg(long, default_value_t = 100.0)]
    p99_ms: f64,
    /// The fivex binary (default: next to this one).
    #[arg(long)]
    fivex: Option<PathBuf>,
    /// Worker threads of the service (default: its own).
    #[arg(long)]
    workers: Option<usize>,
}

/// The program every controller runs: a square with the rotary axes turning, forever.
const PROGRAM: &str = "#1=0\nWHILE [#1 LT 1000000] DO1\nG90 G01 X100. Y0 Z10. A10. C90. F3000\nX100. Y100. A0 C180.\nX0 Y100. A-10. C270.\nX0 Y0 A0 C360.\n#1=#1+1\nEND1\nM30\n";

#[derive(Deserialize)]
struct Frame {
    #[serde(rename = "type")]
    kind: String,
    #[serde(default)]
    t: f64,
    #[serde(default)]
    wall_ms: f64,
}

fn now_ms() -> f64 {
    std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).unwrap().as_secs_f64() * 1000.0
}

/// user + system CPU seconds of a process (Linux `/proc/PID/stat`).
fn cpu_seconds(pid: u32) -> Option<f64> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    let rest = &stat[stat.rfind(')')? + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

/// Per subscriber: lags measured, and the simulated time at the start and end of measuring.
#[derive(Default)]
struct Seen {
    lags: Vec<f64>,
    first_t: Option<(f64, f64)>,
    last_t: Option<(f64, f64)>,
}

fn percentile(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    sorted[((sorted.len() - 1) as f64 * p).round() as usize]
}

#[tokio::main(flavor = "multi_thread", worker_threads = 2)]
async fn main() {
    let args = Args::parse();
    let fivex = args.fivex.clone().unwrap_or_else(|| std::env::current_exe().unwrap().with_file_name("fivex"));
    let dir = std::env::temp_dir().join(format!("fivex-load-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let db = dir.join("load.db");
    let mut cmd = tokio::process::Command::new(&fivex);
    cmd.arg("serve")
        .arg("--db")
        .arg(&db)
        .args(["--addr", "127.0.0.1:0"])
        .env("RUST_LOG", "warn,fivex_server::serve=info");
    if let Some(w) = args.workers {
        cmd.args(["--workers", &w.to_string()]);
    }
    let mut child =
        cmd.stderr(Stdio::piped()).stdout(Stdio::null()).kill_on_drop(true).spawn().expect("start fivex serve");
    let pid = child.id().unwrap();
    let mut lines = BufReader::new(child.stderr.take().unwrap()).lines();
    let addr = loop {
        let line = lines.next_line().await.unwrap().expect("fivex serve ended before listening");
        if let Some(at) = line.find("listening on http://") {
            break line[at + "listening on http://".len()..].trim().to_string();
        }
    };
    tokio::spawn(async move { while let Ok(Some(_)) = lines.next_line().await {} });
    let base = format!("http://{addr}/api/v1");
    let http = Http::new();

    // Controllers and their program.
    let mut ids = Vec::new();
    for k in 0..args.controllers {
        let c = http
            .post(&format!("{base}/controllers"), &json!({"name": format!("load {k}"), "preset": args.preset}))
            .await;
        let id = c["id"].as_str().expect("a controller id").to_string();
        http.put_text(&format!("{base}/controllers/{id}/programs/1"), PROGRAM).await;
        ids.push(id);
    }
    // A subscriber each, then cycle start.
    let measuring = Arc::new(AtomicBool::new(false));
    let seen: Vec<Arc<Mutex<Seen>>> = ids.iter().map(|_| Arc::new(Mutex::new(Seen::default()))).collect();
    for (id, seen) in ids.iter().zip(&seen) {
        let url = format!("ws://{addr}/api/v1/controllers/{id}/stream?rate={}", args.rate);
        let (ws, _) = tokio_tungstenite::connect_async(url).await.expect("websocket");
        let (seen, measuring) = (seen.clone(), measuring.clone());
        tokio::spawn(async move {
            let (_, mut rx) = ws.split();
            while let Some(Ok(msg)) = rx.next().await {
                let tokio_tungstenite::tungstenite::Message::Text(text) = msg else { continue };
                let Ok(frame) = serde_json::from_str::<Frame>(text.as_str()) else { continue };
                if frame.kind != "position" || !measuring.load(Ordering::Relaxed) {
                    continue;
                }
                let now = now_ms();
                let mut s = seen.lock().unwrap();
                s.lags.push(now - frame.wall_ms);
                s.first_t.get_or_insert((frame.t, now));
                s.last_t = Some((frame.t, now));
            }
        });
    }
    for id in &ids {
        http.post(&format!("{base}/controllers/{id}/cycle-start"), &json!({"program": 1})).await;
    }
    tokio::time::sleep(Duration::from_secs_f64(args.warmup)).await;
    let (cpu0, t0) = (cpu_seconds(pid), Instant::now());
    measuring.store(true, Ordering::Relaxed);
    tokio::time::sleep(Duration::from_secs_f64(args.seconds)).await;
    measuring.store(false, Ordering::Relaxed);
    let (cpu1, wall) = (cpu_seconds(pid), t0.elapsed().as_secs_f64());

    // Every controller still running, no alarms.
    let mut running = 0;
    for id in &ids {
        if http.get(&format!("{base}/controllers/{id}")).await["run_state"] == "running" {
            running += 1;
        }
    }
    let mut lags = Vec::new();
    let (mut behind, mut silent, mut worst_ratio) = (0, 0, f64::INFINITY);
    for s in &seen {
        let s = s.lock().unwrap();
        lags.extend_from_slice(&s.lags);
        match (s.first_t, s.last_t) {
            (Some((t0, w0)), Some((t1, w1))) if w1 - w0 > 1000.0 => {
                let ratio = (t1 - t0) / ((w1 - w0) / 1000.0);
                worst_ratio = worst_ratio.min(ratio);
                if ratio < 0.99 {
                    behind += 1;
                }
            }
            _ => silent += 1,
        }
    }
    lags.sort_by(f64::total_cmp);
    let cores = match (cpu0, cpu1) {
        (Some(a), Some(b)) => (b - a) / wall,
        _ => f64::NAN,
    };
    let p99 = percentile(&lags, 0.99);
    let report = json!({
        "controllers": args.controllers,
        "preset": args.preset,
        "rate_hz": args.rate,
        "measured_s": wall,
        "frames": lags.len(),
        "lag_ms": {"p50": percentile(&lags, 0.5), "p99": p99, "max": lags.last().copied().unwrap_or(f64::NAN)},
        "running_at_end": running,
        "behind_real_time": behind,
        "without_frames": silent,
        "slowest_sim_per_wall": worst_ratio,
        "service_cpu_cores": cores,
        "cores": std::thread::available_parallelism().map_or(0, |n| n.get()),
    });
    println!("{}", serde_json::to_string_pretty(&report).unwrap());
    let _ = child.kill().await;
    let _ = std::fs::remove_dir_all(&dir);
    let ok = p99 < args.p99_ms && behind == 0 && silent == 0 && running == args.controllers;
    std::process::exit(if ok { 0 } else { 1 });
}

/// A minimal JSON-over-HTTP client (hyper), enough for setting the load up.
struct Http {
    client: hyper_util::client::legacy::Client<
        hyper_util::client::legacy::connect::HttpConnector,
        http_body_util::Full<bytes::Bytes>,
    >,
}

impl Http {
    fn new() -> Http {
        let client = hyper_util::client::legacy::Client::builder(hyper_util::rt::TokioExecutor::new()).build_http();
        Http { client }
    }

    async fn send(&self, method: &str, url: &str, content_type: &str, body: String) -> Value {
        use http_body_util::BodyExt;
        let request = hyper::Request::builder()
            .method(method)
            .uri(url)
            .header("content-type", content_type)
            .body(http_body_util::Full::new(bytes::Bytes::from(body)))
            .unwrap();
        let response = self.client.request(request).await.unwrap_or_else(|e| panic!("{method} {url}: {e}"));
        let status = response.status();
        let bytes = response.into_body().collect().await.unwrap().to_bytes();
        assert!(status.is_success(), "{method} {url}: {status} {}", String::from_utf8_lossy(&bytes));
        serde_json::from_slice(&bytes).unwrap_or(Value::Null)
    }

    async fn get(&self, url: &str) -> Value {
        self.send("GET", url, "application/json", String::new()).await
    }

    async fn post(&self, url: &str, body: &Value) -> Value {
        self.send("POST", url, "application/json", body.to_string()).await
    }

    async fn put_text(&self, url: &str, text: &str) -> Value {
        self.send("PUT", url, "text/plain", text.to_string()).await
    }
}
