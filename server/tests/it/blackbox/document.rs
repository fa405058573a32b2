//! The OpenAPI document is exact (issue 19, docs/api.md "Checking the document"): the answers
//! no handler writes (400, 413, 415, 422, the websocket handshake's 400) are among those the
//! served document lists for the operation, and request bodies are read as its schemas say
//! (an object, never an array; `4.0` is an integer). schemathesis checks the same at large
//! (`scripts/schemathesis.sh`); these keep the cases it found.

use hyper::Method;
use serde_json::{json, Value};

use super::served::{Reply, Served};

/// The statuses the served document lists for `method` on `path` (as the document writes it).
fn documented(document: &Value, method: &str, path: &str) -> Vec<String> {
    let responses = &document["paths"][path][method]["responses"];
    let listed: Vec<String> = responses.as_object().map(|r| r.keys().cloned().collect()).unwrap_or_default();
    assert!(!listed.is_empty(), "{method} {path} is not in the document");
    listed
}

/// Asserts the reply is the JSON error with `status`, and that the document lists it.
fn answered_as_documented(reply: &Reply, status: u16, document: &Value, method: &str, path: &str) {
    assert_eq!(reply.status, status, "{method} {path}: {}", String::from_utf8_lossy(&reply.body));
    assert!(reply.json()["error"].is_string(), "{method} {path}: not the JSON error");
    let listed = documented(document, method, path);
    assert!(listed.contains(&status.to_string()), "{method} {path} answered {status}, the document lists {listed:?}");
}

async fn controller(served: &Served) -> String {
    let created =
        served.send_json(Method::POST, "/api/v1/controllers", &json!({"name": "doc", "preset": "mill3"})).await;
    assert_eq!(created.status, 201);
    created.json()["id"].as_str().expect("id").to_owned()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_answers_no_handler_writes_are_documented() {
    let served = Served::start(&[]);
    let document = served.get("/api-docs/openapi.json").await.json();
    let id = controller(&served).await;

    // 400: a path value of the wrong type, a query value of the wrong type, JSON that does not parse.
    let reply = served.get(&format!("/api/v1/controllers/{id}/programs/-1")).await;
    answered_as_documented(&reply, 400, &document, "get", "/api/v1/controllers/{id}/programs/{number}");
    let reply = served.get(&format!("/api/v1/controllers/{id}/runs?limit=true")).await;
    answered_as_documented(&reply, 400, &document, "get", "/api/v1/controllers/{id}/runs");
    let json = [("content-type", "application/json")];
    let path = format!("/api/v1/controllers/{id}/switches");
    let reply = served.request(Method::PUT, &path, &json, "{").await;
    answered_as_documented(&reply, 400, &document, "put", "/api/v1/controllers/{id}/switches");

    // 415: a bodyless action sent as text, a JSON endpoint without a content type.
    let path = format!("/api/v1/controllers/{id}/reset");
    let reply = served.request(Method::POST, &path, &[("content-type", "text/plain")], "").await;
    answered_as_documented(&reply, 415, &document, "post", "/api/v1/controllers/{id}/reset");
    let reply = served.request(Method::PATCH, &format!("/api/v1/controllers/{id}"), &[], "{}").await;
    answered_as_documented(&reply, 415, &document, "patch", "/api/v1/controllers/{id}");

    // 413: a body over the limit (8 MiB + 64 KiB).
    let big = vec![b' '; 8 * 1024 * 1024 + 64 * 1024 + 1];
    let reply = served.request(Method::PUT, &format!("/api/v1/controllers/{id}/mode"), &json, big).await;
    answered_as_documented(&reply, 413, &document, "put", "/api/v1/controllers/{id}/mode");

    // 422: JSON of the wrong shape (an unknown field).
    let path = format!("/api/v1/controllers/{id}/emergency-stop");
    let reply = served.send_json(Method::PUT, &path, &json!({"pressed": true, "extra": 1})).await;
    answered_as_documented(&reply, 422, &document, "put", "/api/v1/controllers/{id}/emergency-stop");

    // A websocket route without the handshake: 400, and the handshake's headers are documented.
    let reply = served.get("/api/v1/stream").await;
    answered_as_documented(&reply, 400, &document, "get", "/api/v1/stream");
    for path in ["/api/v1/stream", "/api/v1/controllers/{id}/stream", "/api/v1/fleet/runs/{id}/stream"] {
        let listed = documented(&document, "get", path);
        for status in ["101", "400", "429", "503"] {
            assert!(listed.contains(&status.to_owned()), "GET {path} lacks {status}: {listed:?}");
        }
        let headers: Vec<&str> = document["paths"][path]["get"]["parameters"]
            .as_array()
            .expect("parameters")
            .iter()
            .filter(|p| p["in"] == "header" && p["required"] == true)
            .filter_map(|p| p["name"].as_str())
            .collect();
        assert_eq!(headers, ["Upgrade", "Connection", "Sec-WebSocket-Version", "Sec-WebSocket-Key"], "GET {path}");
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn bodies_are_read_as_the_schemas_say() {
    let served = Served::start(&[]);
    let id = controller(&served).await;

    // An array is not the object the schema asks for, though serde would read a struct from it.
    let path = format!("/api/v1/controllers/{id}/overrides");
    let refused = served.send_json(Method::PUT, &path, &json!([50, 50])).await;
    assert_eq!(refused.status, 422, "{}", String::from_utf8_lossy(&refused.body));
    assert_eq!(refused.json()["error"], "the request body must be a JSON object");
    let status = served.get(&format!("/api/v1/controllers/{id}")).await.json();
    assert_eq!(status["panel"]["feed_override"], 100.0, "the refused array changed the override");

    // `4.0` is the integer 4 (JSON Schema), `4.5` is not an integer.
    let path = format!("/api/v1/controllers/{id}/manual-signals");
    let taken = served.send_json(Method::PUT, &path, &json!({"handle_select": 4.0})).await;
    assert_eq!(taken.status, 200, "{}", String::from_utf8_lossy(&taken.body));
    assert_eq!(taken.json()["panel"]["signals"]["handle_select"], 4);
    let refused = served.send_json(Method::PUT, &path, &json!({"handle_select": 4.5})).await;
    assert_eq!(refused.status, 422);
    assert!(refused.json()["error"].as_str().unwrap_or("").contains("handle_select"), "{:?}", refused.json());

    // A number at a limit is compared as sent (exact parsing): a wear of 99.999 mm is the
    // range's end, taken and read back as written; a step beyond it is refused.
    let path = format!("/api/v1/controllers/{id}/tool-offsets/1");
    let taken = served.send_json(Method::PUT, &path, &json!({"radius_wear": -99.999})).await;
    assert_eq!(taken.status, 200, "{}", String::from_utf8_lossy(&taken.body));
    assert_eq!(taken.json()["radius_wear"], json!(-99.999));
    let refused = served.send_json(Method::PUT, &path, &json!({"radius_wear": -99.99901})).await;
    assert_eq!(refused.status, 422, "{}", String::from_utf8_lossy(&refused.body));

    // Cycle start's optional body: `null` is no body (resume; nothing to run here: 409).
    let path = format!("/api/v1/controllers/{id}/cycle-start");
    let reply = served.request(Method::POST, &path, &[("content-type", "application/json")], "null").await;
    assert_eq!(reply.status, 409, "{}", String::from_utf8_lossy(&reply.body));
    assert_eq!(reply.json()["error"], "there is no program to run");
}
