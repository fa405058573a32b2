//! `fivex kin fk` / `fivex kin ik` (`docs/contracts.md`): output shapes, the spec's selection example
//! through the real binary, machine files, and usage errors.

use crate::common;

use common::*;
use serde_json::{json, Value};

fn kin(args: &[&str]) -> (i32, Value) {
    let out = fivex(&[&["kin"], args].concat());
    let text = stdout(&out);
    let v: Value = serde_json::from_str(&text)
        .unwrap_or_else(|e| panic!("kin stdout is not one JSON value ({e}):\n{text}\nstderr: {}", stderr(&out)));
    (out.status.code().expect("exit code"), v)
}

#[test]
fn fk_by_hand() {
    let (code, v) = kin(&["fk", "--preset", "head-bc", "--axes", "X=10,Y=20,Z=30,B=90,C=0", "--tool-length", "100"]);
    assert_eq!(code, 0);
    // The B pivot 150 above the nose (docs/machine-config.md, "By hand").
    assert_eq!(v["tip"], json!([-240.0, 20.0, 180.0]));
    assert_eq!(v["tool"], json!([1.0, 0.0, 0.0]));
    // 90° away from the singular posture (tool along the C master).
    assert_eq!(v["singularity"], json!({"axis": "C", "angle": 90.0}));
    let (_, v) = kin(&["fk", "--preset", "table-ac", "--axes", "Z=50,A=90"]);
    assert_eq!(v["tip"], json!([0.0, -170.0, -120.0]));
    assert_eq!(v["tip_machine"], json!([0.0, 0.0, 50.0]));
    assert_eq!(v["tool"], json!([0.0, -1.0, 0.0]));
}

/// fanuc-tcp.md TV-01: from B−70 C30 the candidates (B90, C180) and (B270, C0) give B−90 C0
/// (the direction is −X with right-hand head axes, spec Q-3).
#[test]
fn ik_chooses_as_fanuc_does() {
    let (code, v) = kin(&["ik", "--preset", "head-bc", "--tip", "0,0,0", "--tool", "-1,0,0", "--from", "B=-70,C=30"]);
    assert_eq!(code, 0);
    assert_eq!(v["candidates"].as_array().unwrap().len(), 2);
    // B−90 points the tool along −X: the pivot, 150 above the tip along the tool, is at
    // (150, 0, 150) from the carriage, so the carriage is at (−150, 0, −150).
    assert_eq!(v["chosen"], json!({"X": -150.0, "Y": 0.0, "Z": -150.0, "B": -90.0, "C": 0.0}));
    assert_eq!(v["alarm"], Value::Null);
    assert_eq!(v["singular"], json!([]));
    // TV-05: the tool along +Z is singular; C stays at its current 90.
    let (_, v) = kin(&["ik", "--preset", "head-bc", "--tip", "0,0,0", "--tool", "0,0,1", "--from", "B=45,C=90"]);
    assert_eq!(v["singular"], json!(["C"]));
    assert_eq!(v["chosen"]["C"], json!(90.0));
}

#[test]
fn ik_without_a_solution_reports_the_dialects_alarm() {
    let (code, v) = kin(&["ik", "--preset", "mill3", "--tip", "1,2,3", "--tool", "1,0,0"]);
    assert_eq!(code, 1);
    assert_eq!(v["candidates"], json!([]));
    assert_eq!(v["chosen"], Value::Null);
    assert_eq!(v["alarm"]["code"], "PS5459");
    let (_, v) = kin(&["ik", "--preset", "mill3", "--tip", "1,2,3", "--tool", "1,0,0", "--dialect", "syntec"]);
    assert_eq!(v["alarm"]["code"], "COR-153");
}

#[test]
fn a_machine_file_with_offsets() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.json");
    // A head B about Y whose pivot is 150 mm above the spindle nose.
    let machine = json!({
        "name": "pivot", "tool_axis": [0, 0, 1], "nose": [0, 0, -150],
        "axes": [{"name": "X", "kind": "linear", "rapid": 1}, {"name": "Y", "kind": "linear", "rapid": 1},
                 {"name": "Z", "kind": "linear", "rapid": 1}, {"name": "B", "kind": "rotary", "rapid": 1}],
        "rotary": [{"axis": "B", "side": "head", "direction": [0, 1, 0], "hand": "right"}]
    });
    std::fs::write(&path, machine.to_string()).unwrap();
    let p = path.to_str().unwrap();
    let (_, v) = kin(&["fk", "--machine", p, "--axes", "B=90", "--tool-length", "50"]);
    // Pivot at 0; tool along +X; the tip 200 mm from the pivot toward −X.
    assert_eq!(v["tip"], json!([-200.0, 0.0, 0.0]));
    let (_, v) = kin(&["ik", "--machine", p, "--tip", "-200,0,0", "--tool", "1,0,0", "--tool-length", "50"]);
    assert_eq!(v["chosen"], json!({"X": 0.0, "Y": 0.0, "Z": 0.0, "B": 90.0}));
}

#[test]
fn usage_errors_exit_2() {
    for args in [
        &["kin", "fk", "--preset", "head-bc", "--axes", "Q=1"][..],
        &["kin", "fk", "--preset", "head-bc", "--axes", "B=abc"],
        &["kin", "ik", "--preset", "head-bc", "--tip", "1,2", "--tool", "0,0,1"],
        &["kin", "ik", "--preset", "head-bc", "--tip", "0,0,0", "--tool", "0,0,0"],
        &["kin", "fk", "--preset", "nope"],
    ] {
        let out = fivex(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
        assert!(stdout(&out).is_empty(), "{args:?}");
    }
}

/// `fivex machine --params D` prints a parameter list that `--machine` reads back as the same
/// machine: the same tip in both dialects as from the preset.
#[test]
fn parameter_lists_as_machine_files() {
    let dir = tempfile::tempdir().unwrap();
    let (_, want) = kin(&["fk", "--preset", "mixed-bc", "--axes", "X=5,Y=-7,Z=20,B=-35,C=250", "--tool-length", "80"]);
    for dialect in ["fanuc", "syntec"] {
        let out = fivex(&["machine", "--preset", "mixed-bc", "--params", dialect]);
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
        let file: Value = serde_json::from_str(&stdout(&out)).unwrap();
        assert_eq!(file["dialect"], dialect);
        let path = dir.path().join(format!("{dialect}.json"));
        std::fs::write(&path, stdout(&out)).unwrap();
        let args =
            ["fk", "--machine", path.to_str().unwrap(), "--axes", "X=5,Y=-7,Z=20,B=-35,C=250", "--tool-length", "80"];
        let (code, got) = kin(&args);
        assert_eq!(code, 0);
        for key in ["tip", "tool"] {
            let (a, b) = (got[key].as_array().unwrap(), want[key].as_array().unwrap());
            let close = a.iter().zip(b).all(|(x, y)| (x.as_f64().unwrap() - y.as_f64().unwrap()).abs() < 1e-9);
            assert!(close, "{dialect} {key}: {a:?} vs {b:?}");
        }
    }
    // An inconsistent Syntec list: the spindle type's slave C parallel to the +Z tool.
    let bad = json!({"name": "bad", "dialect": "syntec", "parameters": {
        "21": 1, "22": 2, "23": 3, "24": 4, "25": 5, "201": 0, "202": 0, "203": 0, "204": 1, "205": 1,
        "321": 1, "322": 2, "323": 3, "324": 5, "325": 6, "461": 1000, "462": 1000, "463": 1000, "464": 1000, "465": 1000,
        "3001": 1, "3002": 3, "3005": 2, "3006": 3, "3007": 1, "3008": 1}});
    let path = dir.path().join("bad.json");
    std::fs::write(&path, bad.to_string()).unwrap();
    let out = fivex(&["kin", "fk", "--machine", path.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("COR-155"), "{}", stderr(&out));
    // A machine Syntec cannot describe (X/Y/Z at the pivot, not at the spindle nose): exit 1
    // with the reason; FANUC can (No.19666 = 150).
    let pivot = json!({
        "name": "pivot", "nose": [0, 0, -150],
        "axes": [{"name": "X", "kind": "linear", "rapid": 1}, {"name": "Y", "kind": "linear", "rapid": 1},
                 {"name": "Z", "kind": "linear", "rapid": 1}, {"name": "B", "kind": "rotary", "rapid": 1}],
        "rotary": [{"axis": "B", "side": "head", "direction": [0, 1, 0], "hand": "right"}]
    });
    let path = dir.path().join("pivot.json");
    std::fs::write(&path, pivot.to_string()).unwrap();
    let out = fivex(&["machine", "--machine", path.to_str().unwrap(), "--params", "syntec"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("spindle nose"), "{}", stderr(&out));
    let out = fivex(&["machine", "--machine", path.to_str().unwrap(), "--params", "fanuc"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let file: Value = serde_json::from_str(&stdout(&out)).unwrap();
    assert_eq!(file["parameters"]["19666"], json!(150));
}

#[test]
fn the_dashboards_kinematics_fixture_is_what_the_engine_computes() {
    // web/src/three checks its forward kinematics against this fixture; this keeps the fixture
    // true to the engine (regenerate it with web/src/three/fixtures/generate.mjs after a change).
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../web/src/three/fixtures/kinematics.json");
    let fixture: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let mut checked = 0;
    for machine in fixture["machines"].as_array().unwrap() {
        let file = dir.path().join("machine.json");
        std::fs::write(&file, machine["model"].to_string()).unwrap();
        for pose in machine["poses"].as_array().unwrap() {
            let axes: Vec<String> = pose["axes"].as_object().unwrap().iter().map(|(a, v)| format!("{a}={v}")).collect();
            let length = pose["tool_length"].to_string();
            let (code, v) =
                kin(&["fk", "--machine", file.to_str().unwrap(), "--axes", &axes.join(","), "--tool-length", &length]);
            assert_eq!(code, 0, "{}", machine["source"]);
            for key in ["tip", "tool", "tip_machine", "tool_machine"] {
                for i in 0..3 {
                    let (want, got) = (pose[key][i].as_f64().unwrap(), v[key][i].as_f64().unwrap());
                    assert!((want - got).abs() <= 1e-12, "{} {pose}: {key} is {} now", machine["source"], v[key]);
                }
            }
            checked += 1;
        }
    }
    assert!(checked >= 100, "{checked} poses");
}

/// `--chain` computes with a further mechanism chain (Syntec G10 L5000 P_ Q_): the library's
/// exchangeable head at A90 in set 2 — its pivot 150 above the carriage point, its nose 50
/// below it, A +90° about +X takes the 100 mm tool's tip from 300 below the pivot to 300 along
/// +Y: (0, 300, 150), tool −Y (docs/five-axis.md). Set 1 (the default) turns B instead.
#[test]
fn a_further_mechanism_chain() {
    let machine = concat!(env!("CARGO_MANIFEST_DIR"), "/../machines/head-exchange-bc-ac.json");
    let (code, v) = kin(&["fk", "--machine", machine, "--axes", "A=90", "--tool-length", "100", "--chain", "2"]);
    assert_eq!(code, 0);
    assert_eq!((v["tip"].clone(), v["tool"].clone()), (json!([0.0, 300.0, 150.0]), json!([0.0, -1.0, 0.0])));
    let (_, v) = kin(&["fk", "--machine", machine, "--axes", "A=90", "--tool-length", "100"]);
    assert_eq!(v["tip"], json!([0.0, 0.0, -100.0]), "set 1 does not turn A");
    let (code, v) = kin(&[
        "ik",
        "--machine",
        machine,
        "--tip",
        "0,300,150",
        "--tool",
        "0,-1,0",
        "--tool-length",
        "100",
        "--chain",
        "2",
    ]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["chosen"]["A"], json!(90.0), "{v}");
    for bad in ["3", "2,2", "x"] {
        let out = fivex(&["kin", "fk", "--machine", machine, "--chain", bad]);
        assert_eq!(out.status.code(), Some(2), "--chain {bad}");
    }
}
