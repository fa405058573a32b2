//! The wire formats are what the OpenAPI document says they are (issue 19 item 4): the machine
//! documents, `fivex run` summaries and fleet results the CLI and the service write, and every
//! websocket message of the real `fivex serve`, each validated against its schema in the
//! served document (JSON Schema 2020-12, as OpenAPI 3.1 has it). schemathesis checks the REST
//! answers at large (`scripts/schemathesis.sh`); these cover what it cannot reach: the
//! streams, and results on every machine of the library with the run report.

use std::collections::BTreeSet;
use std::path::PathBuf;
use std::time::Duration;

use futures_util::StreamExt;
use hyper::Method;
use serde_json::{json, Value};
use tokio::time::{timeout, Instant};
use tokio_tungstenite::tungstenite::Message;

use super::served::Served;

/// A validator of the document's component `name`: the document's schemas under a root whose
/// `$ref` points at it, so that every `#/components/schemas/…` inside resolves.
fn schema(document: &Value, name: &str) -> jsonschema::Validator {
    let root = json!({"$ref": format!("#/components/schemas/{name}"), "components": document["components"]});
    jsonschema::options().with_draft(jsonschema::Draft::Draft202012).build(&root).expect("a schema")
}

/// Panics with every violation when `value` is not a `name`.
pub(super) fn assert_valid(document: &Value, name: &str, value: &Value, what: &str) {
    let validator = schema(document, name);
    let errors: Vec<String> = validator.iter_errors(value).map(|e| format!("{} at {}", e, e.instance_path())).collect();
    assert!(errors.is_empty(), "{what} is not a {name}: {errors:#?}");
}

#[test]
fn an_axis_letter_is_valid_in_the_schemas_exactly_when_the_service_takes_it() {
    // The pattern names its white space (JSON's four characters) instead of `\s`, whose set
    // differs between ECMA-262, Python and Rust; the service trims the same four.
    use fivex_server::service::panel::{letter, AXIS_LETTER_PATTERN};
    let doc = document();
    let candidates = [
        "X",
        "b",
        " c ",
        "\t\r\nZ\n",
        "",
        " ",
        "XY",
        "1",
        "\u{a0}X",
        "X\u{85}",
        "\u{feff}X",
        "\u{2003}B",
        "\u{1c}A",
        "É",
    ];
    for (component, field) in [("ManualMove", "axis"), ("ManualMove", "tip_rotation"), ("JogSignal", "axis")] {
        let declared = &doc["components"]["schemas"][component]["properties"][field]["pattern"];
        assert_eq!(declared, AXIS_LETTER_PATTERN, "{component}.{field}");
        let validator = schema(&doc, component);
        for s in candidates {
            let mut body = json!({field: s});
            if component == "JogSignal" {
                body["positive"] = json!(true);
            }
            assert_eq!(validator.is_valid(&body), letter(s).is_ok(), "{component}.{field} = {s:?}");
        }
    }
}

#[test]
fn a_tool_table_key_is_valid_in_the_schema_exactly_when_the_service_takes_it() {
    use fivex_server::api::fleet::TOOL_NUMBER_KEY;
    use fivex_server::fleet::{check_tools, Tool};
    let doc = document();
    let declared = &doc["components"]["schemas"]["FleetRequest"]["properties"]["tools"];
    assert_eq!(declared["propertyNames"]["pattern"], TOOL_NUMBER_KEY);
    let validator = schema(&doc, "FleetRequest");
    for key in ["1", "9", "10", "99", "999", "0", "1000", "01", "+1", "-1", " 1", "1 ", "1.0", "1e2", "a", "", "٣"] {
        let tools = json!({key: {"length": 100.0, "radius": 5.0}});
        let request = json!({"program": "M30", "presets": ["mill3"], "tools": tools});
        let taken = serde_json::from_value::<std::collections::BTreeMap<u32, Tool>>(tools)
            .is_ok_and(|t| check_tools(&t).is_ok());
        assert_eq!(validator.is_valid(&request), taken, "tool number key {key:?}");
    }
}

pub(super) fn document() -> Value {
    serde_json::to_value(fivex_server::http::openapi()).expect("the document as JSON")
}

fn fleet_program(name: &str) -> String {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../tests/fleet").join(name);
    std::fs::read_to_string(path).expect("a fleet program")
}

#[test]
fn the_validator_refuses_what_the_schemas_forbid() {
    // Without this the other tests could pass on a validator that takes anything.
    let doc = document();
    let preset = serde_json::to_value(fivex_engine::machine::MachineConfig::preset("table-ac").unwrap()).unwrap();
    assert!(schema(&doc, "MachineConfig").is_valid(&preset));
    let mut curved = preset.clone();
    curved["axes"][0]["kind"] = json!("curved");
    assert!(!schema(&doc, "MachineConfig").is_valid(&curved), "an axis kind outside the enum");
    let mut two_letters = preset.clone();
    two_letters["axes"][0]["name"] = json!("XY");
    assert!(!schema(&doc, "MachineDocument").is_valid(&two_letters), "an axis name of two letters");
    assert!(!schema(&doc, "MachineDocument").is_valid(&json!({"name": "x"})), "neither a model nor a list");
    let stream = json!({"type": "position", "t": 0.0});
    assert!(!schema(&doc, "ControllerMessage").is_valid(&stream), "a position frame without its fields");
    assert!(!schema(&doc, "RunStatus").is_valid(&json!("finished")));
}

#[test]
fn every_preset_and_library_machine_is_a_machine_document() {
    let doc = document();
    for name in fivex_engine::machine::MachineConfig::PRESETS {
        let model = serde_json::to_value(fivex_engine::machine::MachineConfig::preset(name).unwrap()).unwrap();
        assert_valid(&doc, "MachineConfig", &model, name);
    }
    let mut lists = 0;
    for (name, text) in fivex_server::fleet::LIBRARY {
        let file: Value = serde_json::from_str(text).unwrap();
        assert_valid(&doc, "MachineDocument", &file, name);
        if file.get("parameters").is_some() {
            assert_valid(&doc, "ParamFile", &file, name);
            lists += 1;
        }
        // The model the service keeps and answers (`GET /controllers/{id}/machine`).
        let model = serde_json::to_value(fivex_engine::machine_file::parse(text).unwrap()).unwrap();
        assert_valid(&doc, "MachineConfig", &model, name);
    }
    assert!(lists > 0, "the library has parameter lists");
}

#[test]
fn fleet_results_with_reports_validate_on_every_machine() {
    let doc = document();
    let opts = fivex_server::fleet::Options { report: true, report_period_s: 0.01, ..Default::default() };
    let mut entries: Vec<_> = fivex_engine::machine::MachineConfig::PRESETS
        .iter()
        .map(|p| fivex_server::fleet::preset(p, fivex_engine::Dialect::Fanuc).unwrap())
        .collect();
    entries.extend(fivex_server::fleet::whole_library(fivex_engine::Dialect::Fanuc).unwrap());
    let mut statuses = BTreeSet::new();
    for program in ["tilt.nc", "malformed.nc", "overtravel.nc"] {
        let results = fivex_server::fleet::run_fleet(&fleet_program(program), &entries, &opts, &|_| {});
        for result in results {
            let value = serde_json::to_value(result.expect("not cancelled")).unwrap();
            assert_valid(&doc, "FleetResult", &value, &format!("{program} on {}", value["machine"]));
            assert!(value["report"].is_object());
            statuses.insert(value["status"].as_str().unwrap_or_default().to_owned());
        }
    }
    assert_eq!(statuses, BTreeSet::from(["alarm".to_owned(), "completed".to_owned()]), "both ends checked");
}

type Socket = tokio_tungstenite::WebSocketStream<tokio_tungstenite::MaybeTlsStream<tokio::net::TcpStream>>;

async fn connect(served: &Served, path: &str) -> Socket {
    tokio_tungstenite::connect_async(format!("ws://{}{path}", served.addr)).await.expect("websocket").0
}

/// Every text message within `span` (or until the server closes the socket).
async fn messages(ws: &mut Socket, span: Duration, until: impl Fn(&Value) -> bool) -> Vec<Value> {
    let end = Instant::now() + span;
    let mut out = Vec::new();
    while let Ok(Some(Ok(message))) = timeout(end.saturating_duration_since(Instant::now()), ws.next()).await {
        match message {
            Message::Text(text) => {
                let value: Value = serde_json::from_str(text.as_str()).expect("a JSON message");
                let done = until(&value);
                out.push(value);
                if done {
                    break;
                }
            }
            Message::Close(_) => break,
            _ => {}
        }
    }
    out
}

fn types(messages: &[Value]) -> BTreeSet<String> {
    messages.iter().map(|m| m["type"].as_str().unwrap_or_default().to_owned()).collect()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn every_stream_message_is_in_the_document() {
    let served = Served::start(&[]);
    let doc = served.get("/api-docs/openapi.json").await.json();
    let mut fleet = connect(&served, "/api/v1/stream?rate=30").await;

    // A controller whose program moves, sets a variable, prints a message and ends in an alarm.
    let created = served
        .send_json(Method::POST, "/api/v1/controllers", &json!({"name": "wire", "preset": "table-ac", "speed": 100}))
        .await;
    assert_eq!(created.status, 201);
    let id = created.json()["id"].as_str().unwrap().to_owned();
    let text = "O0001\nG90 G01 X10. A5. F3000\n#500=1.5\n#3006=1(CHECK)\nM98 P2\nG01 X20.\n#3000=1(STOP)\nM30\n";
    // O0002 drills with R below Z: a notice (FX1004), on its own line 3.
    let called = "O0002\nG90 G0 Z10.\nG81 X10. Y0 R-5. Z-1. F600.\nG80\nM99\n";
    for (n, text) in [(1, text), (2, called)] {
        let stored = served
            .request(
                Method::PUT,
                &format!("/api/v1/controllers/{id}/programs/{n}"),
                &[("content-type", "text/plain")],
                text,
            )
            .await;
        assert_eq!(stored.status, 201, "{}", String::from_utf8_lossy(&stored.body));
    }
    let mut controller = connect(&served, &format!("/api/v1/controllers/{id}/stream?rate=100")).await;
    // The stream is subscribed once its snapshot came: a workpiece change before that is in the
    // snapshot, not a message of its own (the test's rare flake).
    let mut seen = messages(&mut controller, Duration::from_secs(10), |m| m["type"] == "snapshot").await;
    assert!(seen.iter().any(|m| m["type"] == "snapshot"), "{seen:?}");
    let block = json!({"boxes": [{"min": [-50.0, -50.0, -30.0], "max": [50.0, 50.0, 0.0]}]});
    let put = served.send_json(Method::PUT, &format!("/api/v1/controllers/{id}/workpiece"), &block).await;
    assert_eq!(put.status, 200, "{}", String::from_utf8_lossy(&put.body));
    let started =
        served.send_json(Method::POST, &format!("/api/v1/controllers/{id}/cycle-start"), &json!({"program": 1})).await;
    assert_eq!(started.status, 200, "{}", String::from_utf8_lossy(&started.body));
    // #3006 holds the program (`hold`, not `idle`: the run is not over): cycle start goes on
    // to the alarm.
    let held = |m: &Value| m["type"] == "state" && m["run_state"] == "hold";
    seen.extend(messages(&mut controller, Duration::from_secs(10), held).await);
    assert!(seen.iter().any(|m| m["type"] == "message"), "the #3006 message before the hold: {seen:?}");
    assert!(!seen.iter().any(|m| m["type"] == "state" && m["run_state"] == "idle"), "{seen:?}");
    let resumed = served.send_json(Method::POST, &format!("/api/v1/controllers/{id}/cycle-start"), &json!({})).await;
    assert_eq!(resumed.status, 200, "{}", String::from_utf8_lossy(&resumed.body));
    let rest = messages(&mut controller, Duration::from_secs(10), |m| m["event"] == "raised").await;
    assert!(!rest.iter().any(|m| m["type"] == "state" && m["run_state"] == "idle"), "{rest:?}");
    seen.extend(rest);
    for m in &seen {
        assert_valid(&doc, "ControllerMessage", m, &format!("the controller stream's {}", m["type"]));
    }
    let kinds = types(&seen);
    for kind in ["snapshot", "position", "state", "variables", "message", "alarm", "workpiece", "notice"] {
        assert!(kinds.contains(kind), "no {kind} message among {kinds:?}");
    }
    let notice = seen.iter().find(|m| m["type"] == "notice").unwrap();
    assert_eq!(
        (notice["code"].clone(), notice["line"].clone(), notice["program"].clone()),
        (json!("FX1004"), json!(3), json!(2))
    );
    let alarm = seen.iter().find(|m| m["event"] == "raised").unwrap();
    assert_eq!((alarm["raised"]["line"].clone(), alarm["raised"]["program"].clone()), (json!(7), json!(1)), "{alarm}");

    // The fleet stream: the whole fleet, then a delta with the controller.
    let fleet_seen = messages(&mut fleet, Duration::from_secs(5), |m| m["type"] == "fleet_delta").await;
    for m in &fleet_seen {
        assert_valid(&doc, "FleetMessage", m, &format!("the fleet stream's {}", m["type"]));
    }
    assert_eq!(types(&fleet_seen), BTreeSet::from(["fleet".to_owned(), "fleet_delta".to_owned()]));

    // A fleet run: its progress, the stored run, and the array a waiting request answers.
    let program = fleet_program("tilt.nc");
    let request = json!({"program": program, "presets": ["head-bc", "mill3"], "controllers": [id], "report": true});
    let queued = served.send_json(Method::POST, "/api/v1/fleet/runs?wait=false", &request).await;
    assert_eq!(queued.status, 202);
    assert_valid(&doc, "FleetRunInfo", &queued.json(), "the 202 answer");
    let run = queued.json()["id"].as_str().unwrap().to_owned();
    let mut progress = connect(&served, &format!("/api/v1/fleet/runs/{run}/stream")).await;
    let updates = messages(&mut progress, Duration::from_secs(60), |m| m["finished"] == true).await;
    assert!(updates.last().is_some_and(|m| m["finished"] == true), "the run finished: {updates:?}");
    for m in &updates {
        assert_valid(&doc, "Progress", m, "a progress message");
    }
    let stored = served.get(&format!("/api/v1/fleet/runs/{run}")).await;
    assert_valid(&doc, "FleetRun", &stored.json(), "the stored run");
    assert!(stored.json()["request"]["report"] == true && stored.json()["results"].is_array());
    let waited = served.send_json(Method::POST, "/api/v1/fleet/runs", &request).await;
    assert_eq!(waited.status, 200);
    let array = json!({"type": "array", "items": {"$ref": "#/components/schemas/FleetResult"}});
    let validator = jsonschema::options()
        .with_draft(jsonschema::Draft::Draft202012)
        .build(&json!({"allOf": [array], "components": doc["components"]}))
        .unwrap();
    assert!(validator.is_valid(&waited.json()), "the fleet array: {:?}", validator.iter_errors(&waited.json()).next());
    assert_eq!(waited.json().as_array().map(Vec::len), Some(3));
}

/// A block fivex runs by a rule of its own reaches the controller stream as a `notice` message
/// of the document's shape, with its code and line (the fixture `tcp_posture_nutating_edge.nc`
/// shows the run summary's).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_notice_reaches_the_stream_as_the_document_says() {
    let served = Served::start(&[]);
    let doc = served.get("/api-docs/openapi.json").await.json();
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let machine: Value =
        serde_json::from_str(&std::fs::read_to_string(root.join("machines/nutating-head-b45.json")).unwrap()).unwrap();
    let created = served
        .send_json(Method::POST, "/api/v1/controllers", &json!({"name": "notice", "machine": machine, "speed": 100}))
        .await;
    assert_eq!(created.status, 201, "{}", String::from_utf8_lossy(&created.body));
    let id = created.json()["id"].as_str().unwrap().to_owned();
    let text =
        "O0001\nG90 G00 X0 Y0 Z200. B180. C0\nG43.4 H1 P1\nG00 X0 Y0 Z150.\nG01 X20. B120. C60. F2000.\nG49\nM30\n";
    let stored = served
        .request(Method::PUT, &format!("/api/v1/controllers/{id}/programs/1"), &[("content-type", "text/plain")], text)
        .await;
    assert_eq!(stored.status, 201, "{}", String::from_utf8_lossy(&stored.body));
    let mut controller = connect(&served, &format!("/api/v1/controllers/{id}/stream?rate=10")).await;
    let started =
        served.send_json(Method::POST, &format!("/api/v1/controllers/{id}/cycle-start"), &json!({"program": 1})).await;
    assert_eq!(started.status, 200, "{}", String::from_utf8_lossy(&started.body));
    let seen = messages(&mut controller, Duration::from_secs(20), |m| m["type"] == "notice").await;
    let notice = seen.iter().find(|m| m["type"] == "notice").expect("a notice message");
    assert_valid(&doc, "ControllerMessage", notice, "the notice");
    assert_eq!((notice["code"].as_str(), notice["line"].as_u64()), (Some("FX1001"), Some(5)), "{notice}");
    // The same program in a fleet run: the summary's `notices`.
    let request = json!({"program": text, "library": ["nutating-head-b45"], "presets": ["head-bc"]});
    let answered = served.send_json(Method::POST, "/api/v1/fleet/runs", &request).await;
    assert_eq!(answered.status, 200, "{}", String::from_utf8_lossy(&answered.body));
    let results = answered.json();
    for result in results.as_array().unwrap() {
        assert_valid(&doc, "FleetResult", result, &format!("the fleet result on {}", result["machine"]));
    }
    let noticed: Vec<(&str, usize)> = results
        .as_array()
        .unwrap()
        .iter()
        .map(|r| (r["machine"].as_str().unwrap(), r["notices"].as_array().map_or(0, Vec::len)))
        .collect();
    assert_eq!(noticed, [("head-bc", 0), ("nutating-head-b45", 1)]);
}
