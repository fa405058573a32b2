//! The placement bucket as each node sees it (docs/cluster.md, "The placement view"): a node of
//! the cluster in this process, on a real PostgreSQL and a real `nats-server -js`.

use std::time::{Duration, Instant};

use fivex_server::{cluster, db, http::AppState, placement::Cluster};

use super::nats::NatsServer;
use super::postgres::Postgres;

/// docs/performance.md, "Placement": the time of a node's reconcile (a beat's work) with
/// 2,000 controllers placed on another live member. Run with
/// `cargo test -p fivex-server --test it -- --ignored --nocapture beat_time`.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
#[ignore = "a measurement: run by hand (docs/performance.md)"]
async fn beat_time_with_2000_controllers() {
    const N: usize = 2000;
    let (pg, nats) = (Postgres::start(), NatsServer::start());
    let pool = db::open_postgres(&pg.url()).await.expect("PostgreSQL");
    let machine = serde_json::to_string(&fivex_engine::machine::MachineConfig::preset("head-bc").unwrap()).unwrap();
    let client = async_nats::connect(nats.url()).await.unwrap();
    let connected = cluster::connect(&nats.url()).await.unwrap();
    let me = Cluster::join(&connected, "measured").await.unwrap();
    // Another member, kept alive by this test, owns every controller.
    let js = async_nats::jetstream::new(client);
    let (nodes, placement) =
        (js.get_key_value("fivex_nodes").await.unwrap(), js.get_key_value("fivex_placement").await.unwrap());
    nodes.put("other", "now".into()).await.unwrap();
    let beating = tokio::spawn(async move {
        loop {
            let _ = nodes.put("other", "now".into()).await;
            tokio::time::sleep(Duration::from_secs(1)).await;
        }
    });
    let started = Instant::now();
    for i in 0..N {
        let id = format!("{i:032x}");
        let row = db::ControllerRow {
            id: id.clone(),
            name: format!("c{i}"),
            dialect: "fanuc".into(),
            machine_json: machine.clone(),
            created_at: format!("2026-01-01T00:00:{:02}.{i:06}Z", i % 60),
        };
        db::insert_controller(&pool, &row).await.unwrap();
        placement.put(&id, "other".into()).await.unwrap();
    }
    eprintln!("{N} controllers stored and placed in {:.1} s", started.elapsed().as_secs_f64());
    let state = AppState::clustered(pool, 1, me.clone()).await.unwrap();
    let deadline = Instant::now() + Duration::from_secs(60);
    while !me.view_current() {
        assert!(Instant::now() < deadline, "the placement view is not current within 60 s");
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    let reads = me.placement_reads();
    let mut took = Vec::new();
    for _ in 0..21 {
        let at = Instant::now();
        me.reconcile(&state).await.expect("a reconcile");
        took.push(at.elapsed().as_secs_f64() * 1000.0);
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
    assert_eq!(state.host.len(), 0, "the controllers are another member's");
    assert_eq!(me.placement_reads(), reads, "beats read placements from the bucket");
    took.remove(0);
    took.sort_by(f64::total_cmp);
    eprintln!(
        "a beat with {N} controllers: median {:.1} ms, min {:.1} ms, max {:.1} ms (20 beats)",
        took[took.len() / 2],
        took[0],
        took[took.len() - 1]
    );
    beating.abort();
}

/// Polls `check` every 20 ms until it holds, panicking with `what` after 30 s.
async fn until(what: &str, mut check: impl FnMut() -> bool) {
    let deadline = Instant::now() + Duration::from_secs(30);
    while !check() {
        assert!(Instant::now() < deadline, "{what}: not within 30 s");
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
}

/// Polls `owner(id)` of `node` until it is `expected`; every call answers from the view.
async fn sees(node: &Cluster, id: &str, expected: Option<&str>) {
    let deadline = Instant::now() + Duration::from_secs(30);
    loop {
        let owner = node.owner(id).await.expect("an owner from the view");
        if owner.as_deref() == expected {
            return;
        }
        assert!(Instant::now() < deadline, "{} sees {id} on {owner:?}, not {expected:?}, after 30 s", node.name());
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
}

/// A placement written by another node reaches a node's view through the watch: `owner`
/// answers it without reading the bucket. NATS restarted, each view is built again and follows
/// the changes as before.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_placement_view_follows_other_nodes_without_reading_the_bucket() {
    let mut nats = NatsServer::start();
    let (on_a, on_b) = (cluster::connect(&nats.url()).await.unwrap(), cluster::connect(&nats.url()).await.unwrap());
    let a = Cluster::join(&on_a, "a").await.unwrap();
    let b = Cluster::join(&on_b, "b").await.unwrap();
    until("both views current", || a.view_current() && b.view_current()).await;

    a.place("x").await.unwrap();
    sees(&b, "x", Some("a")).await;
    // Placed on b by b: a sees it at once.
    b.place("x").await.unwrap();
    sees(&a, "x", Some("b")).await;
    a.forget("x").await;
    sees(&b, "x", None).await;
    sees(&a, "x", None).await;
    assert_eq!((a.placement_reads(), b.placement_reads()), (0, 0), "a bucket entry was read");

    // NATS restarts: the connections break, each view is built again, then follows.
    let builds = (a.view_builds(), b.view_builds());
    nats.restart();
    until("both views built again", || {
        a.view_builds() > builds.0 && b.view_builds() > builds.1 && a.view_current() && b.view_current()
    })
    .await;
    let reads = (a.placement_reads(), b.placement_reads());
    a.place("y").await.unwrap();
    sees(&b, "y", Some("a")).await;
    b.place("y").await.unwrap();
    sees(&a, "y", Some("b")).await;
    assert_eq!((a.placement_reads(), b.placement_reads()), reads, "a bucket entry was read");
}
