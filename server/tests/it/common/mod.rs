//! What the service tests share: an application over a fresh database, and requests through
//! `oneshot`.
#![allow(dead_code)]

pub mod exposition;

use std::path::PathBuf;

use axum::body::{Body, Bytes};
use axum::http::{header, Method, Request, StatusCode};
use axum::Router;
use fivex_server::http::{self, AppState};
use http_body_util::BodyExt;
use serde_json::Value;
use tempfile::TempDir;
use tower::ServiceExt;

/// One test's application: its state over a fresh database in a temporary directory that lives
/// as long as the value.
pub struct TestApp {
    pub state: AppState,
    pub db_path: PathBuf,
    pub dir: TempDir,
}

/// Everything a test reads back from a response.
pub struct Reply {
    pub status: StatusCode,
    pub content_type: String,
    pub body: Bytes,
}

impl Reply {
    pub fn json(&self) -> Value {
        serde_json::from_slice(&self.body)
            .unwrap_or_else(|e| panic!("response body is not JSON ({e}): {:?}", String::from_utf8_lossy(&self.body)))
    }

    pub fn text(&self) -> String {
        String::from_utf8(self.body.to_vec()).expect("UTF-8 body")
    }
}

pub async fn spawn_app() -> TestApp {
    let dir = tempfile::tempdir().expect("temporary directory");
    let db_path = dir.path().join("fivex.db");
    let state = AppState::open(&db_path).await.expect("open the database");
    TestApp { state, db_path, dir }
}

impl TestApp {
    pub fn router(&self) -> Router {
        http::app(self.state.clone())
    }

    pub async fn send(&self, request: Request<Body>) -> Reply {
        let response = self.router().oneshot(request).await.expect("infallible");
        let status = response.status();
        let content_type =
            response.headers().get(header::CONTENT_TYPE).map(|v| v.to_str().unwrap().to_owned()).unwrap_or_default();
        let body = response.into_body().collect().await.expect("body").to_bytes();
        Reply { status, content_type, body }
    }

    pub async fn request(&self, method: Method, uri: &str) -> Reply {
        let request = Request::builder().method(method).uri(uri).body(Body::empty()).unwrap();
        self.send(request).await
    }

    pub async fn get(&self, uri: &str) -> Reply {
        self.request(Method::GET, uri).await
    }
}

impl TestApp {
    /// A request with a JSON body.
    pub async fn json(&self, method: Method, uri: &str, body: &Value) -> Reply {
        let request = Request::builder()
            .method(method)
            .uri(uri)
            .header(header::CONTENT_TYPE, "application/json")
            .body(Body::from(body.to_string()))
            .unwrap();
        self.send(request).await
    }

    pub async fn post(&self, uri: &str, body: &Value) -> Reply {
        self.json(Method::POST, uri, body).await
    }

    pub async fn put(&self, uri: &str, body: &Value) -> Reply {
        self.json(Method::PUT, uri, body).await
    }

    /// A request with a raw body and content type.
    pub async fn raw(&self, method: Method, uri: &str, content_type: &str, body: impl Into<Body>) -> Reply {
        let request = Request::builder()
            .method(method)
            .uri(uri)
            .header(header::CONTENT_TYPE, content_type)
            .body(body.into())
            .unwrap();
        self.send(request).await
    }

    /// The service stopped gracefully and started again on the same database.
    pub async fn restart(&self) -> AppState {
        self.state.shutdown().await;
        AppState::open(&self.db_path).await.expect("reopen")
    }
}
