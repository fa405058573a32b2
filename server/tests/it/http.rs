//! HTTP service tests.
//!
//! Most tests drive [`http::app`] directly with `tower::ServiceExt::oneshot`, each on a fresh
//! SQLite database in its own temporary directory (`spawn_app`). One test runs the real server on
//! a loopback port-0 listener and talks to it with a plain HTTP client. The checked-in
//! `openapi/openapi.json` and `docker-compose.yml` are checked here too.

use crate::common;

use std::path::{Path, PathBuf};

use axum::body::{Body, Bytes};
use axum::http::{Method, Request, StatusCode};
use axum::response::IntoResponse;
use common::spawn_app;
use fivex_server::db::{self, ControllerRow};
use fivex_server::http::{self, ApiError, AppState};
use fivex_server::serve;
use http_body_util::BodyExt;
use serde_json::{json, Value};
use tower::ServiceExt;

fn controller(id: &str, name: &str, created_at: &str) -> ControllerRow {
    ControllerRow {
        id: id.into(),
        name: name.into(),
        dialect: "fanuc".into(),
        machine_json: r#"{"kind":"mill3"}"#.into(),
        created_at: created_at.into(),
    }
}

fn workspace_file(relative: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(relative)
}

// ---------------------------------------------------------------------------------------------
// Through `oneshot`

#[tokio::test]
async fn healthz_answers_ok_json() {
    let app = spawn_app().await;
    let reply = app.get("/healthz").await;
    assert_eq!(reply.status, StatusCode::OK);
    assert_eq!(reply.content_type, "application/json");
    assert_eq!(reply.json(), json!({"status": "ok"}));
}

#[tokio::test]
async fn healthz_is_503_json_when_the_database_is_gone() {
    let app = spawn_app().await;
    app.state.db.close().await;
    let reply = app.get("/healthz").await;
    assert_eq!(reply.status, StatusCode::SERVICE_UNAVAILABLE);
    let error = reply.json()["error"].as_str().unwrap().to_owned();
    assert!(error.contains("database"), "{error}");
}

#[tokio::test]
async fn head_healthz_is_200_without_body() {
    let app = spawn_app().await;
    let reply = app.request(Method::HEAD, "/healthz").await;
    assert_eq!(reply.status, StatusCode::OK);
    assert!(reply.body.is_empty());
}

#[tokio::test]
async fn index_serves_the_dashboard_page() {
    let app = spawn_app().await;
    let reply = app.get("/").await;
    assert_eq!(reply.status, StatusCode::OK);
    assert!(reply.content_type.starts_with("text/html"), "{}", reply.content_type);
    let page = reply.text();
    assert!(page.contains("<title>fivex</title>"));
    if fivex_server::assets::dashboard_built() {
        // The built dashboard: its script is served too.
        assert!(page.contains(r#"<div id="app">"#), "{page}");
        let script = page.split("src=\"").nth(1).and_then(|s| s.split('"').next()).expect("a script tag");
        let reply = app.get(script).await;
        assert_eq!(reply.status, StatusCode::OK, "{script}");
        assert!(reply.content_type.starts_with("text/javascript"), "{}", reply.content_type);
    } else {
        assert_eq!(page, fivex_server::assets::FALLBACK_HTML);
    }
    assert_eq!(app.get("/assets/nothing.js").await.status, StatusCode::NOT_FOUND);
}

#[tokio::test]
async fn controllers_list_is_empty_on_a_fresh_database() {
    let app = spawn_app().await;
    let reply = app.get("/api/v1/controllers").await;
    assert_eq!(reply.status, StatusCode::OK);
    assert_eq!(reply.content_type, "application/json");
    assert_eq!(reply.json(), json!([]));
}

#[tokio::test]
async fn stored_controllers_are_hosted_again_oldest_first_and_bad_rows_are_kept() {
    let app = spawn_app().await;
    let machine = serde_json::to_string(&fivex_engine::machine::MachineConfig::preset("table-ac").unwrap()).unwrap();
    let mut second = controller("b", "second", "2025-01-02T00:00:00Z");
    let mut first = controller("a", "first", "2025-01-01T00:00:00Z");
    (second.machine_json, first.machine_json) = (machine.clone(), machine);
    db::insert_controller(&app.state.db, &second).await.unwrap();
    db::insert_controller(&app.state.db, &first).await.unwrap();
    // A row whose machine this version refuses stays in the database, unhosted.
    db::insert_controller(&app.state.db, &controller("z", "odd", "2025-01-03T00:00:00Z")).await.unwrap();
    let again = AppState::open(&app.db_path).await.expect("reopen");
    let reply = http::app(again.clone())
        .oneshot(Request::get("/api/v1/controllers").body(Body::empty()).unwrap())
        .await
        .unwrap();
    assert_eq!(reply.status(), StatusCode::OK);
    let list: Value = serde_json::from_slice(&reply.into_body().collect().await.unwrap().to_bytes()).unwrap();
    let summary: Vec<(String, String, String, String, String, String)> = list
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            let s = |k: &str| c[k].as_str().unwrap().to_string();
            (s("id"), s("name"), s("dialect"), s("created_at"), s("mode"), s("run_state"))
        })
        .collect();
    let row = |id: &str, name: &str, at: &str| {
        (id.into(), name.into(), "fanuc".into(), at.into(), "auto".into(), "idle".into())
    };
    assert_eq!(summary, [row("a", "first", "2025-01-01T00:00:00Z"), row("b", "second", "2025-01-02T00:00:00Z")]);
    assert_eq!(db::list_controllers(&again.db).await.unwrap().len(), 3);
}

#[tokio::test]
async fn unknown_routes_are_404_json() {
    let app = spawn_app().await;
    for uri in ["/nope", "/api/v1/nope", "/api/v1", "/api/v2/controllers"] {
        let reply = app.get(uri).await;
        assert_eq!(reply.status, StatusCode::NOT_FOUND, "{uri}");
        assert_eq!(reply.content_type, "application/json", "{uri}");
        assert_eq!(reply.json(), json!({"error": format!("no route for GET {uri}")}), "{uri}");
    }
}

#[tokio::test]
async fn wrong_methods_are_405_json() {
    let app = spawn_app().await;
    for uri in ["/healthz", "/api/v1/controllers"] {
        let reply = app.request(Method::PATCH, uri).await;
        assert_eq!(reply.status, StatusCode::METHOD_NOT_ALLOWED, "{uri}");
        assert_eq!(reply.json(), json!({"error": format!("method PATCH is not allowed on {uri}")}));
    }
}

#[tokio::test]
async fn api_errors_render_as_json_with_their_status() {
    let cases = [
        (ApiError::BadRequest("bad".into()), 400, "bad"),
        (ApiError::NotFound("gone".into()), 404, "gone"),
        (ApiError::Conflict("taken".into()), 409, "taken"),
        // The database's own message is logged, not sent to the client.
        (ApiError::Database(sqlx::Error::RowNotFound), 500, "internal database error"),
    ];
    for (error, status, message) in cases {
        let response = error.into_response();
        assert_eq!(response.status().as_u16(), status);
        let body = response.into_body().collect().await.unwrap().to_bytes();
        let body: Value = serde_json::from_slice(&body).unwrap();
        assert_eq!(body, json!({ "error": message }));
    }
}

#[tokio::test]
async fn openapi_document_is_served_and_is_openapi_3_1() {
    let app = spawn_app().await;
    let reply = app.get("/api-docs/openapi.json").await;
    assert_eq!(reply.status, StatusCode::OK);
    let doc = reply.json();
    assert!(doc["openapi"].as_str().unwrap().starts_with("3.1"), "{doc}");
    assert_eq!(doc["info"]["title"], "fivex");
    for path in ["/healthz", "/api/v1/controllers"] {
        assert!(doc["paths"][path]["get"].is_object(), "{path} missing");
    }
    let generated: Value = serde_json::from_str(&http::openapi_json()).unwrap();
    assert_eq!(doc, generated);
}

#[tokio::test]
async fn swagger_ui_is_served() {
    let app = spawn_app().await;
    let reply = app.get("/swagger-ui/").await;
    assert_eq!(reply.status, StatusCode::OK);
    assert!(reply.content_type.starts_with("text/html"), "{}", reply.content_type);
    assert!(reply.text().to_lowercase().contains("swagger"));

    let config = app.get("/swagger-ui/swagger-initializer.js").await;
    assert_eq!(config.status, StatusCode::OK);
    assert!(config.text().contains("/api-docs/openapi.json"));

    let bare = app.get("/swagger-ui").await;
    assert!(bare.status.is_redirection(), "{}", bare.status);
}

// ---------------------------------------------------------------------------------------------
// Database

#[tokio::test]
async fn opening_creates_and_migrates_the_database_idempotently() {
    let app = spawn_app().await;
    assert!(app.db_path.is_file());
    let tables: Vec<String> = sqlx::query_scalar(
        "SELECT name FROM sqlite_master WHERE type = 'table' AND name NOT LIKE '\\_%' ESCAPE '\\' \
         AND name NOT LIKE 'sqlite%' ORDER BY name",
    )
    .fetch_all(app.state.db.reads())
    .await
    .unwrap();
    assert_eq!(
        tables,
        [
            "alarm_history",
            "controllers",
            "fleet_run_results",
            "fleet_runs",
            "programs",
            "run_history",
            "tool_offsets",
            "variables",
            "work_offsets"
        ]
    );
    db::insert_controller(&app.state.db, &controller("c1", "kept", "2025-01-01T00:00:00Z")).await.unwrap();
    app.state.db.close().await;

    // Opening again runs no migration twice and keeps the data.
    let again = AppState::open(&app.db_path).await.expect("reopen");
    let rows = db::list_controllers(&again.db).await.unwrap();
    assert_eq!(rows, [controller("c1", "kept", "2025-01-01T00:00:00Z")]);
}

#[tokio::test]
async fn tool_offsets_stored_before_the_corner_radius_read_0() {
    // A database as the version before migration 0006 left it, with a tool offset in it.
    let dir = tempfile::tempdir().expect("temporary directory");
    let path = dir.path().join("old.db");
    {
        let options = sqlx::sqlite::SqliteConnectOptions::new().filename(&path).create_if_missing(true);
        let pool = sqlx::SqlitePool::connect_with(options).await.expect("open");
        let before = sqlx::migrate::Migrator {
            migrations: db::MIGRATOR.migrations.iter().filter(|m| m.version < 6).cloned().collect(),
            ..sqlx::migrate::Migrator::DEFAULT
        };
        before.run(&pool).await.expect("migrations 0001–0005");
        let machine = serde_json::to_string(&fivex_engine::machine::MachineConfig::preset("mill3").unwrap()).unwrap();
        sqlx::query(
            "INSERT INTO controllers (id, name, dialect, machine_json, created_at) \
             VALUES ('old', 'old', 'fanuc', ?, '2025-01-01T00:00:00Z')",
        )
        .bind(machine)
        .execute(&pool)
        .await
        .unwrap();
        sqlx::query(
            "INSERT INTO tool_offsets (controller_id, number, length, length_wear, radius, radius_wear) \
             VALUES ('old', 3, 120.0, 0.0, 4.0, -0.05)",
        )
        .execute(&pool)
        .await
        .unwrap();
        pool.close().await;
    }
    // This version migrates it on start: the row reads corner radius 0, stored and served.
    let state = AppState::open(&path).await.expect("open and migrate");
    let rows = db::tool_offsets(&state.db, "old").await.unwrap();
    let three = rows.iter().find(|t| t.number == 3).copied().expect("offset 3 kept");
    assert_eq!(
        three,
        db::ToolRow { number: 3, length: 120.0, length_wear: 0.0, radius: 4.0, radius_wear: -0.05, corner_radius: 0.0 }
    );
    let reply = http::app(state.clone())
        .oneshot(Request::get("/api/v1/controllers/old/tool-offsets").body(Body::empty()).unwrap())
        .await
        .unwrap();
    assert_eq!(reply.status(), StatusCode::OK);
    let tools: Value = serde_json::from_slice(&reply.into_body().collect().await.unwrap().to_bytes()).unwrap();
    let three = tools.as_array().unwrap().iter().find(|t| t["number"] == 3).cloned();
    assert_eq!(
        three,
        Some(
            json!({"number": 3, "length": 120.0, "length_wear": 0.0, "radius": 4.0, "radius_wear": -0.05, "corner_radius": 0.0})
        )
    );
    state.shutdown().await;
}

#[tokio::test]
async fn deleting_a_controller_cascades_to_programs_and_variables() {
    let app = spawn_app().await;
    db::insert_controller(&app.state.db, &controller("c1", "m", "2025-01-01T00:00:00Z")).await.unwrap();
    let pool = app.state.db.writes();
    sqlx::query("INSERT INTO programs (controller_id, number, text) VALUES ('c1', 1, 'O0001\nM30\n')")
        .execute(pool)
        .await
        .unwrap();
    sqlx::query("INSERT INTO variables (controller_id, number, value) VALUES ('c1', 500, 1.5), ('c1', 501, NULL)")
        .execute(pool)
        .await
        .unwrap();
    // Foreign keys are enforced: no program for an unknown controller. A handler that meets
    // this (the controller deleted by another request after it was found) answers 404.
    let orphan =
        sqlx::query("INSERT INTO programs (controller_id, number, text) VALUES ('zz', 1, '')").execute(pool).await;
    let response = ApiError::from(orphan.expect_err("refused")).into_response();
    assert_eq!(response.status(), StatusCode::NOT_FOUND);
    let body = response.into_body().collect().await.unwrap().to_bytes();
    let error: Value = serde_json::from_slice(&body).unwrap();
    assert!(error["error"].as_str().unwrap().contains("deleted"), "{error}");

    sqlx::query("DELETE FROM controllers WHERE id = 'c1'").execute(pool).await.unwrap();
    for table in ["programs", "variables"] {
        let count: i64 = sqlx::query_scalar(&format!("SELECT COUNT(*) FROM {table}")).fetch_one(pool).await.unwrap();
        assert_eq!(count, 0, "{table}");
    }
}

/// The one-writer design (docs/api.md, "The database"): the readers refuse every write, so a
/// write that went to them would fail here instead of racing the writer for the lock; the
/// writer is a single connection.
#[tokio::test]
async fn only_the_writer_writes() {
    let app = spawn_app().await;
    let refused = sqlx::query(
        "INSERT INTO controllers (id, name, dialect, machine_json, created_at) \
                               VALUES ('r', 'r', 'fanuc', '{}', '2025-01-01T00:00:00Z')",
    )
    .execute(app.state.db.reads())
    .await
    .expect_err("a reader refuses to write");
    assert!(refused.to_string().contains("readonly"), "{refused}");
    assert_eq!(app.state.db.writes().options().get_max_connections(), 1);
    db::insert_controller(&app.state.db, &controller("w", "w", "2025-01-01T00:00:00Z")).await.unwrap();
    assert_eq!(db::list_controllers(&app.state.db).await.unwrap().len(), 1, "a reader sees what the writer wrote");
}

/// The background writer puts what has arrived in one transaction; a record that fails (a
/// deleted controller's, on the foreign key) is logged and the others in its batch are kept.
#[tokio::test]
async fn a_failed_record_does_not_lose_the_others_in_its_batch() {
    use fivex_server::host::Record;
    let app = spawn_app().await;
    db::insert_controller(&app.state.db, &controller("c1", "m", "2025-01-01T00:00:00Z")).await.unwrap();
    let (tx, rx) = tokio::sync::mpsc::unbounded_channel();
    let run = |controller: &str, program| Record::Run {
        controller: controller.into(),
        program: Some(program),
        started_at: "2025-01-01T00:00:00Z".into(),
        ended_at: "2025-01-01T00:00:01Z".into(),
        cycle_time_s: 1.0,
        result: "completed",
    };
    // Sent before the writer starts, so they arrive as one batch.
    tx.send(run("c1", 1)).unwrap();
    tx.send(Record::Variables { controller: "gone".into(), values: vec![(500, Some(1.0))] }).unwrap();
    tx.send(run("gone", 2)).unwrap();
    tx.send(Record::Variables { controller: "c1".into(), values: vec![(500, Some(2.5)), (501, None)] }).unwrap();
    tx.send(run("c1", 3)).unwrap();
    drop(tx);
    db::write_records(app.state.db.clone(), rx).await;
    let runs = db::run_history(&app.state.db, "c1", 10).await.unwrap();
    assert_eq!(runs.iter().map(|r| r.program).collect::<Vec<_>>(), [Some(3), Some(1)]);
    assert_eq!(db::retained_variables(&app.state.db, "c1").await.unwrap(), [(500, 2.5)]);
    let orphans: i64 = sqlx::query_scalar("SELECT COUNT(*) FROM run_history WHERE controller_id = 'gone'")
        .fetch_one(app.state.db.reads())
        .await
        .unwrap();
    assert_eq!(orphans, 0);
}

// ---------------------------------------------------------------------------------------------
// A real server on a loopback port

#[tokio::test]
async fn real_server_on_port_0_serves_and_shuts_down_gracefully() {
    use hyper_util::client::legacy::Client;
    use hyper_util::rt::TokioExecutor;

    let app = spawn_app().await;
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
    let server = tokio::spawn(serve::serve(listener, app.state.clone(), async {
        let _ = stopped.await;
    }));

    let client: Client<_, http_body_util::Empty<Bytes>> = Client::builder(TokioExecutor::new()).build_http();
    let get = |path: &str| {
        let uri = format!("http://{addr}{path}").parse().unwrap();
        let client = client.clone();
        async move {
            let response = client.get(uri).await.expect("request");
            let status = response.status();
            let body = response.into_body().collect().await.unwrap().to_bytes();
            (status, serde_json::from_slice::<Value>(&body).unwrap())
        }
    };

    assert_eq!(get("/healthz").await, (StatusCode::OK, json!({"status": "ok"})));
    assert_eq!(get("/api/v1/controllers").await, (StatusCode::OK, json!([])));
    let (status, body) = get("/missing").await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    assert_eq!(body, json!({"error": "no route for GET /missing"}));
    drop(client);

    stop.send(()).unwrap();
    let result = tokio::time::timeout(std::time::Duration::from_secs(5), server)
        .await
        .expect("server stops promptly after the shutdown signal")
        .expect("server task");
    assert!(result.is_ok(), "{result:?}");
    // The port is free again.
    tokio::net::TcpListener::bind(addr).await.unwrap();
}

#[test]
fn run_blocking_creates_the_database_and_reports_an_address_in_use() {
    let dir = tempfile::tempdir().unwrap();
    let db_path = dir.path().join("new.db");
    let taken = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = taken.local_addr().unwrap().to_string();
    let error = serve::run_blocking(&db_path, &addr).unwrap_err();
    assert!(error.contains(&format!("cannot listen on {addr}")), "{error}");
    // The database was created and migrated before binding.
    assert!(db_path.is_file());
}

#[test]
fn run_blocking_reports_a_database_that_cannot_be_created() {
    let dir = tempfile::tempdir().unwrap();
    let db_path = dir.path().join("no/such/dir/fivex.db");
    let error = serve::run_blocking(&db_path, "127.0.0.1:0").unwrap_err();
    assert!(error.contains("cannot open database"), "{error}");
    assert!(error.contains("fivex.db"), "{error}");
}

/// The `fivex serve` binary end to end: it announces its address, answers, and on SIGTERM stops
/// gracefully with exit status 0.
#[cfg(unix)]
#[test]
fn fivex_serve_binary_answers_and_stops_gracefully_on_sigterm() {
    use std::io::{BufRead, BufReader, Read, Write};
    use std::process::{Command, Stdio};
    use std::sync::mpsc;
    use std::time::{Duration, Instant};

    let dir = tempfile::tempdir().unwrap();
    let db_path = dir.path().join("bin.db");
    let mut child = Command::new(env!("CARGO_BIN_EXE_fivex"))
        .arg("serve")
        .arg("--db")
        .arg(&db_path)
        .args(["--addr", "127.0.0.1:0"])
        .env("RUST_LOG", "info")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start fivex serve");
    let stderr = child.stderr.take().unwrap();
    let (lines_tx, lines) = mpsc::channel::<String>();
    let reader = std::thread::spawn(move || {
        for line in BufReader::new(stderr).lines() {
            let Ok(line) = line else { break };
            if lines_tx.send(line).is_err() {
                break;
            }
        }
    });
    let mut log = Vec::new();
    let next_line = |log: &mut Vec<String>| {
        let line = lines.recv_timeout(Duration::from_secs(20)).ok()?;
        log.push(line.clone());
        Some(line)
    };

    let marker = "listening on http://";
    let addr = loop {
        match next_line(&mut log) {
            Some(line) => {
                if let Some(at) = line.find(marker) {
                    break line[at + marker.len()..].trim().to_owned();
                }
            }
            None => {
                let _ = child.kill();
                panic!("fivex serve never announced its address; log: {log:#?}");
            }
        }
    };

    let mut stream = std::net::TcpStream::connect(&addr).unwrap();
    stream.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    stream.write_all(b"GET /healthz HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n\r\n").unwrap();
    let mut response = String::new();
    stream.read_to_string(&mut response).unwrap();
    assert!(response.starts_with("HTTP/1.1 200"), "{response}");
    assert!(response.ends_with(r#"{"status":"ok"}"#), "{response}");
    assert!(db_path.is_file());

    let kill = Command::new("kill").args(["-TERM", &child.id().to_string()]).status().unwrap();
    assert!(kill.success());
    let deadline = Instant::now() + Duration::from_secs(20);
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("fivex serve did not stop within 20 s of SIGTERM; log: {log:#?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    reader.join().unwrap();
    while let Some(_line) = next_line(&mut log) {}
    assert!(status.success(), "{status}; log: {log:#?}");
    let log = log.join("\n");
    assert!(log.contains("received SIGTERM"), "{log}");
    assert!(log.contains("fivex stopped"), "{log}");
}

// ---------------------------------------------------------------------------------------------
// Checked-in artefacts

/// `openapi/openapi.json` must be what the code generates. `FIVEX_BLESS=1` rewrites it.
#[test]
fn checked_in_openapi_json_matches_the_code() {
    let path = workspace_file("openapi/openapi.json");
    let generated = http::openapi_json();
    if std::env::var("FIVEX_BLESS").as_deref() == Ok("1") {
        std::fs::write(&path, &generated).expect("write openapi/openapi.json");
        return;
    }
    let checked_in = std::fs::read_to_string(&path).unwrap_or_default();
    if checked_in != generated {
        let (line, ours, theirs) = checked_in
            .lines()
            .chain(std::iter::repeat("<end of file>"))
            .zip(generated.lines())
            .enumerate()
            .find(|(_, (a, b))| a != b)
            .map(|(i, (a, b))| (i + 1, a.to_owned(), b.to_owned()))
            .unwrap_or((checked_in.lines().count() + 1, "<more lines>".into(), String::new()));
        panic!(
            "openapi/openapi.json is out of date with the code (first difference at line {line}):\n  \
             checked in: {ours}\n  generated:  {theirs}\n\
             Regenerate it with: FIVEX_BLESS=1 cargo test -p fivex-server --test it checked_in_openapi"
        );
    }
}

/// A compose file as JSON, its YAML merge keys (`<<: *node`) applied.
fn compose_file(name: &str) -> Value {
    let text = std::fs::read_to_string(workspace_file(name)).unwrap();
    let mut yaml: serde_norway::Value = serde_norway::from_str(&text).unwrap_or_else(|e| panic!("{name} is YAML: {e}"));
    yaml.apply_merge().unwrap_or_else(|e| panic!("{name}: merge keys: {e}"));
    serde_json::to_value(yaml).unwrap()
}

/// A service's `command` as words.
fn command_of(service: &Value) -> Vec<&str> {
    match &service["command"] {
        Value::Array(items) => items.iter().map(|v| v.as_str().unwrap()).collect(),
        Value::String(line) => line.split_whitespace().collect(),
        other => panic!("command: {other}"),
    }
}

fn strings(value: &Value) -> Vec<&str> {
    value.as_array().unwrap_or_else(|| panic!("not a list: {value}")).iter().map(|v| v.as_str().unwrap()).collect()
}

/// The single-process compose file: `fivex serve` on SQLite with the data on a named volume.
#[test]
fn docker_compose_single_runs_fivex_serve_with_a_data_volume() {
    let compose = compose_file("docker-compose.single.yml");
    let services = compose["services"].as_object().expect("services");
    assert_eq!(services.keys().collect::<Vec<_>>(), ["fivex"]);
    let fivex = &services["fivex"];
    assert_eq!(command_of(fivex), ["serve", "--db", "/data/fivex.db", "--addr", "0.0.0.0:8080"]);

    let ports = strings(&fivex["ports"]);
    assert!(ports.iter().any(|p| p.ends_with(":8080")), "no host port maps to container port 8080: {ports:?}");

    let volumes = strings(&fivex["volumes"]);
    let data = volumes
        .iter()
        .find(|v| v.split(':').nth(1) == Some("/data"))
        .unwrap_or_else(|| panic!("no volume mounted at /data: {volumes:?}"));
    let volume_name = data.split(':').next().unwrap();
    assert!(compose["volumes"].get(volume_name).is_some(), "named volume {volume_name} is not declared");

    // It builds this repository with the Dockerfile next to it, whose entry point is `fivex`.
    let build = &fivex["build"];
    let context = build.as_str().or(build["context"].as_str()).expect("build");
    assert_eq!(context, ".");
    let dockerfile = std::fs::read_to_string(workspace_file("Dockerfile")).unwrap();
    assert!(dockerfile.contains("--bin fivex"), "Dockerfile builds the fivex binary");
    assert!(dockerfile.contains(r#"ENTRYPOINT ["/usr/local/bin/fivex"]"#));
    assert!(dockerfile.contains("EXPOSE 8080"));
}

/// The cluster compose file (docs/cluster.md, "With Docker Compose"): PostgreSQL, NATS with
/// JetStream, three nodes of this repository's image with distinct names, one proxy publishing
/// 8080 with the repository's nginx.conf, which names the three nodes. (The black-box test
/// `blackbox::compose` runs the same commands, environment and nginx.conf on loopback.)
#[test]
fn docker_compose_runs_three_nodes_on_postgres_and_nats_behind_one_proxy() {
    let compose = compose_file("docker-compose.yml");
    let services = compose["services"].as_object().expect("services");
    let mut names: Vec<&str> = services.keys().map(|k| k.as_str()).collect();
    names.sort();
    assert_eq!(names, ["fivex-1", "fivex-2", "fivex-3", "nats", "postgres", "proxy"]);

    assert!(command_of(&services["nats"]).contains(&"-js"), "NATS runs without JetStream");
    assert!(services["postgres"]["image"].as_str().unwrap().starts_with("postgres:"));
    let nginx = std::fs::read_to_string(workspace_file("deploy/nginx.conf")).unwrap();
    for (i, name) in ["fivex-1", "fivex-2", "fivex-3"].into_iter().enumerate() {
        let node = &services[name];
        assert_eq!(node["build"], ".", "{name} is built from this repository");
        assert_eq!(command_of(node), ["serve", "--node", name], "{name}: its node name is its service name");
        let env = &node["environment"];
        let db = env["FIVEX_DB"].as_str().expect("FIVEX_DB");
        assert!(db.starts_with("postgres://") && db.contains("@postgres:5432/"), "{name}: FIVEX_DB {db}");
        assert_eq!(env["FIVEX_NATS"], "nats://nats:4222", "{name}");
        assert_eq!(env["FIVEX_ADDR"], "0.0.0.0:8080", "{name}");
        let depends = node["depends_on"].as_object().expect("depends_on");
        for needed in ["postgres", "nats"] {
            assert_eq!(depends[needed]["condition"], "service_healthy", "{name} waits for {needed}");
        }
        assert_eq!(node["stop_signal"], "SIGTERM", "{name}: a stopped node hands its controllers over");
        assert!(nginx.contains(&format!("server fivex-{}:8080", i + 1)), "nginx.conf does not name {name}");
    }
    let proxy = &services["proxy"];
    assert_eq!(strings(&proxy["ports"]), ["8080:8080"]);
    assert_eq!(strings(&proxy["volumes"]), ["./deploy/nginx.conf:/etc/nginx/nginx.conf:ro"]);
    for volume in ["postgres-data", "nats-data"] {
        assert!(compose["volumes"].get(volume).is_some(), "named volume {volume} is not declared");
    }
}

#[test]
fn every_operation_has_its_own_id_and_query_options_are_query_parameters() {
    // Generated clients (the dashboard's among them) name their calls by operationId and put
    // parameters where the document says.
    let doc: serde_json::Value = serde_json::from_str(&http::openapi_json()).unwrap();
    let mut seen = std::collections::HashMap::new();
    for (path, ops) in doc["paths"].as_object().unwrap() {
        for (method, op) in ops.as_object().unwrap() {
            let Some(id) = op.get("operationId").and_then(|v| v.as_str()) else { continue };
            if let Some(other) = seen.insert(id.to_string(), format!("{method} {path}")) {
                panic!("operationId {id} of {method} {path} is also {other}");
            }
            for param in op.get("parameters").and_then(|p| p.as_array()).into_iter().flatten() {
                if param["in"] == "path" {
                    let name = param["name"].as_str().unwrap();
                    assert!(
                        path.contains(&format!("{{{name}}}")),
                        "{method} {path}: path parameter {name} is not in the path"
                    );
                }
            }
        }
    }
}
