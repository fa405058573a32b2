//! `fivex-load`: a bounded load test of `fivex serve` on loopback. It starts the service (the
//! `fivex` binary next to this one, or `--fivex PATH`) on a fresh database, creates N
//! controllers running an endless program, subscribes to each controller's stream, and after a
//! warm-up measures for a while:
//!
//! - position frame lag: the client's clock when a frame arrives minus the server's clock when
//!   the frame was made (`wall_ms`), p50 / p99 / max over every frame;
//! - real time: how far each controller's simulated time advanced against the wall clock over
//!   the measurement (a controller "behind" advanced less than 99 %);
//! - CPU: the service's user + system time over the measurement, in cores;
//! - memory: the service's resident set (`VmRSS`) empty, with the controllers idle, running,
//!   and every `--sample-every` seconds while measuring (its growth says whether memory is flat);
//! - with `--fleet-subscribers`, fleet stream messages and bytes; with `--writes-per-s`, a
//!   writer of variables (`PUT …/variables/500`) round-robin over the controllers; every
//!   refused request and every stream that ended counts as an error;
//! - with `--scrape-every`, `GET /metrics` that often: how long a scrape takes and its size, and
//!   what the service itself says (controllers behind real time, the largest lag, frames sent).
//!
//! - with `--nodes N --db postgres://… --nats nats://…`, a cluster of N nodes instead of one
//!   process on SQLite: controller k is created (so hosted) through node k mod N, its stream
//!   opened through the same node or, with `--relay`, through the next one (relayed); CPU and
//!   memory are the nodes' sums, and the report says what each node hosts at the end
//!   (`bench/cluster.sh` starts PostgreSQL and NATS and runs the series).
//!
//! - with `--mtconnect`, the service's MTConnect agent on: one `/sample` stream per controller
//!   (its device, `interval=100`) counting observations, their order and their age at arrival,
//!   and one client polling the whole agent from each `nextSequence` counting missing numbers;
//!   with `--opcua` its OPC UA server on, and `--opcua-client CMD` run beside (its JSON report
//!   taken in; `bench/shopfloor.sh`); `--no-streams` leaves the websockets out, and the
//!   service's own count of controllers behind real time (`/metrics`) decides.
//!
//! It prints one JSON object and exits 0 if the goal holds (p99 lag under `--p99-ms`, no
//! controller behind, no error, memory growth under `--max-growth-mb`), 1 otherwise.
//! `docs/performance.md` has the commands and the figures; `scripts/soak.sh` the soak.

use std::path::PathBuf;
use std::process::Stdio;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use clap::Parser;
use futures_util::StreamExt;
use serde::Deserialize;
use serde_json::{json, Value};
use tokio::io::{AsyncBufReadExt, BufReader};

mod shopfloor;

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
    /// Fleet stream subscribers (`GET /stream?rate=2`).
    #[arg(long, default_value_t = 0)]
    fleet_subscribers: usize,
    /// Variable writes per second, round-robin over the controllers.
    #[arg(long, default_value_t = 0.0)]
    writes_per_s: f64,
    /// Seconds between two readings of the service's memory while measuring.
    #[arg(long, default_value_t = 10.0)]
    sample_every: f64,
    /// Leave the controllers idle (no cycle start): what standing machines cost their
    /// subscribers (the goal is then only no error and flat memory).
    #[arg(long)]
    idle: bool,
    /// The goal: the service's resident set grows less than this many MB while measuring.
    #[arg(long, default_value_t = 50.0)]
    max_growth_mb: f64,
    /// Seconds between two scrapes of `/metrics` while measuring (0: none).
    #[arg(long, default_value_t = 0.0)]
    scrape_every: f64,
    /// A cluster of this many nodes (`fivex serve --node loadK`) on `--db` and `--nats` instead
    /// of one process on a SQLite file of its own; controller k is created (and so hosted)
    /// through node k mod N.
    #[arg(long, default_value_t = 0)]
    nodes: usize,
    /// With `--nodes`: the PostgreSQL database (`postgres://…`, a fresh one per run).
    #[arg(long)]
    db: Option<String>,
    /// With `--nodes`: the NATS server (`nats://…`, JetStream on).
    #[arg(long)]
    nats: Option<String>,
    /// With `--nodes` ≥ 2: subscribe to each controller's stream through the next node, which
    /// relays it, instead of through the node hosting it.
    #[arg(long)]
    relay: bool,
    /// Turn the MTConnect agent on and run its clients (a `/sample` stream per controller, a
    /// poller of the whole agent).
    #[arg(long)]
    mtconnect: bool,
    /// Turn the OPC UA server on.
    #[arg(long)]
    opcua: bool,
    /// With --opcua: a command run beside the measurement with the endpoint and the seconds as
    /// its last arguments, printing a JSON report (`bench/opcua_load.py`).
    #[arg(long, requires = "opcua")]
    opcua_client: Option<String>,
    /// No websocket subscribers (measure the shop-floor clients alone).
    #[arg(long)]
    no_streams: bool,
    /// Write each service's log (at `info`) to DIR/ADDRESS.log.
    #[arg(long)]
    logs: Option<PathBuf>,
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

/// The resident set of a process in MB (Linux `/proc/PID/status`).
fn rss_mb(pid: u32) -> Option<f64> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    Some(line.split_whitespace().nth(1)?.parse::<f64>().ok()? / 1024.0)
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
    let mut services = Vec::new();
    if args.nodes == 0 {
        let db = dir.join("load.db");
        services.push(start(&fivex, &args, &[std::ffi::OsStr::new("--db"), db.as_os_str()]).await);
    } else {
        let db = args.db.clone().expect("--nodes needs --db postgres://…");
        let nats = args.nats.clone().expect("--nodes needs --nats nats://…");
        for k in 0..args.nodes {
            // Unique per run: a killed run's nodes stay members for their lease.
            let node = format!("load{}-{k}", std::process::id());
            let extra = ["--db", db.as_str(), "--nats", nats.as_str(), "--node", node.as_str()];
            let extra: Vec<&std::ffi::OsStr> = extra.iter().map(std::ffi::OsStr::new).collect();
            services.push(start(&fivex, &args, &extra).await);
        }
        // Every node sees every other before any controller is made.
        let http = Http::new();
        for (_, addr, _, _) in &services {
            let deadline = Instant::now() + Duration::from_secs(30);
            while http.get(&format!("http://{addr}/readyz")).await["cluster"]["members"].as_array().map_or(0, Vec::len)
                < args.nodes
            {
                assert!(Instant::now() < deadline, "the nodes did not all join within 30 s");
                tokio::time::sleep(Duration::from_millis(200)).await;
            }
        }
    }
    let pids: Vec<u32> = services.iter().map(|(child, _, _, _)| child.id().unwrap()).collect();
    let addrs: Vec<String> = services.iter().map(|(_, addr, _, _)| addr.clone()).collect();
    let addr = addrs[0].clone();
    let base = format!("http://{addr}/api/v1");
    // Controller k's node (the one it is created through, so hosting it) and the node its
    // stream is opened through.
    let owner_of = |k: usize| &addrs[k % addrs.len()];
    let stream_node_of = |k: usize| &addrs[(k + usize::from(args.relay)) % addrs.len()];
    let http = Http::new();
    let cpu_all = || pids.iter().map(|p| cpu_seconds(*p)).sum::<Option<f64>>();
    let rss_all = || pids.iter().map(|p| rss_mb(*p)).sum::<Option<f64>>();

    let errors = Arc::new(AtomicUsize::new(0));
    tokio::time::sleep(Duration::from_secs(1)).await;
    let rss_empty = rss_all();
    // Controllers and their program.
    let mut ids = Vec::new();
    for k in 0..args.controllers {
        let base = format!("http://{}/api/v1", owner_of(k));
        let c = http
            .post(&format!("{base}/controllers"), &json!({"name": format!("load {k}"), "preset": args.preset}))
            .await;
        let id = c["id"].as_str().expect("a controller id").to_string();
        http.put_text(&format!("{base}/controllers/{id}/programs/1"), PROGRAM).await;
        ids.push(id);
    }
    tokio::time::sleep(Duration::from_secs(2)).await;
    let rss_idle = rss_all();
    // A subscriber each, then cycle start.
    let measuring = Arc::new(AtomicBool::new(false));
    let seen: Vec<Arc<Mutex<Seen>>> = ids.iter().map(|_| Arc::new(Mutex::new(Seen::default()))).collect();
    for (k, (id, seen)) in ids.iter().zip(&seen).enumerate().filter(|_| !args.no_streams) {
        let url = format!("ws://{}/api/v1/controllers/{id}/stream?rate={}", stream_node_of(k), args.rate);
        let (ws, _) = tokio_tungstenite::connect_async(url).await.expect("websocket");
        let (seen, measuring, errors) = (seen.clone(), measuring.clone(), errors.clone());
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
            // The stream ended while the service runs: an error.
            errors.fetch_add(1, Ordering::Relaxed);
        });
    }
    // Fleet subscribers: messages and bytes while measuring.
    let fleet_seen = Arc::new((AtomicUsize::new(0), AtomicUsize::new(0)));
    for _ in 0..args.fleet_subscribers {
        let (ws, _) =
            tokio_tungstenite::connect_async(format!("ws://{addr}/api/v1/stream?rate=2")).await.expect("websocket");
        let (fleet_seen, measuring, errors) = (fleet_seen.clone(), measuring.clone(), errors.clone());
        tokio::spawn(async move {
            let (_, mut rx) = ws.split();
            while let Some(Ok(msg)) = rx.next().await {
                if measuring.load(Ordering::Relaxed) {
                    fleet_seen.0.fetch_add(1, Ordering::Relaxed);
                    fleet_seen.1.fetch_add(msg.len(), Ordering::Relaxed);
                }
            }
            errors.fetch_add(1, Ordering::Relaxed);
        });
    }
    // The MTConnect clients: a stream per controller from its node's agent, a poller per agent.
    let mt_seen = Arc::new(Mutex::new(shopfloor::Seen::default()));
    if args.mtconnect {
        let client = shopfloor::client();
        let nodes = services.len();
        for (i, (_, _, _, interfaces)) in services.iter().enumerate() {
            let agent = interfaces.mtconnect.clone().expect("the agent's address");
            let from = shopfloor::next_sequence(&client, &agent).await;
            shopfloor::poll(client.clone(), agent.clone(), from, mt_seen.clone(), measuring.clone());
            // Controller k is hosted by node k mod N (created through it).
            for id in ids.iter().skip(i).step_by(nodes) {
                shopfloor::stream(client.clone(), agent.clone(), id.clone(), from, mt_seen.clone(), measuring.clone());
            }
        }
    }
    for (k, id) in ids.iter().enumerate().filter(|_| !args.idle) {
        http.post(&format!("http://{}/api/v1/controllers/{id}/cycle-start", owner_of(k)), &json!({"program": 1})).await;
    }
    // The writer: variables, as an operator or a cell computer would set them.
    let writes = Arc::new(AtomicUsize::new(0));
    let mut writer = None;
    if args.writes_per_s > 0.0 {
        let (ids, base, writes, errors) = (ids.clone(), base.clone(), writes.clone(), errors.clone());
        let every = Duration::from_secs_f64(1.0 / args.writes_per_s);
        writer = Some(tokio::spawn(async move {
            let http = Http::new();
            let mut tick = tokio::time::interval(every);
            for k in 0usize.. {
                tick.tick().await;
                let id = &ids[k % ids.len()];
                let url = format!("{base}/controllers/{id}/variables/500");
                match http.try_send("PUT", &url, "application/json", json!({"value": k as f64}).to_string()).await {
                    Ok(_) => writes.fetch_add(1, Ordering::Relaxed),
                    Err(e) => {
                        eprintln!("write refused: {e}");
                        errors.fetch_add(1, Ordering::Relaxed)
                    }
                };
            }
        }));
    }
    // The OPC UA client connects and subscribes during the warm-up, then measures as long.
    let opcua_client = match (&args.opcua_client, services[0].3.opcua.clone()) {
        (Some(command), Some(endpoint)) => {
            let (command, seconds) = (command.clone(), args.seconds);
            Some(tokio::spawn(async move { shopfloor::opcua_client(&command, &endpoint, seconds).await }))
        }
        _ => None,
    };
    tokio::time::sleep(Duration::from_secs_f64(args.warmup)).await;
    // The scraper: each scrape's time (ms) and the last answer.
    let scrapes = Arc::new(Mutex::new((Vec::<f64>::new(), String::new())));
    let scraper = (args.scrape_every > 0.0 && args.scrape_every.is_finite()).then(|| {
        let (url, scrapes, errors) = (format!("http://{addr}/metrics"), scrapes.clone(), errors.clone());
        let every = Duration::from_secs_f64(args.scrape_every).max(Duration::from_millis(1));
        tokio::spawn(async move {
            let http = Http::new();
            let mut tick = tokio::time::interval(every);
            loop {
                tick.tick().await;
                let started = Instant::now();
                match http.get_text(&url).await {
                    Ok(text) => {
                        let mut s = scrapes.lock().unwrap();
                        s.0.push(started.elapsed().as_secs_f64() * 1000.0);
                        s.1 = text;
                    }
                    Err(e) => {
                        eprintln!("scrape refused: {e}");
                        errors.fetch_add(1, Ordering::Relaxed);
                    }
                }
            }
        })
    });
    let rss_running = rss_all();
    let (cpu0, t0) = (cpu_all(), Instant::now());
    let writes0 = writes.load(Ordering::Relaxed);
    measuring.store(true, Ordering::Relaxed);
    let mut rss_samples = Vec::new();
    let end = t0 + Duration::from_secs_f64(args.seconds);
    loop {
        rss_samples.push(rss_all().unwrap_or(f64::NAN));
        let left = end.saturating_duration_since(Instant::now());
        if left.is_zero() {
            break;
        }
        tokio::time::sleep(left.min(Duration::from_secs_f64(args.sample_every))).await;
    }
    measuring.store(false, Ordering::Relaxed);
    let (cpu1, wall) = (cpu_all(), t0.elapsed().as_secs_f64());
    let writes_done = writes.load(Ordering::Relaxed) - writes0;
    // The writer and the scraper stop with the measurement (their requests would fail once the
    // service is gone).
    if let Some(writer) = writer {
        writer.abort();
    }
    if let Some(scraper) = scraper {
        scraper.abort();
    }
    let metrics = {
        let (mut times, text) = scrapes.lock().unwrap().clone();
        times.sort_by(f64::total_cmp);
        // A sample without labels in the last scrape.
        let value =
            |name: &str| text.lines().find_map(|l| l.strip_prefix(name)?.strip_prefix(' ')?.parse::<f64>().ok());
        json!({
            "scrapes": times.len(),
            "scrape_ms": {"p50": percentile(&times, 0.5), "max": times.last().copied().unwrap_or(f64::NAN)},
            "bytes": text.len(),
            "behind_real_time": value("fivex_controllers_behind_real_time"),
            "max_lag_s": value("fivex_controllers_max_lag_seconds"),
            "frames_sent": value("fivex_position_frames_sent_total"),
        })
    };

    let mtconnect = args.mtconnect.then(|| shopfloor::report(&mt_seen.lock().unwrap(), ids.len(), wall));
    let opcua_report = match opcua_client {
        Some(task) => Some(task.await.unwrap_or_else(|e| json!({"error": e.to_string()}))),
        None => None,
    };
    // The service's own count of controllers behind real time, at the end.
    let behind_now = http.get_text(&format!("http://{addr}/metrics")).await.ok().and_then(|text| {
        text.lines().find_map(|l| l.strip_prefix("fivex_controllers_behind_real_time ")?.parse::<f64>().ok())
    });
    // Every controller still running, no alarms.
    let mut running = 0;
    for (k, id) in ids.iter().enumerate() {
        if http.get(&format!("http://{}/api/v1/controllers/{id}", owner_of(k))).await["run_state"] == "running" {
            running += 1;
        }
    }
    // What each node hosts at the end (a cluster: from its `/readyz`).
    let mut hosted = Vec::new();
    for a in &addrs {
        let ready = http.get(&format!("http://{a}/readyz")).await;
        hosted.push(ready["cluster"]["controllers"].as_array().map_or(ids.len(), Vec::len));
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
    let per_controller_kb = |a: Option<f64>, b: Option<f64>| match (a, b) {
        (Some(a), Some(b)) => (b - a) * 1024.0 / args.controllers as f64,
        _ => f64::NAN,
    };
    let growth = rss_samples.last().copied().unwrap_or(f64::NAN) - rss_samples.first().copied().unwrap_or(f64::NAN);
    let max_rss = rss_samples.iter().copied().fold(f64::NAN, f64::max);
    let errors = errors.load(Ordering::Relaxed);
    let report = json!({
        "controllers": args.controllers,
        "nodes": args.nodes,
        "relayed": args.relay && args.nodes > 1,
        "hosted_per_node": hosted,
        "preset": args.preset,
        "idle": args.idle,
        "rate_hz": args.rate,
        "measured_s": wall,
        "frames": lags.len(),
        "lag_ms": {"p50": percentile(&lags, 0.5), "p99": p99, "max": lags.last().copied().unwrap_or(f64::NAN)},
        "running_at_end": running,
        "behind_real_time": behind,
        "without_frames": silent,
        "slowest_sim_per_wall": worst_ratio,
        "service_cpu_cores": cores,
        "frames_per_subscriber_per_s": lags.len() as f64 / args.controllers as f64 / wall,
        "memory_mb": {
            "empty": rss_empty, "idle": rss_idle, "running": rss_running,
            "first_sample": rss_samples.first(), "last_sample": rss_samples.last(), "max": max_rss,
            "growth": growth,
        },
        "kb_per_controller": {"idle": per_controller_kb(rss_empty, rss_idle), "running": per_controller_kb(rss_empty, rss_running)},
        "fleet_subscribers": args.fleet_subscribers,
        "fleet_messages_per_subscriber_per_s": fleet_seen.0.load(Ordering::Relaxed) as f64 / args.fleet_subscribers.max(1) as f64 / wall,
        "fleet_bytes_per_subscriber_per_s": fleet_seen.1.load(Ordering::Relaxed) as f64 / args.fleet_subscribers.max(1) as f64 / wall,
        "writes": writes_done,
        "metrics": metrics,
        "behind_real_time_at_end": behind_now,
        "mtconnect": mtconnect,
        "opcua": opcua_report,
        "errors": errors,
        "cores": std::thread::available_parallelism().map_or(0, |n| n.get()),
    });
    println!("{}", serde_json::to_string_pretty(&report).unwrap());
    for (mut child, _, _, _) in services {
        let _ = child.kill().await;
    }
    let _ = std::fs::remove_dir_all(&dir);
    let streams_kept_up =
        if args.no_streams { behind_now == Some(0.0) } else { p99 < args.p99_ms && behind == 0 && silent == 0 };
    let moving = args.idle || (streams_kept_up && running == args.controllers);
    let mt = mt_seen.lock().unwrap();
    let shopfloor_ok = mt.gaps == 0
        && mt.out_of_order == 0
        && mt.errors == 0
        && opcua_report.as_ref().is_none_or(shopfloor::opcua_kept_up);
    let ok = moving && errors == 0 && growth < args.max_growth_mb && shopfloor_ok;
    std::process::exit(if ok { 0 } else { 1 });
}

/// A started service: the process, its address, the task reading its log, and the addresses
/// its shop-floor interfaces announced (`http://…` of the MTConnect agent, `opc.tcp://…`).
type Service = (tokio::process::Child, String, tokio::task::JoinHandle<()>, Shopfloor);

#[derive(Debug, Clone, Default)]
struct Shopfloor {
    mtconnect: Option<String>,
    opcua: Option<String>,
}

/// Starts `fivex serve --addr 127.0.0.1:0 EXTRA…` (and its shop-floor interfaces when asked)
/// and waits for its address; its log is read (and dropped) from then on.
async fn start(fivex: &std::path::Path, args: &Args, extra: &[&std::ffi::OsStr]) -> Service {
    let mut cmd = tokio::process::Command::new(fivex);
    let log = if args.logs.is_some() { "info" } else { "warn,fivex_server::serve=info,fivex_server::shopfloor=info" };
    cmd.arg("serve").args(["--addr", "127.0.0.1:0"]).args(extra).env("RUST_LOG", log);
    if let Some(w) = args.workers {
        cmd.args(["--workers", &w.to_string()]);
    }
    if args.mtconnect {
        cmd.args(["--mtconnect", "127.0.0.1:0"]);
    }
    if args.opcua {
        // A free port now (the server is given one).
        let port = std::net::TcpListener::bind("127.0.0.1:0").and_then(|l| l.local_addr()).expect("a free port").port();
        cmd.args(["--opcua", &format!("127.0.0.1:{port}")]);
    }
    let mut child =
        cmd.stderr(Stdio::piped()).stdout(Stdio::null()).kill_on_drop(true).spawn().expect("start fivex serve");
    let mut lines = BufReader::new(child.stderr.take().unwrap()).lines();
    let mut shopfloor = Shopfloor::default();
    let announced = |line: &str, marker: &str| {
        line.find(marker).map(|at| {
            line[at + marker.len()..].split_whitespace().next().unwrap_or("").trim_end_matches('/').to_string()
        })
    };
    let addr = loop {
        let line = lines.next_line().await.unwrap().expect("fivex serve ended before listening");
        shopfloor.mtconnect = shopfloor.mtconnect.or(announced(&line, "MTConnect agent at "));
        shopfloor.opcua = shopfloor.opcua.or(announced(&line, "OPC UA server at "));
        if let Some(at) = line.find("listening on http://") {
            break line[at + "listening on http://".len()..].trim().to_string();
        }
    };
    // With `--logs DIR`, the service's log goes to DIR/ADDR.log (its port names it).
    let mut file = args.logs.as_ref().map(|dir| {
        let _ = std::fs::create_dir_all(dir);
        std::fs::File::create(dir.join(format!("{}.log", addr.replace(':', "_")))).expect("a log file")
    });
    let drain = tokio::spawn(async move {
        while let Ok(Some(line)) = lines.next_line().await {
            if let Some(f) = file.as_mut() {
                use std::io::Write;
                let _ = writeln!(f, "{line}");
            }
        }
    });
    (child, addr, drain, shopfloor)
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
        self.try_send(method, url, content_type, body).await.unwrap_or_else(|e| panic!("{e}"))
    }

    /// A request; the reason when it fails or is refused.
    async fn try_send(&self, method: &str, url: &str, content_type: &str, body: String) -> Result<Value, String> {
        use http_body_util::BodyExt;
        let request = hyper::Request::builder()
            .method(method)
            .uri(url)
            .header("content-type", content_type)
            .body(http_body_util::Full::new(bytes::Bytes::from(body)))
            .unwrap();
        let response = self.client.request(request).await.map_err(|e| format!("{method} {url}: {e}"))?;
        let status = response.status();
        let bytes = response.into_body().collect().await.map_err(|e| format!("{method} {url}: {e}"))?.to_bytes();
        if !status.is_success() {
            return Err(format!("{method} {url}: {status} {}", String::from_utf8_lossy(&bytes)));
        }
        Ok(serde_json::from_slice(&bytes).unwrap_or(Value::Null))
    }

    async fn get(&self, url: &str) -> Value {
        self.send("GET", url, "application/json", String::new()).await
    }

    /// A GET answered as text (`/metrics`).
    async fn get_text(&self, url: &str) -> Result<String, String> {
        use http_body_util::BodyExt;
        let request = hyper::Request::get(url).body(http_body_util::Full::new(bytes::Bytes::new())).unwrap();
        let response = self.client.request(request).await.map_err(|e| format!("GET {url}: {e}"))?;
        let status = response.status();
        let bytes = response.into_body().collect().await.map_err(|e| format!("GET {url}: {e}"))?.to_bytes();
        if !status.is_success() {
            return Err(format!("GET {url}: {status}"));
        }
        String::from_utf8(bytes.to_vec()).map_err(|e| format!("GET {url}: {e}"))
    }

    async fn post(&self, url: &str, body: &Value) -> Value {
        self.send("POST", url, "application/json", body.to_string()).await
    }

    async fn put_text(&self, url: &str, text: &str) -> Value {
        self.send("PUT", url, "text/plain", text.to_string()).await
    }
}
