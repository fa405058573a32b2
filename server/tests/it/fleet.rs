//! Fleet runs over HTTP (`POST/GET /api/v1/fleet/runs`, `GET /fleet/runs/{id}`, the progress
//! websocket; `docs/api.md`): the answer is the `fivex fleet` array, equal to `fivex run` per
//! machine; runs are stored; a run's workpiece is probed on every machine; bad requests are 4xx
//! JSON with the reason.

use crate::common;

use std::path::PathBuf;

use axum::http::{Method, StatusCode};
use common::*;
use fivex_server::db::{self, FleetRunRow};
use futures_util::StreamExt;
use serde_json::{json, Value};

fn workspace_file(relative: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..").join(relative)
}

fn program(name: &str) -> String {
    std::fs::read_to_string(workspace_file(&format!("tests/fleet/{name}"))).unwrap()
}

const PRESETS: [&str; 5] = ["mill3", "head-bc", "table-ac", "table-bc", "mixed-bc"];

/// `fivex run PROGRAM --preset P --dialect D` through the real binary.
fn run_alone(name: &str, preset: &str, dialect: &str) -> Value {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_fivex"))
        .args(["run", workspace_file(&format!("tests/fleet/{name}")).to_str().unwrap(), "--preset", preset])
        .args(["--dialect", dialect])
        .output()
        .unwrap();
    serde_json::from_slice(&out.stdout).unwrap()
}

fn without_fleet_fields(v: &Value) -> Value {
    let mut v = v.clone();
    for k in ["machine", "dialect", "report"] {
        v.as_object_mut().unwrap().remove(k);
    }
    v
}

#[tokio::test]
async fn a_fleet_run_answers_the_fleet_array_equal_to_fivex_run_and_is_stored() {
    let app = spawn_app().await;
    let request = json!({"program": program("everywhere.nc"), "presets": PRESETS, "dialect": "syntec"});
    let reply = app.post("/api/v1/fleet/runs", &request).await;
    assert_eq!(reply.status, StatusCode::OK, "{}", reply.text());
    let items = reply.json();
    let items = items.as_array().unwrap();
    assert_eq!(items.len(), 5);
    for (item, preset) in items.iter().zip(PRESETS) {
        assert_eq!(item["machine"], preset);
        assert_eq!(item["dialect"], "syntec");
        assert_eq!(item["status"], "completed");
        assert_eq!(without_fleet_fields(item), run_alone("everywhere.nc", preset, "syntec"), "{preset}");
    }
    // The history lists it; the run itself gives the request and the same array back.
    let list = app.get("/api/v1/fleet/runs").await.json();
    assert_eq!(list.as_array().unwrap().len(), 1);
    let info = &list[0];
    assert_eq!((info["status"].as_str(), info["machines"].as_u64()), (Some("done"), Some(5)));
    assert_eq!((info["completed"].as_u64(), info["alarms"].as_u64()), (Some(5), Some(0)));
    let id = info["id"].as_str().unwrap();
    let run = app.get(&format!("/api/v1/fleet/runs/{id}")).await;
    assert_eq!(run.status, StatusCode::OK);
    let run = run.json();
    assert_eq!(run["results"], Value::Array(items.clone()));
    assert_eq!(run["request"]["presets"], json!(PRESETS));
    assert_eq!(run["request"]["program"], request["program"]);
    assert!(run["finished_at"].is_string());
    assert_eq!(app.get("/api/v1/fleet/runs/nope").await.status, StatusCode::NOT_FOUND);
}

#[tokio::test]
async fn machines_from_documents_the_library_and_controllers_with_reports() {
    let app = spawn_app().await;
    let created =
        app.post("/api/v1/controllers", &json!({"name": "cell 4", "preset": "table-ac", "dialect": "fanuc"})).await;
    assert_eq!(created.status, StatusCode::CREATED);
    let controller = created.json()["id"].as_str().unwrap().to_string();
    let document: Value =
        serde_json::from_str(&std::fs::read_to_string(workspace_file("machines/cradle-bc-110.json")).unwrap()).unwrap();
    let reply = app
        .post(
            "/api/v1/fleet/runs",
            &json!({
                "program": program("tilt.nc"),
                "presets": ["mill3"],
                "machines": [document],
                "library": ["mixed-bc-200"],
                "controllers": [controller],
                "report": true,
            }),
        )
        .await;
    assert_eq!(reply.status, StatusCode::OK, "{}", reply.text());
    let items = reply.json();
    let names: Vec<&str> = items.as_array().unwrap().iter().map(|v| v["machine"].as_str().unwrap()).collect();
    assert_eq!(names, ["mill3", "cradle-bc-110", "mixed-bc-200", "cell 4"]);
    // No rotary axes for the tool vectors on mill3: no solution (PS5459).
    assert_eq!(items[0]["status"], "alarm");
    assert_eq!(items[0]["alarms"][0]["code"], "PS5459");
    assert_eq!(items[0]["report"]["alarm"]["code"], "PS5459");
    // A Syntec parameter list runs in Syntec.
    assert_eq!(items[1]["dialect"], "syntec");
    for item in &items.as_array().unwrap()[1..] {
        assert_eq!(item["status"], "completed", "{item}");
        assert!(item["report"]["tip_deviation"]["max"].as_f64().unwrap() < 1e-6);
        assert_eq!(item["report"]["cycle_time_s"], item["cycle_time_s"]);
    }
    // The whole library.
    let reply = app.post("/api/v1/fleet/runs", &json!({"program": program("everywhere.nc"), "library": ["*"]})).await;
    assert_eq!(reply.status, StatusCode::OK);
    assert!(reply.json().as_array().unwrap().len() >= 20);
}

#[tokio::test]
async fn a_tool_table_may_give_corner_radii_and_is_stored_as_posted() {
    let app = spawn_app().await;
    // Offset 2 without a corner radius, offset 1 with one: both taken, the run is the one
    // without the corner radius (nothing in it reads one).
    let tools =
        json!({"1": {"length": 120.0, "radius": 4.0, "corner_radius": 1.0}, "2": {"length": 80.0, "radius": 3.0}});
    let request = json!({"program": program("everywhere.nc"), "presets": ["mill3"], "tools": tools});
    let reply = app.post("/api/v1/fleet/runs", &request).await;
    assert_eq!(reply.status, StatusCode::OK, "{}", reply.text());
    let plain = json!({"1": {"length": 120.0, "radius": 4.0}, "2": {"length": 80.0, "radius": 3.0}});
    let again = app
        .post("/api/v1/fleet/runs", &json!({"program": request["program"], "presets": ["mill3"], "tools": plain}))
        .await;
    assert_eq!(again.status, StatusCode::OK, "{}", again.text());
    assert_eq!(reply.json(), again.json());
    let list = app.get("/api/v1/fleet/runs").await.json();
    let mut stored = Vec::new();
    for info in list.as_array().unwrap() {
        let run = app.get(&format!("/api/v1/fleet/runs/{}", info["id"].as_str().unwrap())).await.json();
        stored.push(run["request"]["tools"].clone());
    }
    // Newest first; a tool without a corner radius is stored without one.
    assert_eq!(stored, [plain, tools]);
}

#[tokio::test]
async fn every_machine_probes_the_workpiece_of_the_run_and_a_controller_its_own() {
    let app = spawn_app().await;
    let nc = program("probe.nc");
    let block: Value =
        serde_json::from_str(&std::fs::read_to_string(workspace_file("tests/fleet/probe_block.json")).unwrap())
            .unwrap();
    // probe.nc: G31 Z-10 from above X25 Y20; the block's top is at Z-3 there.
    let skip_z = |items: &Value| -> Vec<f64> {
        items.as_array().unwrap().iter().map(|v| v["variables"]["#101"].as_f64().unwrap()).collect()
    };
    let air = app.post("/api/v1/fleet/runs", &json!({"program": nc, "presets": ["mill3", "table-ac"]})).await;
    assert_eq!(air.status, StatusCode::OK, "{}", air.text());
    assert_eq!(skip_z(&air.json()), [-10.0, -10.0]);
    let request = json!({"program": nc, "presets": ["mill3", "table-ac"], "workpiece": block});
    let probed = app.post("/api/v1/fleet/runs", &request).await;
    assert_eq!(probed.status, StatusCode::OK, "{}", probed.text());
    assert_eq!(skip_z(&probed.json()), [-3.0, -3.0]);
    // The machine ends where the probe stopped (tool length 100), as `fivex run --workpiece`.
    assert_eq!(probed.json()[0]["position"]["machine"]["Z"], 97.0);
    let id = app.get("/api/v1/fleet/runs").await.json()[0]["id"].as_str().unwrap().to_string();
    assert_eq!(app.get(&format!("/api/v1/fleet/runs/{id}")).await.json()["request"]["workpiece"], block);

    // An existing controller brings what is on its table, unless the run gives a workpiece.
    let created =
        app.post("/api/v1/controllers", &json!({"name": "probing", "preset": "mill3", "workpiece": block})).await;
    assert_eq!(created.status, StatusCode::CREATED, "{}", created.text());
    let controller = created.json()["id"].as_str().unwrap().to_string();
    let own = app.post("/api/v1/fleet/runs", &json!({"program": nc, "controllers": [controller]})).await;
    assert_eq!(own.status, StatusCode::OK, "{}", own.text());
    assert_eq!(skip_z(&own.json()), [-3.0]);
    let cleared = app
        .post("/api/v1/fleet/runs", &json!({"program": nc, "controllers": [controller], "workpiece": {"boxes": []}}))
        .await;
    assert_eq!(cleared.status, StatusCode::OK, "{}", cleared.text());
    assert_eq!(skip_z(&cleared.json()), [-10.0]);
    // The controller's own workpiece is untouched by the run.
    assert_eq!(app.get(&format!("/api/v1/controllers/{controller}/workpiece")).await.json(), block);
}

#[tokio::test]
async fn a_tool_table_replaces_a_controllers_tool_offsets_and_keeps_its_work_offsets() {
    let app = spawn_app().await;
    let created = app.post("/api/v1/controllers", &json!({"name": "g54 set", "preset": "head-bc"})).await;
    assert_eq!(created.status, StatusCode::CREATED, "{}", created.text());
    let controller = created.json()["id"].as_str().unwrap().to_string();
    let g54 = json!({"axes": {"X": 10.0, "Y": -20.0, "Z": -100.0}});
    let set = app.put(&format!("/api/v1/controllers/{controller}/work-offsets/G54"), &g54).await;
    assert_eq!(set.status, StatusCode::OK, "{}", set.text());
    // B = C = 0: the machine point is the program point plus G54, plus H3 along Z under G43.
    let nc = "O0001\nG90 G54 G0 X1. Y2. Z3.\n#500=#5221\n#501=#5222\n#502=#5223\nG43 H3 Z3.\nM30\n";
    // The table's wear acts as the API's tool offset's does (it was dropped without a word).
    let worn = json!({"3": {"length": 50.0, "radius": 1.0, "length_wear": -0.5, "radius_wear": 0.1}});
    for (tools, h) in [(None, 100.0), (Some(json!({"3": {"length": 50.0, "radius": 1.0}})), 50.0), (Some(worn), 49.5)] {
        let mut request = json!({"program": nc, "controllers": [controller]});
        if let Some(t) = &tools {
            request["tools"] = t.clone();
        }
        let reply = app.post("/api/v1/fleet/runs", &request).await;
        assert_eq!(reply.status, StatusCode::OK, "{}", reply.text());
        let item = &reply.json()[0];
        assert_eq!(item["status"], "completed", "{item}");
        let vars = &item["variables"];
        assert_eq!([&vars["#500"], &vars["#501"], &vars["#502"]], [10.0, -20.0, -100.0], "tools {tools:?}");
        let machine = &item["position"]["machine"];
        // The controller's own H3 is 100 mm (its defaults); the table's 50 mm (less its wear).
        assert_eq!([&machine["X"], &machine["Y"], &machine["Z"]], [11.0, -18.0, 3.0 - 100.0 + h], "tools {tools:?}");
    }
}

/// A mill3 controller named `name` at `speed`: its status URI.
async fn mill3_controller(app: &TestApp, name: &str, speed: u32) -> String {
    let created = app.post("/api/v1/controllers", &json!({"name": name, "preset": "mill3", "speed": speed})).await;
    assert_eq!(created.status, StatusCode::CREATED, "{}", created.text());
    format!("/api/v1/controllers/{}", created.json()["id"].as_str().unwrap())
}

/// The status at `uri` once `done` holds for it (polled for up to 10 s; the last one otherwise).
async fn status_when(app: &TestApp, uri: &str, done: impl Fn(&Value) -> bool) -> Value {
    let mut status = Value::Null;
    for _ in 0..500 {
        status = app.get(uri).await.json();
        if done(&status) {
            break;
        }
        tokio::time::sleep(std::time::Duration::from_millis(20)).await;
    }
    status
}

/// Audit of views F1: an existing controller's machine starts where its axes stand (it started
/// at machine zero: #5021 read 0 and the G91 move ended at X10). Decision (`docs/api.md`,
/// "Fleet runs"): only the position is taken over; the modal state is a fresh run's, so the
/// G91 the controller's MDI left does not make the program's `Y5.` incremental.
#[tokio::test]
async fn a_controllers_machine_starts_where_its_axes_stand() {
    let app = spawn_app().await;
    let c = mill3_controller(&app, "moved", 20).await;
    let controller = c.rsplit('/').next().unwrap();
    let mdi = app.post(&format!("{c}/mdi"), &json!({"text": "G91 G00 X100. Y50. Z-20."})).await;
    assert_eq!(mdi.status, StatusCode::OK, "{}", mdi.text());
    let status = status_when(&app, &c, |s| s["run_state"] == "idle").await;
    let stands = &status["position"]["machine"];
    assert_eq!([&stands["X"], &stands["Y"], &stands["Z"]], [100.0, 50.0, -20.0], "{status}");
    let nc = "O0001\n#500=#5021\n#501=#5022\n#502=#5023\nG00 Y5.\nG91 G01 X10. F3000.\nM30\n";
    let reply = app.post("/api/v1/fleet/runs", &json!({"program": nc, "controllers": [controller]})).await;
    assert_eq!(reply.status, StatusCode::OK, "{}", reply.text());
    let item = &reply.json()[0];
    assert_eq!(item["status"], "completed", "{item}");
    let vars = &item["variables"];
    assert_eq!([&vars["#500"], &vars["#501"], &vars["#502"]], [100.0, 50.0, -20.0], "{item}");
    let machine = &item["position"]["machine"];
    assert_eq!([&machine["X"], &machine["Y"], &machine["Z"]], [110.0, 5.0, -20.0], "{item}");
    // The controller itself did not move.
    let after = app.get(&c).await.json();
    assert_eq!(after["position"]["machine"], status["position"]["machine"]);
}

/// A controller held in the middle of a block: its interpreter has read the block's end (and
/// beyond), its axes stand short of it. The fleet run starts where the axes stand (it started
/// at the read-ahead point: #5021 read 100 with X at a few mm).
#[tokio::test]
async fn a_held_controllers_machine_starts_where_its_axes_stand_not_where_it_read_to() {
    let app = spawn_app().await;
    let c = mill3_controller(&app, "held", 1).await;
    let controller = c.rsplit('/').next().unwrap();
    let text = "G91 G01 X100. F600.\nY100.\nM30\n".to_string();
    let stored = app.raw(Method::PUT, &format!("{c}/programs/1"), "text/plain", text).await;
    assert!(stored.status.is_success(), "{}", stored.text());
    let started = app.post(&format!("{c}/cycle-start"), &json!({"program": 1})).await;
    assert_eq!(started.status, StatusCode::OK, "{}", started.text());
    tokio::time::sleep(std::time::Duration::from_millis(300)).await;
    assert_eq!(app.post(&format!("{c}/feed-hold"), &json!({})).await.status, StatusCode::OK);
    let status = status_when(&app, &c, |s| s["run_state"] == "hold" && s["feed"] == 0.0).await;
    let x = status["position"]["machine"]["X"].as_f64().unwrap();
    assert!(x > 0.0 && x < 100.0, "held inside the first block: {status}");
    let nc = "O0001\n#500=#5021\n#501=#5022\nM30\n";
    let reply = app.post("/api/v1/fleet/runs", &json!({"program": nc, "controllers": [controller]})).await;
    assert_eq!(reply.status, StatusCode::OK, "{}", reply.text());
    let vars = &reply.json()[0]["variables"];
    assert_eq!([vars["#500"].as_f64(), vars["#501"].as_f64()], [Some(x), Some(0.0)], "{vars} against {status}");
}

#[tokio::test]
async fn a_malformed_program_is_a_run_whose_machines_alarm() {
    let app = spawn_app().await;
    let reply = app.post("/api/v1/fleet/runs", &json!({"program": program("malformed.nc"), "presets": PRESETS})).await;
    assert_eq!(reply.status, StatusCode::OK);
    for item in reply.json().as_array().unwrap() {
        assert_eq!((item["alarms"][0]["code"].as_str(), item["alarms"][0]["line"].as_u64()), (Some("PS0004"), Some(5)));
    }
    let info = &app.get("/api/v1/fleet/runs").await.json()[0];
    assert_eq!((info["completed"].as_u64(), info["alarms"].as_u64()), (Some(0), Some(5)));
}

#[tokio::test]
async fn bad_requests_are_4xx_json_with_the_reason() {
    let app = spawn_app().await;
    let nc = program("everywhere.nc");
    for (body, status, reason) in [
        (json!({"program": "  ", "presets": ["mill3"]}), StatusCode::UNPROCESSABLE_ENTITY, "empty"),
        (json!({"program": nc}), StatusCode::UNPROCESSABLE_ENTITY, "no machines"),
        (json!({"program": nc, "presets": ["nope"]}), StatusCode::UNPROCESSABLE_ENTITY, "unknown preset"),
        (json!({"program": nc, "library": ["nope"]}), StatusCode::UNPROCESSABLE_ENTITY, "no library machine"),
        (json!({"program": nc, "controllers": ["nope"]}), StatusCode::UNPROCESSABLE_ENTITY, "no controller"),
        (
            json!({"program": nc, "machines": [{"name": "x", "axes": []}]}),
            StatusCode::UNPROCESSABLE_ENTITY,
            "machines[0]",
        ),
        (
            json!({"program": nc, "presets": ["mill3"], "dialect": "heidenhain"}),
            StatusCode::UNPROCESSABLE_ENTITY,
            "heidenhain",
        ),
        (
            json!({"program": nc, "presets": ["mill3"], "tools": {"0": {"length": 1.0, "radius": 1.0}}}),
            StatusCode::UNPROCESSABLE_ENTITY,
            "out of range",
        ),
        (
            json!({"program": nc, "presets": ["mill3"], "tools": {"1": {"length": 1.0, "radius": 1.0, "corner_radius": -0.5}}}),
            StatusCode::UNPROCESSABLE_ENTITY,
            "corner_radius",
        ),
        // Beyond the range G10 takes (`interp::tool_value_limit`): a length no program could set.
        (
            json!({"program": nc, "presets": ["mill3"], "tools": {"1": {"length": 1000.0, "radius": 1.0}}}),
            StatusCode::UNPROCESSABLE_ENTITY,
            "tool offset 1: length 1000 is outside ±999.999 mm",
        ),
        (
            json!({"program": nc, "presets": ["mill3"], "tools": {"2": {"length": 1.0, "radius": -1000.0}}}),
            StatusCode::UNPROCESSABLE_ENTITY,
            "tool offset 2: radius -1000 is outside ±999.999 mm",
        ),
        (
            json!({"program": nc, "presets": ["mill3"], "tools": {"3": {"length": 1.0, "radius": 1.0, "corner_radius": 1000.0}}}),
            StatusCode::UNPROCESSABLE_ENTITY,
            "tool offset 3: corner_radius 1000",
        ),
        (
            json!({"program": nc, "presets": ["mill3"], "tools": {"1": {"length": 1.0, "radius": 1.0, "corner_radius": "1"}}}),
            StatusCode::UNPROCESSABLE_ENTITY,
            "corner_radius",
        ),
        // Any field of a tool but the five of the API's tool offset is refused, not dropped
        // (a misspelled wear ran without it); a wear beyond G10's ±99.999 mm too.
        (
            json!({"program": nc, "presets": ["mill3"], "tools": {"1": {"length": 1.0, "radius": 1.0, "wear": 1.0}}}),
            StatusCode::UNPROCESSABLE_ENTITY,
            "unknown field `wear`",
        ),
        (
            json!({"program": nc, "presets": ["mill3"], "tools": {"1": {"lenght": 1.0, "length": 1.0, "radius": 1.0}}}),
            StatusCode::UNPROCESSABLE_ENTITY,
            "unknown field `lenght`",
        ),
        (
            json!({"program": nc, "presets": ["mill3"], "tools": {"4": {"length": 1.0, "radius": 1.0, "radius_wear": -100.0}}}),
            StatusCode::UNPROCESSABLE_ENTITY,
            "tool offset 4: radius_wear -100 is outside ±99.999 mm",
        ),
        (json!({"program": nc, "presets": ["mill3"], "colour": "red"}), StatusCode::UNPROCESSABLE_ENTITY, "colour"),
        (
            json!({"program": nc, "presets": ["mill3"], "workpiece": {"boxes": [{"min": [0, 0, 0], "max": [10, 10, 0]}]}}),
            StatusCode::UNPROCESSABLE_ENTITY,
            "workpiece: box 0: min must be less than max",
        ),
        (
            json!({"program": nc, "presets": ["mill3"], "workpiece": {"boxes": [], "colour": "red"}}),
            StatusCode::UNPROCESSABLE_ENTITY,
            "colour",
        ),
        (json!({"presets": ["mill3"]}), StatusCode::UNPROCESSABLE_ENTITY, "program"),
    ] {
        let reply = app.post("/api/v1/fleet/runs", &body).await;
        assert_eq!(reply.status, status, "{body}: {}", reply.text());
        let error = reply.json()["error"].as_str().unwrap().to_string();
        assert!(error.contains(reason), "{body}: {error}");
    }
    let reply = app.raw(Method::POST, "/api/v1/fleet/runs", "application/json", "{").await;
    assert_eq!(reply.status, StatusCode::BAD_REQUEST);
    assert!(reply.json()["error"].is_string());
    let too_many: Vec<&str> = std::iter::repeat_n("mill3", 201).collect();
    let reply = app.post("/api/v1/fleet/runs", &json!({"program": nc, "presets": too_many})).await;
    assert_eq!(reply.status, StatusCode::UNPROCESSABLE_ENTITY);
    // Nothing was stored for refused requests.
    assert_eq!(app.get("/api/v1/fleet/runs").await.json(), json!([]));
}

#[tokio::test]
async fn progress_over_the_websocket_and_runs_cut_off_by_a_restart() {
    let app = spawn_app().await;
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
    let server = tokio::spawn(fivex_server::serve::serve(listener, app.state.clone(), async {
        let _ = stopped.await;
    }));
    // wait=false: 202 at once with the id; the stream gives progress up to "finished".
    let mut presets: Vec<&str> = PRESETS.to_vec();
    presets.extend(PRESETS);
    let reply = app
        .post(
            "/api/v1/fleet/runs?wait=false",
            &json!({"program": program("tilt.nc"), "presets": presets, "report": true}),
        )
        .await;
    assert_eq!(reply.status, StatusCode::ACCEPTED, "{}", reply.text());
    let id = reply.json()["id"].as_str().unwrap().to_string();
    let (mut ws, _) =
        tokio_tungstenite::connect_async(format!("ws://{addr}/api/v1/fleet/runs/{id}/stream")).await.unwrap();
    let mut last = Value::Null;
    let mut done_seen = Vec::new();
    while let Some(Ok(message)) = ws.next().await {
        let tokio_tungstenite::tungstenite::Message::Text(text) = message else { break };
        let v: Value = serde_json::from_str(&text).unwrap();
        assert_eq!(
            (v["type"].as_str(), v["id"].as_str(), v["total"].as_u64()),
            (Some("progress"), Some(id.as_str()), Some(10))
        );
        done_seen.push(v["done"].as_u64().unwrap());
        last = v;
    }
    assert_eq!(last["finished"], true);
    assert_eq!(last["done"], 10);
    assert!(done_seen.windows(2).all(|w| w[0] <= w[1]), "{done_seen:?}");
    let states: Vec<&str> = last["machines"].as_array().unwrap().iter().map(|m| m["state"].as_str().unwrap()).collect();
    assert_eq!(states.iter().filter(|s| **s == "alarm").count(), 2, "mill3 twice: {states:?}");
    // The run is stored as done; its stream now sends the final state and closes.
    let run = app.get(&format!("/api/v1/fleet/runs/{id}")).await.json();
    assert_eq!(run["status"], "done");
    assert_eq!(run["results"].as_array().unwrap().len(), 10);
    let (mut ws, _) =
        tokio_tungstenite::connect_async(format!("ws://{addr}/api/v1/fleet/runs/{id}/stream")).await.unwrap();
    let first = ws.next().await.unwrap().unwrap();
    let v: Value = serde_json::from_str(first.to_text().unwrap()).unwrap();
    assert_eq!((v["finished"].as_bool(), v["done"].as_u64()), (Some(true), Some(10)));
    let _ = stop.send(());
    server.await.unwrap().unwrap();
    // A run the service stopped in the middle of shows as interrupted after a restart.
    db::insert_fleet_run(
        &app.state.db,
        &FleetRunRow {
            id: "cut".into(),
            created_at: "2026-01-01T00:00:00Z".into(),
            finished_at: None,
            status: "running".into(),
            machines: 3,
            completed: 0,
            alarms: 0,
            program: "M30\n".into(),
            request_json: "{}".into(),
            results_json: None,
        },
    )
    .await
    .unwrap();
    let state = app.restart().await;
    let row = db::fleet_run(&state.db, "cut").await.unwrap().unwrap();
    assert_eq!(row.status, "interrupted");
}
