//! What a subscriber of a controller's stream holds on the service's side: the heap bytes still
//! allocated after 20 websocket subscribers connected to the real service on loopback and got
//! their snapshot and first position, counted by a global allocator that keeps the live total
//! (as `tests/memory.rs` counts a controller). `fivex-load`'s RSS figure of a running
//! controller includes its subscriber; `docs/performance.md` has both measures.
//!
//! It runs alone in its test binary (the allocator counts every thread's allocations; the
//! service's threads free memory after their test ends, which would be counted in another's), in
//! well under a second. `cargo test -p fivex-server --test memory_stream -- --nocapture` prints
//! the figure.

mod counting;

use counting::live;
use std::io::{Read, Write};
use std::sync::Arc;
use std::time::Duration;

use fivex_engine::machine::MachineConfig;
use fivex_engine::Dialect;
use fivex_server::host::{Hosted, Spec};

const COUNT: usize = 20;

/// Connects a websocket subscriber to `id`'s stream with a blocking std socket (it allocates
/// nothing, so the count is the service's alone) and reads until the first position frame came.
fn subscribe(addr: std::net::SocketAddr, id: &str, buf: &mut [u8]) -> std::net::TcpStream {
    let mut socket = std::net::TcpStream::connect(addr).expect("connect");
    socket.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    write!(
        socket,
        "GET /api/v1/controllers/{id}/stream HTTP/1.1\r\nHost: {addr}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Version: 13\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n\r\n"
    )
    .unwrap();
    let mut read = 0;
    const POSITION: &[u8] = b"\"type\":\"position\"";
    while !buf[..read].windows(POSITION.len()).any(|w| w == POSITION) {
        let n =
            socket.read(&mut buf[read..]).unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&buf[..read])));
        assert!(n > 0, "the stream ended: {}", String::from_utf8_lossy(&buf[..read]));
        read += n;
    }
    assert!(buf.starts_with(b"HTTP/1.1 101"), "{}", String::from_utf8_lossy(&buf[..read]));
    socket
}

#[test]
fn a_stream_subscriber_holds_under_8_kb() {
    let runtime = tokio::runtime::Builder::new_multi_thread().worker_threads(2).enable_all().build().unwrap();
    let dir = tempfile::tempdir().unwrap();
    let state = runtime.block_on(fivex_server::http::AppState::open(&dir.path().join("memory.db"))).unwrap();
    let machine = MachineConfig::preset("table-ac").expect("the table-ac preset");
    for k in 0..=COUNT {
        state.host.add(Arc::new(Hosted::new(Spec {
            id: format!("c{k}"),
            name: format!("load {k}"),
            dialect: Dialect::Fanuc,
            machine: machine.clone(),
            created_at: String::new(),
            speed: 1.0,
        })));
    }
    let listener = runtime.block_on(tokio::net::TcpListener::bind("127.0.0.1:0")).unwrap();
    let addr = listener.local_addr().unwrap();
    let serving = runtime.spawn(fivex_server::serve::serve(listener, state.clone(), std::future::pending()));
    let mut buf = vec![0u8; 64 * 1024];
    let mut sockets = Vec::with_capacity(COUNT);
    // One first, so what the first connection sets up once (the runtime's, the router's) is not
    // counted.
    let first = subscribe(addr, "c0", &mut buf);
    std::thread::sleep(Duration::from_millis(200));
    let before = live();
    for k in 1..=COUNT {
        sockets.push(subscribe(addr, &format!("c{k}"), &mut buf));
    }
    // The connections' request buffers are released after the upgrade.
    std::thread::sleep(Duration::from_millis(200));
    let after = live();
    let kb = (after - before) as f64 / COUNT as f64 / 1024.0;
    println!("heap per stream subscriber (the service's side): {kb:.1} kB");
    // Measured 2026-11-25: 5.6 kB (the session's task, the websocket and its buffers: 256 bytes
    // to read, the largest message sent to write). With tungstenite's default read buffer
    // (128 KiB) it was 133 kB, with 4 KiB 9.4 kB.
    assert!(kb < 8.0, "a stream subscriber holds {kb:.1} kB");
    drop((first, sockets));
    serving.abort();
    runtime.shutdown_timeout(Duration::from_secs(1));
}
