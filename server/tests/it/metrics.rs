//! `/readyz` through `oneshot` (docs/api.md, "Readiness and metrics"): readiness and its 503s,
//! open without the token.

use crate::common::{spawn_app, TestApp};

use axum::body::Body;
use axum::http::{header, Method, Request, StatusCode};
use serde_json::{json, Value};

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
}

#[tokio::test]
async fn readyz_needs_no_token_and_refuses_a_foreign_host() {
    let app = spawn_app().await;
    let app = TestApp { state: app.state.clone().with_token(Some("secret".into())), ..app };
    assert_eq!(app.get("/api/v1/controllers").await.status, StatusCode::UNAUTHORIZED);
    assert_eq!(app.get("/readyz").await.status, StatusCode::OK);
    for path in ["/healthz", "/readyz"] {
        let request =
            Request::builder().method(Method::GET).uri(path).header(header::HOST, "evil.example").body(Body::empty());
        let reply = app.send(request.unwrap()).await;
        assert_eq!(reply.status, StatusCode::FORBIDDEN, "{path}");
        assert_eq!(reply.content_type, "application/json", "{path}");
    }
}
