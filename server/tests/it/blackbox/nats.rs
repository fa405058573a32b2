//! Distributed fleet runs over NATS JetStream (issue 23, item 3; docs/fleet.md "Over NATS"): a
//! real `nats-server -js` from Debian's `nats-server` package on a loopback port (a store of its
//! own in a temporary directory, killed at the end) and several `fivex serve --nats` nodes. A run
//! posted to one node is shared out as one job per machine and answers exactly what a single
//! node answers; a node killed (SIGKILL) in the middle of its jobs leaves them to the others and
//! the run still completes with every result; `fivex fleet --nats` prints what `fivex fleet`
//! prints; without a node it gives up with a clear error; a job that does not parse is
//! terminated; a cancel withdraws the waiting jobs and stops the running ones. On a cluster with
//! one PostgreSQL a run outlives the node it was submitted to (killed, or stopped cleanly): a
//! survivor takes it over and completes it; a single SQLite node killed mid-run finds its run
//! interrupted after a restart.

use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use hyper::Method;
use serde_json::{json, Value};

use super::postgres::Postgres;
use super::served::Served;

/// A `nats-server -js` of its own, killed when dropped.
pub struct NatsServer {
    child: Child,
    port: u16,
    _dir: tempfile::TempDir,
    bin: PathBuf,
}

/// `nats-server -js` on `port` with its store in `dir`.
fn spawn(bin: &Path, port: u16, dir: &Path) -> Child {
    Command::new(bin)
        .args(["-js", "-a", "127.0.0.1", "-p", &port.to_string(), "-sd"])
        .arg(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap_or_else(|e| panic!("cannot start {}: {e}", bin.display()))
}

impl NatsServer {
    /// Starts it on a free loopback port and waits until it accepts connections. Panics where
    /// `nats-server` is not installed: `scripts/test.sh` and `.ci/run` install Debian's.
    pub fn start() -> NatsServer {
        let bin = ["/usr/sbin/nats-server", "/usr/bin/nats-server"]
            .into_iter()
            .map(PathBuf::from)
            .find(|p| p.exists())
            .or_else(|| which("nats-server"))
            .unwrap_or_else(|| panic!("nats-server not found: install Debian's `nats-server` (scripts/test.sh does)"));
        let dir = tempfile::tempdir().expect("temporary directory");
        let port = std::net::TcpListener::bind("127.0.0.1:0").expect("a free port").local_addr().unwrap().port();
        let child = spawn(&bin, port, dir.path());
        let mut server = NatsServer { child, port, _dir: dir, bin };
        server.wait_listening();
        server
    }

    /// Kills the server and starts it again on the same port and store (its streams and
    /// buckets kept): every client loses its connection and reconnects.
    pub fn restart(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
        self.child = spawn(&self.bin, self.port, self._dir.path());
        self.wait_listening();
    }

    fn wait_listening(&mut self) {
        let deadline = Instant::now() + Duration::from_secs(30);
        while TcpStream::connect(("127.0.0.1", self.port)).is_err() {
            if let Ok(Some(status)) = self.child.try_wait() {
                panic!("nats-server exited at start: {status}");
            }
            assert!(Instant::now() < deadline, "nats-server did not listen on {} within 30 s", self.port);
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    pub fn url(&self) -> String {
        format!("nats://127.0.0.1:{}", self.port)
    }
}

impl Drop for NatsServer {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn which(program: &str) -> Option<PathBuf> {
    std::env::var_os("PATH")?.to_str()?.split(':').map(|d| Path::new(d).join(program)).find(|p| p.exists())
}

fn workspace_file(relative: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..").join(relative)
}

const PRESETS: [&str; 5] = ["mill3", "head-bc", "table-ac", "table-bc", "mixed-bc"];

/// A program that keeps a machine busy for a while (many blocks), the same on every machine.
fn long_program(turns: u32) -> String {
    let mut p = String::from("G90 G21 G17\nG00 X0 Y0 Z50\n");
    for i in 0..turns {
        let x = 10 + i % 40;
        p.push_str(&format!("G01 X{x} Y{} F2000\nG01 X0 Y0\n", i % 30));
    }
    p.push_str("M30\n");
    p
}

/// `presets` repeated to `n` machines.
fn machines(n: usize) -> Vec<&'static str> {
    PRESETS.iter().cycle().take(n).copied().collect()
}

async fn post_fleet(served: &Served, request: &Value) -> Value {
    let reply = served.send_json(Method::POST, "/api/v1/fleet/runs", request).await;
    assert_eq!(reply.status, 200, "{}: {}", reply.json(), served.log());
    reply.json()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_fleet_run_over_nats_equals_the_single_node_run_and_survives_a_killed_node() {
    let nats = NatsServer::start();
    let url = nats.url();
    let nodes: Vec<Served> = (0..3).map(|_| Served::start(&["--nats", &url, "--nats-jobs", "2"])).collect();
    let alone = Served::start(&[]);

    // Every machine's result equals the single node's, in machine order.
    let request = json!({"program": std::fs::read_to_string(workspace_file("tests/fleet/everywhere.nc")).unwrap(),
                         "presets": machines(15), "library": ["trunnion-ac-120", "fork-head-bc"], "dialect": "syntec"});
    let expected = post_fleet(&alone, &request).await;
    assert_eq!(expected.as_array().unwrap().len(), 17);
    let distributed = post_fleet(&nodes[1], &request).await;
    assert_eq!(distributed, expected);
    // Stored as a single node stores it.
    let runs = nodes[1].get("/api/v1/fleet/runs").await.json();
    let id = runs[0]["id"].as_str().unwrap().to_string();
    let run = nodes[1].get(&format!("/api/v1/fleet/runs/{id}")).await.json();
    assert_eq!(run["status"], "done");
    assert_eq!(run["results"], expected);
    // The work was shared: more than one node ran jobs.
    let working = nodes.iter().filter(|n| n.log().contains("fleet job done")).count();
    assert!(working >= 2, "only {working} node(s) ran jobs");

    // 40 machines, node 0 killed while it runs some: the run completes with every result.
    let request = json!({"program": long_program(8000), "presets": machines(40)});
    let expected = post_fleet(&alone, &request).await;
    let mut nodes = nodes;
    let posted = tokio::spawn(nodes[1].send_json_detached(Method::POST, "/api/v1/fleet/runs", &request));
    // Wait until node 0 has finished two jobs, then kill it just after it starts another (a job
    // takes a good part of a second: it is killed in the middle of that one).
    let deadline = Instant::now() + Duration::from_secs(300);
    let mut seen = Vec::new();
    loop {
        let log = nodes[0].log();
        let started = indices(&log, "fleet job started");
        let done = indices(&log, "fleet job done");
        if done.len() >= 2 && started.iter().any(|i| !seen.contains(i) && !done.contains(i)) {
            break;
        }
        seen = started;
        assert!(Instant::now() < deadline, "node 0 never ran two jobs; log: {log}");
        tokio::time::sleep(Duration::from_millis(5)).await;
    }
    nodes[0].kill();
    let reply = posted.await.unwrap();
    assert_eq!(reply.status, 200, "{}", reply.json());
    assert_eq!(reply.json(), expected);
    // The jobs node 0 had under way when it died were run again by the others.
    let log = nodes[0].log();
    let done = indices(&log, "fleet job done");
    let unfinished: Vec<usize> = indices(&log, "fleet job started").into_iter().filter(|i| !done.contains(i)).collect();
    assert!(!unfinished.is_empty(), "node 0 was not killed in the middle of a job; log: {log}");
    let elsewhere: Vec<usize> = nodes[1..].iter().flat_map(|n| indices(&n.log(), "fleet job done")).collect();
    for i in &unfinished {
        assert!(elsewhere.contains(i), "machine {i}, under way on the killed node, was not run again");
    }

    // `fivex fleet --nats` prints what `fivex fleet` prints.
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("p.nc");
    std::fs::write(&program, std::fs::read_to_string(workspace_file("tests/fleet/everywhere.nc")).unwrap()).unwrap();
    let fleet = |extra: &[&str]| {
        let mut args = vec!["fleet", program.to_str().unwrap(), "--quiet", "--library", "cradle-bc-110,vmc-4th-a"];
        for p in PRESETS {
            args.extend(["--preset", p]);
        }
        args.extend(extra);
        let out = Command::new(env!("CARGO_BIN_EXE_fivex")).args(&args).output().unwrap();
        assert!(out.status.code().is_some_and(|c| c < 2), "{:?}: {}", out.status, String::from_utf8_lossy(&out.stderr));
        (out.status.code(), String::from_utf8(out.stdout).unwrap())
    };
    assert_eq!(fleet(&["--nats", &url]), fleet(&[]));
}

/// The machine indices of the log lines with `what` (`index=N`).
/// A run's workpiece goes with its jobs: every node probes it as the single node does, through
/// the API and `fivex fleet --nats --workpiece`.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_workpiece_travels_with_the_jobs() {
    let nats = NatsServer::start();
    let url = nats.url();
    let node = Served::start(&["--nats", &url, "--nats-jobs", "2"]);
    let alone = Served::start(&[]);
    let block_file = workspace_file("tests/fleet/probe_block.json");
    let block: Value = serde_json::from_str(&std::fs::read_to_string(&block_file).unwrap()).unwrap();
    let program_file = workspace_file("tests/fleet/probe.nc");
    let request = json!({"program": std::fs::read_to_string(&program_file).unwrap(),
                         "presets": ["mill3", "table-ac", "head-bc"], "workpiece": block});
    let expected = post_fleet(&alone, &request).await;
    let distributed = post_fleet(&node, &request).await;
    assert_eq!(distributed, expected);
    // probe.nc stops on the block's top (Z-3), not at the end of its move (Z-10).
    for item in distributed.as_array().unwrap() {
        assert_eq!(item["variables"]["#101"], -3.0, "{item}");
    }

    let fleet = |extra: &[&str]| {
        let mut args = vec!["fleet", program_file.to_str().unwrap(), "--quiet", "--preset", "mill3"];
        args.extend(["--workpiece", block_file.to_str().unwrap()]);
        args.extend(extra);
        let out = Command::new(env!("CARGO_BIN_EXE_fivex")).args(&args).output().unwrap();
        assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
        String::from_utf8(out.stdout).unwrap()
    };
    let local = fleet(&[]);
    assert!(local.contains("\"#101\": -3.0"), "{local}");
    assert_eq!(fleet(&["--nats", &url]), local);
}

fn indices(log: &str, what: &str) -> Vec<usize> {
    log.lines()
        .filter(|l| l.contains(what))
        .filter_map(|l| l.split("index=").nth(1)?.split(|c: char| !c.is_ascii_digit()).next()?.parse().ok())
        .collect()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn over_nats_no_node_is_a_clear_error_bad_jobs_end_and_cancel_withdraws_the_jobs() {
    let nats = NatsServer::start();
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("p.nc");
    std::fs::write(&program, "G00 X1\nM30\n").unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_fivex"))
        .args(["fleet", program.to_str().unwrap(), "--preset", "mill3", "--nats", &nats.url()])
        .args(["--nats-timeout-s", "2"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("no fleet node heard from"), "{stderr}");
    // A node with --nats refuses existing controllers (they cannot be sent), clearly.
    let node = Served::start(&["--nats", &nats.url()]);
    let created =
        node.send_json(Method::POST, "/api/v1/controllers", &json!({"name": "cell", "preset": "mill3"})).await;
    assert_eq!(created.status, 201, "{}", created.json());
    let id = created.json()["id"].as_str().unwrap().to_string();
    let reply = node
        .send_json(Method::POST, "/api/v1/fleet/runs", &json!({"program": "G00 X1\nM30\n", "controllers": [id]}))
        .await;
    assert_eq!(reply.status, 422, "{}", reply.json());
    assert!(reply.json()["error"].as_str().unwrap_or_default().contains("--nats"), "{}", reply.json());
    // A job that does not parse is logged and terminated, not redelivered; the node goes on.
    let client = async_nats::connect(nats.url()).await.unwrap();
    let js = async_nats::jetstream::new(client);
    js.publish("fivex.fleet.jobs.junk.0", "{not json".into()).await.unwrap().await.unwrap();
    let deadline = Instant::now() + Duration::from_secs(60);
    while !node.log().contains("fleet job is not a job: terminated") {
        assert!(Instant::now() < deadline, "the bad job was not terminated; log: {}", node.log());
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    let mut stream = js.get_stream("FIVEX_FLEET").await.unwrap();
    let deadline = Instant::now() + Duration::from_secs(60);
    while stream.info().await.unwrap().state.messages != 0 {
        assert!(Instant::now() < deadline, "the bad job stayed in the queue");
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    let reply = node
        .send_json(Method::POST, "/api/v1/fleet/runs", &json!({"program": "G00 X1\nM30\n", "presets": ["mill3"]}))
        .await;
    assert_eq!(reply.status, 200, "{}", reply.json());
    assert_eq!(reply.json()[0]["status"], "completed");

    // Cancel: the running jobs stop, the waiting ones never run (purged from the queue).
    let request = json!({"program": long_program(8000), "presets": machines(12)});
    let reply = node.send_json(Method::POST, "/api/v1/fleet/runs?wait=false", &request).await;
    assert_eq!(reply.status, 202, "{}", reply.json());
    let id = reply.json()["id"].as_str().unwrap().to_string();
    let deadline = Instant::now() + Duration::from_secs(120);
    while !node.log().lines().any(|l| l.contains("fleet job started") && l.contains(&id)) {
        assert!(Instant::now() < deadline, "no job of the run started; log: {}", node.log());
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    let reply = node.request(Method::POST, &format!("/api/v1/fleet/runs/{id}/cancel"), &[], "").await;
    assert_eq!(reply.status, 200, "{}", reply.json());
    assert_eq!(reply.json()["status"], "cancelled");
    let run = node.get(&format!("/api/v1/fleet/runs/{id}")).await.json();
    let results = run["results"].as_array().unwrap();
    assert_eq!(results.len(), 12);
    assert!(results.iter().any(Value::is_null), "{run}");
    assert_eq!(stream.info().await.unwrap().state.messages, 0, "the run's waiting jobs are still queued");
    let deadline = Instant::now() + Duration::from_secs(60);
    while !node.log().lines().any(|l| l.contains("fleet job cancelled") && l.contains(&id)) {
        assert!(Instant::now() < deadline, "the running jobs were not stopped; log: {}", node.log());
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
}

/// The number of messages on JetStream stream `name`.
async fn stored(js: &async_nats::jetstream::Context, name: &str) -> (u64, usize) {
    let mut stream = js.get_stream(name).await.unwrap_or_else(|e| panic!("stream {name}: {e}"));
    let info = stream.info().await.unwrap();
    (info.state.messages, info.state.consumer_count)
}

/// Waits (60 s at most) until the streams of the results and of the collectors' keys hold
/// nothing and no consumer reads the results: what the runs over left on NATS.
async fn nothing_left_on_nats(url: &str) {
    let js = async_nats::jetstream::new(async_nats::connect(url).await.unwrap());
    let deadline = Instant::now() + Duration::from_secs(60);
    loop {
        let results = stored(&js, "FIVEX_FLEET_RESULTS").await;
        let keys = stored(&js, "KV_fivex_fleet_runs").await.0;
        let jobs = stored(&js, "FIVEX_FLEET").await.0;
        if results == (0, 0) && keys == 0 && jobs == 0 {
            return;
        }
        assert!(
            Instant::now() < deadline,
            "left on NATS: {results:?} results and consumers, {keys} collector keys, {jobs} jobs"
        );
        tokio::time::sleep(Duration::from_millis(200)).await;
    }
}

/// Posts fleet run `request` to `via` without waiting: its id and path.
async fn submit(via: &Served, request: &Value) -> (String, String) {
    let reply = via.send_json(Method::POST, "/api/v1/fleet/runs?wait=false", request).await;
    assert_eq!(reply.status, 202, "{}", reply.json());
    let id = reply.json()["id"].as_str().unwrap().to_string();
    let path = format!("/api/v1/fleet/runs/{id}");
    (id, path)
}

/// Waits until the run at `path`, read through `via`, has at least `at_least` results while it
/// is still under way (it must not end first): how many it has then.
async fn results_under_way(via: &Served, path: &str, at_least: u64) -> u64 {
    let deadline = Instant::now() + Duration::from_secs(300);
    loop {
        let (n, status) = counted(&via.get(path).await.json());
        assert!(under_way(&status), "the run ended ({status}) with {n} results, before {at_least}");
        if n >= at_least {
            return n;
        }
        assert!(Instant::now() < deadline, "the run never reached {at_least} results ({n})");
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
}

/// `completed + alarms` of a stored run and its status.
fn counted(run: &Value) -> (u64, String) {
    let n = run["completed"].as_u64().unwrap() + run["alarms"].as_u64().unwrap();
    (n, run["status"].as_str().unwrap().to_string())
}

fn under_way(status: &str) -> bool {
    matches!(status, "queued" | "running")
}

/// Polls run `id` through every node of `through` until none reads it under way (300 s at
/// most); meanwhile the machines counted never exceed `total` nor go back.
async fn until_over(through: &[&Served], id: &str, total: u64, mut seen: u64) {
    let path = format!("/api/v1/fleet/runs/{id}");
    let deadline = Instant::now() + Duration::from_secs(300);
    loop {
        let mut over = 0;
        for node in through {
            let (n, status) = counted(&node.get(&path).await.json());
            assert!(n <= total, "{n} results counted of {total} machines");
            if under_way(&status) {
                assert!(n >= seen, "the results counted went back from {seen} to {n}");
                seen = n;
            } else {
                over += 1;
            }
        }
        if over == through.len() {
            return;
        }
        assert!(Instant::now() < deadline, "run {id} not over within 300 s ({seen} of {total} results)");
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_fleet_run_outlives_the_node_that_took_it() {
    let (pg, nats) = (Postgres::start(), NatsServer::start());
    let url = nats.url();
    let node = |name: &str| {
        Served::start_on(&pg.url(), &["--nats", &url, "--node", name, "--nats-jobs", "2", "--workers", "1"])
    };
    let (mut one, mut two, three) = (node("one"), node("two"), node("three"));
    let alone = Served::start(&[]);
    let request = json!({"program": long_program(8000), "presets": machines(40)});
    let expected = post_fleet(&alone, &request).await;
    assert_eq!(expected.as_array().unwrap().len(), 40);

    // Submitted to node one; followed through node three, which neither took nor collects it.
    let (id, path) = submit(&one, &request).await;
    let (mut ws, _) = tokio_tungstenite::connect_async(format!("ws://{}{path}/stream", three.addr)).await.unwrap();
    let first = super::nodes::next_json_within(&mut ws, Duration::from_secs(60)).await;
    assert_eq!((first["total"].as_u64(), first["finished"].as_bool()), (Some(40), Some(false)), "{first}");
    // Halfway, as node two reads it, node one is killed.
    let halfway = results_under_way(&two, &path, 20).await;
    one.kill();
    assert!(halfway < 40, "node one was killed after the run's end");
    until_over(&[&two, &three], &id, 40, halfway).await;
    // Every machine's result exactly once, in order, read alike through both survivors.
    for n in [&two, &three] {
        let run = n.get(&path).await.json();
        assert_eq!(run["status"], "done", "{}", run["status"]);
        assert_eq!(counted(&run).0, 40);
        assert_eq!(run["results"], expected);
    }
    let takers: Vec<&Served> = [&two, &three]
        .into_iter()
        .filter(|n| n.log().lines().any(|l| l.contains("fleet run taken over") && l.contains(&id)))
        .collect();
    assert_eq!(takers.len(), 1, "taken over by {} nodes", takers.len());
    // The stream through node three followed it to its end.
    let mut done = first["done"].as_u64().unwrap();
    let last = loop {
        let p = super::nodes::next_json_within(&mut ws, Duration::from_secs(60)).await;
        let now = p["done"].as_u64().unwrap();
        assert!(now >= done && now <= 40, "progress went from {done} to {now}: {p}");
        done = now;
        if p["finished"] == true {
            break p;
        }
    };
    assert_eq!((last["status"].as_str(), last["done"].as_u64()), (Some("done"), Some(40)), "{last}");
    assert!(last["machines"].as_array().unwrap().iter().all(|m| m["state"] == "completed"), "{last}");
    nothing_left_on_nats(&url).await;

    // A run whose collector stops cleanly (SIGTERM) mid-run is handed over: node three, or two
    // started again under its name, completes it.
    let request = json!({"program": long_program(8000), "presets": machines(20)});
    let (id, path) = submit(&two, &request).await;
    let before = results_under_way(&three, &path, 5).await;
    let (status, _) = two.terminate(Duration::from_secs(60));
    assert!(status.success(), "{status}; log: {}", two.log());
    assert!(two.log().contains("handed over"), "{}", two.log());
    let again = node("two");
    until_over(&[&three, &again], &id, 20, before).await;
    for n in [&three, &again] {
        let run = n.get(&path).await.json();
        assert_eq!(run["status"], "done");
        assert_eq!(run["results"].as_array().unwrap()[..], expected.as_array().unwrap()[..20]);
    }
    nothing_left_on_nats(&url).await;

    // A run whose node died while it published its jobs: stored, its collector gone (a node
    // that never beat), one machine's result on the results stream, one job on the queue, three
    // never published. A node takes it over, publishes the three again and completes it.
    let program = long_program(300);
    let presets = machines(5);
    let request = json!({"program": program, "presets": presets});
    let expected = post_fleet(&alone, &request).await;
    let id = "0123456789abcdef0123456789abcdef".to_string();
    let js = async_nats::jetstream::new(async_nats::connect(&url).await.unwrap());
    let keys = js.get_key_value("fivex_fleet_runs").await.unwrap();
    keys.create(&id, "ghost".into()).await.unwrap();
    let entries: Vec<_> =
        presets.iter().map(|p| fivex_server::fleet::preset(p, fivex_engine::Dialect::Fanuc).unwrap()).collect();
    let sources = presets.iter().map(|p| fivex_server::cluster::Source::Preset(p.to_string())).collect();
    let jobs = fivex_server::cluster::Job::all(&id, &program, &entries, sources, &Default::default());
    let result = json!({"index": 0, "result": expected[0]}).to_string();
    js.publish(format!("fivex.fleet.results.{id}.0"), result.into()).await.unwrap().await.unwrap();
    let job = serde_json::to_vec(&jobs[1]).unwrap();
    js.publish(format!("fivex.fleet.jobs.{id}.1"), job.into()).await.unwrap().await.unwrap();
    let db = fivex_server::db::open_postgres(&pg.url()).await.unwrap();
    let row = fivex_server::db::FleetRunRow {
        id: id.clone(),
        created_at: "2026-01-01T00:00:00Z".into(),
        finished_at: None,
        status: "running".into(),
        machines: 5,
        completed: 0,
        alarms: 0,
        program: program.clone(),
        request_json: request.to_string(),
        results_json: None,
    };
    fivex_server::db::insert_fleet_run(&db, &row).await.unwrap();
    until_over(&[&three, &again], &id, 5, 0).await;
    let run = three.get(&format!("/api/v1/fleet/runs/{id}")).await.json();
    assert_eq!(run["status"], "done");
    assert_eq!(run["results"], expected);
    let taken: Vec<String> = [&three, &again]
        .iter()
        .flat_map(|n| {
            n.log()
                .lines()
                .filter(|l| l.contains("fleet run taken over") && l.contains(&id))
                .map(String::from)
                .collect::<Vec<_>>()
        })
        .collect();
    assert_eq!(taken.len(), 1, "{taken:?}");
    assert!(taken[0].contains("from=\"ghost\"") && taken[0].contains("republished=3"), "{}", taken[0]);
    nothing_left_on_nats(&url).await;

    // A run collected by node three, cancelled through node two: ended `cancelled` for both.
    let request = json!({"program": long_program(8000), "presets": machines(12)});
    let (_, path) = submit(&three, &request).await;
    let deadline = Instant::now() + Duration::from_secs(300);
    while counted(&again.get(&path).await.json()).0 == 0 {
        assert!(Instant::now() < deadline, "no result of the run recorded");
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    let reply = again.request(Method::POST, &format!("{path}/cancel"), &[], "").await;
    assert_eq!(reply.status, 200, "{}", reply.json());
    assert_eq!(reply.json()["status"], "cancelled");
    for n in [&three, &again] {
        let run = n.get(&path).await.json();
        assert_eq!(run["status"], "cancelled");
        let results = run["results"].as_array().unwrap();
        assert!(results.iter().any(Value::is_null) && results.iter().any(|r| !r.is_null()), "{run}");
        assert_eq!(counted(&run).0, results.iter().filter(|r| !r.is_null()).count() as u64);
    }
    nothing_left_on_nats(&url).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_single_sqlite_node_killed_mid_run_finds_it_interrupted_after_a_restart() {
    let nats = NatsServer::start();
    let args = ["--nats", &nats.url(), "--nats-jobs", "1"];
    let mut node = Served::start(&args);
    let request = json!({"program": long_program(8000), "presets": machines(12)});
    let (id, path) = submit(&node, &request).await;
    let recorded = results_under_way(&node, &path, 2).await;
    node.kill();
    let js = async_nats::jetstream::new(async_nats::connect(nats.url()).await.unwrap());
    assert!(stored(&js, "FIVEX_FLEET").await.0 > 0, "no job of the run left to withdraw");
    let dir = std::mem::replace(&mut node.dir, tempfile::tempdir().unwrap());
    let node = Served::start_in(dir, &args);
    let run = node.get(&path).await.json();
    assert_eq!(run["status"], "interrupted", "{}", run["status"]);
    // With the results it had recorded (at least those seen before it was killed).
    let results = run["results"].as_array().unwrap();
    assert_eq!(results.len(), 12);
    let kept = results.iter().filter(|r| !r.is_null()).count() as u64;
    assert!(kept >= recorded && kept < 12, "{kept} results kept, {recorded} seen recorded");
    assert_eq!(counted(&run).0, kept);
    // Its jobs and results are withdrawn from NATS.
    let deadline = Instant::now() + Duration::from_secs(60);
    while stored(&js, "FIVEX_FLEET").await.0 != 0 || stored(&js, "FIVEX_FLEET_RESULTS").await.0 != 0 {
        assert!(Instant::now() < deadline, "the interrupted run's jobs or results stayed on NATS");
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
    // Withdrawn, not run by the node started again.
    let ran = node.log().lines().any(|l| l.contains("fleet job started") && l.contains(&id));
    assert!(!ran, "{}", node.log());
}
