//! What a running controller holds (issue 18 asks for under 200 kB each): the heap bytes still
//! allocated after hosting controllers and running the load program on them the way a worker
//! does (tick, collect the events, publish a position), counted by a global allocator that keeps
//! the live total. `docs/performance.md` has the figures, where they come from (the motion
//! planner's look-ahead), and the RSS measurement beside this one.
//!
//! It runs alone in its test binary (the allocator counts every thread's allocations), in well
//! under a second, and measures the same bytes every time: the run is the same ticks of the same
//! program. `cargo test -p fivex-server --test memory -- --nocapture` prints the figures;
//! `tests/memory_stream.rs` measures a stream subscriber the same way.

mod counting;

use counting::live;
use std::sync::Arc;

use fivex_engine::controller::RunState;
use fivex_engine::machine::MachineConfig;
use fivex_engine::Dialect;
use fivex_server::host::{Hosted, Published, Reading, Spec};

/// The load program of `fivex-load` (`server/src/bin/fivex-load.rs`): a square with A and C
/// turning, forever.
const PROGRAM: &str = "#1=0\nWHILE [#1 LT 1000000] DO1\nG90 G01 X100. Y0 Z10. A10. C90. F3000\nX100. Y100. A0 C180.\nX0 Y100. A-10. C270.\nX0 Y0 A0 C360.\n#1=#1+1\nEND1\nM30\n";

const COUNT: usize = 20;

#[test]
fn a_running_controller_holds_under_200_kb() {
    let machine = MachineConfig::preset("table-ac").expect("the table-ac preset");
    let before = live();
    let hosted: Vec<Arc<Hosted>> = (0..COUNT)
        .map(|k| {
            Arc::new(Hosted::new(Spec {
                id: format!("c{k}"),
                name: format!("load {k}"),
                dialect: Dialect::Fanuc,
                machine: machine.clone(),
                created_at: String::new(),
                speed: 1.0,
            }))
        })
        .collect();
    let idle = live();
    // A subscriber each, as under load: the position watch and the event channel.
    let subscribers: Vec<_> = hosted.iter().map(|h| (h.positions(), h.events())).collect();
    for h in &hosted {
        let mut station = h.station();
        station.controller.select_program(PROGRAM).expect("the program is taken");
        station.controller.cycle_start().expect("cycle start");
        station.begin_run(Some(1));
    }
    // Ten simulated seconds each, by 10 ms ticks, as a worker runs them.
    let mut last = Vec::new();
    for _ in 0..1000 {
        last.clear();
        for h in &hosted {
            let mut station = h.station();
            station.controller.tick(0.01);
            let (messages, _records) = station.collect(&h.id, 0.01, true);
            drop(messages);
            last.push(Arc::new(Published::new(Reading::of(&station))));
        }
    }
    for h in &hosted {
        assert_eq!(h.station().controller.run_state(), RunState::Running, "the load program runs");
    }
    let running = live();
    let idle_kb = (idle - before) as f64 / COUNT as f64 / 1024.0;
    let running_kb = (running - before) as f64 / COUNT as f64 / 1024.0;
    println!("heap per controller: {idle_kb:.1} kB idle, {running_kb:.1} kB running (with its last position)");
    // Measured 2026-11-25: 58.1 kB idle, 186.7 kB running, most of it the planner's look-ahead
    // (288 segments of 384 bytes and their junction speeds).
    assert!(running_kb < 200.0, "a running controller holds {running_kb:.1} kB ({idle_kb:.1} kB idle)");
    drop(subscribers);
}
