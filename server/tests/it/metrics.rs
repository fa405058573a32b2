//! `/readyz` and `/metrics` through `oneshot` (docs/api.md, "Readiness and metrics"): readiness
//! and its 503s, the metrics in the Prometheus text format read by two parsers (a strict one here
//! and Python's `prometheus_client`), their values against what the API says, and both routes
//! open without the token.

use crate::common::exposition::{parse_both, Exposition};
use crate::common::{spawn_app, TestApp};

use axum::body::Body;
use axum::http::{header, Method, Request, StatusCode};
use serde_json::{json, Value};

async fn scrape(app: &TestApp) -> (String, Exposition) {
    let reply = app.get("/metrics").await;
    assert_eq!(reply.status, StatusCode::OK, "{}", reply.text());
    assert_eq!(reply.content_type, "text/plain; version=0.0.4; charset=utf-8");
    let text = reply.text();
    let read = parse_both(&text);
    (text, read)
}

async fn create(app: &TestApp, name: &str) -> String {
    let reply = app.post("/api/v1/controllers", &json!({"name": name, "preset": "mill3"})).await;
    assert_eq!(reply.status, StatusCode::CREATED, "{}", reply.text());
    reply.json()["id"].as_str().expect("an id").to_owned()
}

#[tokio::test]
async fn readyz_answers_ready_json_with_the_node_and_no_cluster() {
    let app = spawn_app().await;
    create(&app, "one").await;
    let reply = app.get("/readyz").await;
    assert_eq!(reply.status, StatusCode::OK);
    assert_eq!(reply.content_type, "application/json");
    let body = reply.json();
    assert_eq!(body["status"], "ready");
    assert_eq!(body["cluster"], Value::Null);
    let node = &body["node"];
    assert_eq!(node["database"], "sqlite");
    assert_eq!(node["controllers"], 1);
    assert_eq!(node["workers"].as_u64(), Some(app.state.host.workers() as u64));
    assert_eq!(node["version"], env!("CARGO_PKG_VERSION"));
    assert!(!node["id"].as_str().unwrap().is_empty());
    // The same node id on every answer of this process.
    assert_eq!(app.get("/readyz").await.json()["node"]["id"], node["id"]);
    // `/healthz` keeps its contract.
    assert_eq!(app.get("/healthz").await.json(), json!({"status": "ok"}));
}

#[tokio::test]
async fn readyz_is_503_json_when_the_database_is_closed() {
    let app = spawn_app().await;
    app.state.db.close().await;
    let reply = app.get("/readyz").await;
    assert_eq!(reply.status, StatusCode::SERVICE_UNAVAILABLE);
    assert_eq!(reply.content_type, "application/json");
    let error = reply.json()["error"].as_str().unwrap().to_owned();
    assert!(error.contains("database does not answer"), "{error}");
}

#[tokio::test]
async fn readyz_is_503_once_the_service_shuts_down_and_when_the_workers_stopped() {
    let app = spawn_app().await;
    app.state.close();
    let reply = app.get("/readyz").await;
    assert_eq!(reply.status, StatusCode::SERVICE_UNAVAILABLE);
    assert!(reply.json()["error"].as_str().unwrap().contains("shutting down"), "{}", reply.text());

    let app = spawn_app().await;
    let host = app.state.host.clone();
    tokio::task::spawn_blocking(move || host.shutdown()).await.unwrap();
    let reply = app.get("/readyz").await;
    assert_eq!(reply.status, StatusCode::SERVICE_UNAVAILABLE);
    let error = reply.json()["error"].as_str().unwrap().to_owned();
    assert!(error.contains("worker threads stopped"), "{error}");
    // Liveness does not look at the workers.
    assert_eq!(app.get("/healthz").await.status, StatusCode::OK);
    let (_, read) = scrape(&app).await;
    assert_eq!(read.value("fivex_workers_running", &[]), 0.0);
    assert_eq!(read.value("fivex_workers", &[]), app.state.host.workers() as f64);
}

#[tokio::test]
async fn metrics_are_the_prometheus_text_format_and_agree_with_the_api() {
    let app = spawn_app().await;
    let (_, empty) = scrape(&app).await;
    for state in ["idle", "running", "hold", "alarm"] {
        assert_eq!(empty.value("fivex_controllers", &[("state", state)]), 0.0, "{state}");
    }
    assert_eq!(empty.value("fivex_controllers_max_lag_seconds", &[]), 0.0);

    let ids = [create(&app, "a").await, create(&app, "b").await, create(&app, "c").await];
    // One in alarm: its emergency stop pressed.
    let reply = app.put(&format!("/api/v1/controllers/{}/emergency-stop", ids[2]), &json!({"pressed": true})).await;
    assert_eq!(reply.json()["run_state"], "alarm", "{}", reply.text());
    let (text, read) = scrape(&app).await;

    // Every family is fivex's, with a HELP and units in its name where it has one.
    for (name, kind) in &read.types {
        assert!(name.starts_with("fivex_"), "{name}");
        assert!(text.contains(&format!("# HELP {name} ")), "{name} has no HELP");
        assert_eq!(kind == "counter", name.ends_with("_total"), "{name}: {kind}");
    }
    // The controllers by run state, as the API lists them.
    let list = app.get("/api/v1/controllers").await.json();
    for state in ["idle", "running", "hold", "alarm"] {
        let listed = list.as_array().unwrap().iter().filter(|c| c["run_state"] == state).count();
        assert_eq!(read.value("fivex_controllers", &[("state", state)]), listed as f64, "{state}");
    }
    assert_eq!(read.value("fivex_controllers", &[("state", "alarm")]), 1.0);
    assert_eq!(read.sum("fivex_controllers"), 3.0);
    assert_eq!(read.value("fivex_controllers_behind_real_time", &[]), 0.0);
    assert!(read.value("fivex_controllers_max_lag_seconds", &[]) >= 0.0);
    assert_eq!(read.value("fivex_workers_running", &[]), app.state.host.workers() as f64);
    assert_eq!(read.value("fivex_websocket_subscribers", &[("stream", "controller")]), 0.0);
    assert_eq!(read.value("fivex_position_frames_sent_total", &[]), 0.0);
    assert_eq!(read.value("fivex_position_frame_lag_seconds_count", &[]), 0.0);
    assert_eq!(read.value("fivex_fleet_jobs", &[]), 1.0);
    // The requests so far, all answered 2xx: a scrape, three creations, the emergency stop (a
    // request is counted once answered: a scrape does not count itself).
    assert_eq!(read.value("fivex_http_requests_total", &[("class", "2xx")]), 5.0);
    assert_eq!(read.value("fivex_http_requests_total", &[("class", "4xx")]), 0.0);
    assert_eq!(app.get("/api/v1/controllers/nope").await.status, StatusCode::NOT_FOUND);
    let (_, later) = scrape(&app).await;
    assert_eq!(later.value("fivex_http_requests_total", &[("class", "4xx")]), 1.0);
    assert_eq!(later.value("fivex_http_requests_total", &[("class", "2xx")]), 7.0);
}

#[tokio::test]
async fn fleet_runs_are_counted_by_status() {
    let app = spawn_app().await;
    let run = json!({"program": "O1\nG01 X10. F1000\nM30\n", "presets": ["mill3"]});
    let reply = app.post("/api/v1/fleet/runs", &run).await;
    assert_eq!(reply.status, StatusCode::OK, "{}", reply.text());
    let (_, read) = scrape(&app).await;
    assert_eq!(read.value("fivex_fleet_runs_finished_total", &[("status", "done")]), 1.0);
    assert_eq!(read.value("fivex_fleet_runs_finished_total", &[("status", "cancelled")]), 0.0);
    assert_eq!(read.value("fivex_fleet_runs", &[("status", "queued")]), 0.0);
    assert_eq!(read.value("fivex_fleet_runs", &[("status", "running")]), 0.0);
    assert_eq!(read.value("fivex_fleet_jobs_running", &[]), 0.0);
}

#[tokio::test]
async fn metrics_answer_without_the_database_and_count_its_errors() {
    let app = spawn_app().await;
    create(&app, "a").await;
    app.state.db.close().await;
    let reply = app.get("/api/v1/fleet/runs").await;
    assert_eq!(reply.status, StatusCode::INTERNAL_SERVER_ERROR, "{}", reply.text());
    let (_, read) = scrape(&app).await;
    assert_eq!(read.value("fivex_database_errors_total", &[("source", "request")]), 1.0);
    assert_eq!(read.value("fivex_database_errors_total", &[("source", "records")]), 0.0);
    assert_eq!(read.value("fivex_http_requests_total", &[("class", "5xx")]), 1.0);
    assert_eq!(read.sum("fivex_controllers"), 1.0);
}

#[tokio::test]
async fn readyz_and_metrics_need_no_token_and_refuse_a_foreign_host() {
    let app = spawn_app().await;
    let app = TestApp { state: app.state.clone().with_token(Some("secret".into())), ..app };
    assert_eq!(app.get("/api/v1/controllers").await.status, StatusCode::UNAUTHORIZED);
    assert_eq!(app.get("/readyz").await.status, StatusCode::OK);
    scrape(&app).await;
    for path in ["/healthz", "/readyz", "/metrics"] {
        let request =
            Request::builder().method(Method::GET).uri(path).header(header::HOST, "evil.example").body(Body::empty());
        let reply = app.send(request.unwrap()).await;
        assert_eq!(reply.status, StatusCode::FORBIDDEN, "{path}");
        assert_eq!(reply.content_type, "application/json", "{path}");
    }
}
