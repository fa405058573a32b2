//! Kinematics speed per call (`docs/performance.md`, "Kinematics"): forward kinematics, inverse
//! kinematics (every candidate), and inverse plus the dialect's choice, on every 5-axis preset.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use fivex_engine::kin::{Kinematics, Selection};
use fivex_engine::machine::MachineConfig;
use fivex_engine::Dialect;

fn kinematics(c: &mut Criterion) {
    for name in ["head-bc", "table-ac", "mixed-bc"] {
        let k = Kinematics::new(&MachineConfig::preset(name).unwrap()).unwrap();
        let q = [12.5, -40.0, 30.0, 35.0, 250.0];
        let pose = k.forward(&q, 80.0);
        let from = [0.0, 0.0, 0.0, 30.0, 240.0];
        c.bench_function(&format!("fk/{name}"), |b| b.iter(|| k.forward(black_box(&q), black_box(80.0))));
        c.bench_function(&format!("ik/{name}"), |b| {
            b.iter(|| k.inverse(black_box(pose.tip), black_box(pose.tool), 80.0, black_box(&from)))
        });
        for dialect in [Dialect::Fanuc, Dialect::Syntec] {
            let how = Selection { dialect, pri: false, p: 0 };
            c.bench_function(&format!("ik+select/{name}/{}", dialect.name()), |b| {
                b.iter(|| {
                    let candidates = k.inverse(black_box(pose.tip), black_box(pose.tool), 80.0, black_box(&from));
                    k.select(&candidates, &from, how).map(|choice| choice.pos[3])
                })
            });
        }
    }
}

criterion_group!(benches, kinematics);
criterion_main!(benches);
