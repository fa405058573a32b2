//! The service's tests in one test binary (one link instead of one per file): the API through
//! `oneshot` (`api`, `http`, `fleet`, `metrics`: `/readyz` and `/metrics`), the black-box tests
//! that start the real `fivex serve` (`blackbox`) and the layering of the sources (`layers`).
//! `common` holds what the `oneshot` tests share (and `common::exposition`, the readers of the
//! Prometheus text format). (`memory.rs` stays a binary of its own: it installs a counting
//! global allocator.)

mod api;
mod blackbox;
mod common;
mod estimate;
mod fleet;
mod http;
mod layers;
mod metrics;
mod restart;
mod shopfloor;
mod stored_programs;
