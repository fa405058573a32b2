//! The MTConnect agent of `fivex serve --mtconnect`: every document it answers validates against
//! the standard's 2.5 schemas (lxml), says what the REST API says (positions, alarms with the
//! dialect's code), and `/sample` numbers every change once, in order, without gaps — polled
//! and streamed — while controllers run.

use std::time::{Duration, Instant};

use bytes::Bytes;
use http_body_util::{BodyExt, Empty};
use hyper::{Method, Request, StatusCode};
use hyper_util::client::legacy::Client;
use hyper_util::rt::TokioExecutor;
use serde_json::{json, Value};

use super::{announced, run_python};
use crate::blackbox::served::Served;

/// Validates every file named after the schema directory against the MTConnect schema its root
/// element names; prints `valid NAME` per file, or fails with lxml's errors.
const VALIDATE: &str = r#"
import sys, lxml.etree as et
d = sys.argv[1]
schemas = {k: et.XMLSchema(et.parse(f"{d}/MTConnect{k}_2.5_1.0.xsd")) for k in ["Devices", "Streams", "Assets", "Error"]}
bad = []
for f in sys.argv[2:]:
    doc = et.parse(f)
    kind = et.QName(doc.getroot()).localname.replace("MTConnect", "")
    schema = schemas[kind]
    if schema.validate(doc):
        print("valid", f.rsplit("/", 1)[-1])
    else:
        bad.append(f + ": " + "; ".join(f"line {e.line}: {e.message}" for e in list(schema.error_log)[:5]))
if bad:
    sys.exit("\n".join(bad))
"#;

struct Agent {
    served: Served,
    /// `http://HOST:PORT`
    base: String,
    client: Client<hyper_util::client::legacy::connect::HttpConnector, Empty<Bytes>>,
}

struct Reply {
    status: StatusCode,
    content_type: String,
    body: String,
}

impl Agent {
    fn start(args: &[&str]) -> Agent {
        let mut all = vec!["--mtconnect", "127.0.0.1:0"];
        all.extend_from_slice(args);
        let served = Served::start(&all);
        let base = format!("http://{}", announced(|| served.log(), "MTConnect agent at http://"));
        Agent { served, base, client: Client::builder(TokioExecutor::new()).build_http() }
    }

    async fn get_with(&self, path: &str, accept: Option<&str>) -> Reply {
        let mut request = Request::builder().method(Method::GET).uri(format!("{}{path}", self.base));
        if let Some(accept) = accept {
            request = request.header("accept", accept);
        }
        let response = self.client.request(request.body(Empty::new()).unwrap()).await.expect("agent answers");
        let status = response.status();
        let content_type =
            response.headers().get("content-type").and_then(|v| v.to_str().ok()).unwrap_or("").to_string();
        let body = response.into_body().collect().await.expect("body").to_bytes();
        Reply { status, content_type, body: String::from_utf8(body.to_vec()).expect("UTF-8") }
    }

    async fn get(&self, path: &str) -> Reply {
        self.get_with(path, None).await
    }

    async fn json(&self, path: &str) -> Value {
        let reply = self.get_with(path, Some("application/json")).await;
        assert_eq!(reply.status, 200, "{path}: {}", reply.body);
        assert_eq!(reply.content_type, "application/json");
        serde_json::from_str(&reply.body).expect("JSON")
    }

    async fn create(&self, name: &str, preset: &str, dialect: &str) -> String {
        let reply = self
            .served
            .send_json(
                Method::POST,
                "/api/v1/controllers",
                &json!({"name": name, "preset": preset, "dialect": dialect}),
            )
            .await;
        assert_eq!(reply.status, 201, "{}", String::from_utf8_lossy(&reply.body));
        reply.json()["id"].as_str().unwrap().to_string()
    }

    async fn mdi(&self, id: &str, text: &str) {
        let reply =
            self.served.send_json(Method::POST, &format!("/api/v1/controllers/{id}/mdi"), &json!({"text": text})).await;
        assert_eq!(reply.status, 200, "{}", String::from_utf8_lossy(&reply.body));
    }

    /// Three busy machines (table-ac, head-bc, mill3) named `prefix`0…2, each running the MDI
    /// `text`: the agent's `nextSequence` before they started, and their ids.
    async fn busy(&self, prefix: &str, text: &str) -> (u64, Vec<String>) {
        let mut ids = Vec::new();
        for (i, preset) in ["table-ac", "head-bc", "mill3"].iter().enumerate() {
            ids.push(self.create(&format!("{prefix}{i}"), preset, "fanuc").await);
        }
        let start = attribute(&self.get("/current").await.body, "<Header", "nextSequence").unwrap().parse().unwrap();
        for id in &ids {
            self.mdi(id, text).await;
        }
        (start, ids)
    }

    /// A multipart stream of `query` (`/sample?…`): the response and its boundary.
    async fn stream(&self, query: &str) -> (hyper::Response<hyper::body::Incoming>, String) {
        let url = format!("{}{query}", self.base);
        let response = self.client.request(Request::get(url).body(Empty::new()).unwrap()).await.unwrap();
        assert_eq!(response.status(), 200);
        let content_type = response.headers()["content-type"].to_str().unwrap().to_string();
        let boundary = content_type.split("boundary=").nth(1).expect("a multipart stream").to_string();
        (response, boundary)
    }

    async fn status(&self, id: &str) -> Value {
        self.served.get(&format!("/api/v1/controllers/{id}")).await.json()
    }

    /// Polls the REST status of `id` until `done` holds (30 s at most).
    async fn status_until(&self, id: &str, done: impl Fn(&Value) -> bool) -> Value {
        let deadline = Instant::now() + Duration::from_secs(30);
        loop {
            let status = self.status(id).await;
            if done(&status) {
                return status;
            }
            assert!(Instant::now() < deadline, "never reached: {status}");
            tokio::time::sleep(Duration::from_millis(50)).await;
        }
    }
}

/// `name="VALUE"` of the first element in `xml` after `after` (a plain scan: the documents are
/// validated by lxml separately).
fn attribute(xml: &str, after: &str, name: &str) -> Option<String> {
    let rest = &xml[xml.find(after)?..];
    let start = rest.find(&format!(" {name}=\""))? + name.len() + 3;
    Some(rest[start..start + rest[start..].find('"')?].to_string())
}

/// The number an observation of the data item whose id ends in `suffix` carries.
fn value_of(xml: &str, suffix: &str) -> Option<f64> {
    let at = xml.find(&format!("{suffix}\""))?;
    let text = &xml[at + xml[at..].find('>')? + 1..];
    text[..text.find('<')?].parse().ok()
}

fn sequences(xml: &str) -> Vec<u64> {
    xml.match_indices(" sequence=\"")
        .map(|(at, m)| {
            let rest = &xml[at + m.len()..];
            rest[..rest.find('"').unwrap()].parse().unwrap()
        })
        .collect()
}

/// A program waiting at a stop of its own is held (`hold`), and the agent's Execution says why
/// (MTConnect 2.5 `ExecutionValueType`): PROGRAM_STOPPED at M00, OPTIONAL_STOP at M01 (the
/// switch on), READY at the end.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_program_stop_is_program_stopped_or_optional_stop() {
    let agent = Agent::start(&[]);
    let id = agent.create("stops", "mill3", "fanuc").await;
    let path = format!("/api/v1/controllers/{id}/switches");
    let reply = agent.served.send_json(Method::PUT, &path, &json!({"optional_stop": true})).await;
    assert_eq!(reply.status, 200, "{}", String::from_utf8_lossy(&reply.body));
    agent.mdi(&id, "G91 G00 X1.\nM00\nX1.\nM01\nX1.").await;
    for (x, state, execution) in
        [(1.0, "hold", "PROGRAM_STOPPED"), (2.0, "hold", "OPTIONAL_STOP"), (3.0, "idle", "READY")]
    {
        agent.status_until(&id, |s| s["run_state"] == state && s["position"]["machine"]["X"] == x).await;
        let deadline = Instant::now() + Duration::from_secs(10);
        loop {
            let current = agent.get(&format!("/{id}/current")).await.body;
            if current.contains(&format!(">{execution}</Execution>")) {
                break;
            }
            assert!(Instant::now() < deadline, "X{x}: never {execution}: {current}");
            tokio::time::sleep(Duration::from_millis(50)).await;
        }
        if state == "hold" {
            let path = format!("/api/v1/controllers/{id}/cycle-start");
            let reply = agent.served.send_json(Method::POST, &path, &json!({})).await;
            assert_eq!(reply.status, 200, "{}", String::from_utf8_lossy(&reply.body));
        }
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn every_document_validates_and_says_what_the_api_says() {
    let agent = Agent::start(&[]);
    let table = agent.create("cell 1", "table-ac", "fanuc").await;
    let head = agent.create("head", "head-bc", "syntec").await;
    agent.mdi(&table, "G91 G01 X12.5 Y-3. A10. F3000 M03 S1200").await;
    agent.status_until(&table, |s| s["run_state"] == "idle" && s["position"]["machine"]["X"] == 12.5).await;
    agent.mdi(&head, "#3000=1(BOOM)").await;
    let status = agent.status_until(&head, |s| s["run_state"] == "alarm").await;
    let code = status["alarms"][0]["code"].as_str().unwrap().to_string();

    // The spindle override scales the speed the spindle reports (S1200 at 80 %).
    let path = format!("/api/v1/controllers/{table}/overrides");
    let reply = agent.served.send_json(Method::PUT, &path, &json!({"spindle": 80})).await;
    assert_eq!(reply.status, 200, "{}", String::from_utf8_lossy(&reply.body));
    assert_eq!(reply.json()["spindle"], 960.0);

    // What the API says, the agent says within a round of the observer.
    let machine = agent.status(&table).await["position"]["machine"].clone();
    let deadline = Instant::now() + Duration::from_secs(10);
    let current = loop {
        let current = agent.get(&format!("/{table}/current")).await.body;
        if value_of(&current, "_Xact") == machine["X"].as_f64() && value_of(&current, "_Sovr") == Some(80.0) {
            break current;
        }
        assert!(Instant::now() < deadline, "X never {}: {current}", machine["X"]);
        tokio::time::sleep(Duration::from_millis(50)).await;
    };
    for (axis, value) in machine.as_object().unwrap() {
        let shown = value_of(&current, &format!("_{axis}act")).unwrap_or_else(|| panic!("no {axis}: {current}"));
        assert!((shown - value.as_f64().unwrap()).abs() < 1e-6, "{axis}: {shown} vs {value}");
    }
    assert!(current.contains(">960</RotaryVelocity>"), "{current}");
    assert!(current.contains(">80</RotaryVelocityOverride>"), "{current}");
    assert!(current.contains(">READY</Execution>"), "{current}");
    assert!(current.contains(">MANUAL_DATA_INPUT</ControllerMode>"), "{current}");
    let alarmed = agent.get(&format!("/{head}/current")).await.body;
    assert_eq!(attribute(&alarmed, "<Fault ", "nativeCode").as_deref(), Some(code.as_str()), "{alarmed}");
    assert!(alarmed.contains(">STOPPED</Execution>"), "{alarmed}");

    // Every kind of document, each request form, and the errors.
    let asset = format!("{table}.T1");
    let requests: Vec<(String, u16)> = vec![
        ("/probe".into(), 200),
        ("/".into(), 200),
        ("/cell%201/probe".into(), 200),
        (format!("/{head}/probe"), 200),
        ("/current".into(), 200),
        ("/sample?count=1000".into(), 200),
        (format!("/{head}/sample?from=1&count=5"), 200),
        ("/assets?count=5".into(), 200),
        (format!("/{table}/assets?count=2"), 200),
        (format!("/asset/{asset}"), 200),
        ("/asset/nothing".into(), 404),
        ("/sample?from=99999999".into(), 400),
        ("/sample?count=0".into(), 400),
        ("/sample?count=ten".into(), 400),
        ("/sample?interval=18446744073709551615".into(), 400),
        ("/sample?interval=10&heartbeat=99999999999".into(), 400),
        ("/sample?path=//Axes".into(), 400),
        ("/nobody/current".into(), 404),
        ("/a/b/c".into(), 404),
    ];
    let dir = tempfile::tempdir().unwrap();
    let mut files = Vec::new();
    for (i, (path, status)) in requests.iter().enumerate() {
        let reply = agent.get(path).await;
        assert_eq!(reply.status.as_u16(), *status, "{path}: {}", reply.body);
        assert!(reply.content_type.starts_with("text/xml"), "{path}: {}", reply.content_type);
        if *status != 200 {
            assert!(reply.body.contains("<MTConnectError"), "{path}: {}", reply.body);
        }
        let file = dir.path().join(format!("{i}.xml"));
        std::fs::write(&file, &reply.body).unwrap();
        files.push(file.to_string_lossy().into_owned());
    }
    let schemas = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/mtconnect");
    let mut args = vec![schemas];
    args.extend(files.iter().map(String::as_str));
    let out = run_python(VALIDATE, &args);
    assert_eq!(out.lines().filter(|l| l.starts_with("valid ")).count(), requests.len(), "{out}");

    // The probe: both devices, each axis with its kinematics, the spindle.
    let probe = agent.get("/probe").await.body;
    assert!(probe.contains(&format!("uuid=\"{table}\"")) && probe.contains(&format!("uuid=\"{head}\"")));
    assert!(probe.contains("type=\"REVOLUTE\"") && probe.contains("type=\"PRISMATIC\""), "{probe}");
    assert!(probe.contains("<Value>SPINDLE</Value>"), "{probe}");
    let assets = agent.get(&format!("/asset/{asset}")).await.body;
    assert!(assets.contains(">100</FunctionalLength>") && assets.contains(">10</CuttingDiameterMax>"), "{assets}");

    // The JSON form, by Accept or by ?format=json: the same observations.
    let by_accept = agent.json(&format!("/{head}/current")).await;
    let by_query: Value = serde_json::from_str(&agent.get(&format!("/{head}/current?format=json")).await.body).unwrap();
    for doc in [&by_accept, &by_query] {
        let streams = &doc["MTConnectStreams"];
        assert_eq!(streams["jsonVersion"], 2);
        let components = streams["Streams"]["DeviceStream"][0]["ComponentStream"].as_array().unwrap();
        let controller = components.iter().find(|c| c["component"] == "Controller").expect("controller stream");
        assert_eq!(controller["Condition"]["Fault"][0]["nativeCode"], code.as_str(), "{controller}");
    }
    let error = agent.get_with("/sample?from=99999999", Some("application/json")).await;
    assert_eq!(error.status, 400);
    let error: Value = serde_json::from_str(&error.body).unwrap();
    assert_eq!(error["MTConnectError"]["Errors"]["Error"][0]["errorCode"], "OUT_OF_RANGE");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn sample_numbers_every_change_once_in_order_polled_and_streamed() {
    let agent = Agent::start(&["--shopfloor-period-ms", "20"]);
    let (start, ids) = agent.busy("m", "G91 G01 X40. Y20. F1200").await;

    // A streaming client (interval 0: each part as soon as there is news) beside a polling one.
    let (response, boundary) =
        agent.stream(&format!("/sample?from={start}&interval=0&count=1000&heartbeat=1000")).await;
    let streamed = tokio::spawn(async move {
        let mut body = response.into_body();
        let mut text = String::new();
        let deadline = Instant::now() + Duration::from_secs(3);
        while Instant::now() < deadline {
            match tokio::time::timeout(Duration::from_secs(2), body.frame()).await {
                Ok(Some(Ok(frame))) => {
                    if let Ok(data) = frame.into_data() {
                        text.push_str(&String::from_utf8_lossy(&data));
                    }
                }
                _ => break,
            }
        }
        text
    });

    let mut from = start;
    let mut polled = Vec::new();
    let deadline = Instant::now() + Duration::from_secs(3);
    while Instant::now() < deadline {
        let reply = agent.get(&format!("/sample?from={from}&count=37")).await;
        assert_eq!(reply.status, 200, "{}", reply.body);
        let next: u64 = attribute(&reply.body, "<Header", "nextSequence").unwrap().parse().unwrap();
        let mut seen = sequences(&reply.body);
        seen.sort_unstable();
        assert!(seen.len() <= 37);
        assert_eq!(seen, (from..next).collect::<Vec<_>>(), "a gap or a repeat in [{from}, {next})");
        polled.extend(seen);
        from = next;
        tokio::time::sleep(Duration::from_millis(30)).await;
    }
    assert!(polled.len() > 100, "the running machines made only {} observations", polled.len());

    let text = streamed.await.unwrap();
    let parts: Vec<&str> = text.split(&format!("--{boundary}")).filter(|p| p.contains("<MTConnectStreams")).collect();
    assert!(parts.len() > 5, "{} parts", parts.len());
    let mut expected = start;
    for part in parts {
        let next: u64 = attribute(part, "<Header", "nextSequence").unwrap().parse().unwrap();
        let mut seen = sequences(part);
        seen.sort_unstable();
        assert_eq!(seen, (expected..next).collect::<Vec<_>>(), "streamed part [{expected}, {next})");
        expected = next;
    }
    assert!(expected > start + 100, "the stream saw only {} observations", expected - start);

    // One device's sample: only its observations, still in order.
    let one = agent.get(&format!("/{}/sample?from={start}&count=200", ids[1])).await.body;
    // (A document groups observations by component: their sequences are distinct, not in
    // document order.)
    let mut seen = sequences(&one);
    seen.sort_unstable();
    assert!(seen.len() > 10 && seen.windows(2).all(|w| w[0] < w[1]), "{seen:?}");
    assert!(!one.contains(&format!("uuid=\"{}\"", ids[0])));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_client_left_behind_by_the_buffer_is_told_out_of_range() {
    let agent = Agent::start(&["--mtconnect-buffer", "64", "--shopfloor-period-ms", "20"]);
    let id = agent.create("m", "table-ac", "fanuc").await;
    agent.mdi(&id, "G91 G01 X40. Y20. A30. F1200").await;
    let deadline = Instant::now() + Duration::from_secs(20);
    loop {
        let header = agent.get("/current").await.body;
        let first: u64 = attribute(&header, "<Header", "firstSequence").unwrap().parse().unwrap();
        if first > 1 {
            assert_eq!(attribute(&header, "<Header", "bufferSize").as_deref(), Some("64"));
            break;
        }
        assert!(Instant::now() < deadline, "the buffer never wrapped: {header}");
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    let reply = agent.get("/sample?from=1").await;
    assert_eq!(reply.status, 400);
    assert_eq!(attribute(&reply.body, "<Error", "errorCode").as_deref(), Some("OUT_OF_RANGE"), "{}", reply.body);
}

/// Validates the XML documents `bodies` against the standard's schemas (lxml).
fn validate(bodies: &[String]) {
    let dir = tempfile::tempdir().unwrap();
    let mut files = Vec::new();
    for (i, body) in bodies.iter().enumerate() {
        let file = dir.path().join(format!("{i}.xml"));
        std::fs::write(&file, body).unwrap();
        files.push(file.to_string_lossy().into_owned());
    }
    let schemas = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/mtconnect");
    let mut args = vec![schemas];
    args.extend(files.iter().map(String::as_str));
    let out = run_python(VALIDATE, &args);
    assert_eq!(out.lines().filter(|l| l.starts_with("valid ")).count(), bodies.len(), "{out}");
}

/// Polls `path` until its body holds `text` (10 s at most).
async fn until_shown(agent: &Agent, path: &str, text: &str) -> String {
    let deadline = Instant::now() + Duration::from_secs(10);
    loop {
        let body = agent.get(path).await.body;
        if body.contains(text) {
            return body;
        }
        assert!(Instant::now() < deadline, "{path} never showed {text}: {body}");
        tokio::time::sleep(Duration::from_millis(30)).await;
    }
}

/// A device's model is rebuilt when its controller is renamed or its name is freed (a name
/// collision resolved): a `/sample` across it held two `DeviceStream`s of one uuid with the
/// same `componentId`s (an `xs:ID`), which the schema refuses. Now one stream per device,
/// named as the device is now, and every such document validates.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_sample_across_a_rebuilt_device_model_has_one_stream_per_device_and_validates() {
    let agent = Agent::start(&["--shopfloor-period-ms", "20"]);
    let renamed = agent.create("before", "mill3", "fanuc").await;
    let first = agent.create("twin", "mill3", "fanuc").await;
    let second = agent.create("twin", "table-ac", "fanuc").await;
    until_shown(&agent, "/probe", &format!("name=\"twin-{}\"", &second[..8])).await;
    until_shown(&agent, "/probe", "name=\"before\"").await;
    agent.mdi(&renamed, "G91 G01 X1. F600").await;

    let path = format!("/api/v1/controllers/{renamed}");
    let reply = agent.served.send_json(Method::PATCH, &path, &json!({"name": "after"})).await;
    assert_eq!(reply.status, 200, "{}", String::from_utf8_lossy(&reply.body));
    // The earlier "twin" goes: the later one takes the plain name (its model made again).
    let reply = agent.served.send_json(Method::DELETE, &format!("/api/v1/controllers/{first}"), &Value::Null).await;
    assert!(reply.status.is_success(), "{}", String::from_utf8_lossy(&reply.body));
    until_shown(&agent, "/probe", "name=\"after\"").await;
    until_shown(&agent, "/probe", &format!("name=\"twin\" uuid=\"{second}\"")).await;
    agent.status_until(&renamed, |s| s["run_state"] == "idle" && s["position"]["machine"]["X"] == 1.0).await;
    agent.mdi(&renamed, "G91 G01 X1. F600").await;
    agent.status_until(&renamed, |s| s["run_state"] == "idle" && s["position"]["machine"]["X"] == 2.0).await;
    tokio::time::sleep(Duration::from_millis(200)).await;

    let mut bodies = Vec::new();
    for path in [
        "/sample?from=1&count=100000".to_string(),
        format!("/{renamed}/sample?from=1&count=100000"),
        "/after/sample?from=1&count=100000".to_string(),
        format!("/{second}/sample?from=1&count=100000"),
        "/current".to_string(),
    ] {
        let reply = agent.get(&path).await;
        assert_eq!(reply.status, 200, "{path}: {}", reply.body);
        for uuid in [&renamed, &second] {
            let streams = reply.body.matches(&format!("uuid=\"{uuid}\"")).count();
            assert!(streams <= 1, "{path}: {streams} DeviceStreams of {uuid}: {}", reply.body);
        }
        bodies.push(reply.body);
    }
    // Named as the devices are now; the observations before the rename are in it.
    assert!(bodies[1].contains(&format!("name=\"after\" uuid=\"{renamed}\"")), "{}", bodies[1]);
    let avail = format!("dataItemId=\"d{renamed}_avail\"");
    assert_eq!(bodies[1].matches(&avail).count(), 2, "both models' observations, in one stream: {}", bodies[1]);
    assert!(bodies[3].contains(&format!("name=\"twin\" uuid=\"{second}\"")), "{}", bodies[3]);

    // A stream's part spanning the rebuilds too.
    let url = format!("{}/sample?from=1&interval=0&count=100000", agent.base);
    let response = agent.client.request(Request::get(url).body(Empty::new()).unwrap()).await.unwrap();
    let mut body = response.into_body();
    let mut text = String::new();
    while !text.contains("</MTConnectStreams>") {
        let frame = tokio::time::timeout(Duration::from_secs(5), body.frame()).await.unwrap().unwrap().unwrap();
        if let Ok(data) = frame.into_data() {
            text.push_str(&String::from_utf8_lossy(&data));
        }
    }
    let part = &text[text.find("<?xml").expect("an XML part")..text.find("</MTConnectStreams>").unwrap() + 19];
    assert_eq!(part.matches(&format!("uuid=\"{renamed}\"")).count(), 1, "{part}");
    bodies.push(part.to_string());
    validate(&bodies);
}

/// `sample?interval=` sent at most `count` observations per interval however many were
/// waiting, so a stream fell behind busy machines (and ended OUT_OF_RANGE once the buffer no
/// longer held its next one). A part that could not hold all there was is followed at once by
/// the next: the stream keeps up, gaplessly.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_stream_sends_what_count_left_over_at_once_and_keeps_up() {
    let agent = Agent::start(&["--shopfloor-period-ms", "20"]);
    let (start, _) = agent.busy("busy", "G91 G01 X200. Y100. F1200").await;
    tokio::time::sleep(Duration::from_millis(300)).await;

    let (response, boundary) = agent.stream(&format!("/sample?from={start}&interval=1000&count=20")).await;
    let streamed = tokio::spawn(async move {
        let mut body = response.into_body();
        let mut text = String::new();
        let deadline = Instant::now() + Duration::from_millis(3500);
        while let Ok(Some(Ok(frame))) = tokio::time::timeout_at(deadline.into(), body.frame()).await {
            if let Ok(data) = frame.into_data() {
                text.push_str(&String::from_utf8_lossy(&data));
            }
        }
        text
    });
    tokio::time::sleep(Duration::from_millis(1500)).await;
    let agent_next: u64 =
        attribute(&agent.get("/current").await.body, "<Header", "nextSequence").unwrap().parse().unwrap();
    let text = streamed.await.unwrap();

    let parts: Vec<&str> = text.split(&format!("--{boundary}")).filter(|p| p.contains("</MTConnectStreams>")).collect();
    let mut expected = start;
    for part in &parts {
        let next: u64 = attribute(part, "<Header", "nextSequence").unwrap().parse().unwrap();
        let mut seen = sequences(part);
        seen.sort_unstable();
        assert!(seen.len() <= 20, "at most count per part");
        assert_eq!(seen, (expected..next).collect::<Vec<_>>(), "streamed part [{expected}, {next})");
        expected = next;
    }
    assert!(agent_next > start + 200, "the machines made only {} observations by 1.5 s", agent_next - start);
    assert!(
        expected >= agent_next,
        "the stream fell behind: at 3.5 s it had reached {expected}, the agent was at {agent_next} by 1.5 s ({} parts)",
        parts.len()
    );
}

/// A path segment that is not UTF-8 once percent-decoded got axum's `text/plain` 400: it is an
/// MTConnectError document (`INVALID_URI`, as for any path the agent does not answer), in the
/// form asked for, valid against the schema.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_path_that_is_not_utf8_is_an_mtconnect_error() {
    let agent = Agent::start(&[]);
    let mut bodies = Vec::new();
    for path in ["/%FF/probe", "/%C3%28/current", "/%FF/sample?count=5", "/%FF/assets", "/asset/%FF", "/%FF"] {
        let reply = agent.get(path).await;
        assert_eq!(reply.status, 404, "{path}: {}", reply.body);
        assert!(reply.content_type.starts_with("text/xml"), "{path}: {}", reply.content_type);
        assert_eq!(attribute(&reply.body, "<Error", "errorCode").as_deref(), Some("INVALID_URI"), "{}", reply.body);
        bodies.push(reply.body);
    }
    validate(&bodies);
    let reply = agent.get_with("/asset/%FF", Some("application/json")).await;
    assert_eq!(reply.status, 404);
    let error: Value = serde_json::from_str(&reply.body).expect("JSON");
    assert_eq!(error["MTConnectError"]["Errors"]["Error"][0]["errorCode"], "INVALID_URI");
}
