//! The machine library (`machines/*.json`, `docs/fleet.md`): every file loads as the CLI loads it
//! (a model file, or a vendor parameter list in its own dialect), builds a kinematic model, and
//! its inverse kinematics finds the pose again from the tip and tool direction that forward
//! kinematics gives at a few poses inside the strokes and ranges.

use fivex_engine::kin::{Kinematics, MachineKind, Vec3};
use fivex_engine::machine::{AxisKind, MachineConfig, MAX_AXES};
use fivex_engine::vendor::{self, ParamFile};
use fivex_engine::Dialect;
use std::path::PathBuf;

fn library() -> Vec<(String, MachineConfig, Option<Dialect>)> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../machines");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("machines/")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    files
        .into_iter()
        .map(|path| {
            let text = std::fs::read_to_string(&path).unwrap();
            let value: serde_json::Value = serde_json::from_str(&text).unwrap();
            let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
            let (m, dialect) = if value.get("parameters").is_some() {
                let f: ParamFile = serde_json::from_value(value).unwrap();
                let m = vendor::machine_from(f.dialect, &f.name, &f.parameters)
                    .unwrap_or_else(|e| panic!("{stem}: {}", e.describe(f.dialect)));
                (m, Some(f.dialect))
            } else {
                (serde_json::from_value::<MachineConfig>(value).unwrap_or_else(|e| panic!("{stem}: {e}")), None)
            };
            m.validate().unwrap_or_else(|e| panic!("{stem}: {e}"));
            assert_eq!(m.name, stem, "a library machine's name is its file name");
            (stem, m, dialect)
        })
        .collect()
}

/// A position `frac` of the way through the axis's stroke (a rollover axis: `frac` × 360°).
fn inside(m: &MachineConfig, i: usize, frac: f64) -> f64 {
    let axis = &m.axes[i];
    let range = m.rotary.iter().find(|l| l.axis == axis.name).and_then(|l| l.range);
    match axis.stroke.or(range) {
        Some([lo, hi]) => lo + (hi - lo) * frac,
        None if axis.kind == AxisKind::Rotary => 360.0 * frac,
        None => 0.0,
    }
}

#[test]
fn the_library_covers_every_kind_and_every_dialect() {
    let lib = library();
    assert!(lib.len() >= 20, "{} machines", lib.len());
    let kinds: Vec<MachineKind> = lib.iter().map(|(_, m, _)| Kinematics::new(m).unwrap().kind).collect();
    for kind in [
        MachineKind::ThreeAxis,
        MachineKind::HeadHead,
        MachineKind::TableTable,
        MachineKind::HeadTable,
        MachineKind::Head,
        MachineKind::Table,
    ] {
        assert!(kinds.contains(&kind), "no {kind:?} machine");
    }
    for dialect in [Dialect::Fanuc, Dialect::Syntec, Dialect::Haas] {
        assert!(lib.iter().any(|(_, _, d)| *d == Some(dialect)), "no {dialect:?} parameter list");
    }
    // Inclined axes (nutating heads and tables): a rotary direction off the coordinate axes.
    assert!(lib.iter().any(|(_, m, _)| m.rotary.iter().any(|l| l.direction.iter().filter(|c| **c != 0.0).count() > 1)));
}

#[test]
fn the_library_is_documented() {
    let doc = std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../docs/fleet.md")).unwrap();
    for (name, _, _) in library() {
        assert!(doc.contains(&format!("| `{name}` |")), "docs/fleet.md does not list {name}");
    }
}

#[test]
fn every_library_machine_round_trips_fk_and_ik() {
    const L: f64 = 120.0;
    for (name, m, _) in library() {
        let kin = Kinematics::new(&m).unwrap_or_else(|e| panic!("{name}: {e:?}"));
        for frac in [0.5, 0.2, 0.85, 0.65] {
            let mut pose = [0.0; MAX_AXES];
            for (i, p) in pose.iter_mut().enumerate().take(m.axes.len()) {
                *p = inside(&m, i, frac);
            }
            let fk = kin.forward(&pose, L);
            let candidates = kin.inverse(fk.tip, fk.tool, L, &pose[..m.axes.len()]);
            assert!(!candidates.is_empty(), "{name} at {frac}: no inverse solution");
            let mut found_pose = false;
            for c in candidates.iter() {
                let mut q = [0.0; MAX_AXES];
                q[..c.pos.len()].copy_from_slice(&c.pos);
                let back = kin.forward(&q, L);
                let err: Vec3 = back.tip - fk.tip;
                assert!(err.norm() < 1e-6, "{name} at {frac}: tip off by {}", err.norm());
                assert!((back.tool - fk.tool).norm() < 1e-9, "{name} at {frac}: tool direction differs");
                // One of the candidates is the pose itself (rotary angles modulo 360).
                found_pose |= m.axes.iter().enumerate().all(|(i, a)| {
                    let d = q[i] - pose[i];
                    match a.kind {
                        AxisKind::Linear => d.abs() < 1e-6,
                        AxisKind::Rotary => {
                            let r = d.rem_euclid(360.0);
                            !(1e-6..=360.0 - 1e-6).contains(&r)
                        }
                    }
                });
            }
            assert!(found_pose, "{name} at {frac}: the pose is not among the inverse solutions");
        }
    }
}

/// Every library machine loads without a "not modelled" warning: what it sets, fivex carries
/// out (a parameter list's bits beside the ones read, No.1006#1 ROS, say, would be reported).
#[test]
fn the_library_sets_nothing_fivex_does_not_model() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../machines");
    for (stem, _, _) in library() {
        let text = std::fs::read_to_string(dir.join(format!("{stem}.json"))).unwrap();
        assert_eq!(fivex_engine::machine_file::warnings(&stem, &text), Vec::<String>::new(), "{stem}");
    }
}
