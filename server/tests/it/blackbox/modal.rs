//! What the service shows is the executing block's state: `GET …/modal` during a tool centre
//! point move says G43.4 and G01 although the interpreter has read on to the G49 and G00 behind
//! it.

use hyper::Method;
use serde_json::json;

use super::served::Served;

const PROGRAM: &str = "O0001\n\
G90 G54 G00 X0 Y0 Z50.\n\
G43.4 H1\n\
G01 X40. B20. F1200.\n\
G01 X0 B0\n\
G49\n\
G00 Z60.\n\
M30\n";

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_modal_state_is_the_executing_blocks_through_a_tcp_program() {
    let served = Served::start(&[]);
    let created =
        served.send_json(Method::POST, "/api/v1/controllers", &json!({"name": "m", "preset": "head-bc"})).await;
    assert_eq!(created.status, 201, "{:?}", created.json());
    let id = created.json()["id"].as_str().unwrap().to_owned();
    let base = format!("/api/v1/controllers/{id}");
    let tool = served.send_json(Method::PUT, &format!("{base}/tool-offsets/1"), &json!({"length": 100.0})).await;
    assert!(tool.status.is_success(), "{:?}", tool.json());
    let stored =
        served.request(Method::PUT, &format!("{base}/programs/1"), &[("content-type", "text/plain")], PROGRAM).await;
    assert!(stored.status.is_success(), "{:?}", stored.json());
    let started = served.send_json(Method::POST, &format!("{base}/cycle-start"), &json!({"program": 1})).await;
    assert!(started.status.is_success(), "{:?}", started.json());

    let mut checked = 0;
    for _ in 0..2000 {
        let before = served.get(&base).await.json();
        let modal = served.get(&format!("{base}/modal")).await.json();
        let after = served.get(&base).await.json();
        if before["run_state"] != "running" {
            break;
        }
        // Only where the same TCP line was executing before and after the modal request.
        let line = before["line"].as_u64().unwrap();
        if [4, 5].contains(&line) && after["line"] == before["line"] {
            assert_eq!(modal["groups"]["8"], "G43.4", "line {line}: {modal}");
            assert_eq!(modal["groups"]["1"], "G01", "line {line}: {modal}");
            assert_eq!(modal["h"], 1, "line {line}: {modal}");
            checked += 1;
        }
        tokio::time::sleep(std::time::Duration::from_millis(20)).await;
    }
    assert!(checked >= 5, "only {checked} samples were taken during the TCP moves");
    let end = served.get(&format!("{base}/modal")).await.json();
    assert_eq!(end["groups"]["8"], "G49", "{end}");
}
