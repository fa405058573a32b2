//! The end-to-end tests in one test binary: the real `fivex` binary on every fixture (insta
//! snapshots in `snapshots/`), the CLI contract, `fivex kin`, fleet runs and the service.

mod cli;
mod common;
mod fixtures;
mod fleet;
mod kin_cli;
mod nurbs_scipy;
mod peer_crc;
mod service;
