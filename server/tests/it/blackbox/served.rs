//! Starting and stopping the real `fivex serve` binary, and plain HTTP requests to it.
#![allow(dead_code)]

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use bytes::Bytes;
use http_body_util::{BodyExt, Full};
use hyper::{HeaderMap, Method, Request, StatusCode};
use hyper_util::client::legacy::{connect::HttpConnector, Client};
use hyper_util::rt::TokioExecutor;

/// A running `fivex serve` process over a database in its own temporary directory.
pub struct Served {
    child: Child,
    /// `host:port` it listens on.
    pub addr: String,
    log: Arc<Mutex<Vec<String>>>,
    pub dir: tempfile::TempDir,
    client: Client<HttpConnector, Full<Bytes>>,
}

/// What a test reads back from a response.
pub struct Reply {
    pub status: StatusCode,
    pub headers: HeaderMap,
    pub body: Bytes,
}

impl Reply {
    pub fn json(&self) -> serde_json::Value {
        serde_json::from_slice(&self.body).unwrap_or_else(|e| {
            panic!("{}: body is not JSON ({e}): {:?}", self.status, String::from_utf8_lossy(&self.body))
        })
    }

    pub fn content_type(&self) -> &str {
        self.headers.get(hyper::header::CONTENT_TYPE).and_then(|v| v.to_str().ok()).unwrap_or("")
    }
}

impl Served {
    /// Starts `fivex serve --db DIR/fivex.db --addr 127.0.0.1:0 ARGS…` and waits until it
    /// announces its address.
    pub fn start(args: &[&str]) -> Self {
        let dir = tempfile::tempdir().expect("temporary directory");
        Self::start_in(dir, args)
    }

    /// As [`Served::start`], over the database already in `dir` (a restart).
    pub fn start_in(dir: tempfile::TempDir, args: &[&str]) -> Self {
        Self::start_with_env(dir, args, &[])
    }

    /// As [`Served::start_in`], with these environment variables set.
    pub fn start_with_env(dir: tempfile::TempDir, args: &[&str], envs: &[(&str, &str)]) -> Self {
        let db = dir.path().join("fivex.db");
        let mut command = Command::new(env!("CARGO_BIN_EXE_fivex"));
        command.arg("serve").arg("--db").arg(db).args(["--addr", "127.0.0.1:0"]).args(args);
        Self::spawn(dir, command, envs)
    }

    /// As [`Served::start`], on the database `db` names (a `postgres://` URL).
    pub fn start_on(db: &str, args: &[&str]) -> Self {
        let mut command = Command::new(env!("CARGO_BIN_EXE_fivex"));
        command.args(["serve", "--db", db, "--addr", "127.0.0.1:0"]).args(args);
        Self::spawn(tempfile::tempdir().expect("temporary directory"), command, &[])
    }

    /// `fivex ARGS…` exactly as given, with these environment variables (the listening address
    /// among them, or in `args`; it must be a loopback one with port 0).
    pub fn start_as_given(args: &[&str], envs: &[(&str, &str)]) -> Self {
        let mut command = Command::new(env!("CARGO_BIN_EXE_fivex"));
        command.args(args);
        Self::spawn(tempfile::tempdir().expect("temporary directory"), command, envs)
    }

    fn spawn(dir: tempfile::TempDir, mut command: Command, envs: &[(&str, &str)]) -> Self {
        let mut child = command
            .env("RUST_LOG", "info")
            .envs(envs.iter().copied())
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start fivex serve");
        let stderr = child.stderr.take().expect("stderr piped");
        let log = Arc::new(Mutex::new(Vec::new()));
        let (addr_tx, addr_rx) = std::sync::mpsc::channel();
        let lines = Arc::clone(&log);
        std::thread::spawn(move || {
            let marker = "listening on http://";
            for line in BufReader::new(stderr).lines() {
                let Ok(line) = line else { break };
                if let Some(at) = line.find(marker) {
                    let _ = addr_tx.send(line[at + marker.len()..].trim().to_owned());
                }
                lines.lock().unwrap().push(line);
            }
        });
        let Ok(addr) = addr_rx.recv_timeout(Duration::from_secs(30)) else {
            let _ = child.kill();
            panic!("fivex serve never announced its address; log: {:#?}", log.lock().unwrap());
        };
        let client = Client::builder(TokioExecutor::new()).build_http();
        Self { child, addr, log, dir, client }
    }

    pub fn url(&self, path: &str) -> String {
        format!("http://{}{path}", self.addr)
    }

    /// Everything the process wrote to stderr so far.
    pub fn log(&self) -> String {
        self.log.lock().unwrap().join("\n")
    }

    /// Its log as it grows (to print after the process is gone or moved).
    pub fn log_handle(&self) -> Arc<Mutex<Vec<String>>> {
        Arc::clone(&self.log)
    }

    /// One request; `body` is sent as given with the headers given (no content type is added).
    pub async fn request(&self, method: Method, path: &str, headers: &[(&str, &str)], body: impl Into<Bytes>) -> Reply {
        let mut request = Request::builder().method(method).uri(self.url(path));
        for (name, value) in headers {
            request = request.header(*name, *value);
        }
        let response = self.client.request(request.body(Full::new(body.into())).unwrap()).await.expect("request sent");
        let status = response.status();
        let headers = response.headers().clone();
        let body = response.into_body().collect().await.expect("response body").to_bytes();
        Reply { status, headers, body }
    }

    pub async fn get(&self, path: &str) -> Reply {
        self.request(Method::GET, path, &[], Bytes::new()).await
    }

    /// A request with a JSON body and `Content-Type: application/json`.
    pub async fn send_json(&self, method: Method, path: &str, body: &serde_json::Value) -> Reply {
        self.request(method, path, &[("content-type", "application/json")], body.to_string()).await
    }

    /// As [`Served::send_json`], as a future that does not borrow `self` (to spawn).
    pub fn send_json_detached(
        &self,
        method: Method,
        path: &str,
        body: &serde_json::Value,
    ) -> impl std::future::Future<Output = Reply> + Send + 'static {
        let client = self.client.clone();
        let request = Request::builder()
            .method(method)
            .uri(self.url(path))
            .header("content-type", "application/json")
            .body(Full::new(Bytes::from(body.to_string())))
            .unwrap();
        async move {
            let response = client.request(request).await.expect("request sent");
            let status = response.status();
            let headers = response.headers().clone();
            let body = response.into_body().collect().await.expect("response body").to_bytes();
            Reply { status, headers, body }
        }
    }

    /// Kills the process (SIGKILL: no shutdown of any kind) and waits for it.
    pub fn kill(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }

    /// Sends SIGTERM and waits (at most `limit`) for the process to exit; returns its status and
    /// how long it took.
    pub fn terminate(&mut self, limit: Duration) -> (ExitStatus, Duration) {
        let started = Instant::now();
        if let Some(status) = self.child.try_wait().expect("wait") {
            // Stopped already (an earlier terminate, or it ended on its own).
            return (status, Duration::ZERO);
        }
        let kill = Command::new("kill").args(["-TERM", &self.child.id().to_string()]).status().expect("kill");
        assert!(kill.success());
        loop {
            if let Some(status) = self.child.try_wait().expect("wait") {
                return (status, started.elapsed());
            }
            if started.elapsed() > limit {
                let _ = self.child.kill();
                panic!("fivex serve did not stop within {limit:?} of SIGTERM; log: {}", self.log());
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// Stops the process and hands back its directory (to start it again over the same database).
    pub fn stop(mut self) -> tempfile::TempDir {
        self.terminate(Duration::from_secs(60));
        let dir = tempfile::tempdir().expect("temporary directory");
        std::mem::replace(&mut self.dir, dir)
    }
}

impl Drop for Served {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
