//! `fivex serve`'s start on its database file (docs/api.md, "The database"): one service per
//! SQLite file, and a file it cannot use refused at once with the reason.

use std::io::Read;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use super::served::Served;

/// Runs `fivex serve --db DB` and expects it to refuse to start: its exit status and stderr.
/// Panics if it is still running after `limit` (it started: killed first).
fn refused_start(db: &Path, limit: Duration) -> (Option<i32>, String) {
    refused_start_as(&[], db, limit)
}

/// As [`refused_start`], run through `prefix` (`runuser -u nobody --`).
fn refused_start_as(prefix: &[&str], db: &Path, limit: Duration) -> (Option<i32>, String) {
    let mut command = match prefix.split_first() {
        Some((program, args)) => {
            let mut c = Command::new(program);
            c.args(args).arg(env!("CARGO_BIN_EXE_fivex"));
            c
        }
        None => Command::new(env!("CARGO_BIN_EXE_fivex")),
    };
    let mut child = command
        .arg("serve")
        .arg("--db")
        .arg(db)
        .args(["--addr", "127.0.0.1:0"])
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start fivex serve");
    let started = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        if started.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            let mut log = String::new();
            let _ = child.stderr.take().unwrap().read_to_string(&mut log);
            panic!("fivex serve --db {} started (or hung) instead of refusing within {limit:?}: {log}", db.display());
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut log = String::new();
    child.stderr.take().unwrap().read_to_string(&mut log).unwrap();
    (status.code(), log)
}

/// A second service on the file a running one serves is refused at start with the reason (also
/// when it names the file another way); once the first is gone — stopped, or killed — the
/// file serves again.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_second_service_on_one_sqlite_file_is_refused() {
    let first = Served::start(&[]);
    let db = first.dir.path().join("fivex.db");
    let other_spelling = first.dir.path().join(".").join("fivex.db");
    for db in [&db, &other_spelling] {
        let (code, log) = refused_start(db, Duration::from_secs(20));
        assert_eq!(code, Some(2), "{log}");
        assert!(log.contains("another fivex serve uses it"), "{log}");
    }
    assert_eq!(first.get("/healthz").await.status, 200, "the first goes on");
    // Killed (no shutdown of any kind): the operating system lets the lock go.
    let mut first = first;
    first.kill();
    let second = Served::start_in(first.stop(), &[]);
    assert_eq!(second.get("/healthz").await.status, 200);
    // Stopped gracefully: the same.
    let third = Served::start_in(second.stop(), &[]);
    assert_eq!(third.get("/healthz").await.status, 200);
}

/// The audit's F12: a file that is not a database is refused at once with SQLite's reason (it
/// took 68 s, then said "pool timed out").
#[test]
fn a_file_that_is_not_a_database_is_refused_at_once_with_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let header_only = b"SQLite format 3\0".to_vec();
    for (name, bytes) in [("garbage.db", vec![0xA5u8; 8192]), ("header.db", header_only)] {
        let db = dir.path().join(name);
        std::fs::write(&db, &bytes).unwrap();
        let started = Instant::now();
        let (code, log) = refused_start(&db, Duration::from_secs(30));
        assert_eq!(code, Some(2), "{name}: {log}");
        assert!(started.elapsed() < Duration::from_secs(10), "{name}: took {:?}", started.elapsed());
        assert!(log.contains("not a database") || log.contains("malformed"), "{name}: {log}");
        assert!(!log.contains("timed out"), "{name}: {log}");
        assert_eq!(std::fs::read(&db).unwrap(), bytes, "{name} is left as it was");
    }
}

/// The audit's F12: a database file the service may read but not write is refused at start
/// (it started, said ready, and answered 500 to every write). As root the service runs as
/// `nobody` (root writes any file).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_database_file_the_service_cannot_write_is_refused_at_start() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("fivex.db");
    // A real database with a controller in it, then read-only.
    let served = Served::start_in(dir, &[]);
    let reply = served
        .send_json(hyper::Method::POST, "/api/v1/controllers", &serde_json::json!({"name": "c", "preset": "mill3"}))
        .await;
    assert_eq!(reply.status, 201);
    let dir = served.stop();
    std::fs::set_permissions(dir.path(), std::fs::Permissions::from_mode(0o777)).unwrap();
    std::fs::set_permissions(&db, std::fs::Permissions::from_mode(0o444)).unwrap();
    let root = std::process::Command::new("id").arg("-u").output().unwrap().stdout == b"0\n";
    let prefix: &[&str] = if root { &["runuser", "-u", "nobody", "--"] } else { &[] };
    let (code, log) = refused_start_as(prefix, &db, Duration::from_secs(30));
    assert_eq!(code, Some(2), "{log}");
    assert!(log.contains("readonly") || log.contains("read-only"), "{log}");
}
