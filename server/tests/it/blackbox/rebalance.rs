//! Rebalancing on join (docs/cluster.md, "Rebalancing"): two `fivex serve --node` nodes host
//! twelve controllers on a real PostgreSQL and a real `nats-server -js`; a third joins and the
//! two hand their surplus over until each hosts four — but only idle controllers move: those
//! running a program stay where they run until they are reset. What was written before a
//! handover (through the API, and by a program that ended just before it) reads back after it
//! through every node, and requests during the moves answer either the controller's value or
//! 503 with Retry-After.

use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use hyper::{Method, StatusCode};
use serde_json::{json, Value};

use super::nats::NatsServer;
use super::nodes::{hosted, node};
use super::postgres::Postgres;
use super::served::Served;

const C: &str = "/api/v1/controllers";

/// Waits (generously: the machine is shared) until `check` answers `None`, else panics with
/// `what` and the last reason.
async fn eventually<F, Fut>(what: &str, deadline: Duration, mut check: F)
where
    F: FnMut() -> Fut,
    Fut: std::future::Future<Output = Option<String>>,
{
    let deadline = Instant::now() + deadline;
    loop {
        let Some(why_not) = check().await else { return };
        assert!(Instant::now() < deadline, "{what}: not in time: {why_not}");
        tokio::time::sleep(Duration::from_millis(200)).await;
    }
}

/// What a reader got while controllers moved: the status, whether it said Retry-After, the
/// value read (200), the value written.
#[derive(Clone)]
struct Answer {
    status: StatusCode,
    retry: bool,
    value: Value,
    expected: f64,
}

/// The controller's run state through `via`.
async fn run_state(via: &Served, id: &str) -> Value {
    let status = via.get(&format!("{C}/{id}")).await;
    assert_eq!(status.status, StatusCode::OK, "{id}: {:?}", status.body);
    status.json()["run_state"].clone()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_joining_node_gets_its_share_of_idle_controllers_and_running_ones_stay() {
    let (pg, nats) = (Postgres::start(), NatsServer::start());
    let one = node(&pg, &nats, "one");
    let two = node(&pg, &nats, "two");
    eventually("both nodes see two members, their placement views current", Duration::from_secs(30), || async {
        for n in [&one, &two] {
            let cluster = n.get("/readyz").await.json()["cluster"].clone();
            if cluster["members"] != json!(["one", "two"]) || cluster["placement_view"] != "current" {
                return Some(format!("{cluster}"));
            }
        }
        None
    })
    .await;

    // Six created through each node: six hosted by each, their fair share.
    let mut on = [Vec::new(), Vec::new()];
    for (k, via) in [&one, &two].into_iter().enumerate() {
        for i in 0..6 {
            let reply = via.send_json(Method::POST, C, &json!({"name": format!("n{k}c{i}"), "preset": "mill3"})).await;
            assert_eq!(reply.status, StatusCode::CREATED, "{:?}", reply.body);
            on[k].push(reply.json()["id"].as_str().unwrap().to_owned());
        }
        on[k].sort();
    }
    let [running, idle] = on;
    assert_eq!(hosted(&one).await, running);
    assert_eq!(hosted(&two).await, idle);
    let mut all: Vec<String> = running.iter().chain(&idle).cloned().collect();
    all.sort();

    // Node one's six run a program that never ends (started through node two: forwarded).
    let forever = "O0001\nWHILE[1EQ1]DO1\nG91 G01 X1. F600\nX-1.\nEND1\nM30\n";
    // Node two's six run one that writes #500 at once and #501 as it ends, 11 s later: idle (and
    // unaddressed for more than the 10 s a controller must be) just as the third node joins.
    let ends = |k: usize| format!("O0002\n#500={k}.25\nG04 X11.\n#501={k}.75\nM30\n");
    for id in &running {
        let stored =
            two.request(Method::PUT, &format!("{C}/{id}/programs/1"), &[("content-type", "text/plain")], forever).await;
        assert_eq!(stored.status, StatusCode::CREATED, "{:?}", stored.body);
        let started = two.send_json(Method::POST, &format!("{C}/{id}/cycle-start"), &json!({"program": 1})).await;
        assert!(started.status.is_success(), "{:?}", started.body);
    }
    for (k, id) in idle.iter().enumerate() {
        let path = format!("{C}/{id}/programs/2");
        let stored = one.request(Method::PUT, &path, &[("content-type", "text/plain")], ends(k)).await;
        assert_eq!(stored.status, StatusCode::CREATED, "{:?}", stored.body);
        let started = one.send_json(Method::POST, &format!("{C}/{id}/cycle-start"), &json!({"program": 2})).await;
        assert!(started.status.is_success(), "{:?}", started.body);
    }
    // A retained variable written through the API on every controller (acknowledged: stored).
    for (k, id) in all.iter().enumerate() {
        let via = if k % 2 == 0 { &one } else { &two };
        let put = via.send_json(Method::PUT, &format!("{C}/{id}/variables/502"), &json!({"value": k as f64})).await;
        assert_eq!(put.status, StatusCode::OK, "{:?}", put.body);
    }

    // The third node joins. Meanwhile a reader asks node one for node two's controllers
    // (forwarded; reading does not keep a controller from moving): every answer is the value
    // written, or 503 with Retry-After during a move.
    let three = node(&pg, &nats, "three");
    let one = Arc::new(one);
    let written = |id: &String| all.iter().position(|a| a == id).unwrap() as f64;
    let answers: Arc<Mutex<Vec<Answer>>> = Arc::default();
    let reader = {
        let (one, answers) = (one.clone(), answers.clone());
        let idle: Vec<(String, f64)> = idle.iter().map(|id| (id.clone(), written(id))).collect();
        tokio::spawn(async move {
            loop {
                for (id, expected) in &idle {
                    let read = one.get(&format!("{C}/{id}/variables/502")).await;
                    let retry = read.headers.contains_key("retry-after");
                    let value = if read.status == StatusCode::OK { read.json()["value"].clone() } else { Value::Null };
                    answers.lock().unwrap().push(Answer { status: read.status, retry, value, expected: *expected });
                }
                tokio::time::sleep(Duration::from_millis(50)).await;
            }
        })
    };

    // Node two hands two of its (now idle) controllers to node three; node one's are all
    // running: it says its handover waits, and they stay there, running.
    eventually("node three hosts two of node two's controllers", Duration::from_secs(90), || async {
        let (two_has, three_has) = (hosted(&two).await, hosted(&three).await);
        let from_two = three_has.iter().filter(|id| idle.contains(id)).count();
        (two_has.len() != 4 || three_has.len() != 2 || from_two != 2)
            .then(|| format!("two {two_has:?}, three {three_has:?}"))
    })
    .await;
    eventually("node one says its surplus is busy", Duration::from_secs(30), || async {
        (!one.log().contains("their handover waits until they are idle")).then(|| "not yet".to_string())
    })
    .await;
    assert_eq!(hosted(&one).await, running, "a running controller moved");
    for id in &running {
        assert_eq!(run_state(&three, id).await, json!("running"), "{id}");
    }

    // Two of them reset (through node three): idle, they move to node three; the others keep
    // running on node one.
    let (reset, still) = running.split_at(2);
    for id in reset {
        let done = three.send_json(Method::POST, &format!("{C}/{id}/reset"), &json!({})).await;
        assert!(done.status.is_success(), "{:?}", done.body);
    }
    eventually("each node hosts four", Duration::from_secs(90), || async {
        let counts = [hosted(&one).await.len(), hosted(&two).await.len(), hosted(&three).await.len()];
        (counts != [4, 4, 4]).then(|| format!("{counts:?}"))
    })
    .await;
    let on_three = hosted(&three).await;
    assert!(reset.iter().all(|id| on_three.contains(id)), "the reset ones moved to node three: {on_three:?}");
    assert_eq!(hosted(&one).await, still.to_vec());
    for id in still {
        assert_eq!(run_state(&two, id).await, json!("running"), "{id}");
    }
    reader.abort();

    // Every write reads back through every node: the API's, and the program's last one, written
    // by the worker as the program ended, just before its controller moved.
    for via in [&*one, &two, &three] {
        for (k, id) in all.iter().enumerate() {
            let read = via.get(&format!("{C}/{id}/variables/502")).await;
            assert_eq!(read.json()["value"], json!(k as f64), "#502 of {id}: {:?}", read.body);
        }
        for (k, id) in idle.iter().enumerate() {
            for (number, value) in [(500, k as f64 + 0.25), (501, k as f64 + 0.75)] {
                let read = via.get(&format!("{C}/{id}/variables/{number}")).await;
                assert_eq!(read.json()["value"], json!(value), "#{number} of {id}: {:?}", read.body);
            }
        }
        // The reset's run record, written before the controller moved.
        for id in reset {
            let runs = via.get(&format!("{C}/{id}/runs")).await.json();
            assert_eq!(runs[0]["result"], "reset", "{id}: {runs}");
        }
    }
    // During the moves: the value, or 503 with Retry-After; never anything else.
    let answers = answers.lock().unwrap().clone();
    for Answer { status, retry, value, expected } in &answers {
        match *status {
            StatusCode::OK => assert_eq!(value, &json!(expected)),
            StatusCode::SERVICE_UNAVAILABLE => assert!(retry, "503 without Retry-After"),
            other => panic!("{other} during the moves"),
        }
    }
}

/// The handover's barrier (`placement::handover`, step 3): once the database writer's count of
/// records done reaches the host's count of records sent, every record sent before is stored.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn records_sent_before_the_count_are_stored_once_the_writer_reaches_it() {
    use fivex_server::{db, host::Record, http::AppState};
    let dir = tempfile::tempdir().unwrap();
    let state = AppState::open(&dir.path().join("fivex.db")).await.unwrap();
    let machine = serde_json::to_string(&fivex_engine::machine::MachineConfig::preset("mill3").unwrap()).unwrap();
    let row = db::ControllerRow {
        id: "c1".into(),
        name: "c1".into(),
        dialect: "fanuc".into(),
        machine_json: machine,
        created_at: "2026-01-01T00:00:00Z".into(),
    };
    db::insert_controller(&state.db, &row).await.unwrap();
    for round in 0..5u32 {
        for k in 0..200u32 {
            let value = f64::from(round * 1000 + k);
            state.host.record(Record::Variables { controller: "c1".into(), values: vec![(500 + k, Some(value))] });
        }
        let sent = state.host.records_sent();
        assert_eq!(sent, u64::from(round + 1) * 200);
        let deadline = Instant::now() + Duration::from_secs(30);
        while state.db.records_done() < sent {
            assert!(Instant::now() < deadline, "the writer did not reach {sent} within 30 s");
            tokio::time::sleep(Duration::from_millis(1)).await;
        }
        let mut stored = db::retained_variables(&state.db, "c1").await.unwrap();
        stored.sort_by_key(|(n, _)| *n);
        let expected: Vec<(u32, f64)> = (0..200).map(|k| (500 + k, f64::from(round * 1000 + k))).collect();
        assert_eq!(stored, expected, "round {round}");
    }
}
