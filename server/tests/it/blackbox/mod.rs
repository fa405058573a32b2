//! Black-box tests of the service: each starts the real `fivex serve` binary on loopback with a
//! fresh SQLite file, talks to it over TCP as a client would, and stops it. One module per concern
//! of the service's hardening (docs/api.md).

mod compose;
mod document;
mod limits;
mod metrics;
mod modal;
mod nats;
mod nodes;
mod origin;
mod placement_view;
pub mod postgres;
mod rebalance;
mod relay;
pub mod served;
mod startup;
mod store;
mod streams;
mod wire;

use std::time::Duration;

use served::Served;

/// The harness itself: the binary starts, answers `/healthz`, and stops on SIGTERM with status 0.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_binary_answers_and_stops_on_sigterm() {
    let mut served = Served::start(&[]);
    let reply = served.get("/healthz").await;
    assert_eq!(reply.status, 200);
    assert_eq!(reply.json()["status"], "ok");
    let (status, _took) = served.terminate(Duration::from_secs(20));
    assert!(status.success(), "{status}; log: {}", served.log());
    assert!(served.log().contains("fivex stopped"), "{}", served.log());
}
