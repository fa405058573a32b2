//! Parse, then run the interpreter and the ideal executor with a small block budget, on a 3-axis
//! and a 5-axis preset, in both dialects. Any panic (or a hang past the block budget), and a
//! cycle time or end position that is no number, is a bug.
#![no_main]

use fivex_engine::interp::{Config, Interpreter};
use fivex_engine::lang::parse_file;
use fivex_engine::machine::MachineConfig;
use fivex_engine::run::{run, RunOptions};
use fivex_engine::Dialect;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let file = parse_file(&text);
    for preset in ["mill3", "head-bc"] {
        for dialect in [Dialect::Fanuc, Dialect::Syntec, Dialect::Haas] {
            let mut cfg = Config::new(MachineConfig::preset(preset).expect("preset"), dialect);
            cfg.max_blocks = 10_000;
            let mut interp = Interpreter::new(file.clone(), cfg);
            for n in 1..=99 {
                if let Some(t) = interp.state.offsets.tool_mut(n) {
                    t.h_geometry = 100.0;
                    t.d_geometry = 5.0;
                }
            }
            let options = RunOptions { period_s: 0.0, max_time_s: 1.0e6, ..RunOptions::default() };
            let result = run(&mut interp, &options, |_| {});
            // Never a confident wrong answer: the time and where the machine ends are numbers.
            assert!(result.cycle_time_s.is_finite(), "cycle time {}", result.cycle_time_s);
            assert!(result.machine.iter().all(|x| x.is_finite()), "ends at {:?}", result.machine);
        }
    }
});
