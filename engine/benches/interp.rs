//! Interpreter speed: the two programs of `docs/performance.md` (the same generator as
//! `bench/programs/gen.py`, built here so the benchmark needs no files).

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use fivex_engine::interp::{Config, Interpreter};
use fivex_engine::lang::parse_file;
use fivex_engine::machine::MachineConfig;
use fivex_engine::Dialect;
use std::fmt::Write;

/// 200,000 linear moves with decimal-point coordinates (a zig-zag, like a CAM finishing pass).
fn linear_program(moves: usize) -> String {
    let mut s = String::from("O0001\nG21 G90 G17 G94 G54\nG00 X0 Y0 Z5.\nG01 Z0 F1000.\n");
    for i in 0..moves {
        let x = (i % 1000) as f64 * 0.05;
        let y = (i / 1000) as f64 * 0.25 - 25.0;
        let z = -0.5 + ((i % 37) as f64) * 0.001;
        if i % 10 == 0 {
            let _ = writeln!(s, "N{} G01 X{x:.3} Y{y:.3} Z{z:.3}", (i / 10) % 99_999 + 1);
        } else {
            let _ = writeln!(s, "G01 X{x:.3} Y{y:.3} Z{z:.3}");
        }
    }
    s.push_str("G00 Z5.\nM30\n");
    s
}

/// A 200,000-iteration WHILE loop with SIN, SQRT, ABS and additions.
fn macro_program(iterations: usize) -> String {
    format!(
        "O0002\n#1=0\n#2=0\nWHILE [#1 LT {iterations}] DO 1\n#2 = #2 + SIN[#1] + SQRT[ABS[#1]] + ABS[#1 - 100]\n#1 = #1 + 1\nEND 1\n#100 = #2\nM30\n"
    )
}

fn interpret(text: &str) -> usize {
    let cfg = Config::new(MachineConfig::preset("mill3").expect("preset"), Dialect::Fanuc);
    let mut interp = Interpreter::new(parse_file(text), cfg);
    let mut n = 0;
    interp.run(|_| n += 1).expect("no alarm");
    n
}

fn benches(c: &mut Criterion) {
    let linear = linear_program(200_000);
    let macro_loop = macro_program(200_000);
    let mut g = c.benchmark_group("interp");
    g.sample_size(10);
    g.throughput(Throughput::Elements(200_000));
    g.bench_function("parse linear-200k", |b| b.iter(|| parse_file(&linear).programs.len()));
    g.bench_function("interpret linear-200k", |b| b.iter(|| interpret(&linear)));
    g.bench_function("interpret macro-200k", |b| b.iter(|| interpret(&macro_loop)));
    g.finish();
}

criterion_group!(interp, benches);
criterion_main!(interp);
