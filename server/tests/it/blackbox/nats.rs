//! Distributed fleet runs over NATS JetStream (issue 23, item 3; docs/fleet.md "Over NATS"): a
//! real `nats-server -js` from Debian's `nats-server` package on a loopback port (a store of its
//! own in a temporary directory, killed at the end) and several `fivex serve --nats` nodes. A run
//! posted to one node is shared out as one job per machine and answers exactly what a single
//! node answers; a node killed (SIGKILL) in the middle of its jobs leaves them to the others and
//! the run still completes with every result; `fivex fleet --nats` prints what `fivex fleet`
//! prints; without a node it gives up with a clear error; a job that does not parse is
//! terminated; a cancel withdraws the waiting jobs and stops the running ones.

use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use hyper::Method;
use serde_json::{json, Value};

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
