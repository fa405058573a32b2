//! The OPC UA server: the real `fivex serve --opcua` driven over the network by Python's asyncua
//! (`opcua_client.py`, an independent implementation of the protocol), beside the REST API.
//! What a client sees is compared with what the REST API says of the same controllers.

use std::time::{Duration, Instant};

use hyper::Method;
use serde_json::{json, Value};

use super::{announced, run_python};
use crate::blackbox::served::{Reply, Served};

const CLIENT: &str = include_str!("opcua_client.py");
const MACHINE_TOOL: &str = "http://opcfoundation.org/UA/MachineTool/";
/// 500 mm at 1500 mm/min: 20 s of motion along +X.
const LONG_MOVE: &str = "O0001\nG90 G01 X500. F1500\nM30\n";
/// FANUC's macro alarm #3000: MC3001 BOOM.
const ALARM: &str = "O0002\n#3000=1(BOOM)\nM30\n";

/// A served process with the OPC UA server, its `opc.tcp://` URL and the token it requires.
struct Opcua {
    served: Served,
    url: String,
    token: Option<&'static str>,
}

impl Opcua {
    fn start(token: Option<&'static str>) -> Opcua {
        let mut args = vec!["--opcua", "127.0.0.1:0"];
        if let Some(token) = token {
            args.extend(["--token", token]);
        }
        Opcua::wrap(Served::start(&args), token)
    }

    fn wrap(served: Served, token: Option<&'static str>) -> Opcua {
        let url = announced(|| served.log(), "OPC UA server at ");
        assert!(url.starts_with("opc.tcp://127.0.0.1:"), "{url}");
        Opcua { served, url, token }
    }

    /// A REST request with the token, if any; JSON body when `body` is not null.
    async fn api(&self, method: Method, path: &str, body: Value) -> Reply {
        let bearer = self.token.map(|t| format!("Bearer {t}"));
        let mut headers = vec![("content-type", "application/json")];
        if let Some(bearer) = &bearer {
            headers.push(("authorization", bearer.as_str()));
        }
        let body = if body.is_null() { String::new() } else { body.to_string() };
        self.served.request(method, &format!("/api/v1{path}"), &headers, body).await
    }

    async fn create(&self, name: &str, preset: &str) -> String {
        let reply = self.api(Method::POST, "/controllers", json!({"name": name, "preset": preset})).await;
        assert_eq!(reply.status, 201, "{}", String::from_utf8_lossy(&reply.body));
        reply.json()["id"].as_str().expect("an id").to_string()
    }

    async fn store(&self, id: &str, number: u32, text: &str) {
        let bearer = self.token.map(|t| format!("Bearer {t}"));
        let mut headers = vec![("content-type", "text/plain")];
        if let Some(bearer) = &bearer {
            headers.push(("authorization", bearer.as_str()));
        }
        let path = format!("/api/v1/controllers/{id}/programs/{number}");
        let reply = self.served.request(Method::PUT, &path, &headers, text.to_string()).await;
        assert!(reply.status.is_success(), "{}: {}", reply.status, String::from_utf8_lossy(&reply.body));
    }

    async fn status(&self, id: &str) -> Value {
        let reply = self.api(Method::GET, &format!("/controllers/{id}"), Value::Null).await;
        assert_eq!(reply.status, 200);
        reply.json()
    }

    /// Waits (60 s at most) until the controller's run state is `state`; its status.
    async fn until(&self, id: &str, state: &str) -> Value {
        let deadline = Instant::now() + Duration::from_secs(60);
        loop {
            let status = self.status(id).await;
            if status["run_state"] == state {
                return status;
            }
            assert!(Instant::now() < deadline, "never {state}: {status}");
            tokio::time::sleep(Duration::from_millis(50)).await;
        }
    }

    async fn panel(&self, id: &str, action: &str, body: Value) {
        let reply = self.api(Method::POST, &format!("/controllers/{id}/{action}"), body).await;
        assert_eq!(reply.status, 200, "{action}: {}", String::from_utf8_lossy(&reply.body));
    }

    /// Runs the client: `security` (`none`, `basic256sha256`, `aes256sha256rsapss`), `user`
    /// (`-`: anonymous) and `password`, `command` and its arguments; its JSON lines.
    async fn client(&self, security: &str, user: &str, password: &str, command: &[&str]) -> Vec<Value> {
        let mut args: Vec<String> = vec![self.url.clone(), security.into(), user.into(), password.into()];
        args.extend(command.iter().map(|s| s.to_string()));
        let out = tokio::task::spawn_blocking(move || {
            let args: Vec<&str> = args.iter().map(String::as_str).collect();
            run_python(CLIENT, &args)
        })
        .await
        .expect("the client ran");
        out.lines()
            .filter(|l| l.starts_with('{'))
            .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{e}: {l}")))
            .collect()
    }

    /// Calls `Panel/{method}` of machine `name`: the status code's name.
    async fn call(&self, security: &str, user: &str, password: &str, name: &str, method: &str) -> String {
        let lines = self.client(security, user, password, &["call", name, method]).await;
        let line = &lines[0];
        line["status"].as_str().or(line["refused"].as_str().map(|_| "refused")).unwrap_or_default().to_string()
    }
}

/// Each controller is a `MachineToolType` under Objects/Machines with what the REST API says
/// of it: identity, channel, program state and the axes' positions (equal to 1e-9 once idle);
/// machines come and go with the controllers; the certificate and the machines survive a
/// restart.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn controllers_are_machine_tools_with_the_rest_positions() {
    let opcua = Opcua::start(None);
    let mill = opcua.create("mill one", "mill3").await;
    let five = opcua.create("five axis", "table-ac").await;
    opcua.panel(&mill, "mdi", json!({"text": "G90 G01 X12.345 Y-6.5 Z-3.25 F5000"})).await;
    opcua.panel(&five, "mdi", json!({"text": "G90 G00 X10. A30. C45."})).await;
    let mut rest = serde_json::Map::new();
    for (name, id) in [("mill one", &mill), ("five axis", &five)] {
        let status = opcua.until(id, "idle").await;
        rest.insert(name.to_string(), status["position"]["machine"].clone());
    }
    assert_eq!(rest["mill one"]["X"], 12.345, "the move happened: {rest:?}");

    for (name, expected) in &rest {
        let lines = opcua.client("none", "-", "-", &["positions", name, &expected.to_string()]).await;
        let axes = lines[0]["axes"].as_object().expect("axes").clone();
        let expected = expected.as_object().unwrap();
        assert_eq!(axes.keys().collect::<Vec<_>>().len(), expected.len(), "{name}: {axes:?} vs {expected:?}");
        for (axis, value) in expected {
            let shown = axes[axis].as_f64().unwrap_or(f64::NAN);
            assert!((shown - value.as_f64().unwrap()).abs() <= 1e-9, "{name} {axis}: OPC UA {shown}, REST {value}");
        }
    }

    let machines = opcua.client("none", "-", "-", &["browse", "2"]).await;
    assert_eq!(machines.len(), 2, "{machines:?}");
    for (name, id, preset) in [("mill one", &mill, "mill3"), ("five axis", &five, "table-ac")] {
        let m = machines.iter().find(|m| m["machine"] == name).unwrap_or_else(|| panic!("{name} in {machines:?}"));
        assert_eq!(m["type"], "MachineToolType", "{m}");
        assert_eq!(m["type_namespace"], MACHINE_TOOL, "{m}");
        assert!(m["node"].as_str().unwrap().ends_with(&format!(";s={id}")), "{m}");
        assert_eq!(m["manufacturer"], "fivex");
        assert_eq!(m["model"], preset);
        assert_eq!(m["serial"], id.as_str());
        // MDI: MachineOperationMode Automatic (1), ChannelMode MdaMdi (1); idle: ChannelState
        // Reset (2); no AUTO program yet: Initializing.
        assert_eq!(
            (&m["operation_mode"], &m["channel_mode"], &m["channel_state"]),
            (&json!(1), &json!(1), &json!(2)),
            "{m}"
        );
        assert_eq!(m["feed_override"], 100.0);
        assert_eq!(m["feed_override_range"], json!([0.0, 200.0]));
        assert_eq!(m["is_rotating"], false);
        assert_eq!(m["spindle_override"], 100.0);
        assert_eq!(m["spindle_override_range"], json!([50.0, 120.0]));
        assert_eq!((&m["program"], &m["program_state"]), (&json!(""), &json!("Initializing")), "{m}");
        assert_eq!(m["x_unit"], "mm");
    }

    let reply = opcua.api(Method::DELETE, &format!("/controllers/{five}"), Value::Null).await;
    assert_eq!(reply.status, 204);
    opcua.create("third", "head-bc").await;
    let names = opcua.client("none", "-", "-", &["names", r#"["mill one", "third"]"#]).await;
    assert_eq!(names[0]["names"], json!(["mill one", "third"]));

    // The certificate is kept beside the database and used again after a restart.
    let certificate = opcua.served.dir.path().join("fivex.db-opcua-pki/own/cert.der");
    let before = std::fs::read(&certificate).expect("the certificate beside the database");
    let dir = opcua.served.stop();
    let opcua = Opcua::wrap(Served::start_in(dir, &["--opcua", "127.0.0.1:0"]), None);
    assert_eq!(std::fs::read(&certificate).expect("still there"), before, "the same certificate");
    let names = opcua.client("none", "-", "-", &["names", r#"["mill one", "third"]"#]).await;
    assert_eq!(names[0]["names"], json!(["mill one", "third"]));
}

/// A subscription to a position follows a running program round by round, and an alarm is an
/// event of the machine with the dialect's code.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_running_program_is_followed_and_its_alarm_is_an_event() {
    let opcua = Opcua::start(None);
    let id = opcua.create("cell", "mill3").await;
    opcua.store(&id, 1, LONG_MOVE).await;
    opcua.store(&id, 2, ALARM).await;
    let base = opcua.served.url("");
    let lines = opcua.client("none", "-", "-", &["watch", "cell", &base, &id, "3"]).await;

    let data = |name: &str| -> Vec<Value> {
        lines.iter().filter(|l| l["kind"] == "data" && l["name"] == name).map(|l| l["value"].clone()).collect()
    };
    let x: Vec<f64> = data("x").iter().filter_map(Value::as_f64).collect();
    assert!(x.len() >= 5, "a change every round or so while X moves: {x:?}");
    assert!(x.windows(2).all(|w| w[1] > w[0]), "X moves +X only: {x:?}");
    assert!(x[x.len() - 1] > 10.0 && x[x.len() - 1] < 500.0, "{x:?}");
    let states = data("channel_state");
    let active = states.iter().position(|s| *s == 0).unwrap_or_else(|| panic!("Active while running: {states:?}"));
    assert!(states[active..].contains(&json!(2)), "Reset after the reset and the alarm: {states:?}");

    let events: Vec<&Value> = lines.iter().filter(|l| l["kind"] == "event").collect();
    assert_eq!(events.len(), 1, "one alarm, one event: {lines:?}");
    let event = events[0];
    assert_eq!(event["message"], "MC3001 BOOM");
    assert_eq!(event["identifier"], "MC3001");
    assert_eq!(event["severity"], 900);
    assert_eq!(event["source_name"], "cell");
    assert!(event["source_node"].as_str().unwrap().ends_with(&format!(";s={id}")), "{event}");

    let status = opcua.status(&id).await;
    assert_eq!(status["run_state"], "alarm");
    assert_eq!(status["alarms"][0]["code"], "MC3001");
}

/// The panel methods run the REST API's panel: a refusal is BadInvalidState, CycleStart starts
/// the selected program, FeedHold holds it and Reset ends it.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn panel_methods_run_the_panel() {
    let opcua = Opcua::start(None);
    let name = "cell 2";
    let id = opcua.create(name, "mill3").await;
    opcua.store(&id, 1, LONG_MOVE).await;

    assert_eq!(opcua.call("none", "-", "-", name, "CycleStart").await, "BadInvalidState", "nothing selected yet");
    assert_eq!(opcua.status(&id).await["run_state"], "idle");

    // Select program 1: run it once and reset.
    opcua.panel(&id, "cycle-start", json!({"program": 1})).await;
    opcua.until(&id, "running").await;
    opcua.panel(&id, "reset", Value::Null).await;
    opcua.until(&id, "idle").await;

    assert_eq!(opcua.call("none", "-", "-", name, "CycleStart").await, "Good");
    let status = opcua.until(&id, "running").await;
    assert_eq!(status["program"], 1, "{status}");
    assert_eq!(opcua.call("none", "-", "-", name, "FeedHold").await, "Good");
    opcua.until(&id, "hold").await;
    assert_eq!(opcua.call("none", "-", "-", name, "Reset").await, "Good");
    opcua.until(&id, "idle").await;
}

/// With `--token`, anonymous sessions read but may not call; a user-name session whose
/// password is the token may (over an encrypted channel too); a wrong password is refused.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn with_a_token_only_its_holders_call_the_methods() {
    const TOKEN: &str = "s3cret-T0ken";
    let opcua = Opcua::start(Some(TOKEN));
    let id = opcua.create("guarded", "mill3").await;
    opcua.store(&id, 1, LONG_MOVE).await;
    opcua.panel(&id, "cycle-start", json!({"program": 1})).await;
    opcua.until(&id, "running").await;
    opcua.panel(&id, "reset", Value::Null).await;
    opcua.until(&id, "idle").await;

    let machines = opcua.client("none", "-", "-", &["browse", "1"]).await;
    assert_eq!(machines[0]["machine"], "guarded", "anonymous sessions browse and read");
    assert_eq!(opcua.call("none", "-", "-", "guarded", "CycleStart").await, "BadUserAccessDenied");
    assert_eq!(opcua.status(&id).await["run_state"], "idle");

    let refused = opcua.client("none", "operator", "not the token", &["call", "guarded", "CycleStart"]).await;
    assert_eq!(refused, vec![json!({"refused": "BadUserAccessDenied"})]);
    assert_eq!(opcua.status(&id).await["run_state"], "idle");

    assert_eq!(opcua.call("basic256sha256", "operator", TOKEN, "guarded", "CycleStart").await, "Good");
    opcua.until(&id, "running").await;
    assert_eq!(opcua.call("aes256sha256rsapss", "anyone", TOKEN, "guarded", "Reset").await, "Good");
    opcua.until(&id, "idle").await;
    assert_eq!(opcua.call("none", "someone", TOKEN, "guarded", "CycleStart").await, "Good");
    opcua.until(&id, "running").await;
}

/// With PostgreSQL there is no database file to keep the certificate beside: it is made in a
/// temporary directory of this process, removed when the server stops.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn on_postgresql_the_certificate_is_temporary() {
    let pg = crate::blackbox::postgres::Postgres::start();
    let mut served = Served::start_on(&pg.url(), &["--opcua", "127.0.0.1:0"]);
    let opcua_line = announced(|| served.log(), "OPC UA server at ");
    assert!(opcua_line.starts_with("opc.tcp://127.0.0.1:"));
    let log = served.log();
    let pki = log
        .lines()
        .find(|l| l.contains("OPC UA server at "))
        .and_then(|l| l.split("pki=").nth(1))
        .and_then(|rest| rest.split_whitespace().next())
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| panic!("the pki directory in the log: {log}"));
    assert!(pki.starts_with(std::env::temp_dir()), "{}", pki.display());
    assert!(pki.join("own/cert.der").is_file() && pki.join("private/private.pem").is_file());
    let (status, _) = served.terminate(Duration::from_secs(60));
    assert!(status.success(), "{status}: {}", served.log());
    assert!(!pki.exists(), "{} removed at the stop", pki.display());
}

/// An alarm raised and reset within one period of the observer was never seen: the observer
/// sampled the controller's alarm list, empty again at both readings, so MTConnect had no Fault
/// and OPC UA no event although the alarm history had it. The observer now reads the
/// controller's alarm changes as they happened: the Fault then the Normal of the reset, and the
/// event.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_alarm_reset_within_one_observer_period_is_still_seen() {
    use http_body_util::{BodyExt, Empty};
    let served =
        Served::start(&["--opcua", "127.0.0.1:0", "--mtconnect", "127.0.0.1:0", "--shopfloor-period-ms", "2000"]);
    let agent = format!("http://{}", announced(|| served.log(), "MTConnect agent at http://"));
    let opcua = Opcua::wrap(served, None);
    let id = opcua.create("quick", "mill3").await;
    opcua.store(&id, 2, ALARM).await;
    let base = opcua.served.url("");
    // Resets as soon as the REST status says alarm: well within the 2 s period.
    let lines = opcua.client("none", "-", "-", &["quick", "quick", &base, &id, "2", "5"]).await;
    let events: Vec<&Value> = lines.iter().filter(|l| l["kind"] == "event").collect();
    assert_eq!(events.len(), 1, "the alarm's event: {lines:?}");
    assert_eq!(events[0]["message"], "MC3001 BOOM");
    assert_eq!(events[0]["identifier"], "MC3001");
    let history = opcua.api(Method::GET, &format!("/controllers/{id}/alarms"), Value::Null).await.json();
    assert_eq!(history["history"].as_array().map(Vec::len), Some(1), "{history}");

    let client = hyper_util::client::legacy::Client::builder(hyper_util::rt::TokioExecutor::new()).build_http();
    let url = format!("{agent}/{id}/sample?from=1&count=10000");
    let response = client.request(hyper::Request::get(url).body(Empty::<bytes::Bytes>::new()).unwrap()).await.unwrap();
    let body = response.into_body().collect().await.unwrap().to_bytes();
    let sample = String::from_utf8(body.to_vec()).unwrap();
    let fault = sample.find("<Fault ").unwrap_or_else(|| panic!("no Fault: {sample}"));
    assert!(sample[fault..].contains("nativeCode=\"MC3001\""), "{sample}");
    // What docs/shopfloor.md shows: the code in nativeCode, the text without it.
    assert!(sample[fault..].contains(">BOOM (O0002 line 2)</Fault>"), "{sample}");
    // The Normal of the reset comes after the Fault (by sequence).
    let sequence = |at: usize| -> u64 {
        let rest = &sample[at..];
        let start = rest.find(" sequence=\"").unwrap() + 11;
        rest[start..start + rest[start..].find('"').unwrap()].parse().unwrap()
    };
    let normals: Vec<u64> = sample.match_indices("<Normal ").map(|(at, _)| sequence(at)).collect();
    assert!(normals.iter().any(|&n| n > sequence(fault)), "a Normal after the Fault: {sample}");
    assert_eq!(opcua.status(&id).await["run_state"], "idle");
}

/// A panel method of a controller that is not hosted any more (deleted) is `BadMethodInvalid`,
/// as docs/shopfloor.md says: async-opcua's answer once the machine's nodes are gone, and the
/// server's own in the moment before the next round removes them (the docs said
/// `BadNodeIdUnknown`, which no call answered).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_panel_method_of_a_deleted_controller_is_bad_method_invalid() {
    let opcua = Opcua::start(None);
    let id = opcua.create("doomed", "mill3").await;
    let kept = opcua.create("kept", "mill3").await;
    let names = opcua.client("none", "-", "-", &["names", r#"["doomed", "kept"]"#]).await;
    assert_eq!(names[0]["names"], json!(["doomed", "kept"]));
    assert_eq!(opcua.client("none", "-", "-", &["call-id", &kept, "Reset"]).await[0]["status"], "Good");

    let reply = opcua.api(Method::DELETE, &format!("/controllers/{id}"), Value::Null).await;
    assert!(reply.status.is_success(), "{}", String::from_utf8_lossy(&reply.body));
    // At once (the nodes may still be there) and once the machine is gone.
    assert_eq!(opcua.client("none", "-", "-", &["call-id", &id, "Reset"]).await[0]["status"], "BadMethodInvalid");
    let names = opcua.client("none", "-", "-", &["names", r#"["kept"]"#]).await;
    assert_eq!(names[0]["names"], json!(["kept"]));
    for method in ["Reset", "CycleStart", "FeedHold"] {
        assert_eq!(opcua.client("none", "-", "-", &["call-id", &id, method]).await[0]["status"], "BadMethodInvalid");
    }
}
