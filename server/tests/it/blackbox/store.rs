//! The store (docs/api.md, "The database", "Errors"): acknowledged writes succeed while the
//! controllers write too, a deleted controller's websocket is closed, a program's O number
//! matches its slot, and every error is the documented JSON.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::Duration;

use futures_util::StreamExt;
use hyper::{Method, StatusCode};
use serde_json::{json, Value};
use tokio_tungstenite::tungstenite::protocol::frame::coding::CloseCode;
use tokio_tungstenite::tungstenite::Message;

use super::served::{Reply, Served};

const C: &str = "/api/v1/controllers";

/// Creates a controller on `preset` and answers its id.
async fn create(served: &Served, name: &str, speed: f64) -> String {
    let reply = served.send_json(Method::POST, C, &json!({"name": name, "preset": "table-ac", "speed": speed})).await;
    assert_eq!(reply.status, StatusCode::CREATED, "{:?}", reply.body);
    reply.json()["id"].as_str().expect("an id").to_owned()
}

async fn put_program(served: &Served, id: &str, number: u32, text: &str) -> Reply {
    served
        .request(
            Method::PUT,
            &format!("{C}/{id}/programs/{number}"),
            &[("content-type", "text/plain")],
            text.to_owned(),
        )
        .await
}

/// A reply that must be the documented error: its status, a JSON content type and a JSON object
/// with an `error` message.
fn assert_json_error(reply: &Reply, status: StatusCode) -> String {
    assert_eq!(reply.status, status, "{:?}", String::from_utf8_lossy(&reply.body));
    assert!(reply.content_type().starts_with("application/json"), "{status}: {:?}", reply.content_type());
    let error =
        reply.json()["error"].as_str().unwrap_or_else(|| panic!("no error message: {:?}", reply.body)).to_owned();
    assert!(!error.is_empty());
    error
}

/// The program each loaded controller cycles: it writes retained variables and a tool offset
/// (records the service writes in the background) and ends at once at speed 1000.
const CYCLE: &str = "O0001\n#500=#500+1\n#501=#500*2\nG10 L11 P7 R[#500]\nG91 G01 X1. F6000\nX-1.\nM30\n";

/// Issue 18: uploads failed with 500 "database is locked" while controllers were writing.
/// 20 controllers cycle a program that writes variables and offsets (each cycle also ends in a
/// run record) while their clients write variables and tool offsets, 8 clients upload 40
/// programs each, and one client creates, renames, configures, clones and deletes controllers
/// and posts fleet runs: every acknowledged write succeeds, and what was written last is what
/// is read.
#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn writes_succeed_while_controllers_write() {
    writes_succeed(Arc::new(Served::start(&[]))).await;
}

/// [`writes_succeed_while_controllers_write`] on the service `served` (on SQLite or PostgreSQL).
pub async fn writes_succeed(served: Arc<Served>) {
    let mut ids = Vec::new();
    for i in 0..20 {
        let id = create(&served, &format!("load {i}"), 1000.0).await;
        assert_eq!(put_program(&served, &id, 1, CYCLE).await.status, StatusCode::CREATED);
        ids.push(id);
    }
    let ids = Arc::new(ids);
    let stop = Arc::new(AtomicBool::new(false));
    let (cycles, writes) = (Arc::new(AtomicUsize::new(0)), Arc::new(AtomicUsize::new(0)));
    let failures = Arc::new(std::sync::Mutex::new(Vec::<String>::new()));

    // The controllers' clients: cycle start, and writes of a variable and a tool offset.
    let mut cyclers = Vec::new();
    for id in ids.iter() {
        let id = id.clone();
        let (served, stop, cycles, writes, failures) =
            (served.clone(), stop.clone(), cycles.clone(), writes.clone(), failures.clone());
        cyclers.push(tokio::spawn(async move {
            let mut round = 0u32;
            while !stop.load(Ordering::Relaxed) || round < 5 {
                round += 1;
                let started =
                    served.send_json(Method::POST, &format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
                match started.status {
                    StatusCode::OK => {
                        cycles.fetch_add(1, Ordering::Relaxed);
                    }
                    // Still running the last cycle: the panel refuses, nothing was written.
                    StatusCode::CONFLICT => {}
                    other => failures.lock().unwrap().push(format!("cycle start {other}: {:?}", started.body)),
                }
                for (path, body) in [
                    (format!("{C}/{id}/variables/502"), json!({"value": round})),
                    (format!("{C}/{id}/tool-offsets/9"), json!({"length": round})),
                ] {
                    let reply = served.send_json(Method::PUT, &path, &body).await;
                    if reply.status == StatusCode::OK {
                        writes.fetch_add(1, Ordering::Relaxed);
                    } else {
                        failures.lock().unwrap().push(format!("PUT {path} {}: {:?}", reply.status, reply.body));
                    }
                }
            }
            round
        }));
    }

    // Every other write path: controllers, parameters, work offsets, clones, fleet runs.
    let kept = create(&served, "kept", 1.0).await;
    let keeper = {
        let (served, stop, failures, kept) = (served.clone(), stop.clone(), failures.clone(), kept.clone());
        tokio::spawn(async move {
            let mut round = 0u32;
            while !stop.load(Ordering::Relaxed) || round < 3 {
                round += 1;
                let id = create(&served, &format!("passing {round}"), 1.0).await;
                let clone = served.send_json(Method::POST, &format!("{C}/{id}/clone"), &json!({"name": "copy"})).await;
                let clone_id = clone.json()["id"].as_str().unwrap_or("none").to_owned();
                let steps = [
                    (Method::PATCH, format!("{C}/{id}"), json!({"name": format!("renamed {round}")}), StatusCode::OK),
                    (Method::PUT, format!("{C}/{kept}/parameters/8130"), json!({"value": round}), StatusCode::OK),
                    (
                        Method::PUT,
                        format!("{C}/{kept}/work-offsets/G54"),
                        json!({"axes": {"X": round}}),
                        StatusCode::OK,
                    ),
                    (Method::DELETE, format!("{C}/{clone_id}"), Value::Null, StatusCode::NO_CONTENT),
                    (Method::DELETE, format!("{C}/{id}"), Value::Null, StatusCode::NO_CONTENT),
                    (
                        Method::POST,
                        "/api/v1/fleet/runs".into(),
                        json!({"program": "G91 G01 X1. F1000\nM30\n", "presets": ["mill3"]}),
                        StatusCode::OK,
                    ),
                ];
                if clone.status != StatusCode::CREATED {
                    failures.lock().unwrap().push(format!("clone {}: {:?}", clone.status, clone.body));
                }
                for (method, path, body, want) in steps {
                    let reply = if body.is_null() {
                        served.request(method.clone(), &path, &[], "").await
                    } else {
                        served.send_json(method.clone(), &path, &body).await
                    };
                    if reply.status != want {
                        failures.lock().unwrap().push(format!("{method} {path} {}: {:?}", reply.status, reply.body));
                    }
                }
            }
            round
        })
    };

    // 8 uploaders, 40 programs each, over the controllers' slots 2–9.
    let mut uploaders = Vec::new();
    for u in 0..8u32 {
        let (served, ids, failures) = (served.clone(), ids.clone(), failures.clone());
        uploaders.push(tokio::spawn(async move {
            let mut stored = 0;
            for k in 0..40u32 {
                let id = &ids[((u * 40 + k) % 20) as usize];
                let number = 2 + u;
                let text = format!("O{number:04}\n#100={k}\nG91 G01 X1. F1000\nX-1.\nM99\n");
                let reply = put_program(&served, id, number, &text).await;
                if reply.status.is_success() {
                    stored += 1;
                } else {
                    failures.lock().unwrap().push(format!("upload {}: {:?}", reply.status, reply.body));
                }
            }
            stored
        }));
    }
    let mut stored = 0;
    for uploader in uploaders {
        stored += uploader.await.unwrap();
    }
    stop.store(true, Ordering::Relaxed);
    let mut rounds = Vec::new();
    for cycler in cyclers {
        rounds.push(cycler.await.unwrap());
    }
    let kept_rounds = keeper.await.unwrap();

    let failures = failures.lock().unwrap().clone();
    assert!(failures.is_empty(), "{} failed writes, e.g. {:?}", failures.len(), &failures[..3.min(failures.len())]);
    assert_eq!(stored, 320);
    assert!(cycles.load(Ordering::Relaxed) >= 20, "only {} cycles ran", cycles.load(Ordering::Relaxed));
    assert_eq!(writes.load(Ordering::Relaxed), 2 * rounds.iter().sum::<u32>() as usize);
    let log = served.log();
    let locked: Vec<&str> = log.lines().filter(|l| l.contains("locked") || l.contains("cannot store")).collect();
    assert!(locked.is_empty(), "{locked:#?}");

    // What was acknowledged last is what is stored: each uploader's last text, each client's
    // last variable and offset, and the run records the workers wrote.
    for u in 0..8u32 {
        let k = 39;
        let id = &ids[((u * 40 + k) % 20) as usize];
        let number = 2 + u;
        let text = served.get(&format!("{C}/{id}/programs/{number}")).await;
        assert_eq!(
            String::from_utf8_lossy(&text.body),
            format!("O{number:04}\n#100={k}\nG91 G01 X1. F1000\nX-1.\nM99\n")
        );
    }
    for (id, round) in ids.iter().zip(&rounds) {
        let variable = served.get(&format!("{C}/{id}/variables/502")).await.json();
        assert_eq!(variable["value"], json!(*round as f64), "{id}");
        let tools = served.get(&format!("{C}/{id}/tool-offsets")).await.json();
        let nine = tools.as_array().unwrap().iter().find(|t| t["number"] == 9).cloned();
        assert_eq!(nine.map(|t| t["length"].clone()), Some(json!(*round as f64)), "{id}");
    }
    let parameters = served.get(&format!("{C}/{kept}/parameters")).await.json();
    assert_eq!(parameters["parameters"]["8130"], json!(kept_rounds), "{parameters}");
    let work = served.get(&format!("{C}/{kept}/work-offsets")).await.json();
    let g54 = work.as_array().unwrap().iter().find(|w| w["name"] == "G54").cloned().expect("G54 stored");
    assert_eq!(g54["axes"]["X"], json!(kept_rounds as f64));
    let controllers = served.get(C).await.json();
    assert_eq!(controllers.as_array().unwrap().len(), 21, "the passing controllers and their clones are gone");
    let fleet_runs = served.get("/api/v1/fleet/runs").await.json();
    assert_eq!(fleet_runs.as_array().unwrap().len(), kept_rounds as usize);
    let mut recorded = 0;
    for id in ids.iter() {
        recorded += served.get(&format!("{C}/{id}/runs")).await.json().as_array().unwrap().len();
    }
    assert!(recorded >= 20, "only {recorded} runs recorded");
}

/// Issue 18: a websocket on a deleted controller stayed open forever. Deleting the controller
/// closes it with code 4404 and a reason.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn deleting_a_controller_closes_its_websocket() {
    let served = Served::start(&[]);
    let id = create(&served, "doomed", 1.0).await;
    let url = format!("ws://{}{C}/{id}/stream", served.addr);
    let (mut ws, _) = tokio_tungstenite::connect_async(url).await.expect("websocket");
    let first = ws.next().await.expect("a message").expect("not an error");
    let snapshot: Value = serde_json::from_str(first.to_text().unwrap()).unwrap();
    assert_eq!(snapshot["type"], "snapshot");

    let deleted = served.request(Method::DELETE, &format!("{C}/{id}"), &[], "").await;
    assert_eq!(deleted.status, StatusCode::NO_CONTENT);
    // Everything up to the close frame (a state message may still be under way), within a
    // generous bound.
    let close = tokio::time::timeout(Duration::from_secs(20), async {
        while let Some(message) = ws.next().await {
            if let Message::Close(frame) = message.expect("no protocol error") {
                return frame;
            }
        }
        panic!("the stream ended without a close frame");
    })
    .await
    .expect("a close frame within 20 s of the delete")
    .expect("the close frame has a code");
    assert_eq!(close.code, CloseCode::from(4404));
    assert!(close.reason.contains("deleted"), "{:?}", close.reason);

    // A new stream on the deleted id is a JSON 404, not an upgrade.
    let again = served.get(&format!("{C}/{id}/stream")).await;
    assert_json_error(&again, StatusCode::NOT_FOUND);
}

/// Issue 18: a program stored under 102 whose text starts `O0555` was accepted, then
/// `M98 P102` alarmed. The O number (or the ISO `:` form) must match the slot.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_program_number_must_match_its_slot() {
    let served = Served::start(&[]);
    let id = create(&served, "numbers", 1.0).await;
    for text in ["O0555\nG91 G01 X1. F1000\nM99\n", "%\n(header)\n:0555\nM99\n", "  o555 (name)\nM99\n"] {
        let refused = put_program(&served, &id, 102, text).await;
        let error = assert_json_error(&refused, StatusCode::UNPROCESSABLE_ENTITY);
        assert!(error.contains("O0555") && error.contains("O0102"), "{error}");
        // Not even with force: the number is not a check diagnostic.
        let forced = served
            .request(
                Method::PUT,
                &format!("{C}/{id}/programs/102?force=true"),
                &[("content-type", "text/plain")],
                text.to_owned(),
            )
            .await;
        assert_json_error(&forced, StatusCode::UNPROCESSABLE_ENTITY);
    }
    let listed = served.get(&format!("{C}/{id}/programs")).await.json();
    assert_eq!(listed, json!([]), "nothing was stored");

    // The matching number in either form, and a text without one, are stored; the main program
    // then calls 102 by its slot and runs to its end.
    assert_eq!(put_program(&served, &id, 102, ":0102\n#500=102\nM99\n").await.status, StatusCode::CREATED);
    assert_eq!(put_program(&served, &id, 103, "#501=103\nM99\n").await.status, StatusCode::CREATED);
    assert_eq!(put_program(&served, &id, 1, "O0001\nM98 P102\nM98 P103\nM30\n").await.status, StatusCode::CREATED);
    let started = served.send_json(Method::POST, &format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
    assert_eq!(started.status, StatusCode::OK, "{:?}", started.body);
    let mut status = Value::Null;
    for _ in 0..500 {
        status = served.get(&format!("{C}/{id}")).await.json();
        if status["run_state"] != "running" {
            break;
        }
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    assert_eq!(status["run_state"], "idle", "{status}");
    assert_eq!(status["alarms"], json!([]));
    for (number, value) in [(500, 102.0), (501, 103.0)] {
        let read = served.get(&format!("{C}/{id}/variables/{number}")).await.json();
        assert_eq!(read["value"], json!(value));
    }
}

/// Issue 18: the 413 of an oversized body was `text/plain`. Every error the extractors produce
/// (body too large, bad JSON, wrong content type, a path or query of the wrong type, a plain
/// GET on a websocket route) is the documented JSON.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn every_error_is_the_documented_json() {
    let served = Served::start(&[]);
    let id = create(&served, "errors", 1.0).await;

    // One byte over the limit of 8 MiB + 64 KiB.
    let huge = "(".to_owned() + &"x".repeat(8 * 1024 * 1024 + 64 * 1024) + ")";
    let too_large = put_program(&served, &id, 1, &huge).await;
    assert_json_error(&too_large, StatusCode::PAYLOAD_TOO_LARGE);
    let huge_json = served
        .request(Method::POST, C, &[("content-type", "application/json")], format!("{{\"name\": \"{huge}\"}}"))
        .await;
    assert_json_error(&huge_json, StatusCode::PAYLOAD_TOO_LARGE);

    // Method, path, headers, body, the status.
    type Case = (Method, String, Vec<(&'static str, &'static str)>, &'static str, StatusCode);
    let cases: Vec<Case> = vec![
        // JSON syntax.
        (Method::POST, C.into(), vec![("content-type", "application/json")], "{\"name\": ", StatusCode::BAD_REQUEST),
        // Not JSON at all.
        (Method::POST, C.into(), vec![("content-type", "text/plain")], "{}", StatusCode::UNSUPPORTED_MEDIA_TYPE),
        // Well-formed JSON of the wrong shape.
        (
            Method::POST,
            C.into(),
            vec![("content-type", "application/json")],
            "{\"name\": 5}",
            StatusCode::UNPROCESSABLE_ENTITY,
        ),
        // The optional body of cycle start, malformed.
        (
            Method::POST,
            format!("{C}/{id}/cycle-start"),
            vec![("content-type", "application/json")],
            "{\"program\": ",
            StatusCode::BAD_REQUEST,
        ),
        // A path parameter of the wrong type.
        (Method::GET, format!("{C}/{id}/programs/nine"), vec![], "", StatusCode::BAD_REQUEST),
        // A query of the wrong type.
        (Method::GET, format!("{C}/{id}/alarms?limit=many"), vec![], "", StatusCode::BAD_REQUEST),
        // A websocket route without the upgrade.
        (Method::GET, format!("{C}/{id}/stream"), vec![], "", StatusCode::BAD_REQUEST),
        (Method::GET, "/api/v1/stream".into(), vec![], "", StatusCode::BAD_REQUEST),
        // Already JSON before: no route, wrong method.
        (Method::GET, "/api/v1/nope".into(), vec![], "", StatusCode::NOT_FOUND),
        (Method::DELETE, "/api/v1/presets".into(), vec![], "", StatusCode::METHOD_NOT_ALLOWED),
    ];
    for (method, path, headers, body, status) in cases {
        let reply = served.request(method.clone(), &path, &headers, body.to_owned()).await;
        let error = assert_json_error(&reply, status);
        eprintln!("{method} {path}: {status} {error}");
    }
}

/// What a running program writes is saved every second while it runs (docs/api.md, "What is
/// kept"): the offsets of its G10 as its retained variables, so a `kill -9` in the middle of the
/// program keeps them all. The offsets were saved only when the run state changed: after the
/// kill `#561` was back but tool 22 and G57 X were lost.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_running_programs_offsets_survive_a_kill_as_its_variables_do() {
    let mut served = Served::start(&[]);
    let id = create(&served, "kept", 1.0).await;
    let program = "O0001\nG10 L10 P22 R22.2\nG10 L2 P4 X4.4\n#561=6.6\nG04 X30.\nM30\n";
    assert!(put_program(&served, &id, 1, program).await.status.is_success());
    let started = served.send_json(Method::POST, &format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
    assert!(started.status.is_success(), "{:?}", started.body);
    // The program is in its dwell with everything written.
    let deadline = std::time::Instant::now() + Duration::from_secs(20);
    loop {
        let v = served.get(&format!("{C}/{id}/variables/561")).await.json();
        if v["value"] == json!(6.6) {
            break;
        }
        assert!(std::time::Instant::now() < deadline, "the program never wrote #561: {v}");
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    // More than a second of running, then no shutdown of any kind.
    tokio::time::sleep(Duration::from_millis(3000)).await;
    assert_eq!(served.get(&format!("{C}/{id}")).await.json()["run_state"], "running");
    served.kill();
    let dir = std::mem::replace(&mut served.dir, tempfile::tempdir().unwrap());
    let served = Served::start_in(dir, &[]);
    let v = served.get(&format!("{C}/{id}/variables/561")).await.json();
    assert_eq!(v["value"], json!(6.6), "{v}");
    let tools = served.get(&format!("{C}/{id}/tool-offsets")).await.json();
    let tool = tools.as_array().unwrap().iter().find(|t| t["number"] == 22).cloned();
    assert_eq!(tool.as_ref().map(|t| t["length"].clone()), Some(json!(22.2)), "tool 22: {tool:?}");
    let works = served.get(&format!("{C}/{id}/work-offsets")).await.json();
    let g57 = works.as_array().unwrap().iter().find(|w| w["name"] == "G57").cloned();
    assert_eq!(g57.map(|w| w["axes"]["X"].clone()), Some(json!(4.4)), "{works}");
}
