//! Cross-origin safety and tokens (issue 18, items 2 and 3; docs/api.md, "Security"): a web page
//! from a foreign origin cannot drive the service through the operator's browser, JSON endpoints
//! take JSON only, and a token with `+ / =` works in the header and percent-encoded on every
//! websocket.

use std::time::Duration;

use hyper::Method;
use serde_json::{json, Value};
use tokio_tungstenite::tungstenite::client::IntoClientRequest;
use tokio_tungstenite::tungstenite::{self, Message};

use super::served::{Reply, Served};

const FOREIGN: &str = "http://evil.example";
/// A program that runs for minutes at speed 1 (50 mm at 10 mm/min).
const SLOW: &str = "O1\nG90 G01 X50. F10.\nM30\n";

/// What a websocket handshake ended in: the first text message of an opened socket, or the
/// refusal's status and JSON body.
enum Handshake {
    Opened(Value),
    Refused(u16, Value),
}

/// Opens a websocket to `path` with these request headers and reads its first text message.
async fn websocket(served: &Served, path: &str, headers: &[(&'static str, &str)]) -> Handshake {
    let mut request = format!("ws://{}{path}", served.addr).into_client_request().expect("websocket request");
    for (name, value) in headers {
        request.headers_mut().insert(*name, value.parse().expect("header value"));
    }
    let connect = tokio::time::timeout(Duration::from_secs(30), tokio_tungstenite::connect_async(request));
    match connect.await.expect("handshake ends within 30 s") {
        Ok((mut socket, _)) => {
            use futures_util::StreamExt;
            loop {
                let next = tokio::time::timeout(Duration::from_secs(30), socket.next()).await;
                match next.expect("a message within 30 s").expect("socket open").expect("message") {
                    Message::Text(text) => {
                        return Handshake::Opened(serde_json::from_str(&text).expect("JSON message"))
                    }
                    _ => continue,
                }
            }
        }
        Err(tungstenite::Error::Http(response)) => {
            let body = response.body().clone().unwrap_or_default();
            let json = serde_json::from_slice(&body)
                .unwrap_or_else(|e| panic!("refusal body is not JSON ({e}): {:?}", String::from_utf8_lossy(&body)));
            Handshake::Refused(response.status().as_u16(), json)
        }
        Err(e) => panic!("websocket to {path}: {e}"),
    }
}

fn opened(handshake: Handshake, what: &str) -> Value {
    match handshake {
        Handshake::Opened(first) => first,
        Handshake::Refused(status, body) => panic!("{what}: refused {status} {body}"),
    }
}

fn refused(handshake: Handshake, what: &str) -> (u16, Value) {
    match handshake {
        Handshake::Opened(first) => panic!("{what}: opened, first message {first}"),
        Handshake::Refused(status, body) => (status, body),
    }
}

/// A 403 with the JSON error body naming the cross-origin refusal.
fn assert_forbidden(reply: &Reply, what: &str) {
    assert_eq!(reply.status, 403, "{what}: {:?}", String::from_utf8_lossy(&reply.body));
    assert!(reply.content_type().starts_with("application/json"), "{what}: {}", reply.content_type());
    assert!(reply.json()["error"].as_str().unwrap().contains("cross-origin"), "{what}: {}", reply.json());
}

/// A controller running [`SLOW`], created and started by a client without `Origin`.
async fn running_controller(served: &Served) -> String {
    let created = served.send_json(Method::POST, "/api/v1/controllers", &json!({"name": "c", "preset": "mill3"})).await;
    assert_eq!(created.status, 201, "{:?}", created.body);
    let id = created.json()["id"].as_str().unwrap().to_owned();
    let stored = served
        .request(Method::PUT, &format!("/api/v1/controllers/{id}/programs/1"), &[("content-type", "text/plain")], SLOW)
        .await;
    assert_eq!(stored.status, 201, "{:?}", stored.body);
    let started =
        served.send_json(Method::POST, &format!("/api/v1/controllers/{id}/cycle-start"), &json!({"program": 1})).await;
    assert_eq!(started.status, 200, "{:?}", started.body);
    assert_eq!(started.json()["run_state"], "running");
    id
}

async fn run_state(served: &Served, id: &str) -> Value {
    served.get(&format!("/api/v1/controllers/{id}")).await.json()["run_state"].clone()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_foreign_origin_is_refused_on_websockets_and_on_bodyless_and_text_posts() {
    let served = Served::start(&[]);
    let id = running_controller(&served).await;
    let foreign = [("origin", FOREIGN)];

    for path in ["/api/v1/stream".to_owned(), format!("/api/v1/controllers/{id}/stream")] {
        let (status, body) = refused(websocket(&served, &path, &foreign).await, &path);
        assert_eq!(status, 403, "{path}: {body}");
        assert!(body["error"].as_str().unwrap().contains("cross-origin"), "{path}: {body}");
    }

    // What a page can send without the browser asking first: a bodyless POST, a text/plain POST.
    let reset = format!("/api/v1/controllers/{id}/reset");
    assert_forbidden(&served.request(Method::POST, &reset, &foreign, "").await, "bodyless reset");
    let hold = format!("/api/v1/controllers/{id}/feed-hold");
    let text = [("origin", FOREIGN), ("content-type", "text/plain")];
    assert_forbidden(&served.request(Method::POST, &hold, &text, "{}").await, "text/plain feed hold");
    let start = format!("/api/v1/controllers/{id}/cycle-start");
    assert_forbidden(&served.request(Method::POST, &start, &text, r#"{"program": 1}"#).await, "text/plain cycle start");
    // A browser that says where the request comes from is refused even without Origin.
    let cross = [("sec-fetch-site", "cross-site")];
    assert_forbidden(&served.request(Method::POST, &reset, &cross, "").await, "Sec-Fetch-Site: cross-site");
    // Storing a program (text/plain, the one text body the API takes) and deleting are guarded too.
    let program = format!("/api/v1/controllers/{id}/programs/2");
    assert_forbidden(&served.request(Method::PUT, &program, &text, SLOW).await, "text/plain program");
    let controller = format!("/api/v1/controllers/{id}");
    assert_forbidden(&served.request(Method::DELETE, &controller, &foreign, "").await, "delete");

    // Nothing of it happened: the program still runs, program 2 was not stored.
    assert_eq!(run_state(&served, &id).await, "running");
    assert_eq!(served.get(&program).await.status, 404);
    // Reading stays open (a foreign page cannot read the answer: no CORS headers are sent).
    let read = served.request(Method::GET, &controller, &foreign, "").await;
    assert_eq!(read.status, 200);
    assert!(read.headers.get("access-control-allow-origin").is_none());
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_served_origin_an_allowed_origin_and_no_origin_are_accepted() {
    let served = Served::start(&["--allow-origin", "http://localhost:5173", "--allow-origin", "https://ops.example/"]);
    let id = running_controller(&served).await;
    let own = format!("http://{}", served.addr);
    let fleet = "/api/v1/stream";
    let stream = format!("/api/v1/controllers/{id}/stream");
    for origin in [own.as_str(), "http://localhost:5173", "https://ops.example"] {
        assert_eq!(opened(websocket(&served, fleet, &[("origin", origin)]).await, origin)["type"], "fleet");
        assert_eq!(opened(websocket(&served, &stream, &[("origin", origin)]).await, origin)["type"], "snapshot");
    }
    assert_eq!(opened(websocket(&served, fleet, &[]).await, "no origin")["type"], "fleet");
    // The dashboard's own requests as a browser sends them.
    let same = [("origin", own.as_str()), ("sec-fetch-site", "same-origin")];
    assert_eq!(opened(websocket(&served, &stream, &same).await, "same-origin")["type"], "snapshot");

    let hold = format!("/api/v1/controllers/{id}/feed-hold");
    let reset = format!("/api/v1/controllers/{id}/reset");
    let start = format!("/api/v1/controllers/{id}/cycle-start");
    let json = ("content-type", "application/json");
    let reply = served.request(Method::POST, &hold, &[("origin", own.as_str())], "").await;
    assert_eq!((reply.status.as_u16(), reply.json()["run_state"].clone()), (200, json!("hold")), "served origin");
    let reply = served.request(Method::POST, &start, &[("origin", "http://localhost:5173"), json], "{}").await;
    assert_eq!((reply.status.as_u16(), reply.json()["run_state"].clone()), (200, json!("running")), "allowed origin");
    let reply = served
        .request(Method::POST, &hold, &[("origin", "https://ops.example"), ("sec-fetch-site", "cross-site")], "")
        .await;
    assert_eq!((reply.status.as_u16(), reply.json()["run_state"].clone()), (200, json!("hold")), "allowed, cross-site");
    // Behind a proxy that rewrites Host the browser still says same-origin.
    let proxied = [("origin", "https://fivex.example"), ("sec-fetch-site", "same-origin")];
    let reply = served.request(Method::POST, &reset, &proxied, "").await;
    // Reset while held and still decelerating: held until the axes stand, then idle.
    assert_eq!(reply.status, 200, "same-origin, proxy");
    assert!(["hold", "idle"].contains(&reply.json()["run_state"].as_str().unwrap()), "{:?}", reply.json());
    // (Not a cycle start here: after a reset in motion the axes still decelerate, and a start
    // meanwhile is 409.)
    let overrides = format!("/api/v1/controllers/{id}/overrides");
    let reply = served.request(Method::PUT, &overrides, &[json], r#"{"feed": 50}"#).await;
    assert_eq!(
        (reply.status.as_u16(), reply.json()["panel"]["feed_override"].clone()),
        (200, json!(50.0)),
        "no origin"
    );
    assert_eq!(served.request(Method::POST, &reset, &[], "").await.status, 200, "no origin, bodyless");
    // An origin like the allowed one is not the allowed one.
    let near = served.request(Method::POST, &hold, &[("origin", "http://localhost:5174")], "").await;
    assert_forbidden(&near, "another port");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_allow_list_comes_from_the_environment_and_bad_origins_are_usage_errors() {
    let dir = tempfile::tempdir().unwrap();
    let envs = [("FIVEX_ALLOW_ORIGIN", "http://a.example,https://b.example:8443")];
    let served = Served::start_with_env(dir, &[], &envs);
    let served = &served;
    let post = |origin: &'static str| async move {
        served.request(Method::POST, "/api/v1/controllers", &[("origin", origin)], "").await
    };
    // Past the Origin check a bodyless create is a JSON error of the handler, not a 403.
    assert_ne!(post("http://a.example").await.status, 403);
    assert_ne!(post("https://b.example:8443").await.status, 403);
    assert_forbidden(&post("https://b.example").await, "the port is part of the origin");

    for bad in ["http://a.example/app", "a.example"] {
        let dir = tempfile::tempdir().unwrap();
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_fivex"))
            .args(["serve", "--addr", "127.0.0.1:0", "--db"])
            .arg(dir.path().join("fivex.db"))
            .env("FIVEX_ALLOW_ORIGIN", format!("http://ok.example,{bad}"))
            .output()
            .expect("run fivex serve");
        assert_eq!(out.status.code(), Some(2), "{bad}: {out:?}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains("is not an origin"), "{bad}: {stderr}");
        assert!(!dir.path().join("fivex.db").exists(), "{bad}: the service started");
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn json_endpoints_refuse_other_content_types_with_415_json() {
    let served = Served::start(&[]);
    let create = json!({"name": "c", "preset": "mill3"}).to_string();
    let as_text =
        served.request(Method::POST, "/api/v1/controllers", &[("content-type", "text/plain")], create.clone()).await;
    let as_form = served
        .request(
            Method::POST,
            "/api/v1/controllers",
            &[("content-type", "application/x-www-form-urlencoded")],
            create.clone(),
        )
        .await;
    let untyped = served.request(Method::POST, "/api/v1/controllers", &[], create.clone()).await;
    for (what, reply) in [("text/plain", &as_text), ("form", &as_form), ("no content type", &untyped)] {
        assert_eq!(reply.status, 415, "{what}: {:?}", String::from_utf8_lossy(&reply.body));
        assert!(reply.json()["error"].as_str().unwrap().contains("application/json"), "{what}: {}", reply.json());
    }
    assert_eq!(served.get("/api/v1/controllers").await.json(), json!([]), "nothing was created");

    let created = served
        .request(Method::POST, "/api/v1/controllers", &[("content-type", "application/json; charset=utf-8")], create)
        .await;
    assert_eq!(created.status, 201);
    let id = created.json()["id"].as_str().unwrap().to_owned();
    // A bodyless action refuses a declared text body too (the reset a form would post).
    let reset = format!("/api/v1/controllers/{id}/reset");
    let text_reset = served.request(Method::POST, &reset, &[("content-type", "text/plain")], "x").await;
    assert_eq!(text_reset.status, 415);
    assert!(text_reset.json()["error"].is_string());
    assert_eq!(served.request(Method::POST, &reset, &[], "").await.status, 200, "bodyless without a type");
    // Program text stays text/plain, and JSON is not program text.
    let program = format!("/api/v1/controllers/{id}/programs/1");
    assert_eq!(served.request(Method::PUT, &program, &[("content-type", "text/plain")], SLOW).await.status, 201);
    let as_json = served.request(Method::PUT, &program, &[("content-type", "application/json")], "\"O1\"").await;
    assert_eq!(as_json.status, 415);
    assert!(as_json.json()["error"].as_str().unwrap().contains("text/plain"));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_token_with_plus_slash_and_equals_works_in_any_bearer_case_and_percent_encoded_on_every_websocket() {
    let served = Served::start(&["--token", "a+b/c=d"]);
    let bearer = |value: &'static str| [("authorization", value)];

    let none = served.get("/api/v1/controllers").await;
    assert_eq!(none.status, 401);
    assert_eq!(none.headers.get("www-authenticate").unwrap(), "Bearer");
    assert!(none.json()["error"].as_str().unwrap().contains("Bearer"));
    for value in ["Bearer a+b/c=d", "bearer a+b/c=d", "BEARER a+b/c=d"] {
        let reply = served.request(Method::GET, "/api/v1/controllers", &bearer(value), "").await;
        assert_eq!(reply.status, 200, "{value}");
    }
    for value in ["Bearer a b/c=d", "Bearer a%2Bb%2Fc%3Dd", "Basic a+b/c=d", "a+b/c=d"] {
        let reply = served.request(Method::GET, "/api/v1/controllers", &bearer(value), "").await;
        assert_eq!(reply.status, 401, "{value}");
    }

    let auth = ("authorization", "bearer a+b/c=d");
    let json = ("content-type", "application/json");
    let created =
        served.request(Method::POST, "/api/v1/controllers", &[auth, json], r#"{"name": "c", "preset": "mill3"}"#).await;
    assert_eq!(created.status, 201);
    let id = created.json()["id"].as_str().unwrap().to_owned();
    let run = json!({"program": "O1\nG01 X1. F1000.\nM30\n", "presets": ["mill3"]}).to_string();
    let posted = served.request(Method::POST, "/api/v1/fleet/runs?wait=false", &[auth, json], run).await;
    assert_eq!(posted.status, 202, "{:?}", String::from_utf8_lossy(&posted.body));
    let run_id = posted.json()["id"].as_str().unwrap().to_owned();

    let sockets = [
        ("/api/v1/stream?rate=2", "fleet"),
        (&*format!("/api/v1/controllers/{id}/stream?rate=5"), "snapshot"),
        (&*format!("/api/v1/fleet/runs/{run_id}/stream"), "progress"),
    ]
    .map(|(p, t)| (p.to_owned(), t));
    for (path, first) in &sockets {
        let sep = if path.contains('?') { '&' } else { '?' };
        let encoded = format!("{path}{sep}token=a%2Bb%2Fc%3Dd");
        assert_eq!(opened(websocket(&served, &encoded, &[]).await, &encoded)["type"], *first, "{encoded}");
        let raw = format!("{path}{sep}token=a+b/c=d");
        assert_eq!(opened(websocket(&served, &raw, &[]).await, &raw)["type"], *first, "{raw}");
        let (status, body) = refused(websocket(&served, path, &[]).await, path);
        assert_eq!(status, 401, "{path}: {body}");
        let wrong = format!("{path}{sep}token=a%2Bb%2Fc%3De");
        assert_eq!(refused(websocket(&served, &wrong, &[]).await, &wrong).0, 401);
    }
    // The dashboard, the health check and the documentation stay open.
    for open in ["/", "/healthz", "/api-docs/openapi.json"] {
        assert_eq!(served.get(open).await.status, 200, "{open}");
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_openapi_document_declares_the_bearer_scheme_on_every_api_operation() {
    let served = Served::start(&[]);
    let doc = served.get("/api-docs/openapi.json").await.json();
    assert_eq!(doc["components"]["securitySchemes"]["bearer"]["type"], "http");
    assert_eq!(doc["components"]["securitySchemes"]["bearer"]["scheme"], "bearer");
    let mut api_operations = 0;
    for (path, item) in doc["paths"].as_object().unwrap() {
        for (method, operation) in item.as_object().unwrap() {
            let security = &operation["security"];
            if path.starts_with("/api/") {
                api_operations += 1;
                assert!(security.as_array().unwrap().contains(&json!({"bearer": []})), "{method} {path}: {security}");
                assert_eq!(
                    operation["responses"]["401"]["content"]["application/json"]["schema"]["$ref"],
                    "#/components/schemas/ErrorBody"
                );
                // Every operation checks Host; the guarded ones the origin too.
                assert!(operation["responses"].get("403").is_some(), "{method} {path}");
            } else {
                assert!(security.is_null(), "{method} {path} is open: {security}");
            }
        }
    }
    assert!(api_operations > 40, "{api_operations} operations under /api/");
}

/// DNS rebinding: a page whose own name was made to point at the operator's 127.0.0.1 is
/// "same-origin" to the browser, which sends that name as `Host`. Only IP addresses,
/// `localhost` and the hosts of allow-listed origins are answered, also for reading, also on a
/// websocket.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_rebound_dns_name_is_refused_for_reading_and_writing() {
    let served = Served::start(&["--allow-origin", "http://cnc.example:8080"]);
    let port = served.addr.rsplit(':').next().unwrap().to_owned();
    let rebound = format!("evil.example:{port}");
    let same_origin = format!("http://{rebound}");
    for (method, path) in
        [(Method::GET, "/api/v1/controllers"), (Method::GET, "/healthz"), (Method::POST, "/api/v1/controllers")]
    {
        let reply = served
            .request(
                method.clone(),
                path,
                &[("host", &rebound), ("origin", &same_origin), ("sec-fetch-site", "same-origin")],
                "{}",
            )
            .await;
        assert_forbidden(&reply, &format!("{method} {path} under a rebound name"));
        assert!(reply.json()["error"].as_str().unwrap().contains("--allow-origin"), "{:?}", reply.json());
    }
    let (status, _) =
        refused(websocket(&served, "/api/v1/stream", &[("host", &rebound)]).await, "fleet stream under a rebound name");
    assert_eq!(status, 403);
    for host in [format!("localhost:{port}"), format!("127.0.0.1:{port}"), "cnc.example:8080".to_owned()] {
        let reply = served.request(Method::GET, "/api/v1/controllers", &[("host", &host)], "").await;
        assert_eq!(reply.status, 200, "{host}: {:?}", reply.json());
    }
}
