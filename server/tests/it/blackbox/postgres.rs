//! fivex on PostgreSQL (issue 23, item 1): a real server from Debian's `postgresql` package,
//! created with `initdb` in a temporary directory and started with `pg_ctl` on a loopback port
//! for the test, then stopped. The schema is the SQLite one, column by column; the service's
//! store test (acknowledged writes while controllers write, `store.rs`) passes on it; a
//! restarted service finds everything it was told to keep.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;
use std::time::Duration;

use fivex_server::db;
use hyper::{Method, StatusCode};
use serde_json::json;
use sqlx::Row;

use super::served::Served;
use super::store::writes_succeed;

/// A PostgreSQL server of its own in a temporary directory, stopped when dropped.
pub struct Postgres {
    dir: tempfile::TempDir,
    bin: PathBuf,
    port: u16,
    /// `runuser -u postgres --` when the tests run as root (the server refuses to).
    as_user: Vec<String>,
}

impl Postgres {
    /// Creates a cluster (user `fivex`, trust on loopback), starts it and creates the database
    /// `fivex`. Panics with the reason where PostgreSQL is not installed: `.ci/run` installs it.
    pub fn start() -> Postgres {
        let bin = server_binaries().unwrap_or_else(|| {
            panic!(
                "PostgreSQL's server binaries (initdb, pg_ctl) not found: install Debian's `postgresql` (.ci/run does)"
            )
        });
        let dir = tempfile::tempdir().expect("temporary directory");
        let root = command_output("id", &["-u"]) == "0";
        let as_user = if root {
            let uid: u32 = command_output("id", &["-u", "postgres"]).parse().expect("a postgres user");
            std::os::unix::fs::chown(dir.path(), Some(uid), None).expect("chown");
            vec!["runuser".into(), "-u".into(), "postgres".into(), "--".into()]
        } else {
            Vec::new()
        };
        let port = free_port();
        let pg = Postgres { dir, bin, port, as_user };
        let data = pg.dir.path().join("data");
        let data = data.to_str().unwrap().to_owned();
        pg.run("initdb", &["-D", &data, "-A", "trust", "-U", "fivex", "--no-sync", "-E", "UTF8"]);
        let options = format!("-p {port} -h 127.0.0.1 -k {} -F", pg.dir.path().display());
        let log = pg.dir.path().join("server.log");
        pg.run("pg_ctl", &["-D", &data, "-o", &options, "-l", log.to_str().unwrap(), "-w", "start"]);
        pg.run("createdb", &["-h", "127.0.0.1", "-p", &port.to_string(), "-U", "fivex", "fivex"]);
        pg
    }

    pub fn url(&self) -> String {
        format!("postgres://fivex@127.0.0.1:{}/fivex", self.port)
    }

    fn run(&self, program: &str, args: &[&str]) {
        let tool = self.bin.join(program);
        let (head, rest) = match self.as_user.split_first() {
            Some((head, rest)) => (PathBuf::from(head), rest.iter().map(String::as_str).collect::<Vec<_>>()),
            None => (tool.clone(), Vec::new()),
        };
        let mut command = Command::new(head);
        command.args(rest);
        if !self.as_user.is_empty() {
            command.arg(&tool);
        }
        let out = command.args(args).output().unwrap_or_else(|e| panic!("cannot run {program}: {e}"));
        assert!(
            out.status.success(),
            "{program} {args:?}: {}\n{}\n{}",
            out.status,
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

impl Drop for Postgres {
    fn drop(&mut self) {
        let data = self.dir.path().join("data");
        let data = data.to_str().unwrap().to_owned();
        if Path::new(&data).join("postmaster.pid").exists() {
            self.run("pg_ctl", &["-D", &data, "-m", "immediate", "-w", "stop"]);
        }
    }
}

/// The directory of `initdb` and `pg_ctl`: Debian keeps them in /usr/lib/postgresql/N/bin (the
/// newest there), other systems on the PATH.
fn server_binaries() -> Option<PathBuf> {
    let mut versions: Vec<(u32, PathBuf)> = std::fs::read_dir("/usr/lib/postgresql")
        .into_iter()
        .flatten()
        .flatten()
        .filter_map(|e| Some((e.file_name().to_str()?.parse().ok()?, e.path().join("bin"))))
        .filter(|(_, bin)| bin.join("initdb").is_file())
        .collect();
    versions.sort();
    versions.pop().map(|(_, bin)| bin).or_else(|| {
        let found = command_output("sh", &["-c", "command -v initdb"]);
        Path::new(&found).parent().map(Path::to_path_buf).filter(|_| !found.is_empty())
    })
}

fn command_output(program: &str, args: &[&str]) -> String {
    Command::new(program)
        .args(args)
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_owned())
        .unwrap_or_default()
}

fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0").expect("a free port").local_addr().unwrap().port()
}

/// Every table's columns as (table, column, type, not null, part of the primary key), the
/// types in SQLite's words (BIGINT is INTEGER, DOUBLE PRECISION is REAL).
async fn columns(db: &db::Db) -> Vec<(String, String, String, bool, bool)> {
    let sql = match db.backend() {
        db::Backend::Sqlite => {
            "SELECT m.name AS tab, p.name AS col, upper(p.type) AS typ, p.\"notnull\" AS nn, \
             CAST(p.pk > 0 AS INTEGER) AS pk FROM sqlite_master m JOIN pragma_table_info(m.name) p \
             WHERE m.type = 'table' AND m.name NOT LIKE '\\_%' ESCAPE '\\' AND m.name NOT LIKE 'sqlite%'"
        }
        db::Backend::Postgres => {
            "SELECT CAST(c.table_name AS TEXT) AS tab, CAST(c.column_name AS TEXT) AS col, \
             CAST(CASE c.data_type WHEN 'bigint' THEN 'INTEGER' WHEN 'double precision' THEN 'REAL' \
             ELSE upper(c.data_type) END AS TEXT) AS typ, \
             CAST(c.is_nullable = 'NO' AS INTEGER) AS nn, \
             CAST(EXISTS (SELECT 1 FROM information_schema.key_column_usage k JOIN information_schema.table_constraints t \
               ON t.constraint_name = k.constraint_name AND t.constraint_type = 'PRIMARY KEY' \
               WHERE k.table_name = c.table_name AND k.column_name = c.column_name) AS INTEGER) AS pk \
             FROM information_schema.columns c WHERE c.table_schema = 'public' AND c.table_name NOT LIKE '\\_%' \
             AND NOT (c.table_name = 'fleet_runs' AND c.column_name = 'rowid')"
        }
    };
    let mut out: Vec<_> = sqlx::query(sql)
        .fetch_all(db.reads())
        .await
        .expect("the columns")
        .iter()
        .map(|r| {
            let flag = |name: &str| r.try_get::<i64, _>(name).map(|v| v != 0).or_else(|_| r.try_get::<bool, _>(name));
            (
                r.try_get::<String, _>("tab").unwrap(),
                r.try_get::<String, _>("col").unwrap(),
                r.try_get::<String, _>("typ").unwrap(),
                flag("nn").unwrap(),
                flag("pk").unwrap(),
            )
        })
        .collect();
    out.sort();
    out
}

/// The two migration sets make the same tables: names, columns, types, nullability, keys (an
/// INTEGER PRIMARY KEY in SQLite is NOT NULL implicitly, as PostgreSQL's keys are).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_schema_is_the_same_on_sqlite_and_on_postgres() {
    let pg = Postgres::start();
    let on_pg = db::open_postgres(&pg.url()).await.expect("open on PostgreSQL");
    let dir = tempfile::tempdir().unwrap();
    let on_sqlite = db::open(&dir.path().join("fivex.db")).await.expect("open on SQLite");
    let (a, b) = (columns(&on_sqlite).await, columns(&on_pg).await);
    assert!(a.len() >= 40, "{} columns", a.len());
    let normalized: Vec<_> = a.into_iter().map(|(t, c, ty, notnull, pk)| (t, c, ty, notnull || pk, pk)).collect();
    assert_eq!(normalized, b);
    // Opening again migrates nothing twice.
    on_pg.close().await;
    db::open_postgres(&pg.url()).await.expect("open again").close().await;
}

/// `store.rs`'s test on PostgreSQL: 20 controllers cycling programs that write variables and
/// offsets, clients writing the same, uploads, clones, deletes and fleet runs at once — every
/// acknowledged write succeeds and is what is read.
#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn writes_succeed_while_controllers_write_on_postgres() {
    let pg = Postgres::start();
    writes_succeed(Arc::new(Served::start_on(&pg.url(), &[]))).await;
}

/// A service stopped and started again on the same PostgreSQL database brings its controllers
/// back with their programs, retained variables, tool offsets, workpiece, run and alarm
/// history, and its fleet runs; the URL's password is not logged.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_restarted_service_finds_what_it_kept_on_postgres() {
    const C: &str = "/api/v1/controllers";
    let pg = Postgres::start();
    let url = pg.url().replace("fivex@", "fivex:secret@");
    let served = Served::start_on(&url, &[]);
    assert!(!served.log().contains("secret"), "{}", served.log());
    let reply = served.send_json(Method::POST, C, &json!({"name": "kept", "preset": "head-bc"})).await;
    assert_eq!(reply.status, StatusCode::CREATED, "{:?}", reply.body);
    let id = reply.json()["id"].as_str().unwrap().to_owned();
    let workpiece = json!({"boxes": [{"min": [-10.0, -10.0, -30.0], "max": [10.0, 10.0, 0.0]}]});
    let put = served.send_json(Method::PUT, &format!("{C}/{id}/workpiece"), &workpiece).await;
    assert_eq!(put.status, StatusCode::OK, "{:?}", put.body);
    let program = "O0001\n#500=12.5\n#501=#0\nG10 L10 P3 R42.\nG91 G01 X1. F6000\nX-1.\nM30\n";
    let stored =
        served.request(Method::PUT, &format!("{C}/{id}/programs/1"), &[("content-type", "text/plain")], program).await;
    assert_eq!(stored.status, StatusCode::CREATED);
    let started = served.send_json(Method::POST, &format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
    assert!(started.status.is_success(), "{:?}", started.body);
    // The run ends (a record the service writes in the background).
    let mut runs = json!([]);
    for _ in 0..200 {
        runs = served.get(&format!("{C}/{id}/runs")).await.json();
        if !runs.as_array().unwrap().is_empty() {
            break;
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    assert_eq!(runs[0]["result"], "completed", "{runs}");
    // An alarm (history) and a fleet run (its own table), kept too.
    let stop = "O0002\n#3000=1(STOP HERE)\nM30\n";
    let stored =
        served.request(Method::PUT, &format!("{C}/{id}/programs/2"), &[("content-type", "text/plain")], stop).await;
    assert_eq!(stored.status, StatusCode::CREATED);
    let started = served.send_json(Method::POST, &format!("{C}/{id}/cycle-start"), &json!({"program": 2})).await;
    assert!(started.status.is_success(), "{:?}", started.body);
    let fleet = json!({"program": "G91 G01 X1. F1000\nM30\n", "presets": ["mill3", "head-bc"]});
    let posted = served.send_json(Method::POST, "/api/v1/fleet/runs", &fleet).await;
    assert!(posted.status.is_success(), "{:?}", posted.body);
    let fleet_id = posted.headers.get("x-fleet-run").expect("a fleet run id").to_str().unwrap().to_owned();
    let (mut alarms, mut fleet_run) = (json!([]), json!({}));
    for _ in 0..200 {
        alarms = served.get(&format!("{C}/{id}/alarms")).await.json();
        fleet_run = served.get(&format!("/api/v1/fleet/runs/{fleet_id}")).await.json();
        // The alarm's run is recorded too (its own record, written after the alarm's).
        runs = served.get(&format!("{C}/{id}/runs")).await.json();
        let ended = runs.as_array().unwrap().len() == 2;
        if !alarms["history"].as_array().unwrap().is_empty() && fleet_run["status"] == "done" && ended {
            break;
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    assert!(alarms.to_string().contains("STOP HERE"), "{alarms}");
    assert_eq!(fleet_run["status"], "done", "{fleet_run}");
    assert_eq!(runs[0]["result"], "alarm", "{runs}");
    let mut served = served;
    let (status, _) = served.terminate(Duration::from_secs(30));
    assert!(status.success(), "{status}; log: {}", served.log());

    let again = Served::start_on(&url, &[]);
    let controllers = again.get(C).await.json();
    assert_eq!(controllers.as_array().unwrap().len(), 1, "{controllers}");
    assert_eq!(controllers[0]["name"], "kept");
    let text = again.get(&format!("{C}/{id}/programs/1")).await;
    assert_eq!(String::from_utf8_lossy(&text.body), program);
    assert_eq!(again.get(&format!("{C}/{id}/variables/500")).await.json()["value"], json!(12.5));
    assert_eq!(again.get(&format!("{C}/{id}/workpiece")).await.json(), workpiece);
    let tools = again.get(&format!("{C}/{id}/tool-offsets")).await.json();
    let three = tools.as_array().unwrap().iter().find(|t| t["number"] == 3).cloned().expect("offset 3");
    assert_eq!(three["length"], json!(42.0));
    assert_eq!(again.get(&format!("{C}/{id}/runs")).await.json(), runs);
    assert_eq!(again.get(&format!("{C}/{id}/alarms")).await.json()["history"], alarms["history"]);
    assert_eq!(again.get(&format!("/api/v1/fleet/runs/{fleet_id}")).await.json(), fleet_run);
}
