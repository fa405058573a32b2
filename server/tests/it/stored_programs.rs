//! Stored programs as the controller runs them: each O number is one program, the selected one
//! runs (never another in its place), and MDI and AUTO call the same stored programs.

use crate::common;

use std::time::Duration;

use axum::http::{Method, StatusCode};
use common::{spawn_app, Reply, TestApp};
use serde_json::{json, Value};

const C: &str = "/api/v1/controllers";

async fn create(app: &TestApp) -> String {
    let reply = app.post(C, &json!({"name": "m", "preset": "mill3", "speed": 20})).await;
    assert_eq!(reply.status, StatusCode::CREATED, "{}", reply.text());
    reply.json()["id"].as_str().unwrap().to_string()
}

async fn store(app: &TestApp, id: &str, number: u32, text: &str) -> Reply {
    app.raw(Method::PUT, &format!("{C}/{id}/programs/{number}"), "text/plain", text.to_string()).await
}

/// The status once the controller is `want` after the command (`idle`: the run ended).
async fn settled(app: &TestApp, id: &str, want: &str) -> Value {
    for _ in 0..500 {
        tokio::time::sleep(Duration::from_millis(20)).await;
        let status = app.get(&format!("{C}/{id}")).await.json();
        if status["run_state"] == want {
            return status;
        }
    }
    panic!("{id} never became {want}: {}", app.get(&format!("{C}/{id}")).await.text());
}

async fn variable(app: &TestApp, id: &str, n: u32) -> Value {
    app.get(&format!("{C}/{id}/variables/{n}")).await.json()["value"].clone()
}

/// The audit's F1: an empty selected text made the next stored program (O0002) the main one.
#[tokio::test]
async fn a_selected_program_without_blocks_runs_nothing_not_the_next_stored_program() {
    let app = spawn_app().await;
    let id = create(&app).await;
    assert_eq!(store(&app, &id, 2, "O0002\nG90 G0 Y7.\n#100=2\nM30\n").await.status, StatusCode::CREATED);
    for empty in ["", "%\n%\n", "(only a comment)\n", "\n\n"] {
        assert!(store(&app, &id, 1, empty).await.status.is_success(), "{empty:?}");
        let started = app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
        assert_eq!(started.status, StatusCode::OK, "{}", started.text());
        // A comment only is a program of no block: FANUC memory operation reads its end of
        // record at once (PS5010, `docs/dialects.md`); the other texts hold no program at all.
        let comment = empty.contains('(');
        let done = settled(&app, &id, if comment { "alarm" } else { "idle" }).await;
        if comment {
            assert_eq!(done["alarms"][0]["code"], "PS5010", "{done}");
            app.post(&format!("{C}/{id}/reset"), &json!({})).await;
            settled(&app, &id, "idle").await;
        }
        assert_eq!(done["position"]["machine"]["Y"], 0.0, "{empty:?}: {done}");
        assert_eq!(variable(&app, &id, 100).await, Value::Null, "{empty:?}");
        // The preview and the estimate are of the same (empty) run.
        let path = app.get(&format!("{C}/{id}/programs/1/path")).await.json();
        let xyz = path["xyz"].as_array().unwrap();
        assert!(xyz.chunks(3).all(|p| p[1] == 0.0), "{empty:?}: {path}");
    }
    let runs = app.get(&format!("{C}/{id}/runs")).await.json();
    let results: Vec<_> =
        runs.as_array().unwrap().iter().map(|r| (r["program"].clone(), r["result"].clone())).collect();
    assert_eq!(results.len(), 4, "{runs}");
    assert!(results.iter().all(|(p, _)| *p == 1), "{runs}");
    assert_eq!(results.iter().filter(|(_, r)| *r == "completed").count(), 3, "{runs}");
}

/// The audit's F4: `M98 P18` ran an `O0018` inside slot 17's text instead of program 18.
#[tokio::test]
async fn a_stored_text_is_one_program_so_m98_runs_the_program_stored_under_its_number() {
    let app = spawn_app().await;
    let id = create(&app).await;
    for (slot, text, line, number) in [
        (17, "O0017\nM99\nO0018\nG1 Z-1. F100.\n#100=18\nM99\n", 3, json!(18)),
        // A second program with the slot's own number, or after an anonymous first one.
        (17, "O0017\nM99\n%\nO0017\nM99\n", 4, json!(17)),
        (5, "G0 X1.\nM99\n:0005\nM99\n", 3, json!(5)),
    ] {
        for force in ["", "?force=true"] {
            let uri = format!("{C}/{id}/programs/{slot}{force}");
            let refused = app.raw(Method::PUT, &uri, "text/plain", text.to_string()).await;
            assert_eq!(refused.status, StatusCode::UNPROCESSABLE_ENTITY, "{text:?}: {}", refused.text());
            let body = refused.json();
            assert!(body["error"].as_str().unwrap().contains("second program"), "{body}");
            assert_eq!(body["details"], json!({"slot": slot, "line": line, "text_number": number}), "{body}");
        }
    }
    assert_eq!(app.get(&format!("{C}/{id}/programs/17")).await.status, StatusCode::NOT_FOUND);
    store(&app, &id, 1, "O0001\nG90 G0 X1.\nM98 P17\nM98 P18\nM30\n").await;
    store(&app, &id, 17, "O0017\n#101=17\nM99\n").await;
    store(&app, &id, 18, "O0018\n#100=180\nM99\n").await;
    app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
    let done = settled(&app, &id, "idle").await;
    assert_eq!((variable(&app, &id, 100).await, variable(&app, &id, 101).await), (json!(180.0), json!(17.0)));
    assert_eq!(done["position"]["machine"]["Z"], 0.0, "{done}");
}

/// The audit's F7: MDI `M98 P1` was PS0078 with program 1 stored; on the control an MDI
/// program calls the programs in memory.
#[tokio::test]
async fn mdi_calls_the_stored_programs() {
    let app = spawn_app().await;
    let id = create(&app).await;
    store(&app, &id, 1, "O0001\n#100=11\nG91 G0 Y1.\nM99\n").await;
    store(&app, &id, 2, "#101=#1+1\nM99\n").await;
    let reply = app.post(&format!("{C}/{id}/mdi"), &json!({"text": "M98 P1\nG65 P2 A4."})).await;
    assert_eq!(reply.status, StatusCode::OK, "{}", reply.text());
    let done = settled(&app, &id, "idle").await;
    assert_eq!(done["alarms"], json!([]), "{done}");
    assert_eq!(done["position"]["machine"]["Y"], 1.0, "{done}");
    assert_eq!((variable(&app, &id, 100).await, variable(&app, &id, 101).await), (json!(11.0), json!(5.0)));
    // An empty MDI text runs nothing, not program 1.
    app.post(&format!("{C}/{id}/mdi"), &json!({"text": "(nothing)"})).await;
    assert_eq!(settled(&app, &id, "idle").await["position"]["machine"]["Y"], 1.0);
    // A program not stored is still the dialect's alarm.
    app.post(&format!("{C}/{id}/mdi"), &json!({"text": "M98 P3"})).await;
    let status = settled(&app, &id, "alarm").await;
    assert_eq!(status["alarms"][0]["code"], "PS0078", "{status}");
}

/// The audit's F8 and F10: the list's `size` is bytes like the store's answer; a body needs
/// `text/plain` declared, in UTF-8.
#[tokio::test]
async fn program_sizes_are_bytes_and_a_body_is_declared_utf_8_text() {
    let app = spawn_app().await;
    let id = create(&app).await;
    let text = "(日本語 コメント)\nG0 X1 (ü)\nM30\n";
    let stored = store(&app, &id, 7, text).await.json();
    // 7 three-byte characters and one two-byte one: 25 characters, 40 bytes.
    assert_eq!((text.chars().count(), stored["size"].clone()), (25, json!(40)));
    assert_eq!(app.get(&format!("{C}/{id}/programs")).await.json(), json!([{"number": 7, "size": 40}]));
    let uri = format!("{C}/{id}/programs/30");
    let untyped = axum::http::Request::builder().method(Method::PUT).uri(&uri).body("G0X1".into()).unwrap();
    let refused = app.send(untyped).await;
    assert_eq!(refused.status, StatusCode::UNSUPPORTED_MEDIA_TYPE, "{}", refused.text());
    assert!(refused.json()["error"].as_str().unwrap().contains("text/plain"));
    for media in ["text/plain; charset=utf-16", "text/plain;charset=\"ISO-8859-1\"", "text/csv"] {
        let refused = app.raw(Method::PUT, &uri, media, "G0X1").await;
        assert_eq!(refused.status, StatusCode::UNSUPPORTED_MEDIA_TYPE, "{media}: {}", refused.text());
    }
    for media in ["text/plain", "Text/Plain; charset=UTF-8", "text/plain; format=flowed; charset=\"utf-8\""] {
        assert!(app.raw(Method::PUT, &uri, media, "G0X1").await.status.is_success(), "{media}");
    }
    // No body and no type: an empty program.
    let empty = axum::http::Request::builder().method(Method::PUT).uri(&uri).body(axum::body::Body::empty()).unwrap();
    assert_eq!(app.send(empty).await.status, StatusCode::OK);
    assert_eq!(app.get(&uri).await.text(), "");
}

/// The audit's F3: an alarm in a called program was given a line of the hidden text the
/// service composes (line 8 for line 3 of O0002), under the selected program's number.
#[tokio::test]
async fn an_alarm_in_a_called_program_gives_its_line_in_that_program_and_names_it() {
    let app = spawn_app().await;
    let id = create(&app).await;
    store(&app, &id, 1, "O0001\nG90 G0 X1.\nM98 P2\nM30\n").await;
    // Program 2 without its own O line, so the service gives it one in the composed text.
    store(&app, &id, 2, "(sub)\nG0 Y1.\n#3000=1(BOOM)\nM99\n").await;
    store(&app, &id, 3, "O0003\nM99\n").await;
    app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
    let status = settled(&app, &id, "alarm").await;
    let raised = json!({"code": "MC3001", "message": "BOOM", "line": 3, "n": null, "program": 2});
    assert_eq!(status["alarms"], json!([raised]), "{status}");
    assert_eq!(
        (status["program"].clone(), status["line"].clone(), status["line_program"].clone()),
        (json!(1), json!(3), json!(2))
    );
    let history = async {
        for _ in 0..250 {
            let alarms = app.get(&format!("{C}/{id}/alarms")).await.json();
            if !alarms["history"].as_array().unwrap().is_empty() {
                return alarms;
            }
            tokio::time::sleep(Duration::from_millis(20)).await;
        }
        panic!("no history");
    };
    let alarms = history.await;
    assert_eq!(alarms["active"], json!([raised]));
    let past = &alarms["history"][0];
    assert_eq!((past["line"].clone(), past["program"].clone()), (json!(3), json!(2)), "{alarms}");
    // The estimate's alarm is located the same way.
    app.post(&format!("{C}/{id}/reset"), &json!({})).await;
    settled(&app, &id, "idle").await;
    let uri = format!("{C}/{id}/programs/1/estimate");
    let mut estimate = app.get(&uri).await.json();
    for _ in 0..250 {
        if estimate["state"] != "pending" {
            break;
        }
        tokio::time::sleep(Duration::from_millis(20)).await;
        estimate = app.get(&uri).await.json();
    }
    assert_eq!(estimate["alarm"], raised, "{estimate}");
    // In MDI the MDI blocks are no stored program's; a called one's are.
    app.post(&format!("{C}/{id}/mdi"), &json!({"text": "G0 X2.\n#3000=2(MDI)"})).await;
    let status = settled(&app, &id, "alarm").await;
    assert_eq!((status["alarms"][0]["line"].clone(), status["alarms"][0]["program"].clone()), (json!(2), Value::Null));
    app.post(&format!("{C}/{id}/reset"), &json!({})).await;
    settled(&app, &id, "idle").await;
    app.post(&format!("{C}/{id}/mdi"), &json!({"text": "M98 P2"})).await;
    let status = settled(&app, &id, "alarm").await;
    assert_eq!(status["alarms"], json!([raised]), "{status}");
}

/// Audit of views F4: the fleet stream (`GET /api/v1/stream`) gives an alarm in a called
/// program as the status does, naming that program (it gave `program: null`), and the line
/// there in that program's own numbering (it gave line 8 of the composed text). Its entry names
/// the program its `line` is in, `line_program`, as the status does (it had none: line 3 of
/// which program?).
#[tokio::test]
async fn the_fleet_stream_names_the_program_an_alarm_happened_in() {
    use futures_util::StreamExt;
    let app = spawn_app().await;
    let id = create(&app).await;
    store(&app, &id, 1, "O0001\nG90 G0 X1.\nM98 P2\nM30\n").await;
    store(&app, &id, 2, "(sub)\nG0 Y1.\n#3000=1(BOOM)\nM99\n").await;
    app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
    let status = settled(&app, &id, "alarm").await;
    let raised = json!({"code": "MC3001", "message": "BOOM", "line": 3, "n": null, "program": 2});
    assert_eq!(status["alarms"], json!([raised]), "{status}");
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
    let server = tokio::spawn(fivex_server::serve::serve(listener, app.state.clone(), async {
        let _ = stopped.await;
    }));
    let (mut ws, _) = tokio_tungstenite::connect_async(format!("ws://{addr}/api/v1/stream?rate=30")).await.unwrap();
    let first = ws.next().await.unwrap().unwrap();
    let fleet: Value = serde_json::from_str(first.to_text().unwrap()).unwrap();
    assert_eq!(fleet["type"], "fleet", "{fleet}");
    let entry = &fleet["controllers"][0];
    assert_eq!(entry["id"], json!(id), "{fleet}");
    assert_eq!(entry["alarm"], raised, "{entry}");
    let shown = |v: &Value| [v["program"].clone(), v["line"].clone(), v["line_program"].clone()];
    assert_eq!(shown(entry), shown(&status), "{entry}");
    assert_eq!(shown(entry), [json!(1), json!(3), json!(2)], "{entry}");
    drop(ws);
    let _ = stop.send(());
    server.await.unwrap().unwrap();
}

/// The path's points give their lines in the program each is in: a called program's blocks
/// were lines of the hidden composed text (line 6 for line 2 of O0002).
#[tokio::test]
async fn the_path_gives_each_point_its_line_in_the_program_it_is_in() {
    let app = spawn_app().await;
    let id = create(&app).await;
    store(&app, &id, 1, "O0001\nG90 G0 X1.\nM98 P2\nG0 X3.\nM30\n").await;
    store(&app, &id, 2, "(sub)\nG0 Y2.\nM99\n").await;
    let path = app.get(&format!("{C}/{id}/programs/1/path")).await.json();
    // The start, X1 (O0001 line 2), Y2 (O0002 line 2), X3 (O0001 line 4).
    assert_eq!(path["lines"], json!([0, 2, 2, 4]), "{path}");
    assert_eq!(path["line_programs"], json!([1, 1, 2, 1]), "{path}");
    let xyz: Vec<f64> = path["xyz"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    assert_eq!(xyz.chunks(3).map(|p| (p[0], p[1])).collect::<Vec<_>>(), [(0., 0.), (1., 0.), (1., 2.), (3., 2.)]);
}

/// Programs 1 and 2 are refused a new text and a removal (409), and 2 keeps its text.
async fn refused(app: &TestApp, id: &str, when: &str) {
    for n in [1, 2] {
        let put = store(app, id, n, "G0 X9.\nM30\n").await;
        assert_eq!(put.status, StatusCode::CONFLICT, "{when}: PUT {n}: {}", put.text());
        assert!(put.json()["error"].as_str().unwrap().contains("in use by the run"), "{}", put.text());
        let delete = app.request(Method::DELETE, &format!("{C}/{id}/programs/{n}")).await;
        assert_eq!(delete.status, StatusCode::CONFLICT, "{when}: DELETE {n}: {}", delete.text());
    }
    assert_eq!(app.get(&format!("{C}/{id}/programs/2")).await.text(), "G91 G01 X50. F10\nM99\n", "{when}");
}

/// The audit's F9: the program a run under way started, and the one it called and is in, are
/// neither replaced nor removed (409, the text kept) while the run runs or holds; the others
/// are; once the run is over both can change again.
#[tokio::test]
async fn the_programs_a_run_reads_do_not_change_under_it() {
    let app = spawn_app().await;
    let id = create(&app).await;
    assert_eq!(store(&app, &id, 1, "M98 P2\nM30\n").await.status, StatusCode::CREATED);
    assert_eq!(store(&app, &id, 2, "G91 G01 X50. F10\nM99\n").await.status, StatusCode::CREATED);
    assert_eq!(store(&app, &id, 3, "G0 X1.\nM30\n").await.status, StatusCode::CREATED);
    let started = app.post(&format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
    assert_eq!(started.status, StatusCode::OK, "{}", started.text());
    let status = settled(&app, &id, "running").await;
    assert_eq!((status["program"].clone(), status["line_program"].clone()), (json!(1), json!(2)), "{status}");
    refused(&app, &id, "running").await;
    // Another program changes (background editing), and a new one is stored.
    assert_eq!(store(&app, &id, 3, "G0 X2.\nM30\n").await.status, StatusCode::OK);
    assert_eq!(store(&app, &id, 4, "M30\n").await.status, StatusCode::CREATED);
    assert_eq!(app.request(Method::DELETE, &format!("{C}/{id}/programs/4")).await.status, StatusCode::NO_CONTENT);
    assert_eq!(app.post(&format!("{C}/{id}/feed-hold"), &json!({})).await.status, StatusCode::OK);
    settled(&app, &id, "hold").await;
    refused(&app, &id, "held").await;
    assert_eq!(app.post(&format!("{C}/{id}/reset"), &json!({})).await.status, StatusCode::OK);
    settled(&app, &id, "idle").await;
    assert_eq!(store(&app, &id, 1, "G0 X9.\nM30\n").await.status, StatusCode::OK);
    assert_eq!(app.request(Method::DELETE, &format!("{C}/{id}/programs/2")).await.status, StatusCode::NO_CONTENT);
}
