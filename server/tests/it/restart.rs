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
    // By line; an MDI move after the search: PS0099 when MDI reads it (M/S/T before it keep
    // the search).
    let status = app.post(&format!("{C}/{id}/restart"), &json!({"type": "q", "line": 5, "occurrence": 1})).await.json();
    assert_eq!(status["restart"]["n"], 40, "{status}");
    let status = app.post(&format!("{C}/{id}/mdi"), &json!({"text": "S200 M03"})).await.json();
    assert_eq!(status["alarms"], json!([]), "{status}");
    let status = status_until(&app, &id, |s| s["run_state"] == "idle").await;
    assert_eq!(status["restart"]["phase"], "searched", "{status}");
    app.post(&format!("{C}/{id}/mdi"), &json!({"text": "G91 G00 X1."})).await;
    let status = status_until(&app, &id, |s| s["run_state"] != "running").await;
    assert_eq!(status["alarms"][0]["code"], "PS0099", "{status}");
    assert_eq!(status["restart"], Value::Null);
    assert_eq!(status["position"]["machine"]["X"], 0.0, "the move is not made");
}

#[tokio::test]
async fn p_type_after_a_coordinate_system_setting_or_an_external_offset_change_is_refused() {
    let app = spawn_app().await;
    let id = controller(&app, "fanuc").await;
    let run_to_end = || {
        let app = &app;
        let id = id.clone();
        async move {
            app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
            status_until(app, &id, |s| s["run_state"] == "idle").await;
        }
    };
    // G92 in MDI after the run: PS0094.
    run_to_end().await;
    app.post(&format!("{C}/{id}/mdi"), &json!({"text": "G92 X0 Y0"})).await;
    status_until(&app, &id, |s| s["run_state"] == "idle").await;
    app.put(&format!("{C}/{id}/mode"), &json!({"mode": "auto"})).await;
    let status = app.post(&format!("{C}/{id}/restart"), &json!({"type": "p", "n": 40})).await.json();
    assert_eq!(status["alarms"][0]["code"], "PS0094", "{status}");
    app.post(&format!("{C}/{id}/reset"), &json!({})).await;
    // The external work offset changed: PS0095.
    run_to_end().await;
    let reply = app.put(&format!("{C}/{id}/work-offsets/EXT"), &json!({"axes": {"X": 1.5}})).await;
    assert_eq!(reply.status, StatusCode::OK, "{}", reply.text());
    let status = app.post(&format!("{C}/{id}/restart"), &json!({"type": "p", "n": 40})).await.json();
    assert_eq!(status["alarms"][0]["code"], "PS0095", "{status}");
    assert_eq!(status["alarms"][0]["message"], "P TYPE NOT ALLOWED (EXT OFS CHG)");
}

#[tokio::test]
async fn the_searched_program_cannot_change_until_the_restart_ran_or_was_forgotten() {
    let app = spawn_app().await;
    let id = controller(&app, "fanuc").await;
    let put = |text: &'static str| {
        let app = &app;
        let id = id.clone();
        async move { app.raw(Method::PUT, &format!("{C}/{id}/programs/1"), "text/plain", text.to_string()).await }
    };
    let status = app.post(&format!("{C}/{id}/restart"), &json!({"program": 1, "type": "q", "n": 50})).await.json();
    assert_eq!(status["restart"]["phase"], "searched", "{status}");
    let refused = put(PROGRAM).await;
    assert_eq!(refused.status, StatusCode::CONFLICT, "{}", refused.text());
    assert!(refused.json()["error"].as_str().unwrap().contains("restart"), "{}", refused.text());
    let refused = app.request(Method::DELETE, &format!("{C}/{id}/programs/1")).await;
    assert_eq!(refused.status, StatusCode::CONFLICT, "{}", refused.text());
    // M/S/T in MDI keep the search, and the hold on the program.
    app.post(&format!("{C}/{id}/mdi"), &json!({"text": "M08"})).await;
    status_until(&app, &id, |s| s["run_state"] == "idle").await;
    assert_eq!(put(PROGRAM).await.status, StatusCode::CONFLICT);
    // A reset forgets the search: the program may change.
    app.post(&format!("{C}/{id}/reset"), &json!({})).await;
    assert_eq!(put(PROGRAM).await.status, StatusCode::OK);
    // The restart ran to its end: it may change too.
    app.put(&format!("{C}/{id}/mode"), &json!({"mode": "auto"})).await;
    app.post(&format!("{C}/{id}/restart"), &json!({"program": 1, "type": "q", "n": 50})).await;
    app.post(&format!("{C}/{id}/cycle-start"), &json!({})).await;
    let done = status_until(&app, &id, |s| s["run_state"] == "idle").await;
    assert_eq!(done["alarms"], json!([]), "{done}");
    assert_eq!(put(PROGRAM).await.status, StatusCode::OK);
}

/// A loop of `passes` (three blocks each) before N50.
fn long_program(passes: u32) -> String {
    format!("O0002\n#500 = 0\nWHILE [#500 LT {passes}] DO1\n#500 = #500 + 1\nEND1\nN50 G00 X5.\nN60 M30\n")
}

#[tokio::test]
async fn a_long_search_runs_over_the_ticks_without_blocking_the_service_and_a_reset_stops_it() {
    let app = spawn_app().await;
    let id = controller(&app, "fanuc").await;
    for (n, passes) in [(2, 1_000_000), (3, 20_000)] {
        let text = long_program(passes).replace("O0002", &format!("O{n:04}"));
        let stored = app.raw(Method::PUT, &format!("{C}/{id}/programs/{n}"), "text/plain", text).await;
        assert!(stored.status.is_success(), "{}", stored.text());
    }
    // A million passes: the answer comes at once, the search goes on.
    let reply = app.post(&format!("{C}/{id}/restart"), &json!({"program": 2, "type": "q", "n": 50})).await;
    assert_eq!(reply.status, StatusCode::OK, "{}", reply.text());
    let status = reply.json();
    assert_eq!(status["restart"]["phase"], "searching", "{status}");
    assert_eq!(status["run_state"], "running");
    let status = app.get(&format!("{C}/{id}")).await.json();
    assert_eq!(status["restart"]["phase"], "searching", "the service answers meanwhile: {status}");
    let again = app.post(&format!("{C}/{id}/restart"), &json!({"type": "q", "n": 50})).await;
    assert_eq!(again.status, StatusCode::CONFLICT);
    assert!(again.json()["error"].as_str().unwrap().starts_with("searching"), "{}", again.text());
    let edit = app.raw(Method::PUT, &format!("{C}/{id}/programs/2"), "text/plain", long_program(5)).await;
    assert_eq!(edit.status, StatusCode::CONFLICT, "{}", edit.text());
    // A reset stops it.
    let status = app.post(&format!("{C}/{id}/reset"), &json!({})).await.json();
    assert_eq!(status["restart"], Value::Null, "{status}");
    assert_eq!(status["run_state"], "idle");
    // A shorter one ends over a few ticks.
    let status = app.post(&format!("{C}/{id}/restart"), &json!({"program": 3, "type": "q", "n": 50})).await.json();
    assert_eq!(status["restart"]["phase"], "searching", "{status}");
    let status = status_until(&app, &id, |s| s["restart"]["phase"] != "searching").await;
    assert_eq!(status["restart"]["phase"], "searched", "{status}");
    assert!(status["restart"]["blocks"].as_u64().unwrap() > 20_000, "{status}");
    assert_eq!(status["run_state"], "idle");
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
    // Every 409 names the state that refuses it.
    let refused = |reply: common::Reply, state: &str| {
        assert_eq!(reply.status, StatusCode::CONFLICT, "{state}: {}", reply.text());
        let error = reply.json()["error"].as_str().unwrap().to_string();
        assert!(error.starts_with(state), "{state}: {error}");
    };
    // Nothing selected yet.
    refused(restart(json!({"type": "q", "n": 10})).await, "no program selected");
    // Outside AUTO.
    app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
    status_until(&app, &id, |s| s["run_state"] == "idle").await;
    app.put(&format!("{C}/{id}/mode"), &json!({"mode": "jog"})).await;
    refused(restart(json!({"type": "q", "n": 10})).await, "not in AUTO");
    app.put(&format!("{C}/{id}/mode"), &json!({"mode": "auto"})).await;
    // In alarm (PS0097 is no longer possible: an alarm of the program's own).
    let bad = app
        .raw(Method::PUT, &format!("{C}/{id}/programs/4?force=true"), "text/plain", "O0004\n#3000 = 1 (STOP)\nM30\n")
        .await;
    assert!(bad.status.is_success(), "{}", bad.text());
    let status = app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 4})).await.json();
    let status = if status["run_state"] == "alarm" {
        status
    } else {
        status_until(&app, &id, |s| s["run_state"] == "alarm").await
    };
    assert_eq!(status["run_state"], "alarm", "{status}");
    refused(restart(json!({"type": "q", "n": 10})).await, "in alarm");
    refused(restart(json!({"program": 1, "type": "q", "n": 10})).await, "in alarm");
    app.post(&format!("{C}/{id}/reset"), &json!({})).await;
    // While the program runs (F10.: a slow move).
    let slow =
        app.raw(Method::PUT, &format!("{C}/{id}/programs/5"), "text/plain", "O0005\nG91 G01 X50. F10.\nM30\n").await;
    assert!(slow.status.is_success(), "{}", slow.text());
    app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 5})).await;
    refused(restart(json!({"type": "q", "n": 10})).await, "running");
    refused(restart(json!({"program": 1, "type": "q", "n": 10})).await, "running");
    // Held.
    app.post(&format!("{C}/{id}/feed-hold"), &json!({})).await;
    status_until(&app, &id, |s| s["run_state"] == "hold").await;
    refused(restart(json!({"type": "q", "n": 10})).await, "holding");
    app.post(&format!("{C}/{id}/reset"), &json!({})).await;
    // Syntec: its manuals describe no restart.
    let syntec = controller(&app, "syntec").await;
    let reply = app.post(&format!("{C}/{syntec}/restart"), &json!({"program": 1, "type": "q", "n": 10})).await;
    refused(reply, "Syntec has no program restart");
}
