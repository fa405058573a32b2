//! The controller API through `oneshot` on a fresh database per test: creating controllers,
//! storing programs, running them, variables, history, restart, and requests that must be
//! refused with a JSON reason.

use crate::common;

use chrono::Timelike;
use std::time::Duration;

use axum::http::{Method, StatusCode};
use common::{spawn_app, Reply, TestApp};
use serde_json::{json, Value};

const C: &str = "/api/v1/controllers";

async fn create(app: &TestApp, body: Value) -> String {
    let reply = app.post(C, &body).await;
    assert_eq!(reply.status, StatusCode::CREATED, "{}", reply.text());
    reply.json()["id"].as_str().unwrap().to_string()
}

async fn store(app: &TestApp, id: &str, number: u32, text: &str) -> Reply {
    app.raw(Method::PUT, &format!("{C}/{id}/programs/{number}"), "text/plain", text.to_string()).await
}

/// Poll the status until `run_state` is `want` (the workers run in real time).
async fn wait_for(app: &TestApp, id: &str, want: &str) -> Value {
    for _ in 0..500 {
        let status = app.get(&format!("{C}/{id}")).await.json();
        if status["run_state"] == want {
            return status;
        }
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    panic!("{id} never became {want}: {}", app.get(&format!("{C}/{id}")).await.text());
}

/// GET `uri` until `done` holds for its JSON (what the background writer stores lands within
/// milliseconds, not before the answer that caused it).
async fn eventually(app: &TestApp, uri: &str, done: impl Fn(&Value) -> bool) -> Value {
    for _ in 0..250 {
        let value = app.get(uri).await.json();
        if done(&value) {
            return value;
        }
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    panic!("{uri} never got there: {}", app.get(uri).await.text());
}

fn error_of(reply: &Reply) -> String {
    assert_eq!(reply.content_type, "application/json", "{}", reply.text());
    reply.json()["error"].as_str().unwrap_or_else(|| panic!("no error field: {}", reply.text())).to_string()
}

#[tokio::test]
async fn a_controller_is_created_from_a_preset_or_a_machine_document() {
    let app = spawn_app().await;
    let reply = app.post(C, &json!({"name": "cell 1", "preset": "table-ac", "dialect": "syntec"})).await;
    assert_eq!(reply.status, StatusCode::CREATED);
    let c = reply.json();
    assert_eq!(
        (c["name"].as_str(), c["dialect"].as_str(), c["machine"].as_str()),
        (Some("cell 1"), Some("syntec"), Some("table-ac"))
    );
    assert_eq!((c["mode"].as_str(), c["run_state"].as_str()), (Some("auto"), Some("idle")));
    let axes: Vec<&String> = c["position"]["machine"].as_object().unwrap().keys().collect();
    assert_eq!(axes, ["X", "Y", "Z", "A", "C"]);

    let machine = serde_json::to_value(fivex_engine::machine::MachineConfig::preset("head-bc").unwrap()).unwrap();
    let id = create(&app, json!({"name": "from a document", "machine": machine})).await;
    let params = fivex_engine::vendor::params_of(
        fivex_engine::Dialect::Fanuc,
        &fivex_engine::machine::MachineConfig::preset("mixed-bc").unwrap(),
    )
    .unwrap();
    let list = json!({"name": "p", "dialect": "fanuc", "parameters": params});
    create(&app, json!({"name": "from parameters", "machine": list})).await;

    let all = app.get(C).await.json();
    let names: Vec<&str> = all.as_array().unwrap().iter().map(|c| c["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["cell 1", "from a document", "from parameters"]);
    assert_eq!(app.get(&format!("{C}/{id}")).await.json()["machine"], "head-bc");
}

#[tokio::test]
async fn invalid_creations_are_refused_with_a_reason() {
    let app = spawn_app().await;
    let cases = [
        (json!({"name": "x", "preset": "nope"}), StatusCode::UNPROCESSABLE_ENTITY, "unknown preset"),
        (json!({"name": "x"}), StatusCode::UNPROCESSABLE_ENTITY, "exactly one"),
        (json!({"name": "x", "preset": "mill3", "machine": {}}), StatusCode::UNPROCESSABLE_ENTITY, "exactly one"),
        (json!({"name": " ", "preset": "mill3"}), StatusCode::UNPROCESSABLE_ENTITY, "name"),
        (json!({"name": "x", "preset": "mill3", "dialect": "heidenhain"}), StatusCode::UNPROCESSABLE_ENTITY, "dialect"),
        (json!({"name": "x", "preset": "mill3", "speed": 0}), StatusCode::UNPROCESSABLE_ENTITY, "speed"),
        (json!({"name": "x", "preset": "mill3", "colour": "red"}), StatusCode::UNPROCESSABLE_ENTITY, "colour"),
        (json!({"preset": "mill3"}), StatusCode::UNPROCESSABLE_ENTITY, "name"),
        (json!({"name": "x", "machine": {"name": "m", "axes": []}}), StatusCode::UNPROCESSABLE_ENTITY, "axes"),
    ];
    for (body, status, why) in cases {
        let reply = app.post(C, &body).await;
        assert_eq!(reply.status, status, "{body}: {}", reply.text());
        assert!(error_of(&reply).contains(why), "{body}: {}", reply.text());
    }
    let malformed = app.raw(Method::POST, C, "application/json", "{\"name\": ").await;
    assert_eq!(malformed.status, StatusCode::BAD_REQUEST);
    error_of(&malformed);
    let not_json = app.raw(Method::POST, C, "text/plain", "name=x").await;
    assert_eq!(not_json.status, StatusCode::UNSUPPORTED_MEDIA_TYPE);
    error_of(&not_json);
    assert_eq!(app.get(C).await.json(), json!([]), "nothing was created");
}

#[tokio::test]
async fn unknown_ids_and_numbers_are_404_json() {
    let app = spawn_app().await;
    for uri in [
        format!("{C}/nope"),
        format!("{C}/nope/programs"),
        format!("{C}/nope/variables/500"),
        format!("{C}/nope/alarms"),
    ] {
        let reply = app.get(&uri).await;
        assert_eq!(reply.status, StatusCode::NOT_FOUND, "{uri}");
        error_of(&reply);
    }
    let id = create(&app, json!({"name": "m", "preset": "mill3"})).await;
    let reply = app.get(&format!("{C}/{id}/programs/12")).await;
    assert_eq!(reply.status, StatusCode::NOT_FOUND);
    let reply = app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 12})).await;
    assert_eq!(reply.status, StatusCode::NOT_FOUND);
    let reply = app.get(&format!("{C}/{id}/programs/abc")).await;
    assert_eq!(reply.status, StatusCode::BAD_REQUEST);
    error_of(&reply);
    assert_eq!(app.request(Method::DELETE, &format!("{C}/{id}")).await.status, StatusCode::NO_CONTENT);
    assert_eq!(app.get(&format!("{C}/{id}")).await.status, StatusCode::NOT_FOUND);
    assert_eq!(app.request(Method::DELETE, &format!("{C}/{id}")).await.status, StatusCode::NOT_FOUND);
}

#[tokio::test]
async fn programs_are_checked_and_stored_only_if_clean_or_forced() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "m", "preset": "mill3"})).await;
    let reply = store(&app, &id, 1, "G01 X10. F100\nM30\n").await;
    assert_eq!(reply.status, StatusCode::CREATED, "{}", reply.text());
    assert_eq!(store(&app, &id, 1, "G00 X0\nM30\n").await.status, StatusCode::OK, "replaced");
    assert_eq!(app.get(&format!("{C}/{id}/programs/1")).await.text(), "G00 X0\nM30\n");

    let bad = "G01 X10. F100\nG01 X[1+\nM30\n";
    let reply = store(&app, &id, 2, bad).await;
    assert_eq!(reply.status, StatusCode::UNPROCESSABLE_ENTITY);
    let body = reply.json();
    assert!(body["error"].as_str().unwrap().contains("force"), "{body}");
    assert_eq!(body["details"][0]["line"], 2, "{body}");
    assert_eq!(app.get(&format!("{C}/{id}/programs/2")).await.status, StatusCode::NOT_FOUND, "not stored");
    let forced = app.raw(Method::PUT, &format!("{C}/{id}/programs/2?force=true"), "text/plain", bad).await;
    assert_eq!(forced.status, StatusCode::CREATED);
    assert_eq!(forced.json()["diagnostics"][0]["line"], 2);

    let binary =
        app.raw(Method::PUT, &format!("{C}/{id}/programs/3"), "text/plain", vec![0xffu8, 0xfe, 0x00, 0x41]).await;
    assert_eq!(binary.status, StatusCode::UNPROCESSABLE_ENTITY);
    error_of(&binary);
    let nul = store(&app, &id, 3, "G00 X0\0\n").await;
    assert_eq!(nul.status, StatusCode::UNPROCESSABLE_ENTITY);
    let octets = app.raw(Method::PUT, &format!("{C}/{id}/programs/3"), "application/octet-stream", "G00 X0").await;
    assert_eq!(octets.status, StatusCode::UNSUPPORTED_MEDIA_TYPE);
    assert_eq!(store(&app, &id, 0, "M30").await.status, StatusCode::UNPROCESSABLE_ENTITY);
    assert_eq!(store(&app, &id, 10000, "M30").await.status, StatusCode::UNPROCESSABLE_ENTITY);
    let huge = "G00 X0\n".repeat(1_300_000);
    let reply = store(&app, &id, 4, &huge).await;
    assert_eq!(reply.status, StatusCode::PAYLOAD_TOO_LARGE, "{}", reply.text());

    let list = app.get(&format!("{C}/{id}/programs")).await.json();
    assert_eq!(list, json!([{"number": 1, "size": 11}, {"number": 2, "size": bad.len()}]));
    assert_eq!(app.request(Method::DELETE, &format!("{C}/{id}/programs/2")).await.status, StatusCode::NO_CONTENT);
    assert_eq!(app.request(Method::DELETE, &format!("{C}/{id}/programs/2")).await.status, StatusCode::NOT_FOUND);
}

/// The audit's F8: the hour timer #3002 goes on while the controller stands idle; a graceful
/// restart keeps where it stood, not its value at the run's end.
#[tokio::test]
async fn the_hour_timer_is_kept_where_it_stood_at_a_graceful_stop() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "timer", "preset": "mill3", "speed": 1000})).await;
    assert_eq!(store(&app, &id, 1, "#3002=5.\nM30\n").await.status, StatusCode::CREATED);
    app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
    wait_for(&app, &id, "idle").await;
    let hours = |reply: Reply| reply.json()["value"].as_f64().unwrap();
    // Idle at speed 1000: 0.3 s of real time is 300 s, 0.083 h.
    tokio::time::sleep(Duration::from_millis(300)).await;
    let before = hours(app.get(&format!("{C}/{id}/variables/3002")).await);
    assert!(before > 5.08, "the timer counts while idle: {before}");
    let state = app.restart().await;
    let again = TestApp { state, db_path: app.db_path.clone(), dir: tempfile::tempdir().unwrap() };
    let after = hours(again.get(&format!("{C}/{id}/variables/3002")).await);
    assert!(after >= before, "#3002 went back over the restart: {before} h before, {after} h after");
}

#[tokio::test]
async fn a_program_reads_the_host_clock_as_date_and_time() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "clock", "preset": "mill3"})).await;
    // Whole local seconds: what #3011/#3012 can show.
    let local = || chrono::Local::now().naive_local().with_nanosecond(0).unwrap();
    let before = local();
    let reply = app.post(&format!("{C}/{id}/mdi"), &json!({"text": "#100=#3011\n#101=#3012"})).await;
    assert_eq!(reply.status, StatusCode::OK, "{}", reply.text());
    wait_for(&app, &id, "idle").await;
    let after = local();
    let read = |n: u32| {
        let app = &app;
        let id = &id;
        async move { app.get(&format!("{C}/{id}/variables/{n}")).await.json()["value"].as_f64().unwrap() as u32 }
    };
    let (date, time) = (read(100).await, read(101).await);
    let read = chrono::NaiveDate::from_ymd_opt((date / 10_000) as i32, date / 100 % 100, date % 100)
        .and_then(|d| d.and_hms_opt(time / 10_000, time / 100 % 100, time % 100))
        .unwrap_or_else(|| panic!("#3011 = {date}, #3012 = {time} is no date and time"));
    assert!(before <= read && read <= after, "#3011/#3012 read {read}, the host's clock was {before} … {after}");
}

#[tokio::test]
async fn a_program_runs_sets_variables_and_everything_survives_a_restart() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "fast", "preset": "head-bc", "speed": 50})).await;
    // #500000… (extended, retained), #100000… (extended, not retained), the part count #3901
    // and the hour timer #3002 (retained through power off).
    let program = "#500=7.5\n#101=2\n#500001=4.25\n#100001=9\n#3901=17\nM98 P2\nG01 X10. F6000\n#3002=1.5\nM30\n";
    assert_eq!(store(&app, &id, 1, program).await.status, StatusCode::CREATED);
    assert_eq!(store(&app, &id, 2, "#501=#500*2\nM99\n").await.status, StatusCode::CREATED);
    let started = app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
    assert_eq!(started.status, StatusCode::OK, "{}", started.text());
    assert_eq!(started.json()["program"], 1);
    let done = wait_for(&app, &id, "idle").await;
    assert_eq!(done["position"]["workpiece"]["X"], 10.0, "{done}");
    let operated = done["counters"]["operating_time_s"].as_f64().unwrap();
    assert!(operated > 0.0, "{done}");
    let var = |n: u32| {
        let app = &app;
        let id = id.clone();
        async move { app.get(&format!("{C}/{id}/variables/{n}")).await.json()["value"].clone() }
    };
    assert_eq!((var(500).await, var(501).await, var(101).await), (json!(7.5), json!(15.0), json!(2.0)));
    assert_eq!((var(500001).await, var(100001).await), (json!(4.25), json!(9.0)));
    // The finished run is in the history.
    let runs = eventually(&app, &format!("{C}/{id}/runs"), |r| r.as_array().is_some_and(|a| !a.is_empty())).await;
    assert_eq!((runs[0]["program"].clone(), runs[0]["result"].clone()), (json!(1), json!("completed")), "{runs}");
    assert!(runs[0]["cycle_time_s"].as_f64().unwrap() > 0.0);

    // An API write of a retained variable is in the database when it answers.
    let set = app.put(&format!("{C}/{id}/variables/502"), &json!({"value": -3.25})).await;
    assert_eq!(set.status, StatusCode::OK);
    let state = app.restart().await;
    let again = TestApp { state, db_path: app.db_path.clone(), dir: tempfile::tempdir().unwrap() };
    let c = again.get(&format!("{C}/{id}")).await.json();
    assert_eq!(
        (c["name"].as_str(), c["run_state"].as_str(), c["speed"].as_f64()),
        (Some("fast"), Some("idle"), Some(50.0))
    );
    // The operating and cutting time go on from what they were (FANUC keeps them through power off).
    assert_eq!(c["counters"]["operating_time_s"].as_f64(), Some(operated), "{c}");
    assert_eq!(c["counters"]["cutting_time_s"], done["counters"]["cutting_time_s"], "{c}");
    for (n, v) in [
        (500, json!(7.5)),
        (501, json!(15.0)),
        (502, json!(-3.25)),
        (101, Value::Null),
        (500001, json!(4.25)),
        (100001, Value::Null),
        (3901, json!(18.0)), // M30 counted one part
    ] {
        assert_eq!(again.get(&format!("{C}/{id}/variables/{n}")).await.json()["value"], v, "#{n} after the restart");
    }
    let hours = again.get(&format!("{C}/{id}/variables/3002")).await.json()["value"].as_f64().unwrap();
    // (It goes on counting the controller's time, 50 times real time here: a little above, by
    // as much as the restart took — up to 36 s of a loaded machine's wall time below 2 hours.)
    assert!((1.5..2.0).contains(&hours), "#3002 after the restart: {hours}");
    assert_eq!(again.get(&format!("{C}/{id}/programs/1")).await.text(), program);
    assert_eq!(again.get(&format!("{C}/{id}/runs")).await.json().as_array().unwrap().len(), 1);
    // At most `limit` rows: 0 is none (it gave one).
    assert_eq!(again.get(&format!("{C}/{id}/runs?limit=0")).await.json(), serde_json::json!([]));
    assert_eq!(again.get(&format!("{C}/{id}/alarms?limit=0")).await.json()["history"], serde_json::json!([]));
    assert_eq!(again.get("/api/v1/fleet/runs?limit=0").await.json(), serde_json::json!([]));
}

/// FANUC keeps G20/G21 through power off ("When the power is turned on, the G code is the same
/// as that held before the power was turned off", B-63944EN/02 §8.2): a restart of the service
/// is the controller's power cycle, and G20 came back as G21 — the next `X1.` moved 1 mm, not
/// 25.4. The Haas NGC starts in the unit of Setting 9 (mm here), as before, and keeps its
/// #100–#199 (FANUC does not).
#[tokio::test]
async fn fanuc_keeps_its_inch_mode_over_a_restart() {
    let app = spawn_app().await;
    let mut ids = Vec::new();
    for dialect in ["fanuc", "haas"] {
        let id = create(&app, json!({"name": "u", "preset": "mill3", "dialect": dialect, "speed": 50})).await;
        let mdi = app.post(&format!("{C}/{id}/mdi"), &json!({"text": "G20\n#101=5."})).await;
        assert_eq!(mdi.status, StatusCode::OK, "{}", mdi.text());
        wait_for(&app, &id, "idle").await;
        assert_eq!(app.get(&format!("{C}/{id}/modal")).await.json()["groups"]["6"], "G20", "{dialect}");
        ids.push((id, dialect));
    }
    tokio::time::sleep(Duration::from_millis(200)).await;
    let state = app.restart().await;
    let again = TestApp { state, db_path: app.db_path.clone(), dir: tempfile::tempdir().unwrap() };
    for (id, dialect) in ids {
        let want = if dialect == "fanuc" { "G20" } else { "G21" };
        assert_eq!(again.get(&format!("{C}/{id}/modal")).await.json()["groups"]["6"], want, "{dialect}");
        let kept = if dialect == "haas" { json!(5.0) } else { Value::Null };
        assert_eq!(again.get(&format!("{C}/{id}/variables/101")).await.json()["value"], kept, "{dialect}");
    }
}

#[tokio::test]
async fn a_run_cut_off_by_a_graceful_stop_is_recorded_interrupted() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "long", "preset": "mill3"})).await;
    store(&app, &id, 1, "G04 X100.\nM30\n").await;
    app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
    wait_for(&app, &id, "running").await;
    let state = app.restart().await;
    let again = TestApp { state, db_path: app.db_path.clone(), dir: tempfile::tempdir().unwrap() };
    assert_eq!(again.get(&format!("{C}/{id}")).await.json()["run_state"], "idle", "back in reset state");
    let runs = again.get(&format!("{C}/{id}/runs")).await.json();
    assert_eq!(runs.as_array().unwrap().len(), 1, "{runs}");
    assert_eq!((runs[0]["program"].clone(), runs[0]["result"].clone()), (json!(1), json!("interrupted")), "{runs}");
    assert!(runs[0]["cycle_time_s"].as_f64().unwrap() < 100.0, "{runs}");
}

#[tokio::test]
async fn an_alarm_is_active_then_in_the_history_and_reset_clears_it() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "m", "preset": "mill3", "speed": 20})).await;
    store(&app, &id, 1, "G01 X5. F3000\n#3000=12 (TOO DEEP)\nM30\n").await;
    app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
    let status = wait_for(&app, &id, "alarm").await;
    assert_eq!(status["alarms"][0]["line"], 2, "{status}");
    let alarms = app.get(&format!("{C}/{id}/alarms")).await.json();
    assert_eq!(alarms["active"].as_array().unwrap().len(), 1, "{alarms}");
    // The history is written by the background writer: give it a moment.
    let alarms =
        eventually(&app, &format!("{C}/{id}/alarms"), |a| a["history"].as_array().is_some_and(|h| !h.is_empty())).await;
    let history = &alarms["history"];
    assert!(history[0]["message"].as_str().unwrap().contains("TOO DEEP"), "{history}");
    assert!(history[0]["raised_at"].as_str().unwrap().ends_with('Z'));
    let refused = app.post(&format!("{C}/{id}/cycle-start"), &json!({})).await;
    assert_eq!(refused.status, StatusCode::CONFLICT);
    error_of(&refused);
    let reset = app.post(&format!("{C}/{id}/reset"), &json!({})).await;
    assert_eq!(reset.json()["alarms"], json!([]));
    wait_for(&app, &id, "idle").await;
}

#[tokio::test]
async fn feed_hold_waits_and_cycle_start_resumes() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "m", "preset": "mill3"})).await;
    store(&app, &id, 1, "G01 X100. F600\nM30\n").await;
    app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
    wait_for(&app, &id, "running").await;
    // Hold once the axis has moved (the worker may not have ticked yet on a busy machine).
    eventually(&app, &format!("{C}/{id}"), |s| s["position"]["machine"]["X"].as_f64().is_some_and(|x| x > 0.0)).await;
    let held = app.post(&format!("{C}/{id}/feed-hold"), &json!({})).await;
    assert_eq!(held.json()["run_state"], "hold");
    tokio::time::sleep(Duration::from_millis(300)).await;
    let x1 = app.get(&format!("{C}/{id}")).await.json()["position"]["machine"]["X"].as_f64().unwrap();
    tokio::time::sleep(Duration::from_millis(200)).await;
    let x2 = app.get(&format!("{C}/{id}")).await.json()["position"]["machine"]["X"].as_f64().unwrap();
    assert_eq!(x1, x2, "held still");
    assert!(x1 > 0.0 && x1 < 100.0);
    // A new program cannot be selected while one holds, nor MDI entered; JOG may be, for a
    // manual intervention, and back to AUTO resumes.
    assert_eq!(app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await.status, StatusCode::CONFLICT);
    assert_eq!(app.put(&format!("{C}/{id}/mode"), &json!({"mode": "mdi"})).await.status, StatusCode::CONFLICT);
    assert_eq!(app.put(&format!("{C}/{id}/mode"), &json!({"mode": "jog"})).await.status, StatusCode::OK);
    assert_eq!(app.post(&format!("{C}/{id}/cycle-start"), &json!({})).await.status, StatusCode::CONFLICT, "not in JOG");
    assert_eq!(app.put(&format!("{C}/{id}/mode"), &json!({"mode": "auto"})).await.status, StatusCode::OK);
    assert_eq!(app.post(&format!("{C}/{id}/cycle-start"), &json!({})).await.json()["run_state"], "running");
    app.post(&format!("{C}/{id}/reset"), &json!({})).await;
    wait_for(&app, &id, "idle").await;
    let runs = eventually(&app, &format!("{C}/{id}/runs"), |r| r.as_array().is_some_and(|a| !a.is_empty())).await;
    assert_eq!(runs[0]["result"], "reset", "{runs}");
}

/// A manual intervention in a held program: the jog ends, the program is still held (its run
/// not over, nothing recorded) until AUTO and cycle start take it to its end.
#[tokio::test]
async fn a_jog_in_a_held_program_leaves_the_run_held() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "jh", "preset": "mill3", "speed": 20})).await;
    store(&app, &id, 1, "G01 X100. F600\nM30\n").await;
    app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
    eventually(&app, &format!("{C}/{id}"), |s| s["position"]["machine"]["X"].as_f64().is_some_and(|x| x > 0.0)).await;
    assert_eq!(app.post(&format!("{C}/{id}/feed-hold"), &json!({})).await.json()["run_state"], "hold");
    assert_eq!(app.put(&format!("{C}/{id}/mode"), &json!({"mode": "jog"})).await.status, StatusCode::OK);
    let jog = app.post(&format!("{C}/{id}/jog"), &json!({"axis": "Y", "positive": true})).await;
    assert_eq!(jog.status, StatusCode::OK, "{}", jog.text());
    eventually(&app, &format!("{C}/{id}"), |s| s["position"]["machine"]["Y"].as_f64().is_some_and(|y| y > 0.0)).await;
    app.post(&format!("{C}/{id}/jog-stop"), &json!({})).await;
    // Until the jog has come to a stop: Y the same over 200 ms.
    let mut y = Value::Null;
    loop {
        tokio::time::sleep(Duration::from_millis(200)).await;
        let status = app.get(&format!("{C}/{id}")).await.json();
        if status["position"]["machine"]["Y"] == y {
            assert_eq!(status["run_state"], "hold", "{status}");
            break;
        }
        y = status["position"]["machine"]["Y"].clone();
    }
    assert_eq!(app.get(&format!("{C}/{id}/runs")).await.json(), json!([]), "nothing ended");
    assert_eq!(app.put(&format!("{C}/{id}/mode"), &json!({"mode": "auto"})).await.status, StatusCode::OK);
    assert_eq!(app.post(&format!("{C}/{id}/cycle-start"), &json!({})).await.json()["run_state"], "running");
    let done = wait_for(&app, &id, "idle").await;
    assert_eq!(done["position"]["machine"]["X"], 100.0, "{done}");
    let runs = eventually(&app, &format!("{C}/{id}/runs"), |r| r.as_array().is_some_and(|a| !a.is_empty())).await;
    assert_eq!((runs.as_array().unwrap().len(), runs[0]["result"].clone()), (1, json!("completed")), "{runs}");
}

#[tokio::test]
async fn a_program_stop_holds_the_run_until_cycle_start_goes_on_or_reset_ends_it() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "m00", "preset": "mill3", "speed": 20})).await;
    let text = "O0001\nG90 G01 X20. F1200.\nM00\nG01 Y20.\nM30\n";
    assert_eq!(store(&app, &id, 1, text).await.status, StatusCode::CREATED);
    let estimate = eventually(&app, &format!("{C}/{id}/programs/1/estimate"), |e| e["state"] != "pending").await;
    assert_eq!((estimate["state"].as_str(), &estimate["depends_on"]), (Some("ready"), &json!(["program_stop"])));
    let started = app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
    assert_eq!(started.status, StatusCode::OK, "{}", started.text());
    // At the M00 the run is held (cycle start goes on), not over: its progress stays, against
    // the estimate of the whole program, and nothing is recorded yet.
    let stopped = wait_for(&app, &id, "hold").await;
    assert_eq!((stopped["line"].clone(), stopped["position"]["machine"]["X"].clone()), (json!(3), json!(20.0)));
    let progress = &stopped["progress"];
    assert_eq!((progress["program"].clone(), progress["estimate"].clone()), (json!(1), estimate.clone()), "{stopped}");
    assert_eq!(progress["caveats"], json!(["held"]), "{stopped}");
    tokio::time::sleep(Duration::from_millis(200)).await;
    assert_eq!(app.get(&format!("{C}/{id}/runs")).await.json(), json!([]), "nothing ended");
    // Held as after a feed hold: another program, MDI and offset changes wait for its end.
    let other = app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
    assert_eq!(other.status, StatusCode::CONFLICT);
    assert!(error_of(&other).contains("under way"), "{}", other.text());
    assert_eq!(app.put(&format!("{C}/{id}/mode"), &json!({"mode": "mdi"})).await.status, StatusCode::CONFLICT);
    let g54 = app.put(&format!("{C}/{id}/work-offsets/G54"), &json!({"axes": {"X": 1.0}})).await;
    assert_eq!(g54.status, StatusCode::CONFLICT, "{}", g54.text());
    // Cycle start goes on to the end: one run, completed, its time the whole program's and the
    // wait at the M00 (simulated time runs on while it waits).
    assert_eq!(app.post(&format!("{C}/{id}/cycle-start"), &json!({})).await.json()["run_state"], "running");
    let done = wait_for(&app, &id, "idle").await;
    assert_eq!(done["position"]["machine"]["Y"], 20.0, "{done}");
    assert!(done["progress"].is_null(), "{done}");
    let runs = eventually(&app, &format!("{C}/{id}/runs"), |r| r.as_array().is_some_and(|a| !a.is_empty())).await;
    assert_eq!(runs.as_array().unwrap().len(), 1, "{runs}");
    assert_eq!((runs[0]["program"].clone(), runs[0]["result"].clone()), (json!(1), json!("completed")), "{runs}");
    assert!(runs[0]["cycle_time_s"].as_f64().unwrap() > estimate["cycle_time_s"].as_f64().unwrap() + 1.0, "{runs}");

    // A single-block stop holds the same way; a reset there ends the run, recorded as reset.
    assert_eq!(app.put(&format!("{C}/{id}/switches"), &json!({"single_block": true})).await.status, StatusCode::OK);
    app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
    wait_for(&app, &id, "hold").await;
    assert_eq!(app.post(&format!("{C}/{id}/reset"), &json!({})).await.json()["run_state"], "idle");
    let runs = eventually(&app, &format!("{C}/{id}/runs"), |r| r.as_array().is_some_and(|a| a.len() == 2)).await;
    assert_eq!(runs[0]["result"], "reset", "{runs}");
}

#[tokio::test]
async fn mdi_runs_blocks_and_panel_settings_are_checked() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "m", "preset": "mill3", "speed": 20})).await;
    let reply = app.post(&format!("{C}/{id}/mdi"), &json!({"text": "G91 G01 X10. F3000\nX5."})).await;
    assert_eq!(reply.status, StatusCode::OK, "{}", reply.text());
    assert_eq!(reply.json()["mode"], "mdi");
    let done = wait_for(&app, &id, "idle").await;
    assert_eq!(done["position"]["machine"]["X"], 15.0);
    let reply = app.put(&format!("{C}/{id}/overrides"), &json!({"feed": 250})).await;
    assert_eq!(reply.status, StatusCode::UNPROCESSABLE_ENTITY);
    assert_eq!(app.put(&format!("{C}/{id}/overrides"), &json!({"feed": 50, "rapid": 25})).await.status, StatusCode::OK);
    assert_eq!(
        app.put(&format!("{C}/{id}/mode"), &json!({"mode": "warp"})).await.status,
        StatusCode::UNPROCESSABLE_ENTITY
    );
    assert_eq!(app.put(&format!("{C}/{id}/switches"), &json!({"single_block": true})).await.status, StatusCode::OK);
    let estop = app.put(&format!("{C}/{id}/emergency-stop"), &json!({"pressed": true})).await;
    assert_eq!(estop.json()["run_state"], "alarm");
    app.put(&format!("{C}/{id}/emergency-stop"), &json!({"pressed": false})).await;
    assert_eq!(app.post(&format!("{C}/{id}/reset"), &json!({})).await.json()["run_state"], "idle");
}

#[tokio::test]
async fn mdi_under_cutter_compensation_moves_the_tool_centre_at_the_offset() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "m", "preset": "mill3", "speed": 20})).await;
    // D1 of the default tools: radius 5. The text's blocks are read ahead together: the inside
    // corner at 40,0 is met at 35,5, the last block ends at its perpendicular vector 35,30.
    let text = "G90 G17 G00 X-20. Y0. Z0.\nG41 D1 G01 X0. F3000.\nX40.\nY30.";
    assert_eq!(app.post(&format!("{C}/{id}/mdi"), &json!({"text": text})).await.status, StatusCode::OK);
    let done = wait_for(&app, &id, "idle").await;
    assert_eq!(
        (done["position"]["machine"]["X"].clone(), done["position"]["machine"]["Y"].clone()),
        (json!(35.0), json!(30.0)),
        "{done}"
    );
    assert!(done["alarms"].as_array().unwrap().is_empty(), "{done}");
    // The next MDI text starts in G40: its first move removes the vector (docs/cutter-compensation.md, "MDI").
    assert_eq!(app.post(&format!("{C}/{id}/mdi"), &json!({"text": "X0."})).await.status, StatusCode::OK);
    let done = wait_for(&app, &id, "idle").await;
    assert_eq!(
        (done["position"]["machine"]["X"].clone(), done["position"]["machine"]["Y"].clone()),
        (json!(0.0), json!(30.0)),
        "{done}"
    );
}

#[tokio::test]
async fn only_common_variables_are_writable_and_values_must_be_numbers() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "m", "preset": "mill3"})).await;
    let v = |n: u32| format!("{C}/{id}/variables/{n}");
    assert_eq!(app.put(&v(100), &json!({"value": 1.5})).await.json(), json!({"number": 100, "value": 1.5}));
    assert_eq!(app.put(&v(100), &json!({"value": null})).await.json()["value"], Value::Null);
    for n in [1, 3000, 5001, 2001, 200] {
        let reply = app.put(&v(n), &json!({"value": 1})).await;
        assert_eq!(reply.status, StatusCode::UNPROCESSABLE_ENTITY, "#{n}");
    }
    assert_eq!(app.put(&v(500), &json!({"value": "high"})).await.status, StatusCode::UNPROCESSABLE_ENTITY);
    // System variables read as a program reads them.
    assert_eq!(app.get(&v(4001)).await.json()["value"], 0.0, "G00 modal");
    assert_eq!(app.get(&v(2201)).await.json()["value"], 100.0, "H1 geometry: the default tools");
    assert_eq!(app.get(&v(99999)).await.status, StatusCode::UNPROCESSABLE_ENTITY);
    app.put(&v(150), &json!({"value": 4})).await;
    assert_eq!(app.get(&format!("{C}/{id}/variables")).await.json(), json!([{"number": 150, "value": 4.0}]));
    // Syntec: #100–#199 are a program's locals, vacant at each cycle start: a value set before
    // it was wiped unseen (the 200 said it was set). Refused with the reason; #500… still set.
    let syntec = create(&app, json!({"name": "s", "preset": "mill3", "dialect": "syntec"})).await;
    let s = |n: u32| format!("{C}/{syntec}/variables/{n}");
    // #1000… are Syntec's modal state, which a Syntec program cannot read as input signals.
    for n in [100, 150, 199, 100_001, 500_001, 1000, 1035] {
        let reply = app.put(&s(n), &json!({"value": 4})).await;
        assert_eq!(reply.status, StatusCode::UNPROCESSABLE_ENTITY, "#{n}");
        assert!(error_of(&reply).contains("Syntec"), "{}", error_of(&reply));
    }
    assert_eq!(app.put(&s(500), &json!({"value": 2.5})).await.status, StatusCode::OK);
    assert_eq!(app.get(&format!("{C}/{syntec}/variables")).await.json(), json!([{"number": 500, "value": 2.5}]));
}

#[tokio::test]
async fn concurrent_commands_on_one_controller_leave_it_consistent() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "m", "preset": "mill3"})).await;
    store(&app, &id, 1, "G01 X200. F600\nM30\n").await;
    let mut tasks = Vec::new();
    for k in 0..24 {
        let (router, id) = (app.router(), id.clone());
        tasks.push(tokio::spawn(async move {
            use tower::ServiceExt;
            let (uri, body) = match k % 3 {
                0 => (format!("{C}/{id}/cycle-start"), json!({"program": 1})),
                1 => (format!("{C}/{id}/feed-hold"), json!({})),
                _ => (format!("{C}/{id}/cycle-start"), json!({})),
            };
            let request = axum::http::Request::post(uri)
                .header("content-type", "application/json")
                .body(axum::body::Body::from(body.to_string()))
                .unwrap();
            router.oneshot(request).await.unwrap().status()
        }));
    }
    for t in tasks {
        let status = t.await.unwrap();
        assert!(matches!(status, StatusCode::OK | StatusCode::CONFLICT), "{status}");
    }
    let status = app.get(&format!("{C}/{id}")).await.json();
    assert!(["running", "hold", "idle"].contains(&status["run_state"].as_str().unwrap()), "{status}");
    app.post(&format!("{C}/{id}/reset"), &json!({})).await;
    wait_for(&app, &id, "idle").await;
}

/// The audit's F7: a name with a control character (NUL among them, which PostgreSQL's text
/// cannot hold: a 500 there) is refused with 422 on creation, rename and clone, and an NC text
/// with a NUL (MDI, a fleet run's program) as a stored program's is; nothing is stored.
#[tokio::test]
async fn control_characters_in_names_and_nul_in_nc_texts_are_refused() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "plain", "preset": "mill3"})).await;
    for bad in ["a\u{0}b", "x\u{0}", "two\nlines", "tab\there", "esc\u{1b}[31m", "del\u{7f}", "c1\u{85}x"] {
        let created = app.post(C, &json!({"name": bad, "preset": "mill3"})).await;
        assert_eq!(created.status, StatusCode::UNPROCESSABLE_ENTITY, "{bad:?}: {}", created.text());
        assert!(error_of(&created).contains("control character"), "{bad:?}: {}", created.text());
        let renamed = app.json(Method::PATCH, &format!("{C}/{id}"), &json!({"name": bad})).await;
        assert_eq!(renamed.status, StatusCode::UNPROCESSABLE_ENTITY, "{bad:?}: {}", renamed.text());
        let cloned = app.post(&format!("{C}/{id}/clone"), &json!({"name": bad})).await;
        assert_eq!(cloned.status, StatusCode::UNPROCESSABLE_ENTITY, "{bad:?}: {}", cloned.text());
    }
    // What is not a control character stays a name: right-to-left marks, emoji, trimmed blanks.
    let fine = app.json(Method::PATCH, &format!("{C}/{id}"), &json!({"name": " \u{202e}cell 🛠 "})).await;
    assert_eq!(fine.json()["name"], "\u{202e}cell 🛠");
    assert_eq!(app.get(C).await.json().as_array().unwrap().len(), 1, "nothing created");
    let mdi = app.post(&format!("{C}/{id}/mdi"), &json!({"text": "(\u{0})G0 X1."})).await;
    assert_eq!(mdi.status, StatusCode::UNPROCESSABLE_ENTITY, "{}", mdi.text());
    let fleet = json!({"program": "(\u{0})\nG0 X1.\n", "presets": ["mill3"]});
    let run = app.post("/api/v1/fleet/runs", &fleet).await;
    assert_eq!(run.status, StatusCode::UNPROCESSABLE_ENTITY, "{}", run.text());
    assert!(error_of(&run).contains("NUL"), "{}", run.text());
    assert_eq!(app.get("/api/v1/fleet/runs").await.json(), json!([]), "no fleet run stored");
}

#[tokio::test]
async fn renaming_and_speed_are_kept() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "old", "preset": "mill3"})).await;
    let reply = app.json(Method::PATCH, &format!("{C}/{id}"), &json!({"name": "new", "speed": 10})).await;
    assert_eq!((reply.json()["name"].clone(), reply.json()["speed"].clone()), (json!("new"), json!(10.0)));
    assert_eq!(
        app.json(Method::PATCH, &format!("{C}/{id}"), &json!({"speed": -1})).await.status,
        StatusCode::UNPROCESSABLE_ENTITY
    );
    let state = app.restart().await;
    let again = TestApp { state, db_path: app.db_path.clone(), dir: tempfile::tempdir().unwrap() };
    assert_eq!(again.get(&format!("{C}/{id}")).await.json()["name"], "new");
}

/// Partial changes sent at once each keep what the others set, in the controller and in the
/// database: four values of one tool offset, two axes of one work offset, a rename and a speed
/// change (each answer acknowledged a value; none may be lost).
#[tokio::test]
async fn partial_changes_sent_at_once_all_stay() {
    use futures_util::future::join_all;
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "old", "preset": "mill3"})).await;
    let tools =
        [("length", 10.0), ("radius", 1.0), ("length_wear", 0.5), ("radius_wear", 0.25), ("corner_radius", 0.125)];
    for number in 40..45 {
        let uri = format!("{C}/{id}/tool-offsets/{number}");
        let bodies: Vec<Value> = tools.iter().map(|(field, v)| json!({ *field: v })).collect();
        for reply in join_all(bodies.iter().map(|b| app.put(&uri, b))).await {
            assert_eq!(reply.status, StatusCode::OK, "{}", reply.text());
        }
    }
    let uri = format!("{C}/{id}/work-offsets/G55");
    let bodies = [json!({"axes": {"X": 1.5}}), json!({"axes": {"Y": 2.5}}), json!({"axes": {"Z": 3.5}})];
    for reply in join_all(bodies.iter().map(|b| app.put(&uri, b))).await {
        assert_eq!(reply.status, StatusCode::OK, "{}", reply.text());
    }
    let patches = [json!({"name": "new"}), json!({"speed": 7})];
    let uri = format!("{C}/{id}");
    for reply in join_all(patches.iter().map(|b| app.json(Method::PATCH, &uri, b))).await {
        assert_eq!(reply.status, StatusCode::OK, "{}", reply.text());
    }
    all_stayed(&app, &id, "in the controller").await;
    let state = app.restart().await;
    let again = TestApp { state, db_path: app.db_path.clone(), dir: tempfile::tempdir().unwrap() };
    all_stayed(&again, &id, "after a restart").await;
}

/// What `partial_changes_sent_at_once_all_stay` set, every value of it.
async fn all_stayed(app: &TestApp, id: &str, when: &str) {
    let listed = app.get(&format!("{C}/{id}/tool-offsets")).await.json();
    for number in 40..45 {
        let t = listed.as_array().unwrap().iter().find(|t| t["number"] == number).cloned();
        let want = json!({"number": number, "length": 10.0, "length_wear": 0.5, "radius": 1.0, "radius_wear": 0.25, "corner_radius": 0.125});
        assert_eq!(t, Some(want), "{when}: tool offset {number}");
    }
    let works = app.get(&format!("{C}/{id}/work-offsets")).await.json();
    assert_eq!(works[2], json!({"name": "G55", "axes": {"X": 1.5, "Y": 2.5, "Z": 3.5}}), "{when}");
    let status = app.get(&format!("{C}/{id}")).await.json();
    assert_eq!((status["name"].clone(), status["speed"].clone()), (json!("new"), json!(7.0)), "{when}");
}

#[tokio::test]
async fn tool_and_work_offsets_are_set_used_and_kept() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "m", "preset": "mill3", "speed": 20})).await;
    let t = app.put(&format!("{C}/{id}/tool-offsets/5"), &json!({"length": 80.0, "radius_wear": -0.1})).await;
    assert_eq!(
        t.json(),
        json!({"number": 5, "length": 80.0, "length_wear": 0.0, "radius": 5.0, "radius_wear": -0.1, "corner_radius": 0.0})
    );
    assert_eq!(
        app.put(&format!("{C}/{id}/tool-offsets/0"), &json!({"length": 1})).await.status,
        StatusCode::UNPROCESSABLE_ENTITY
    );
    assert_eq!(
        app.put(&format!("{C}/{id}/tool-offsets/1000"), &json!({"length": 1})).await.status,
        StatusCode::UNPROCESSABLE_ENTITY
    );
    let w = app.put(&format!("{C}/{id}/work-offsets/G54"), &json!({"axes": {"X": 100.0, "z": -50}})).await;
    assert_eq!(w.json(), json!({"name": "G54", "axes": {"X": 100.0, "Y": 0.0, "Z": -50.0}}));
    // The display follows the edit: the machine stands at 0, so the workpiece X is -100.
    let status = app.get(&format!("{C}/{id}")).await.json();
    assert_eq!(
        (status["position"]["workpiece"]["X"].clone(), status["position"]["workpiece"]["Z"].clone()),
        (json!(-100.0), json!(50.0))
    );
    assert_eq!(status["position"]["tip"], json!([-100.0, 0.0, 50.0]), "the tip follows the offset edit too");
    for (name, body) in [
        ("G53", json!({"axes": {"X": 1}})),
        ("G54", json!({"axes": {"B": 1}})),
        ("G54", json!({"axes": {"X": "a"}})),
        ("G54", json!({"axes": {"X": 1000000.0}})),
    ] {
        let reply = app.put(&format!("{C}/{id}/work-offsets/{name}"), &body).await;
        assert_eq!(reply.status, StatusCode::UNPROCESSABLE_ENTITY, "{name} {body}");
    }
    // The range of a work offset value is G10's: the limit itself is taken.
    let edge = app.put(&format!("{C}/{id}/work-offsets/G59"), &json!({"axes": {"Y": -999999.999}})).await;
    assert_eq!(edge.status, StatusCode::OK);
    // A program's G10 is saved when it ends, and the H5 length acts.
    store(&app, &id, 1, "G10 L2 P2 X7.5\nG90 G55 G43 H5 G01 Z0 F3000\nM30\n").await;
    app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
    let done = wait_for(&app, &id, "idle").await;
    assert_eq!(done["position"]["machine"]["Z"], 80.0, "H5 = 80 above the G55 zero");
    // The tip: machine − H5 − the G55 offset (X 7.5); the programmed point in the workpiece system.
    let pos = &done["position"];
    assert_eq!((&pos["tip"], &pos["tool"]), (&json!([-7.5, 0.0, 0.0]), &json!([0.0, 0.0, 1.0])), "{pos}");
    assert_eq!((&pos["programmed"], &pos["programmed_in"]), (&json!([-7.5, 0.0, 0.0]), &json!("workpiece")), "{pos}");
    let works = eventually(&app, &format!("{C}/{id}/work-offsets"), |w| w[2]["axes"]["X"] == 7.5).await;
    assert_eq!(works.as_array().unwrap().len(), 7, "EXT and G54–G59");
    let state = app.restart().await;
    let again = TestApp { state, db_path: app.db_path.clone(), dir: tempfile::tempdir().unwrap() };
    let tools = again.get(&format!("{C}/{id}/tool-offsets")).await.json();
    assert_eq!(
        tools[4],
        json!({"number": 5, "length": 80.0, "length_wear": 0.0, "radius": 5.0, "radius_wear": -0.1, "corner_radius": 0.0})
    );
    let works = again.get(&format!("{C}/{id}/work-offsets")).await.json();
    assert_eq!((works[1]["axes"]["X"].clone(), works[2]["axes"]["X"].clone()), (json!(100.0), json!(7.5)));
}

/// A tool offset set through the API is held to the range G10 takes (geometry ±999.999 mm, wear
/// ±99.999 mm, `interp::tool_value_limit`): beyond it 422 naming the value and the range, and
/// nothing changes; at the limit it is taken. (The API took any value below 1e6: a tool length
/// of 5 m no program could have set.)
#[tokio::test]
async fn a_tool_offset_value_beyond_the_g10_range_is_refused() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "m", "preset": "mill3"})).await;
    let t3 = format!("{C}/{id}/tool-offsets/3");
    for (field, bad) in [
        ("length", 1000.0),
        ("length", -5000.0),
        ("radius", 999.9991),
        ("length_wear", 100.0),
        ("radius_wear", -99.9991),
        ("corner_radius", 1000.0),
    ] {
        let reply = app.put(&t3, &json!({ field: bad })).await;
        assert_eq!(reply.status, StatusCode::UNPROCESSABLE_ENTITY, "{field} {bad}: {}", reply.text());
        let error = error_of(&reply);
        assert!(error.contains(field) && error.contains("mm"), "{field} {bad}: {error}");
    }
    let t = app.get(&format!("{C}/{id}/tool-offsets")).await.json();
    let three = t.as_array().unwrap().iter().find(|t| t["number"] == 3).cloned();
    let default = json!({"number": 3, "length": 100.0, "length_wear": 0.0, "radius": 5.0, "radius_wear": 0.0, "corner_radius": 0.0});
    assert_eq!(three, Some(default), "nothing changed");
    let limits = json!({"length": -999.999, "radius": 999.999, "length_wear": 99.999, "radius_wear": -99.999, "corner_radius": 999.999});
    let reply = app.put(&t3, &limits).await;
    assert_eq!(reply.status, StatusCode::OK, "{}", reply.text());
    let mut want = limits.clone();
    want["number"] = json!(3);
    assert_eq!(reply.json(), want);
}

#[tokio::test]
async fn a_tool_offset_keeps_its_corner_radius() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "m", "preset": "mill3"})).await;
    let t7 = format!("{C}/{id}/tool-offsets/7");
    // Set with the others, read back; the other values are the default tool's.
    let t = app.put(&t7, &json!({"radius": 6.0, "corner_radius": 1.5})).await;
    assert_eq!(t.status, StatusCode::OK, "{}", t.text());
    let want = json!({"number": 7, "length": 100.0, "length_wear": 0.0, "radius": 6.0, "radius_wear": 0.0, "corner_radius": 1.5});
    assert_eq!(t.json(), want);
    // Absent: kept as it is, and a change of another value leaves it.
    assert_eq!(app.put(&t7, &json!({"length_wear": -0.2})).await.json()["corner_radius"], 1.5);
    // Absent on an offset never given one: 0.
    assert_eq!(
        app.put(&format!("{C}/{id}/tool-offsets/8"), &json!({"length": 90.0})).await.json()["corner_radius"],
        0.0
    );
    // An offset that is only a corner radius is listed (it is not all zero).
    assert_eq!(
        app.put(&format!("{C}/{id}/tool-offsets/150"), &json!({"corner_radius": 2.0})).await.status,
        StatusCode::OK
    );
    let tools = app.get(&format!("{C}/{id}/tool-offsets")).await.json();
    let by_number = |n: u32| tools.as_array().unwrap().iter().find(|t| t["number"] == n).cloned();
    assert_eq!(by_number(7).map(|t| t["corner_radius"].clone()), Some(json!(1.5)), "{tools}");
    assert_eq!(by_number(1).map(|t| t["corner_radius"].clone()), Some(json!(0.0)), "{tools}");
    assert_eq!(
        by_number(150),
        Some(
            json!({"number": 150, "length": 0.0, "length_wear": 0.0, "radius": 0.0, "radius_wear": 0.0, "corner_radius": 2.0})
        )
    );
    // Negative or too large: 422 with the JSON error, and nothing changes.
    for bad in [json!(-0.5), json!(-1.0e-9), json!(1.0e6), json!("1")] {
        let reply = app.put(&t7, &json!({"corner_radius": bad, "length": 1.0})).await;
        assert_eq!(reply.status, StatusCode::UNPROCESSABLE_ENTITY, "{bad}: {}", reply.text());
        assert!(reply.json()["error"].as_str().unwrap_or("").contains("corner_radius"), "{bad}: {}", reply.text());
    }
    let t = app.get(&format!("{C}/{id}/tool-offsets")).await.json();
    let seven = t.as_array().unwrap().iter().find(|t| t["number"] == 7).cloned().unwrap();
    assert_eq!((seven["length"].clone(), seven["corner_radius"].clone()), (json!(100.0), json!(1.5)), "{seven}");
    // 0 is a corner radius too (a square end mill).
    assert_eq!(
        app.put(&format!("{C}/{id}/tool-offsets/150"), &json!({"corner_radius": 0})).await.json()["corner_radius"],
        0.0
    );
    // Kept over a restart, and by a clone.
    let state = app.restart().await;
    let again = TestApp { state, db_path: app.db_path.clone(), dir: tempfile::tempdir().unwrap() };
    let tools = again.get(&format!("{C}/{id}/tool-offsets")).await.json();
    let seven = tools.as_array().unwrap().iter().find(|t| t["number"] == 7).cloned();
    assert_eq!(seven.map(|t| t["corner_radius"].clone()), Some(json!(1.5)), "{tools}");
    assert!(!tools.as_array().unwrap().iter().any(|t| t["number"] == 150), "150 is all zero again: {tools}");
    let copy = again.post(&format!("{C}/{id}/clone"), &json!({"name": "copy"})).await;
    assert_eq!(copy.status, StatusCode::CREATED, "{}", copy.text());
    let copy_id = copy.json()["id"].as_str().unwrap().to_string();
    let tools = again.get(&format!("{C}/{copy_id}/tool-offsets")).await.json();
    let seven = tools.as_array().unwrap().iter().find(|t| t["number"] == 7).cloned();
    assert_eq!(seven.map(|t| t["corner_radius"].clone()), Some(json!(1.5)), "{tools}");
}

#[tokio::test]
async fn parameters_in_the_dialects_numbering_change_the_machine() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "m", "preset": "table-ac"})).await;
    let list = app.get(&format!("{C}/{id}/parameters")).await.json();
    assert_eq!((list["dialect"].clone(), list["parameters"]["19680"].clone()), (json!("fanuc"), json!(12)));
    let strokes = list["parameters"]["1320"].as_array().unwrap().clone();
    // A smaller X stroke: accepted, the controller restarts on it.
    let mut upper: Vec<f64> = strokes.iter().map(|v| v.as_f64().unwrap()).collect();
    upper[0] = 123.0;
    let reply = app.put(&format!("{C}/{id}/parameters/1320"), &json!({"value": upper})).await;
    assert_eq!(reply.status, StatusCode::OK, "{}", reply.text());
    assert_eq!(reply.json()["parameters"]["1320"][0], 123.0);
    // The new stroke acts: a move beyond it is an over-travel alarm.
    let moved = app.post(&format!("{C}/{id}/mdi"), &json!({"text": "G90 G01 X200. F5000"})).await;
    assert_eq!(moved.status, StatusCode::OK);
    let alarm = wait_for(&app, &id, "alarm").await;
    assert!(!alarm["alarms"].as_array().unwrap().is_empty(), "{alarm}");
    app.post(&format!("{C}/{id}/reset"), &json!({})).await;
    // A set that describes no working machine is refused with the vendor's alarm.
    let bad = app.put(&format!("{C}/{id}/parameters/19680"), &json!({"value": 7})).await;
    assert_eq!(bad.status, StatusCode::UNPROCESSABLE_ENTITY);
    assert!(error_of(&bad).contains("19680"), "{}", bad.text());
    let linear = app.put(&format!("{C}/{id}/parameters/19681"), &json!({"value": 1})).await;
    assert_eq!(linear.status, StatusCode::UNPROCESSABLE_ENTITY);
    assert!(error_of(&linear).contains("PS5459"), "TV-KIN-16: {}", linear.text());
    // Not while a program runs (409), and nothing changes.
    store(&app, &id, 1, "G04 X100.\nM30\n").await;
    app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
    let busy = app.put(&format!("{C}/{id}/parameters/8130"), &json!({"value": 5})).await;
    assert_eq!(busy.status, StatusCode::CONFLICT, "{}", busy.text());
    let listed = app.get(&format!("{C}/{id}/parameters")).await.json();
    assert!(listed["parameters"]["8130"].is_null(), "{}", listed["parameters"]["8130"]);
    app.post(&format!("{C}/{id}/reset"), &json!({})).await;
    wait_for(&app, &id, "idle").await;
    // A parameter the model does not read is kept as given (a control keeps them all).
    let kept = app.put(&format!("{C}/{id}/parameters/8130"), &json!({"value": 5})).await;
    assert_eq!((kept.status, kept.json()["parameters"]["8130"].clone()), (StatusCode::OK, json!(5)));
    let state = app.restart().await;
    let again = TestApp { state, db_path: app.db_path.clone(), dir: tempfile::tempdir().unwrap() };
    let after = again.get(&format!("{C}/{id}/parameters")).await.json();
    assert_eq!(
        (after["parameters"]["1320"][0].as_f64(), after["parameters"]["8130"].as_f64()),
        (Some(123.0), Some(5.0))
    );
    // So is one in a parameter list a controller is created from, in the list's dialect.
    let mut params = after["parameters"].clone();
    params["8131"] = json!(7);
    let from_list =
        create(&again, json!({"name": "p", "machine": {"name": "p", "dialect": "fanuc", "parameters": params}})).await;
    assert_eq!(again.get(&format!("{C}/{from_list}/parameters")).await.json()["parameters"]["8131"], 7);
    // Syntec numbering for a Syntec controller.
    let syntec = create(&app, json!({"name": "s", "preset": "head-bc", "dialect": "syntec"})).await;
    assert_eq!(app.get(&format!("{C}/{syntec}/parameters")).await.json()["parameters"]["3001"], 1);
}

/// The audit's F11: after a parameter change the workpiece position was the machine's (0)
/// while the tip was right (−100) until the next move.
#[tokio::test]
async fn a_parameter_change_keeps_the_workpiece_position_of_the_offsets_kept() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "wp", "preset": "mill3"})).await;
    let g54 = app.put(&format!("{C}/{id}/work-offsets/G54"), &json!({"axes": {"X": 100.0}})).await;
    assert_eq!(g54.status, StatusCode::OK, "{}", g54.text());
    let changed = app.put(&format!("{C}/{id}/parameters/8130"), &json!({"value": 3})).await;
    assert_eq!(changed.status, StatusCode::OK, "{}", changed.text());
    let position = app.get(&format!("{C}/{id}")).await.json()["position"].clone();
    assert_eq!((position["machine"]["X"].clone(), position["workpiece"]["X"].clone()), (json!(0.0), json!(-100.0)));
    assert_eq!(position["tip"][0], -100.0, "{position}");
}

#[tokio::test]
async fn a_parameter_value_that_cannot_be_shown_back_is_refused_and_changes_nothing() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "huge", "preset": "head-bc"})).await;
    let before = app.get(&format!("{C}/{id}/parameters")).await.json();
    let strokes: Vec<f64> =
        before["parameters"]["1320"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    // A finite JSON number, but not one the list can show again (it read back as null, and
    // 1e308 on every axis made every later change fail).
    let mut last_huge = strokes.clone();
    *last_huge.last_mut().unwrap() = 1e300;
    for value in [json!(last_huge), json!(vec![1e308; strokes.len()])] {
        let reply = app.put(&format!("{C}/{id}/parameters/1320"), &json!({"value": value})).await;
        assert_eq!(reply.status, StatusCode::UNPROCESSABLE_ENTITY, "{value}: {}", reply.text());
        assert!(error_of(&reply).contains("1320"), "{}", reply.text());
        assert_eq!(app.get(&format!("{C}/{id}/parameters")).await.json(), before, "nothing changed");
    }
    // A large stroke the list can show is taken, shown as given, and later changes still work.
    let mut last_large = strokes.clone();
    *last_large.last_mut().unwrap() = 1e6;
    let reply = app.put(&format!("{C}/{id}/parameters/1320"), &json!({"value": last_large})).await;
    assert_eq!(reply.status, StatusCode::OK, "{}", reply.text());
    let shown: Vec<f64> =
        reply.json()["parameters"]["1320"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    assert_eq!(shown, last_large);
    let kept = app.put(&format!("{C}/{id}/parameters/8130"), &json!({"value": 5})).await;
    assert_eq!(kept.status, StatusCode::OK, "{}", kept.text());
    // A controller made from a list holding such a value is refused as the change is.
    let mut params = before["parameters"].clone();
    params["1320"] = json!(last_huge);
    let doc = json!({"name": "huge-list", "machine": {"name": "h", "dialect": "fanuc", "parameters": params}});
    let reply = app.post(C, &doc).await;
    assert_eq!(reply.status, StatusCode::UNPROCESSABLE_ENTITY, "{}", reply.text());
    assert!(error_of(&reply).contains("1320"), "{}", reply.text());
    assert_eq!(app.get(C).await.json().as_array().unwrap().len(), 1, "nothing created");
}

/// A Haas controller's parameters are the Haas settings list: the MRZP Settings 255–257 and the
/// constructed machine description (`docs/machine-config.md`, "Haas"); a change moves the rotary
/// centres; a machine the list cannot describe has no Haas parameter form.
#[tokio::test]
async fn haas_settings_are_a_haas_controller_s_parameters() {
    let app = spawn_app().await;
    let doc: Value =
        serde_json::from_str(include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/../machines/haas-umc-750.json")))
            .unwrap();
    let id = create(&app, json!({"name": "umc", "machine": doc})).await;
    let list = app.get(&format!("{C}/{id}/parameters")).await.json();
    assert_eq!((list["dialect"].clone(), list["parameters"]["255"].clone()), (json!("haas"), json!(-381)));
    assert_eq!(list["parameters"]["9000"], 3);
    let moved = app.put(&format!("{C}/{id}/parameters/256"), &json!({"value": -250.5})).await;
    assert_eq!(moved.status, StatusCode::OK, "{}", moved.text());
    assert_eq!(moved.json()["parameters"]["256"], -250.5);
    let bad = app.put(&format!("{C}/{id}/parameters/9000"), &json!({"value": 7})).await;
    assert_eq!(bad.status, StatusCode::UNPROCESSABLE_ENTITY);
    assert!(error_of(&bad).contains("9000"), "{}", bad.text());
    let head = create(&app, json!({"name": "h", "preset": "head-bc", "dialect": "haas"})).await;
    assert_eq!(app.get(&format!("{C}/{head}/parameters")).await.status, StatusCode::CONFLICT);
}

#[tokio::test]
async fn with_a_token_the_api_needs_it_and_the_rest_stays_open() {
    let mut app = spawn_app().await;
    app.state = app.state.clone().with_token(Some("s3cret".into()));
    let reply = app.get(C).await;
    assert_eq!(reply.status, StatusCode::UNAUTHORIZED);
    assert!(error_of(&reply).contains("Bearer"));
    let with = |auth: &str| {
        axum::http::Request::get(C).header("authorization", auth.to_string()).body(axum::body::Body::empty()).unwrap()
    };
    assert_eq!(app.send(with("Bearer s3cret")).await.status, StatusCode::OK);
    assert_eq!(app.send(with("Bearer s3cre")).await.status, StatusCode::UNAUTHORIZED);
    assert_eq!(app.send(with("s3cret")).await.status, StatusCode::UNAUTHORIZED);
    assert_eq!(app.get(&format!("{C}?token=s3cret")).await.status, StatusCode::OK);
    for open in ["/healthz", "/", "/api-docs/openapi.json"] {
        assert_eq!(app.get(open).await.status, StatusCode::OK, "{open}");
    }
}

#[tokio::test]
async fn manual_moves_one_axis_along_the_tool_and_about_the_tip() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "m", "preset": "head-bc", "speed": 20})).await;
    let at = |s: &Value, a: &str| s["position"]["machine"][a].as_f64().unwrap();
    // HANDLE needs HANDLE mode.
    let refused = app.post(&format!("{C}/{id}/handle"), &json!({"axis": "X", "amount": 10.0})).await;
    assert_eq!(refused.status, StatusCode::CONFLICT);
    app.put(&format!("{C}/{id}/mode"), &json!({"mode": "handle"})).await;
    app.post(&format!("{C}/{id}/handle"), &json!({"axis": "x", "amount": 10.0})).await;
    let s = wait_for(&app, &id, "idle").await;
    assert!((at(&s, "X") - 10.0).abs() < 1e-9, "{s}");
    // Along the tool (+Z at B0), then the tip stays while B turns.
    app.post(&format!("{C}/{id}/handle"), &json!({"feed": "tool-axis", "amount": 5.0})).await;
    let s = wait_for(&app, &id, "idle").await;
    assert!((at(&s, "Z") - 5.0).abs() < 1e-9, "{s}");
    let put = app.put(&format!("{C}/{id}/manual"), &json!({"jog_feed": 3000.0, "manual_absolute": false})).await;
    assert_eq!(put.status, StatusCode::OK, "{}", put.text());
    let turned = app.post(&format!("{C}/{id}/handle"), &json!({"tip_rotation": "B", "amount": 30.0})).await;
    assert_eq!(turned.status, StatusCode::OK, "{}", turned.text());
    let s = wait_for(&app, &id, "idle").await;
    assert!((at(&s, "B") - 30.0).abs() < 1e-9, "{s}");
    for bad in [
        json!({"axis": "X"}),
        json!({"axis": "X", "feed": "tool-axis", "amount": 1}),
        json!({"axis": "XY", "amount": 1}),
        json!({"feed": "sideways", "amount": 1}),
    ] {
        let reply = app.post(&format!("{C}/{id}/handle"), &bad).await;
        assert_eq!(reply.status, StatusCode::UNPROCESSABLE_ENTITY, "{bad}: {}", reply.text());
    }
    assert_eq!(
        app.post(&format!("{C}/{id}/handle"), &json!({"axis": "W", "amount": 1})).await.status,
        StatusCode::CONFLICT
    );
    // JOG until stopped.
    app.put(&format!("{C}/{id}/mode"), &json!({"mode": "jog"})).await;
    let jog = app.post(&format!("{C}/{id}/jog"), &json!({"axis": "Y", "positive": true})).await;
    assert_eq!(jog.json()["run_state"], "running", "{}", jog.text());
    tokio::time::sleep(Duration::from_millis(200)).await;
    app.post(&format!("{C}/{id}/jog-stop"), &json!({})).await;
    let s = wait_for(&app, &id, "idle").await;
    assert!(at(&s, "Y") > 0.0, "{s}");
    // REF brings every axis home.
    app.put(&format!("{C}/{id}/mode"), &json!({"mode": "ref"})).await;
    app.post(&format!("{C}/{id}/reference-return"), &json!({})).await;
    let s = wait_for(&app, &id, "idle").await;
    for a in ["X", "Y", "Z", "B", "C"] {
        assert!(at(&s, a).abs() < 1e-9, "{a}: {s}");
    }
}

#[tokio::test]
async fn the_modal_state_shows_g_codes_and_words() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "m", "preset": "table-ac", "speed": 20})).await;
    let m = app.get(&format!("{C}/{id}/modal")).await.json();
    assert_eq!(
        (m["groups"]["1"].clone(), m["groups"]["3"].clone(), m["groups"]["8"].clone()),
        (json!("G00"), json!("G90"), json!("G49"))
    );
    app.post(&format!("{C}/{id}/mdi"), &json!({"text": "G91 G01 X1. F1234 S800 T5\nG43.4 H7\nG49"})).await;
    wait_for(&app, &id, "idle").await;
    let m = app.get(&format!("{C}/{id}/modal")).await.json();
    assert_eq!((m["groups"]["1"].clone(), m["groups"]["3"].clone()), (json!("G01"), json!("G91")), "{m}");
    assert_eq!(
        (m["f"].clone(), m["s"].clone(), m["t"].clone(), m["h"].clone()),
        (json!(1234.0), json!(800.0), json!(5), json!(7)),
        "{m}"
    );
}

/// Group 33 (seed: "G54.4 is a modal G code that belongs to group 33 with the M series"):
/// workpiece setting error compensation with its set, on and off; a Syntec control has no G54.4.
#[tokio::test]
async fn the_modal_state_shows_workpiece_setting_error_compensation_in_group_33() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "m", "preset": "head-bc", "speed": 20})).await;
    let g33 = |m: &Value| m["groups"]["33"].clone();
    assert_eq!(g33(&app.get(&format!("{C}/{id}/modal")).await.json()), json!("G54.4 P0"));
    let text = "#26015=10.\nG54.4 P1\nG01 X5. F1000.";
    assert_eq!(app.post(&format!("{C}/{id}/mdi"), &json!({ "text": text })).await.status, StatusCode::OK);
    wait_for(&app, &id, "idle").await;
    let m = app.get(&format!("{C}/{id}/modal")).await.json();
    assert_eq!(g33(&m), json!("G54.4 P1"), "{m}");
    assert_eq!(app.post(&format!("{C}/{id}/mdi"), &json!({"text": "G54.4 P0"})).await.status, StatusCode::OK);
    wait_for(&app, &id, "idle").await;
    assert_eq!(g33(&app.get(&format!("{C}/{id}/modal")).await.json()), json!("G54.4 P0"));
    let syntec = create(&app, json!({"name": "s", "preset": "head-bc", "dialect": "syntec", "speed": 20})).await;
    let m = app.get(&format!("{C}/{syntec}/modal")).await.json();
    assert!(m["groups"].get("33").is_none(), "{m}");
}

#[tokio::test]
async fn unmodelled_machine_settings_are_listed_with_the_controller_and_its_parameters() {
    // Issue 17, item 1: a parameter the model does not read, and an unknown field of a model
    // document, are named on creation, with the status and with the parameters — after a
    // restart too (the parameter; the stored model has no unknown field left).
    let app = spawn_app().await;
    let names = |v: &Value| -> Vec<String> {
        v["unmodelled_parameters"]
            .as_array()
            .unwrap()
            .iter()
            .map(|u| u["parameter"].as_str().unwrap().to_string())
            .collect()
    };
    let preset = create(&app, json!({"name": "p", "preset": "table-ac"})).await;
    assert_eq!(names(&app.get(&format!("{C}/{preset}")).await.json()), Vec::<String>::new());
    let mut params = app.get(&format!("{C}/{preset}/parameters")).await.json()["parameters"].clone();
    params["8130"] = json!(5);
    let reply =
        app.post(C, &json!({"name": "l", "machine": {"name": "l", "dialect": "fanuc", "parameters": params}})).await;
    assert_eq!(reply.status, StatusCode::CREATED, "{}", reply.text());
    assert_eq!(names(&reply.json()), ["No.8130"]);
    let id = reply.json()["id"].as_str().unwrap().to_string();
    assert_eq!(names(&app.get(&format!("{C}/{id}/parameters")).await.json()), ["No.8130"]);
    let mut model = app.get(&format!("{C}/{preset}/machine")).await.json();
    model["coolant"] = json!(true);
    let reply = app.post(C, &json!({"name": "m", "machine": model})).await;
    assert_eq!(reply.status, StatusCode::CREATED, "{}", reply.text());
    assert_eq!(names(&reply.json()), ["coolant"]);
    let state = app.restart().await;
    let again = TestApp { state, db_path: app.db_path.clone(), dir: tempfile::tempdir().unwrap() };
    assert_eq!(names(&again.get(&format!("{C}/{id}")).await.json()), ["No.8130"]);
}

#[tokio::test]
async fn a_tilted_plane_kept_over_a_restart_comes_back_with_the_controller() {
    // syn SYN-25 (§4.6.3, Pr3014): 2 keeps the feature coordinate state over reset and reboot,
    // 1 over reset only; a restart of the service is the controller's reboot.
    let app = spawn_app().await;
    let mut ids = Vec::new();
    for persistence in [2, 1] {
        let id = create(&app, json!({"name": "s", "preset": "head-bc", "dialect": "syntec", "speed": 20})).await;
        let reply = app.put(&format!("{C}/{id}/parameters/3014"), &json!({"value": persistence})).await;
        assert_eq!(reply.status, StatusCode::OK, "{}", reply.text());
        let text = "G90 G01 X0 Y0 Z0 F3000\nG68.2 X10. Y0 Z0 I0 J0 K90.";
        let mdi = app.post(&format!("{C}/{id}/mdi"), &json!({ "text": text })).await;
        assert_eq!(mdi.status, StatusCode::OK, "{}", mdi.text());
        wait_for(&app, &id, "idle").await;
        assert_eq!(app.post(&format!("{C}/{id}/reset"), &json!({})).await.status, StatusCode::OK);
        let m = app.get(&format!("{C}/{id}/modal")).await.json();
        assert_eq!(m["groups"]["16"], "G68.2", "Pr3014 = {persistence}: kept over the reset");
        ids.push((id, persistence));
    }
    tokio::time::sleep(Duration::from_millis(200)).await;
    let state = app.restart().await;
    let again = TestApp { state, db_path: app.db_path.clone(), dir: tempfile::tempdir().unwrap() };
    for (id, persistence) in ids {
        let m = again.get(&format!("{C}/{id}/modal")).await.json();
        let want = if persistence == 2 { "G68.2" } else { "G69" };
        assert_eq!(m["groups"]["16"], want, "Pr3014 = {persistence} after the restart");
        if persistence == 2 {
            // The same plane: FCS X is the workpiece +Y, its origin X10 — the tip at the
            // workpiece origin is FCS (0, 10, 0).
            let status = again.get(&format!("{C}/{id}")).await.json();
            let work = &status["position"]["workpiece"];
            let xyz = [&work["X"], &work["Y"], &work["Z"]].map(|v| v.as_f64().unwrap());
            assert!((xyz[0]).abs() < 1e-6 && (xyz[1] - 10.0).abs() < 1e-6 && xyz[2].abs() < 1e-6, "{status}");
        }
    }
}

#[tokio::test]
async fn a_clone_has_the_machine_programs_offsets_and_variables_but_not_the_history() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "cell 1", "preset": "table-ac", "dialect": "syntec", "speed": 5.0})).await;
    assert_eq!(store(&app, &id, 7, "G00 X10.\nM30\n").await.status, StatusCode::CREATED);
    assert_eq!(app.put(&format!("{C}/{id}/variables/500"), &json!({"value": 2.5})).await.status, StatusCode::OK);
    let tool = app.put(&format!("{C}/{id}/tool-offsets/3"), &json!({"length": 123.0})).await;
    assert_eq!(tool.status, StatusCode::OK, "{}", tool.text());
    let reply = app.post(&format!("{C}/{id}/clone"), &json!({"name": "cell 2"})).await;
    assert_eq!(reply.status, StatusCode::CREATED, "{}", reply.text());
    let copy = reply.json();
    let copy_id = copy["id"].as_str().unwrap();
    assert_ne!(copy_id, id);
    assert_eq!(
        (copy["name"].as_str(), copy["machine"].as_str(), copy["dialect"].as_str()),
        (Some("cell 2"), Some("table-ac"), Some("syntec"))
    );
    assert_eq!((copy["speed"].as_f64(), copy["kind"].as_str()), (Some(5.0), Some("table-table")));
    assert_eq!(app.get(&format!("{C}/{copy_id}/programs/7")).await.text(), "G00 X10.\nM30\n");
    assert_eq!(app.get(&format!("{C}/{copy_id}/variables/500")).await.json()["value"], json!(2.5));
    let tools = app.get(&format!("{C}/{copy_id}/tool-offsets")).await.json();
    assert!(tools.as_array().unwrap().iter().any(|t| t["number"] == 3 && t["length"] == 123.0), "{tools}");
    assert_eq!(app.get(C).await.json().as_array().unwrap().len(), 2);
    // The copy is its own controller: removing the original leaves it.
    assert_eq!(app.request(Method::DELETE, &format!("{C}/{id}")).await.status, StatusCode::NO_CONTENT);
    assert_eq!(app.get(&format!("{C}/{copy_id}/programs/7")).await.status, StatusCode::OK);
    let missing = app.post(&format!("{C}/nothing/clone"), &json!({"name": "x"})).await;
    assert_eq!(missing.status, StatusCode::NOT_FOUND);
    let unnamed = app.post(&format!("{C}/{copy_id}/clone"), &json!({"name": " "})).await;
    assert_eq!(unnamed.status, StatusCode::UNPROCESSABLE_ENTITY);
}

#[tokio::test]
async fn the_machine_model_and_the_presets_are_there_for_the_dashboard() {
    let app = spawn_app().await;
    let presets = app.get("/api/v1/presets").await.json();
    let kinds: Vec<(String, String)> = presets
        .as_array()
        .unwrap()
        .iter()
        .map(|p| (p["name"].as_str().unwrap().to_string(), p["kind"].as_str().unwrap().to_string()))
        .collect();
    for (name, kind) in
        [("mill3", "three-axis"), ("head-bc", "head-head"), ("table-ac", "table-table"), ("mixed-bc", "head-table")]
    {
        assert!(kinds.contains(&(name.to_string(), kind.to_string())), "{kinds:?}");
    }
    let id = create(&app, json!({"name": "m", "preset": "head-bc"})).await;
    let machine = app.get(&format!("{C}/{id}/machine")).await.json();
    assert_eq!(machine["name"], "head-bc");
    let rotary: Vec<&str> = machine["rotary"].as_array().unwrap().iter().map(|r| r["axis"].as_str().unwrap()).collect();
    assert_eq!(rotary, ["C", "B"]);
    assert_eq!(app.get(&format!("{C}/nothing/machine")).await.status, StatusCode::NOT_FOUND);
}

#[tokio::test]
async fn a_program_path_is_the_tip_in_the_table_frame_and_says_where_it_stops() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "m", "preset": "mill3"})).await;
    store(&app, &id, 1, "G90 G00 X10. Y20. Z30.\nG01 X50. F100.\nM30\n").await;
    let path = app.get(&format!("{C}/{id}/programs/1/path")).await.json();
    let xyz: Vec<f64> = path["xyz"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    assert_eq!(xyz.len(), 9, "{path}");
    assert_eq!(path["lines"], json!([0, 1, 2]));
    assert_eq!(path["rapid"], json!([true, true, false]));
    assert_eq!((xyz[6] - xyz[3], xyz[7] - xyz[4]), (40.0, 0.0));
    assert_eq!((path["alarm"].clone(), path["truncated"].clone()), (Value::Null, json!(false)));
    let force = app
        .raw(
            Method::PUT,
            &format!("{C}/{id}/programs/2?force=true"),
            "text/plain",
            "G01 X10. F100.\nG65 P\n".to_string(),
        )
        .await;
    assert!(force.status.is_success(), "{}", force.text());
    let broken = app.get(&format!("{C}/{id}/programs/2/path?max_points=1")).await.json();
    assert_eq!((broken["truncated"].clone(), broken["xyz"].as_array().unwrap().len()), (json!(true), 3));
    let broken = app.get(&format!("{C}/{id}/programs/2/path")).await.json();
    assert!(broken["alarm"]["code"].is_string(), "{broken}");
    assert_eq!(app.get(&format!("{C}/{id}/programs/9/path")).await.status, StatusCode::NOT_FOUND);
    assert_eq!(
        app.get(&format!("{C}/{id}/programs/1/path?max_points=0")).await.status,
        StatusCode::UNPROCESSABLE_ENTITY
    );
}

#[tokio::test]
async fn under_cutter_compensation_the_path_has_the_programmed_path_beside_the_tool_centre() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "m", "preset": "mill3"})).await;
    // A 40 mm square cut outside, clockwise under G41, with D1 (the default tools: radius 5).
    let square =
        "G21 G17 G40 G90\nG00 X-20. Y-20.\nG41 D1 G01 X0. Y0. F500.\nY40.\nX40.\nY0.\nX0.\nG40 X-20. Y-20.\nM30\n";
    store(&app, &id, 1, square).await;
    let path = app.get(&format!("{C}/{id}/programs/1/path")).await.json();
    let programmed = &path["programmed"];
    assert!(programmed.is_object(), "{path}");
    let numbers = |v: &Value| v.as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect::<Vec<f64>>();
    let (centre, written) = (numbers(&path["xyz"]), numbers(&programmed["xyz"]));
    assert_eq!(written.len() / 3, programmed["lines"].as_array().unwrap().len());
    assert_eq!(written.len() / 3, programmed["rapid"].as_array().unwrap().len());
    // The end of line 5 (the top edge, +X): programmed at the square's corner 40,40, the tool
    // centre at the outside corner's offset point 45,45 (both in the table frame: the same nose).
    let end = |xyz: &[f64], lines: &Value, line: u64| {
        let i = lines.as_array().unwrap().iter().rposition(|l| l.as_u64() == Some(line)).unwrap();
        [xyz[3 * i], xyz[3 * i + 1]]
    };
    let (p, c) = (end(&written, &programmed["lines"], 5), end(&centre, &path["lines"], 5));
    assert!(((c[0] - p[0]) - 5.0).abs() < 1e-9 && ((c[1] - p[1]) - 5.0).abs() < 1e-9, "{p:?} {c:?}");
    // Before compensation the two start alike.
    assert_eq!(&centre[..6], &written[..6]);
    // Without compensation the field is absent: the answer is what it was.
    store(&app, &id, 2, "G90 G00 X10.\nG01 X50. F100.\nM30\n").await;
    let plain = app.get(&format!("{C}/{id}/programs/2/path")).await.json();
    assert!(plain.get("programmed").is_none(), "{plain}");
}

#[tokio::test]
async fn the_panel_signals_choose_what_the_jog_keys_and_the_handle_move() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "h", "preset": "head-bc", "speed": 20.0})).await;
    let c = format!("{C}/{id}");
    assert_eq!(app.post(&format!("{c}/mdi"), &json!({"text": "G90 G00 B90."})).await.status, StatusCode::OK);
    wait_for(&app, &id, "idle").await;
    let before = app.get(&c).await.json()["position"]["machine"].clone();
    app.put(&format!("{c}/mode"), &json!({"mode": "jog"})).await;
    let set = app.put(&format!("{c}/manual-signals"), &json!({"alngh": true})).await;
    assert_eq!(set.status, StatusCode::OK, "{}", set.text());
    assert_eq!(set.json()["panel"]["signals"]["alngh"], json!(true));
    // ALNGH: the +J3 (Z) key feeds along the tool, which points along +X at B90.
    assert_eq!(
        app.post(&format!("{c}/jog-signal"), &json!({"axis": "Z", "positive": true})).await.status,
        StatusCode::OK
    );
    tokio::time::sleep(Duration::from_millis(300)).await;
    app.post(&format!("{c}/jog-stop"), &json!({})).await;
    wait_for(&app, &id, "idle").await;
    let after = app.get(&c).await.json()["position"]["machine"].clone();
    let moved = |a: &str| after[a].as_f64().unwrap() - before[a].as_f64().unwrap();
    assert!(moved("X") > 1.0, "{before} → {after}");
    assert!(moved("Z").abs() < 1e-6 && moved("Y").abs() < 1e-6, "{before} → {after}");
    // The handle with select code 2 (the second axis, Y) outside HANDLE mode is refused; in it,
    // it moves Y by what the machine takes.
    assert_eq!(app.post(&format!("{c}/handle-pulses"), &json!({"amount": 0.5})).await.status, StatusCode::CONFLICT);
    app.put(&format!("{c}/mode"), &json!({"mode": "handle"})).await;
    app.put(&format!("{c}/manual-signals"), &json!({"alngh": false, "handle_select": 2})).await;
    let reply = app.post(&format!("{c}/handle-pulses"), &json!({"amount": 0.5})).await;
    assert_eq!(reply.status, StatusCode::OK, "{}", reply.text());
    assert_eq!(reply.json()["taken"], json!(0.5));
    wait_for(&app, &id, "idle").await;
    let y = app.get(&c).await.json()["position"]["machine"]["Y"].as_f64().unwrap();
    assert!((y - before["Y"].as_f64().unwrap() - 0.5).abs() < 1e-9, "{y}");
    let bad = app.put(&format!("{c}/manual-signals"), &json!({"handle_select": 40})).await;
    assert_eq!(bad.status, StatusCode::UNPROCESSABLE_ENTITY);
}

#[tokio::test]
async fn inc_mode_moves_one_increment_and_a_handle_interrupt_shows_its_shift() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "i", "preset": "mill3"})).await;
    let c = format!("{C}/{id}");
    assert_eq!(app.put(&format!("{c}/mode"), &json!({"mode": "inc"})).await.status, StatusCode::OK);
    let set = app.put(&format!("{c}/manual"), &json!({"increment": 0.1})).await;
    assert_eq!(set.json()["panel"]["increment"], json!(0.1));
    assert_eq!(
        app.put(&format!("{c}/manual"), &json!({"increment": -1.0})).await.status,
        StatusCode::UNPROCESSABLE_ENTITY
    );
    app.post(&format!("{c}/jog"), &json!({"axis": "X", "positive": true})).await;
    let x =
        eventually(&app, &c, |s| s["position"]["machine"]["X"].as_f64().is_some_and(|x| (x - 0.1).abs() < 1e-9)).await;
    assert_eq!(x["mode"], "inc");
    // A program runs; handle pulses on Y shift the machine, not the program's coordinates.
    // (The INC step has ended when the controller is idle again: only then a program is stored.)
    wait_for(&app, &id, "idle").await;
    // A store can still meet "internal database error" (500) while the background writer holds
    // SQLite (1 in ~20 runs; issue 18, writes that never fail): this test is about INC mode, so
    // it tries again a few times, and still fails on anything else.
    let mut stored = store(&app, &id, 1, "G90 G01 X50. F100.\nM30\n").await;
    for _ in 0..3 {
        if stored.status != StatusCode::INTERNAL_SERVER_ERROR {
            break;
        }
        stored = store(&app, &id, 1, "G90 G01 X50. F100.\nM30\n").await;
    }
    assert_eq!(stored.status, StatusCode::CREATED, "{}", stored.text());
    let started = app.post(&format!("{c}/cycle-start"), &json!({"program": 1})).await;
    assert_eq!(started.status, StatusCode::OK, "{}", started.text());
    app.put(&format!("{c}/manual-signals"), &json!({"handle_select": 2})).await;
    let reply = app.post(&format!("{c}/handle-pulses"), &json!({"amount": 2.0})).await;
    assert_eq!(reply.status, StatusCode::OK, "{}", reply.text());
    assert_eq!(reply.json()["taken"], json!(2.0));
    // The shift is the pulses' amount at once; the axis gets there at its handle feed.
    let near = |v: &Value, y: f64| v.as_f64().is_some_and(|v| (v - y).abs() < 1e-9);
    let s =
        eventually(&app, &c, |s| near(&s["interrupt_shift"]["Y"], 2.0) && near(&s["position"]["machine"]["Y"], 2.0))
            .await;
    assert_eq!(s["position"]["workpiece"]["Y"], json!(0.0));
    app.post(&format!("{c}/reset"), &json!({})).await;
}

#[tokio::test]
async fn the_host_sets_interface_input_signals_a_program_reads() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "plc", "preset": "mill3"})).await;
    let put = |n: u32, v: Value| {
        let app = &app;
        let id = id.clone();
        async move { app.put(&format!("{C}/{id}/variables/{n}"), &json!({ "value": v })).await.status }
    };
    assert_eq!(put(1002, json!(1.0)).await, StatusCode::OK);
    assert_eq!(app.get(&format!("{C}/{id}/variables/1032")).await.json()["value"], json!(4.0));
    // A bit takes 0 or 1; the outputs are the programs' to write.
    assert_eq!(put(1002, json!(2.0)).await, StatusCode::UNPROCESSABLE_ENTITY);
    assert_eq!(put(1100, json!(1.0)).await, StatusCode::UNPROCESSABLE_ENTITY);
    store(&app, &id, 1, "#500=#1002\n#1101=1\nM30\n").await;
    app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
    wait_for(&app, &id, "idle").await;
    assert_eq!(app.get(&format!("{C}/{id}/variables/500")).await.json()["value"], json!(1.0));
    assert_eq!(app.get(&format!("{C}/{id}/variables/1132")).await.json()["value"], json!(2.0));
}

/// Cycle start's body is optional whatever the content type says: an empty JSON request resumes
/// (here: nothing to run, 409), malformed JSON is 400 and the wrong shape 422, both JSON errors.
#[tokio::test]
async fn cycle_start_takes_an_empty_body_with_a_json_content_type() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "a", "preset": "mill3"})).await;
    let uri = format!("{C}/{id}/cycle-start");
    for (body, status) in [("", 409), ("  \n", 409), ("{", 400), (r#"{"program": "one"}"#, 422)] {
        let reply = app.raw(Method::POST, &uri, "application/json", body).await;
        assert_eq!(reply.status, status, "{body:?}: {}", reply.text());
        assert!(reply.content_type.starts_with("application/json"), "{body:?}");
        assert!(!error_of(&reply).is_empty());
    }
    assert_eq!(error_of(&app.raw(Method::POST, &uri, "application/json", "").await), "there is no program to run");
}

#[tokio::test]
async fn the_status_shows_the_mechanism_chain_a_program_switched_to() {
    // Syntec G10 L5000 on the library's exchangeable-head machine: set 1 at creation, set 2
    // once an MDI program switched and executed, kept after a reset (docs/five-axis.md).
    let app = spawn_app().await;
    let machine: Value = serde_json::from_str(include_str!("../../../machines/head-exchange-bc-ac.json")).unwrap();
    let reply = app.post(C, &json!({"name": "x", "dialect": "syntec", "machine": machine})).await;
    assert_eq!(reply.status, StatusCode::CREATED, "{}", reply.text());
    assert_eq!(reply.json()["chain"], json!({"set": 1, "sub": 1}));
    let id = reply.json()["id"].as_str().unwrap().to_string();
    app.post(&format!("{C}/{id}/mdi"), &json!({"text": "G10 L5000 P2\nG91 G01 X1. F1000."})).await;
    wait_for(&app, &id, "idle").await;
    assert_eq!(app.get(&format!("{C}/{id}")).await.json()["chain"], json!({"set": 2, "sub": 1}));
    app.post(&format!("{C}/{id}/reset"), &json!({})).await;
    assert_eq!(app.get(&format!("{C}/{id}")).await.json()["chain"], json!({"set": 2, "sub": 1}));
}

/// The operator's switches and counters (`docs/dialects.md`): machine lock runs a program
/// without moving the machine, the positions disagree after it until REF; dry run and the locks
/// change only at rest; the spindle override is checked and scales the spindle speed; the part
/// count and the operating and cutting time are in the status.
#[tokio::test]
async fn switches_overrides_and_counters() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "m", "preset": "mill3", "speed": 20})).await;
    let uri = format!("{C}/{id}");
    let switches = |body: Value| {
        let app = &app;
        let uri = format!("{uri}/switches");
        async move { app.put(&uri, &body).await }
    };
    let reply = switches(json!({"machine_lock": true, "dry_run": true, "aux_lock": true})).await;
    assert_eq!(reply.status, StatusCode::OK, "{}", reply.text());
    let panel = &reply.json()["panel"];
    assert_eq!(
        (&panel["machine_lock"], &panel["dry_run"], &panel["aux_lock"]),
        (&json!(true), &json!(true), &json!(true))
    );
    assert_eq!(switches(json!({"dry_run": "yes"})).await.status, StatusCode::UNPROCESSABLE_ENTITY);

    store(&app, &id, 1, "#3902=4\nS1000 M03\nG90 G01 X40. F30000.\nG01 X60. F100.\nM30\n").await;
    app.post(&format!("{uri}/cycle-start"), &json!({"program": 1})).await;
    let done = eventually(&app, &uri, |s| s["run_state"] == "idle" && s["counters"]["parts"] == 1.0).await;
    // Locked: the workpiece position went on, the machine stayed; aux lock: no spindle; dry run:
    // F100 ran at the dry run rate too (the jog feed without No.1410), counted as cutting time.
    assert_eq!((&done["position"]["workpiece"]["X"], &done["position"]["machine"]["X"]), (&json!(60.0), &json!(0.0)));
    assert_eq!(done["lock_offset"]["X"], -60.0);
    assert_eq!(done["spindle"], 0.0);
    let counters = &done["counters"];
    assert_eq!(counters["parts_required"], 4.0);
    let (operating, cutting) =
        (counters["operating_time_s"].as_f64().unwrap(), counters["cutting_time_s"].as_f64().unwrap());
    assert!(cutting > 0.0 && cutting <= operating && operating < 60.0, "{counters}");

    // Off again: the machine stays where it is until the reference return.
    let reply = switches(json!({"machine_lock": false, "aux_lock": false, "dry_run": false})).await;
    assert_eq!(reply.json()["position"]["machine"]["X"], 0.0);
    assert_eq!(reply.json()["lock_offset"]["X"], -60.0);
    app.put(&format!("{uri}/mode"), &json!({"mode": "ref"})).await;
    app.post(&format!("{uri}/reference-return"), &json!({})).await;
    let back = eventually(&app, &uri, |s| s["run_state"] == "idle" && s["lock_offset"]["X"] == 0.0).await;
    assert_eq!(back["position"]["workpiece"]["X"], 0.0);

    // While the axes move, dry run and machine lock are refused and nothing changes.
    store(&app, &id, 2, "G90 G01 X200. F600.\nM30\n").await;
    app.put(&format!("{uri}/mode"), &json!({"mode": "auto"})).await;
    app.post(&format!("{uri}/cycle-start"), &json!({"program": 2})).await;
    eventually(&app, &uri, |s| s["position"]["machine"]["X"].as_f64().is_some_and(|x| x > 0.0)).await;
    let refused = switches(json!({"single_block": true, "machine_lock": true})).await;
    assert_eq!(refused.status, StatusCode::CONFLICT);
    assert!(error_of(&refused).contains("runs"), "{}", refused.text());
    let status = app.get(&uri).await.json();
    assert_eq!((&status["panel"]["single_block"], &status["panel"]["machine_lock"]), (&json!(false), &json!(false)));
    // The overrides change at any time; the spindle's is 50–120 % in steps of 10.
    for bad in [json!({"spindle": 45}), json!({"spindle": 125}), json!({"spindle": 85}), json!({"spindle": "x"})] {
        let reply = app.put(&format!("{uri}/overrides"), &bad).await;
        assert_eq!(reply.status, StatusCode::UNPROCESSABLE_ENTITY, "{bad}");
        assert!(!error_of(&reply).is_empty());
    }
    let reply = app.put(&format!("{uri}/overrides"), &json!({"spindle": 120})).await;
    assert_eq!(reply.json()["panel"]["spindle_override"], 120.0);
    app.post(&format!("{uri}/reset"), &json!({})).await;

    // Z-axis neglect is FANUC's.
    let syntec = create(&app, json!({"name": "s", "preset": "mill3", "dialect": "syntec"})).await;
    let reply = app.put(&format!("{C}/{syntec}/switches"), &json!({"z_neglect": true})).await;
    assert_eq!(reply.status, StatusCode::CONFLICT);
    assert!(error_of(&reply).contains("Z-axis neglect"));
    let reply = switches(json!({"z_neglect": true})).await;
    assert_eq!(reply.json()["panel"]["z_neglect"], true);
}

/// With the spindle running, the override scales the speed the status reports.
#[tokio::test]
async fn the_spindle_override_scales_the_reported_speed() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "m", "preset": "mill3", "speed": 20})).await;
    app.post(&format!("{C}/{id}/mdi"), &json!({"text": "S1000 M04"})).await;
    eventually(&app, &format!("{C}/{id}"), |s| s["spindle"] == -1000.0).await;
    let reply = app.put(&format!("{C}/{id}/overrides"), &json!({"spindle": 50})).await;
    assert_eq!(reply.json()["spindle"], -500.0);
}

#[tokio::test]
async fn the_syntec_teach_screen_latches_the_tip_and_teaches_a_g68_2_block() {
    let app = spawn_app().await;
    let fanuc = create(&app, json!({"name": "f", "preset": "head-bc", "speed": 20})).await;
    for reply in [
        app.get(&format!("{C}/{fanuc}/teach")).await,
        app.post(&format!("{C}/{fanuc}/teach/points/p1"), &json!({})).await,
        app.post(&format!("{C}/{fanuc}/teach/plane"), &json!({"mode": "three_points"})).await,
    ] {
        assert_eq!(reply.status, StatusCode::CONFLICT, "{}", reply.text());
        assert!(error_of(&reply).contains("Syntec"));
    }
    let id = create(&app, json!({"name": "s", "preset": "head-bc", "dialect": "syntec", "speed": 20})).await;
    let teach = format!("{C}/{id}/teach");
    // G49: F1 is refused, and says why.
    let screen = app.get(&teach).await.json();
    assert_eq!(screen["points"], json!([]));
    assert!(screen["latch_refused"].as_str().unwrap().contains("G49"), "{screen}");
    let refused = app.post(&format!("{teach}/points/p1"), &json!({})).await;
    assert_eq!(refused.status, StatusCode::CONFLICT);
    assert!(error_of(&refused).contains("G49"));
    // TV-44 on the machine: P1 (0, 0, 0), P2 (10, 0, 0), P3 (0, −5, 0) under RTCP.
    app.put(&format!("{C}/{id}/tool-offsets/1"), &json!({"length": 50.0})).await;
    for (slot, text) in [("p1", "G90 G43.4 H1\nG01 X0 Y0 Z0 F3000"), ("p2", "G01 X10."), ("p3", "G01 X0 Y-5.")] {
        let run = app.post(&format!("{C}/{id}/mdi"), &json!({ "text": text })).await;
        assert_eq!(run.status, StatusCode::OK, "{}", run.text());
        wait_for(&app, &id, "idle").await;
        let latched = app.post(&format!("{teach}/points/{slot}"), &json!({})).await;
        assert_eq!(latched.status, StatusCode::OK, "{}", latched.text());
        assert_eq!(latched.json()["slot"], slot);
        assert!((latched.json()["tool"][2].as_f64().unwrap() - 1.0).abs() < 1e-9, "{}", latched.text());
    }
    let screen = app.get(&teach).await.json();
    assert_eq!(screen["latch_refused"], Value::Null);
    assert_eq!(screen["points"].as_array().unwrap().len(), 3);
    assert!((screen["points"][1]["point"][0].as_f64().unwrap() - 10.0).abs() < 1e-6, "{screen}");
    let taught = app.post(&format!("{teach}/plane"), &json!({"mode": "three_points"})).await;
    assert_eq!(taught.status, StatusCode::OK, "{}", taught.text());
    let plane = taught.json();
    assert_eq!(plane["block"], "G68.2 X0. Y0. Z0. I0. J180. K0.");
    assert!(
        (plane["z"][2].as_f64().unwrap() + 1.0).abs() < 1e-9 && (plane["y"][1].as_f64().unwrap() + 1.0).abs() < 1e-9
    );
    // Each mode takes its own values; a failed teach says why.
    for (bad, says) in [
        (json!({"mode": "euler", "i": 10, "x": [1, 0, 0]}), "x is not"),
        (json!({"mode": "three_points", "k": 1}), "k is not"),
        (json!({"mode": "two_vectors", "x": [1, 0, 0]}), "both x and z"),
        (json!({"mode": "two_vectors", "x": [1, 0, 0], "z": [1, 0, 1]}), "orthogonal"),
        (json!({"mode": "two_vectors", "x": [1, 0, 0], "z": [0, 0, 0]}), "zero vector"),
        (json!({"mode": "sideways"}), ""),
        (json!({"mode": "euler", "w": 1}), ""),
    ] {
        let reply = app.post(&format!("{teach}/plane"), &bad).await;
        assert_eq!(reply.status, StatusCode::UNPROCESSABLE_ENTITY, "{bad}: {}", reply.text());
        assert!(error_of(&reply).contains(says), "{bad}: {}", reply.text());
    }
    let euler = app.post(&format!("{teach}/plane"), &json!({"mode": "euler", "i": 30, "j": 15, "k": 20})).await;
    assert_eq!(euler.json()["block"], "G68.2 X0. Y0. Z0. I30. J15. K20.");
    let vectors =
        app.post(&format!("{teach}/plane"), &json!({"mode": "two_vectors", "x": [1, 0, 0], "z": [0, 0, 1]})).await;
    assert_eq!(vectors.json()["block"], "G68.2 X0. Y0. Z0. I0. J0. K0.");
    assert_eq!(app.post(&format!("{teach}/points/p4"), &json!({})).await.status, StatusCode::UNPROCESSABLE_ENTITY);
    // F2: the block run in MDI sets the plane; F1 is then refused until G69.
    let block = plane["block"].as_str().unwrap();
    let run = app.post(&format!("{C}/{id}/mdi"), &json!({ "text": format!("G49\n{block}\nG43 H1") })).await;
    assert_eq!(run.status, StatusCode::OK, "{}", run.text());
    wait_for(&app, &id, "idle").await;
    assert_eq!(app.get(&format!("{C}/{id}/modal")).await.json()["groups"]["16"], "G68.2");
    let in_plane = app.post(&format!("{teach}/points/p1"), &json!({})).await;
    assert_eq!(in_plane.status, StatusCode::CONFLICT);
    assert!(error_of(&in_plane).contains("G69"));
    // Emptied, a teach has no P1.
    let cleared = app.request(Method::DELETE, &format!("{teach}/points")).await;
    assert_eq!(cleared.json()["points"], json!([]));
    let empty = app.post(&format!("{teach}/plane"), &json!({"mode": "three_points"})).await;
    assert!(error_of(&empty).contains("P1"), "{}", empty.text());
}

#[tokio::test]
async fn a_stored_program_is_estimated_before_it_runs_and_its_progress_shown_while_it_runs() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "est", "preset": "mill3", "speed": 20})).await;
    // 60 mm at 600 mm/min: six seconds and the speed changes.
    assert_eq!(store(&app, &id, 1, "G90 G01 X60. F600\nM30\n").await.status, StatusCode::CREATED);
    let uri = format!("{C}/{id}/programs/1/estimate");
    let estimate = eventually(&app, &uri, |e| e["state"] != "pending").await;
    assert_eq!(estimate["state"], "ready", "{estimate}");
    let cycle = estimate["cycle_time_s"].as_f64().unwrap();
    assert!((6.0..6.5).contains(&cycle), "{estimate}");
    // Kept: the same inputs answer at once.
    assert_eq!(app.get(&uri).await.json(), estimate);
    assert_eq!(app.get(&format!("{C}/{id}/programs/2/estimate")).await.status, StatusCode::NOT_FOUND);
    assert!(app.get(&format!("{C}/{id}")).await.json()["progress"].is_null(), "no run, no progress");

    let started = app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await.json();
    let progress = &started["progress"];
    assert_eq!((progress["program"].clone(), progress["estimate"].clone()), (json!(1), estimate), "{started}");
    assert_eq!(progress["caveats"], json!([]), "{started}");
    let running = eventually(&app, &format!("{C}/{id}"), |s| {
        s["run_state"] != "running" || s["progress"]["elapsed_s"].as_f64().is_some_and(|e| e > 0.5)
    })
    .await;
    if running["run_state"] == "running" {
        let p = &running["progress"];
        let (elapsed, remaining) = (p["elapsed_s"].as_f64().unwrap(), p["remaining_s"].as_f64().unwrap());
        assert!((remaining - (cycle - elapsed).max(0.0)).abs() < 1e-9, "{p}");
        assert!((p["percent"].as_f64().unwrap() - (elapsed / cycle * 100.0).min(100.0)).abs() < 1e-9, "{p}");
    }
    wait_for(&app, &id, "idle").await;
    let runs = eventually(&app, &format!("{C}/{id}/runs"), |r| r.as_array().is_some_and(|a| !a.is_empty())).await;
    // The run ends within the worker round after its last motion: never shorter than estimated.
    assert!(runs[0]["cycle_time_s"].as_f64().unwrap() >= cycle * 0.99, "{runs}");
    assert!(app.get(&format!("{C}/{id}")).await.json()["progress"].is_null(), "over");
}

#[tokio::test]
async fn the_run_history_and_the_operating_time_end_where_the_program_ends_at_any_speed() {
    let app = spawn_app().await;
    // A tick is 10 ms of wall time times the speed (10 s of simulated time at 1000): the run
    // ends within a tick, and its record must not run on to the tick's end.
    let programs = [("G04 P2000\nM30\n", Some(2.0)), ("G90 G01 X60. F600\nM30\n", None)];
    for (speed, (text, by_hand)) in [(1.0, programs[0]), (1000.0, programs[0]), (1000.0, programs[1])] {
        let id = create(&app, json!({"name": "timed", "preset": "mill3", "speed": speed})).await;
        assert_eq!(store(&app, &id, 1, text).await.status, StatusCode::CREATED);
        let estimate = eventually(&app, &format!("{C}/{id}/programs/1/estimate"), |e| e["state"] != "pending").await;
        assert_eq!(estimate["state"], "ready", "{estimate}");
        // G04 P2000: two seconds (FANUC's P in ms), nothing else; a motion: the estimate, which
        // is `fivex run`'s time.
        let want = by_hand.unwrap_or_else(|| estimate["cycle_time_s"].as_f64().unwrap());
        assert!((estimate["cycle_time_s"].as_f64().unwrap() - want).abs() < 1e-9, "{estimate}");
        app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
        let done = wait_for(&app, &id, "idle").await;
        let runs = eventually(&app, &format!("{C}/{id}/runs"), |r| r.as_array().is_some_and(|a| !a.is_empty())).await;
        let recorded = runs[0]["cycle_time_s"].as_f64().unwrap();
        assert!((recorded - want).abs() < 1e-6, "speed {speed}: recorded {recorded}, not {want}");
        let operated = done["counters"]["operating_time_s"].as_f64().unwrap();
        assert!((operated - want).abs() < 1e-6, "speed {speed}: operating time {operated}, not {want}");
    }
}

#[tokio::test]
async fn a_haas_controller_runs_its_dialect() {
    let app = spawn_app().await;
    let reply = app.post(C, &json!({"name": "vf2", "preset": "mill3", "dialect": "haas", "speed": 50})).await;
    assert_eq!(reply.status, StatusCode::CREATED, "{}", reply.text());
    let id = reply.json()["id"].as_str().unwrap().to_string();
    assert_eq!(app.get(&format!("{C}/{id}")).await.json()["dialect"], "haas");
    // M97 calls N100 of the same program twice; M98 P2 calls program 2 (Haas: P is the program
    // number); the main program ends at its M30, not in the local subprogram.
    let program = "G00 X0 Y0\nM97 P100 L2\nM98 P2\nG01 X20. F6000.\nM30\nN100 #100=[#100+1]\nM99\n";
    assert_eq!(store(&app, &id, 1, program).await.status, StatusCode::CREATED);
    assert_eq!(store(&app, &id, 2, "#101=#100*10\nM99\n").await.status, StatusCode::CREATED);
    let started = app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
    assert_eq!(started.status, StatusCode::OK, "{}", started.text());
    let done = wait_for(&app, &id, "idle").await;
    assert_eq!(done["position"]["workpiece"]["X"], 20.0, "{done}");
    let v100 = app.get(&format!("{C}/{id}/variables/100")).await.json()["value"].clone();
    let v101 = app.get(&format!("{C}/{id}/variables/101")).await.json()["value"].clone();
    assert_eq!((v100, v101), (json!(2.0), json!(20.0)));
    // The panel shows the NGC's codes: G154 for its extra work offsets, and no group whose
    // power-on code the NGC lacks (FANUC's G15 polar coordinates, G67 modal call).
    let mdi = app.post(&format!("{C}/{id}/mdi"), &json!({"text": "G154 P3"})).await;
    assert_eq!(mdi.status, StatusCode::OK, "{}", mdi.text());
    let modal = eventually(&app, &format!("{C}/{id}/modal"), |m| m["groups"]["14"] == "G154").await;
    let groups = modal["groups"].as_object().unwrap();
    assert!(!groups.contains_key("17") && !groups.contains_key("12"), "{modal}");
    assert_eq!(groups["1"], "G01", "{modal}");

    // A Haas code fivex does not build is reported with the Haas alarm when stored...
    let reply = store(&app, &id, 3, "G00 X1.\nG47 P0\nM30\n").await;
    assert_eq!(reply.status, StatusCode::UNPROCESSABLE_ENTITY, "{}", reply.text());
    let body = reply.json();
    assert_eq!(
        (body["details"][0]["line"].clone(), body["details"][0]["code"].clone()),
        (json!(2), json!("310")),
        "{body}"
    );
    // ... and stops a forced run at its block with it.
    app.raw(Method::PUT, &format!("{C}/{id}/programs/3?force=true"), "text/plain", "G00 X1.\nG47 P0\nM30\n").await;
    app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 3})).await;
    let status = wait_for(&app, &id, "alarm").await;
    assert_eq!(
        (status["alarms"][0]["code"].clone(), status["alarms"][0]["line"].clone()),
        (json!("310"), json!(2)),
        "{status}"
    );
    // Teach is Syntec's.
    let teach = app.post(&format!("{C}/{id}/teach/points/p1"), &json!({})).await;
    assert_eq!(teach.status, StatusCode::CONFLICT, "{}", teach.text());
}

/// The workpiece on the table: put through the API, probed by a G31 (the program of
/// `tests/data/probing/skip_down_stops_on_the_top.nc`), kept over a parameter change, a clone
/// and a restart of the service; refused with a reason when it is no workpiece, and while the
/// axes move.
#[tokio::test]
async fn the_workpiece_is_probed_by_g31_and_kept() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "probe", "preset": "mill3", "speed": 50})).await;
    let uri = format!("{C}/{id}/workpiece");
    assert_eq!(app.get(&uri).await.json(), json!({"boxes": []}), "nothing on the table at first");
    let block = json!({"boxes": [{"min": [0.0, 0.0, -20.0], "max": [50.0, 40.0, 0.0]}]});
    let put = app.put(&uri, &block).await;
    assert_eq!((put.status, put.json()), (StatusCode::OK, block.clone()), "{}", put.text());

    // The tool offsets of a new controller have length 100 and G54 is 0 on mill3: the table
    // frame is the workpiece system, and the probe (D0: a point at the tip) stops on the top.
    let program = "G90 G21 G54 G00 G43 H1 Z10.\nX25. Y20.\nG31 Z-10. F100.\n#100=#5063\nM30\n";
    assert_eq!(store(&app, &id, 1, program).await.status, StatusCode::CREATED);
    let run = |number: u32| {
        let (app, id) = (&app, id.clone());
        async move {
            let started = app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": number})).await;
            assert_eq!(started.status, StatusCode::OK, "{}", started.text());
            wait_for(app, &id, "idle").await
        }
    };
    run(1).await;
    let top = app.get(&format!("{C}/{id}/variables/100")).await.json()["value"].as_f64().unwrap();
    assert!(top.abs() < 1e-9, "#100 = {top}: the skip stops on the top of the box");

    // Not a workpiece: a reason, and what is on the table stays.
    for (bad, why) in [
        (json!({"boxes": [{"min": [0, 0, 0], "max": [1, 1, 0]}]}), "min must be less than max"),
        (json!({"boxes": [{"min": [0, 0, 0], "max": [1, 1, 1], "colour": "red"}]}), "unknown field `colour`"),
        (json!({"boxes": [], "stock": true}), "unknown field `stock`"),
        (json!({"boxes": [{"min": [0, 0], "max": [1, 1, 1]}]}), "boxes[0].min"),
        (json!({"boxes": vec![json!({"min": [0, 0, 0], "max": [1, 1, 1]}); 257]}), "at most 256"),
    ] {
        let reply = app.put(&uri, &bad).await;
        assert_eq!(reply.status, StatusCode::UNPROCESSABLE_ENTITY, "{bad}: {}", reply.text());
        assert!(error_of(&reply).contains(why), "{why}: {}", reply.text());
    }
    assert_eq!(app.get(&uri).await.json(), block);

    // While the axes move: 409, and the boxes stay. (A slow feed: the move must still be under
    // way when the request arrives on a loaded machine; the reset below ends it.)
    store(&app, &id, 2, "G90 G00 Z50.\nG01 X200. F10.\nM30\n").await;
    app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 2})).await;
    eventually(&app, &format!("{C}/{id}"), |s| s["position"]["machine"]["X"].as_f64().is_some_and(|x| x > 0.0)).await;
    let busy = app.put(&uri, &json!({"boxes": []})).await;
    assert_eq!(busy.status, StatusCode::CONFLICT, "{}", busy.text());
    assert!(error_of(&busy).contains("block boundary"), "{}", busy.text());
    assert_eq!(app.get(&uri).await.json(), block);
    app.post(&format!("{C}/{id}/reset"), &json!({})).await;
    wait_for(&app, &id, "idle").await;

    // A parameter change puts a new controller on a new machine: the workpiece stays on it.
    let changed = app.put(&format!("{C}/{id}/parameters/8130"), &json!({"value": 5})).await;
    assert_eq!(changed.status, StatusCode::OK, "{}", changed.text());
    assert_eq!(app.get(&uri).await.json(), block);
    // So does a clone, and a controller may be created with one.
    let copy = app.post(&format!("{C}/{id}/clone"), &json!({"name": "copy"})).await.json();
    assert_eq!(app.get(&format!("{C}/{}/workpiece", copy["id"].as_str().unwrap())).await.json(), block);
    let two = json!({"boxes": [{"min": [-5.0, -5.0, -5.0], "max": [5.0, 5.0, 0.0]}, {"min": [100.0, 0.0, -10.0], "max": [120.0, 10.0, 30.0]}]});
    let made = create(&app, json!({"name": "set up", "preset": "mill3", "workpiece": two})).await;
    assert_eq!(app.get(&format!("{C}/{made}/workpiece")).await.json(), two);
    let refused = app
        .post(
            C,
            &json!({"name": "x", "preset": "mill3", "workpiece": {"boxes": [{"min": [0, 0, 0], "max": [0, 1, 1]}]}}),
        )
        .await;
    assert_eq!(refused.status, StatusCode::UNPROCESSABLE_ENTITY, "{}", refused.text());
    assert!(error_of(&refused).contains("min must be less than max"));

    // A restart of the service: the workpiece comes back, and the skip still stops on it.
    let state = app.restart().await;
    let again = TestApp { state, db_path: app.db_path.clone(), dir: tempfile::tempdir().unwrap() };
    assert_eq!(again.get(&uri).await.json(), block);
    assert_eq!(again.get(&format!("{C}/{made}/workpiece")).await.json(), two);
    again.put(&format!("{C}/{id}/variables/100"), &json!({"value": null})).await;
    let started = again.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
    assert_eq!(started.status, StatusCode::OK, "{}", started.text());
    wait_for(&again, &id, "idle").await;
    let top = again.get(&format!("{C}/{id}/variables/100")).await.json()["value"].as_f64().unwrap();
    assert!(top.abs() < 1e-9, "#100 = {top} after the restart");
    // Cleared: the G31 runs its whole move.
    assert_eq!(again.put(&uri, &json!({"boxes": []})).await.status, StatusCode::OK);
    again.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
    wait_for(&again, &id, "idle").await;
    assert_eq!(again.get(&format!("{C}/{id}/variables/100")).await.json()["value"], json!(-10.0));
}

/// A stored workpiece this version cannot read, or one its check refuses (a row written by hand
/// or by another version), is left out at the restart: the controller comes back with nothing on
/// the table rather than with boxes it would not accept through the API.
#[tokio::test]
async fn a_stored_workpiece_that_is_no_workpiece_is_left_out_at_a_restart() {
    let app = spawn_app().await;
    let (a, b) = (
        create(&app, json!({"name": "a", "preset": "mill3"})).await,
        create(&app, json!({"name": "b", "preset": "mill3"})).await,
    );
    let db = &app.state.db;
    assert!(fivex_server::db::save_workpiece(db, &a, r#"{"boxes": 3}"#).await.unwrap());
    let flat = r#"{"boxes": [{"min": [0, 0, 0], "max": [1, 1, 0]}]}"#;
    assert!(fivex_server::db::save_workpiece(db, &b, flat).await.unwrap());
    let state = app.restart().await;
    let again = TestApp { state, db_path: app.db_path.clone(), dir: tempfile::tempdir().unwrap() };
    for id in [&a, &b] {
        let reply = again.get(&format!("{C}/{id}/workpiece")).await;
        assert_eq!((reply.status, reply.json()), (StatusCode::OK, json!({"boxes": []})), "{id}");
    }
}

/// The audit's F13: a bodyless action refuses a body that is not JSON (400, it answered 200)
/// and takes none, `{}` or `null`; a program's byte order mark is left out (it was refused as
/// "unexpected character 'ï'"); an input signal is never vacant (`null` answered 200).
#[tokio::test]
async fn small_contract_mismatches_are_kept_to_the_contract() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "m", "preset": "mill3"})).await;
    let deep = format!("{}{}", "[".repeat(100_000), "]".repeat(100_000));
    for action in ["reset", "feed-hold", "jog-stop"] {
        let uri = format!("{C}/{id}/{action}");
        for bad in ["{", "1e400", deep.as_str(), "{\"a\":}"] {
            let reply = app.raw(Method::POST, &uri, "application/json", bad.to_string()).await;
            assert_eq!(reply.status, StatusCode::BAD_REQUEST, "{action} {:.20}: {}", bad, reply.text());
            assert!(error_of(&reply).contains("not JSON"), "{}", reply.text());
        }
        for fine in ["", "{}", "null", " \n"] {
            let reply = app.raw(Method::POST, &uri, "application/json", fine.to_string()).await;
            assert_eq!(reply.status, StatusCode::OK, "{action} {fine:?}: {}", reply.text());
        }
    }
    let bom = "\u{feff}G90 G0 X1.\nM30\n";
    let stored = store(&app, &id, 1, bom).await;
    assert_eq!(stored.status, StatusCode::CREATED, "{}", stored.text());
    assert_eq!(stored.json()["size"], "G90 G0 X1.\nM30\n".len());
    assert_eq!(app.get(&format!("{C}/{id}/programs/1")).await.text(), "G90 G0 X1.\nM30\n");
    let reply = app.put(&format!("{C}/{id}/variables/1000"), &json!({"value": null})).await;
    assert_eq!(reply.status, StatusCode::UNPROCESSABLE_ENTITY, "{}", reply.text());
    assert_eq!(app.get(&format!("{C}/{id}/variables/1000")).await.json()["value"], 0.0);
}

/// Fleet audit: a key given twice in a request body was taken silently, the last winning
/// (`{"preset": "mill3", "preset": "head-bc"}` made a head-head machine; a tool's second
/// `length` was stored). The body is ambiguous: 422 naming the key and where it stands, and
/// nothing is created or changed.
#[tokio::test]
async fn a_key_given_twice_is_refused() {
    let app = spawn_app().await;
    let created =
        app.raw(Method::POST, C, "application/json", r#"{"name": "m", "preset": "mill3", "preset": "head-bc"}"#).await;
    assert_eq!(created.status, StatusCode::UNPROCESSABLE_ENTITY, "{}", created.text());
    assert!(created.json()["error"].as_str().unwrap().contains("\"preset\" is given twice"), "{}", created.text());
    assert_eq!(app.get(C).await.json(), json!([]), "nothing was created");
    let id = create(&app, json!({"name": "m", "preset": "mill3"})).await;
    let uri = format!("{C}/{id}/tool-offsets/1");
    let before = app.get(&uri).await.json();
    let put = app.raw(Method::PUT, &uri, "application/json", r#"{"length": 11, "length": 22}"#).await;
    assert_eq!(put.status, StatusCode::UNPROCESSABLE_ENTITY, "{}", put.text());
    assert_eq!(app.get(&uri).await.json(), before, "the offset is unchanged");
    // A key in two different objects is no duplicate.
    let fleet = app
        .raw(
            Method::POST,
            "/api/v1/fleet/runs",
            "application/json",
            r#"{"program": "G0X1\nM30", "presets": ["mill3"], "tools": {"1": {"length": 10, "radius": 1}, "2": {"length": 10, "radius": 1}}}"#,
        )
        .await;
    assert!(fleet.status.is_success(), "{}", fleet.text());
}

/// Haas has no external work offset: its G10 L2 P0 and #5201… are G52 (`docs/dialects.md`,
/// "Haas: the dialect's core"). The API's row in place of `EXT` is that G52, what programs set
/// and #5201 reads, and neither `EXT` nor `G52` is set through the API (422). Before, `PUT
/// …/work-offsets/EXT` set a shift Haas programs could neither see (#5201 read 0) nor cancel
/// (it survived `G52 X0`), and after `G10 L2 P0 X3.` the API still showed EXT X 0.
#[tokio::test]
async fn a_haas_controller_shows_its_g52_in_place_of_the_external_offset() {
    let app = spawn_app().await;
    let id = create(&app, json!({"name": "h", "preset": "mill3", "dialect": "haas", "speed": 50})).await;
    for name in ["EXT", "G52"] {
        let reply = app.put(&format!("{C}/{id}/work-offsets/{name}"), &json!({"axes": {"X": 2.5}})).await;
        assert_eq!(reply.status, StatusCode::UNPROCESSABLE_ENTITY, "{name}: {}", reply.text());
        assert!(error_of(&reply).contains("Haas"), "{}", reply.text());
    }
    let mdi = app.post(&format!("{C}/{id}/mdi"), &json!({"text": "G10 L2 P0 X3.\n#100=#5201"})).await;
    assert_eq!(mdi.status, StatusCode::OK, "{}", mdi.text());
    let status = wait_for(&app, &id, "idle").await;
    assert_eq!(status["position"]["workpiece"]["X"], -3.0, "{status}");
    let works = app.get(&format!("{C}/{id}/work-offsets")).await.json();
    assert_eq!(works[0], json!({"name": "G52", "axes": {"X": 3.0, "Y": 0.0, "Z": 0.0}}), "{works}");
    assert_eq!(works.as_array().unwrap().len(), 7, "G52 and G54–G59: {works}");
    assert_eq!(app.get(&format!("{C}/{id}/variables/100")).await.json()["value"], 3.0);
    let mdi = app.post(&format!("{C}/{id}/mdi"), &json!({"text": "G52 X0"})).await;
    assert_eq!(mdi.status, StatusCode::OK, "{}", mdi.text());
    let status = wait_for(&app, &id, "idle").await;
    assert_eq!(status["position"]["workpiece"]["X"], 0.0, "{status}");
    let works = app.get(&format!("{C}/{id}/work-offsets")).await.json();
    assert_eq!(works[0], json!({"name": "G52", "axes": {"X": 0.0, "Y": 0.0, "Z": 0.0}}), "{works}");
    // FANUC keeps its external offset.
    let fanuc = create(&app, json!({"name": "f", "preset": "mill3", "speed": 50})).await;
    let ext = app.put(&format!("{C}/{fanuc}/work-offsets/EXT"), &json!({"axes": {"X": 2.5}})).await;
    assert_eq!(ext.json(), json!({"name": "EXT", "axes": {"X": 2.5, "Y": 0.0, "Z": 0.0}}));
}
