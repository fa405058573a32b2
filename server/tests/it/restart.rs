//! `POST /controllers/{id}/restart` (FANUC program restart, `docs/dialects.md`): the search
//! answers the status with `restart` filled in, cycle start returns the axes and runs the rest
//! of the program; the manual's conditions are alarms, malformed requests 422, the panel's
//! refusals 409.

use crate::common;

use std::time::Duration;

use axum::http::{Method, StatusCode};
use common::{spawn_app, TestApp};
use serde_json::{json, Value};

const C: &str = "/api/v1/controllers";

const PROGRAM: &str =
    "O0001\nN10 G90 G00 X10. Y20. Z30.\nN20 T3 M06\nN30 S1500 M04\nN40 G01 X40. F6000.\nN50 Y-10.\nN60 M30\n";

async fn controller(app: &TestApp, dialect: &str) -> String {
    let reply = app.post(C, &json!({"name": "r", "preset": "mill3", "dialect": dialect, "speed": 20})).await;
    assert_eq!(reply.status, StatusCode::CREATED, "{}", reply.text());
    let id = reply.json()["id"].as_str().unwrap().to_string();
    let stored = app.raw(Method::PUT, &format!("{C}/{id}/programs/1"), "text/plain", PROGRAM.to_string()).await;
    assert!(stored.status.is_success(), "{}", stored.text());
    id
}

/// Poll the status (the workers run in real time) until `done` holds, within 10 s.
async fn status_until(app: &TestApp, id: &str, done: impl Fn(&Value) -> bool) -> Value {
    for _ in 0..500 {
        let status = app.get(&format!("{C}/{id}")).await.json();
        if done(&status) {
            return status;
        }
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    panic!("{id} never got there: {}", app.get(&format!("{C}/{id}")).await.text());
}

#[tokio::test]
async fn a_q_type_restart_searches_then_cycle_start_returns_and_finishes_the_program() {
    let app = spawn_app().await;
    let id = controller(&app, "fanuc").await;
    let reply = app.post(&format!("{C}/{id}/restart"), &json!({"program": 1, "type": "q", "n": 50})).await;
    assert_eq!(reply.status, StatusCode::OK, "{}", reply.text());
    let status = reply.json();
    assert_eq!(status["run_state"], "idle");
    assert_eq!(status["mode"], "auto");
    assert_eq!(status["program"], 1);
    let restart = &status["restart"];
    assert_eq!(restart["type"], "q", "{status}");
    assert_eq!(restart["phase"], "searched");
    assert_eq!((restart["line"].as_u64(), restart["n"].as_u64()), (Some(6), Some(50)));
    assert_eq!(restart["position"], json!({"X": 40.0, "Y": 20.0, "Z": 30.0}));
    assert_eq!((restart["tool"].as_u64(), restart["spindle"].as_f64()), (Some(3), Some(-1500.0)));
    assert_eq!(restart["m_codes"], json!([]));
    assert_eq!(status["position"]["machine"]["X"], 0.0, "the search moves nothing");

    let started = app.post(&format!("{C}/{id}/cycle-start"), &json!({})).await.json();
    assert_eq!(started["run_state"], "running", "{started}");
    assert_eq!(started["restart"]["phase"], "returning");
    let done = status_until(&app, &id, |s| s["run_state"] == "idle").await;
    assert_eq!(done["restart"], Value::Null);
    assert_eq!(done["alarms"], json!([]));
    assert_eq!(done["position"]["machine"], json!({"X": 40.0, "Y": -10.0, "Z": 30.0}));
}

#[tokio::test]
async fn the_manuals_conditions_are_alarms_in_the_status() {
    let app = spawn_app().await;
    let id = controller(&app, "fanuc").await;
    // P type before any automatic operation: PS0097.
    let status = app.post(&format!("{C}/{id}/restart"), &json!({"program": 1, "type": "P", "n": 40})).await.json();
    assert_eq!(status["run_state"], "alarm", "{status}");
    assert_eq!(status["alarms"][0]["code"], "PS0097");
    assert_eq!(status["restart"], Value::Null);
    app.post(&format!("{C}/{id}/reset"), &json!({})).await;
    // A block the program never reaches: PS0071.
    let status = app.post(&format!("{C}/{id}/restart"), &json!({"type": "q", "n": 45})).await.json();
    assert_eq!(status["alarms"][0]["code"], "PS0071", "{status}");
    app.post(&format!("{C}/{id}/reset"), &json!({})).await;
    // By line, after an MDI operation: PS0099 at cycle start in MDI.
    let status = app.post(&format!("{C}/{id}/restart"), &json!({"type": "q", "line": 5, "occurrence": 1})).await.json();
    assert_eq!(status["restart"]["n"], 40, "{status}");
    let status = app.post(&format!("{C}/{id}/mdi"), &json!({"text": "G91 G00 X1."})).await.json();
    assert_eq!(status["alarms"][0]["code"], "PS0099", "{status}");
}

#[tokio::test]
async fn malformed_restarts_are_422_and_the_panels_refusals_409() {
    let app = spawn_app().await;
    let id = controller(&app, "fanuc").await;
    let restart = |body: Value| {
        let app = &app;
        let id = id.clone();
        async move { app.post(&format!("{C}/{id}/restart"), &body).await }
    };
    for body in [
        json!({"type": "q"}),
        json!({"type": "q", "n": 10, "line": 2}),
        json!({"type": "r", "n": 10}),
        json!({"type": "q", "n": 0}),
        json!({"type": "q", "n": 10, "occurrence": 0}),
        json!({"type": "q", "n": 10, "block": 3}),
        json!({"n": 10}),
    ] {
        let reply = restart(body.clone()).await;
        assert_eq!(reply.status, StatusCode::UNPROCESSABLE_ENTITY, "{body}: {}", reply.text());
        assert!(reply.json()["error"].is_string(), "{}", reply.text());
    }
    assert_eq!(restart(json!({"program": 7, "type": "q", "n": 10})).await.status, StatusCode::NOT_FOUND);
    // Nothing selected yet.
    assert_eq!(restart(json!({"type": "q", "n": 10})).await.status, StatusCode::CONFLICT);
    // While the program runs.
    app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
    let busy = restart(json!({"type": "q", "n": 10})).await;
    if busy.status != StatusCode::OK {
        assert_eq!(busy.status, StatusCode::CONFLICT, "{}", busy.text());
    } else {
        // The program was already over (a fast worker): the restart is then allowed.
        assert_eq!(busy.json()["restart"]["phase"], "searched");
    }
    // Syntec: its manuals describe no restart.
    let syntec = controller(&app, "syntec").await;
    let reply = app.post(&format!("{C}/{syntec}/restart"), &json!({"program": 1, "type": "q", "n": 10})).await;
    assert_eq!(reply.status, StatusCode::CONFLICT, "{}", reply.text());
}
