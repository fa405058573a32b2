//! `fivex fleet` (docs/contracts.md "`fivex fleet` stdout", `docs/fleet.md`): one summary per machine
//! with `"machine"`, each equal to `fivex run` on that machine alone; programs that run
//! everywhere, that alarm on some machines (rotary range, over-travel, no solution for a tool
//! direction), and a malformed one; a probe with and without `--workpiece`; usage errors.

use crate::common;

use common::*;
use serde_json::Value;
use std::path::PathBuf;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn program(name: &str) -> String {
    root().join("tests/fleet").join(name).display().to_string()
}

const PRESETS: [&str; 5] = ["mill3", "head-bc", "table-ac", "table-bc", "mixed-bc"];

/// `fivex fleet PROGRAM ARGS`: exit status, the array, stderr.
fn fleet(prog: &str, args: &[&str]) -> (i32, Vec<Value>, String) {
    let p = program(prog);
    let out = fivex(&[&["fleet", p.as_str()], args].concat());
    let text = stdout(&out);
    let v: Value = serde_json::from_str(&text)
        .unwrap_or_else(|e| panic!("fleet stdout is not one JSON value ({e}):\n{text}\nstderr: {}", stderr(&out)));
    let Value::Array(items) = v else { panic!("fleet stdout is not an array: {text}") };
    (out.status.code().expect("exit code"), items, stderr(&out))
}

fn presets_args() -> Vec<&'static str> {
    PRESETS.iter().flat_map(|p| ["--preset", *p]).collect()
}

fn by_machine<'a>(items: &'a [Value], name: &str) -> &'a Value {
    items.iter().find(|v| v["machine"] == name).unwrap_or_else(|| panic!("no {name} in the fleet"))
}

/// The summary without what the fleet adds.
fn summary_of(v: &Value) -> Value {
    let mut v = v.clone();
    let o = v.as_object_mut().unwrap();
    for k in ["machine", "dialect", "report"] {
        o.remove(k);
    }
    v
}

fn library_names() -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(root().join("machines"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn a_program_that_runs_everywhere_matches_fivex_run_bit_for_bit() {
    let mut args = presets_args();
    args.push("--library");
    let (code, items, err) = fleet("everywhere.nc", &args);
    // Exit status 1: the Haas machines end in an alarm (below), every other machine completes.
    assert_eq!(code, 1, "{err}");
    let names = library_names();
    assert!(names.len() >= 20);
    assert_eq!(items.len(), PRESETS.len() + names.len());
    // Presets first in the order given, then the library in name order.
    let order: Vec<&str> = items.iter().map(|v| v["machine"].as_str().unwrap()).collect();
    let expected: Vec<&str> = PRESETS.iter().copied().chain(names.iter().map(|s| s.as_str())).collect();
    assert_eq!(order, expected);
    // One progress line per machine on stderr.
    assert_eq!(err.lines().filter(|l| l.starts_with("fleet: [")).count(), items.len(), "{err}");
    for item in &items {
        let name = item["machine"].as_str().unwrap();
        if name.starts_with("haas-") {
            // A Haas machine's zero is the top of its travels (strokes [-travel, 0]): with G54 at
            // machine zero the program's Z50 is above them, the stroke check's alarm at line 7.
            assert_eq!(
                (item["status"].as_str(), item["alarms"][0]["line"].as_u64()),
                (Some("alarm"), Some(7)),
                "{name}: {item}"
            );
        } else {
            assert_eq!(item["status"], "completed", "{name}: {item}");
        }
        let dialect = item["dialect"].as_str().unwrap();
        let p = program("everywhere.nc");
        let machine = root().join("machines").join(format!("{name}.json")).display().to_string();
        let run_args: Vec<&str> = if PRESETS.contains(&name) {
            vec!["run", &p, "--preset", name, "--dialect", dialect]
        } else {
            vec!["run", &p, "--machine", &machine, "--dialect", dialect]
        };
        let out = fivex(&run_args);
        let alone: Value = serde_json::from_str(&stdout(&out)).unwrap();
        assert_eq!(summary_of(item), alone, "{name}: the fleet's summary differs from fivex run");
    }
}

#[test]
fn the_same_results_whatever_the_number_of_workers() {
    let mut args = presets_args();
    args.extend(["--library", "trunnion-ac-tight-stroke,mixed-bc-singular-5deg,nutating-head-b45", "--report", "-q"]);
    let (_, one, err) = fleet("tilt.nc", &[&args[..], &["--jobs", "1"]].concat());
    assert!(err.is_empty(), "--quiet: {err}");
    let (_, three, _) = fleet("tilt.nc", &[&args[..], &["--jobs", "3"]].concat());
    assert_eq!(one, three);
}

#[test]
fn a_program_that_alarms_on_some_machines() {
    // Tool vectors with G43.5: a 3-axis machine has no rotary axis for them (PS5459, no
    // solution for the tool direction); the 5-axis machines run it and report it.
    let (code, items, _) =
        fleet("tilt.nc", &[&presets_args()[..], &["--library", "vmc-compact-3x", "--report", "-q"]].concat());
    assert_eq!(code, 1);
    let mill3 = by_machine(&items, "mill3");
    assert_eq!(mill3["status"], "alarm");
    assert_eq!(mill3["alarms"][0]["code"], "PS5459");
    assert_eq!(mill3["alarms"][0]["line"], 7);
    assert_eq!(mill3["report"]["status"], "alarm");
    assert_eq!(mill3["report"]["alarm"]["code"], "PS5459");
    // A Syntec parameter list runs in its own dialect.
    let syntec = by_machine(&items, "vmc-compact-3x");
    assert_eq!(syntec["dialect"], "syntec");
    assert_eq!(syntec["status"], "alarm");
    for name in ["head-bc", "table-ac", "table-bc", "mixed-bc"] {
        let v = by_machine(&items, name);
        assert_eq!(v["status"], "completed", "{name}: {v}");
        let report = &v["report"];
        assert_eq!(report["cycle_time_s"], v["cycle_time_s"]);
        // Under G43.5 the tip follows the programmed lines.
        assert!(report["tip_deviation"]["max"].as_f64().unwrap() < 1e-6, "{name}: {report}");
        let axes = report["axes"].as_array().unwrap();
        assert_eq!(axes.len(), 5);
        assert!(axes.iter().any(|a| a["rotary"] == true && a["travel"].as_f64().unwrap() > 0.0));
    }
}

#[test]
fn rotary_range_and_over_travel_alarms() {
    // 105° from +Z: head-bc's B reaches ±110 and runs it; mixed-bc's B stops at ±100, so no
    // solution lies within its range (PS5459).
    let (code, items, _) = fleet("overtilt.nc", &["--preset", "head-bc", "--preset", "mixed-bc", "-q"]);
    assert_eq!(code, 1);
    assert_eq!(by_machine(&items, "head-bc")["status"], "completed");
    let mixed = by_machine(&items, "mixed-bc");
    assert_eq!((mixed["alarms"][0]["code"].as_str(), mixed["alarms"][0]["line"].as_u64()), (Some("PS5459"), Some(7)));
    // X500: the bridge mill reaches it, the compact VMC (X ±260, a Syntec list) and the
    // trunnion (X ±325, FANUC list) do not.
    let (code, items, _) = fleet(
        "overtravel.nc",
        &[
            "--library",
            "vmc-bridge-3x,vmc-compact-3x,trunnion-ac-120",
            "--machine",
            &root().join("machines/fork-head-bc.json").display().to_string(),
            "-q",
        ],
    );
    assert_eq!(code, 1);
    assert_eq!(by_machine(&items, "vmc-bridge-3x")["status"], "completed");
    assert_eq!(by_machine(&items, "fork-head-bc")["status"], "completed");
    assert_eq!(by_machine(&items, "vmc-compact-3x")["alarms"][0]["code"], "MOT-001");
    let trunnion = by_machine(&items, "trunnion-ac-120");
    assert_eq!(
        (trunnion["alarms"][0]["code"].as_str(), trunnion["alarms"][0]["line"].as_u64()),
        (Some("OT0510"), Some(7))
    );
}

#[test]
fn a_malformed_program_alarms_everywhere_at_its_line() {
    let (code, items, _) =
        fleet("malformed.nc", &[&presets_args()[..], &["--library", "cradle-bc-110", "-q"]].concat());
    assert_eq!(code, 1);
    for v in &items {
        let expected = if v["dialect"] == "syntec" { "COR-001" } else { "PS0004" };
        assert_eq!(v["alarms"][0]["code"], expected, "{v}");
        assert_eq!(v["alarms"][0]["line"], 5);
    }
}

#[test]
fn every_machine_probes_the_workpiece_given() {
    let block = root().join("tests/fleet/probe_block.json").display().to_string();
    let machines = ["--preset", "mill3", "--preset", "table-ac"];
    let (code, bare, err) = fleet("probe.nc", &machines);
    assert_eq!(code, 0, "{err}");
    let (code, probed, err) = fleet("probe.nc", &[&machines[..], &["--workpiece", block.as_str()]].concat());
    assert_eq!(code, 0, "{err}");
    for name in ["mill3", "table-ac"] {
        // Nothing on the table: the probe runs its whole move to Z-10 (tool length 100: machine
        // Z 90). The block's top at table Z-3 stops the ball (radius 5) with its tip there.
        let (air, block_) = (by_machine(&bare, name), by_machine(&probed, name));
        assert_eq!(air["variables"]["#101"], -10.0, "{name}: {air}");
        assert_eq!(air["position"]["machine"]["Z"], 90.0, "{name}: {air}");
        assert_eq!(block_["variables"]["#101"], -3.0, "{name}: {block_}");
        assert_eq!(block_["position"]["machine"]["Z"], 97.0, "{name}: {block_}");
        // And each machine's summary is `fivex run --workpiece`'s, bit for bit.
        let p = program("probe.nc");
        let alone = fivex(&["run", &p, "--preset", name, "--workpiece", &block]);
        let alone: Value = serde_json::from_str(&stdout(&alone)).unwrap();
        assert_eq!(summary_of(block_), alone, "{name}");
    }
}

#[test]
fn usage_errors_exit_2() {
    let p = program("everywhere.nc");
    // A box whose min is not below its max (`Workpiece::check`), and a file that is no workpiece.
    let dir = std::env::temp_dir().join(format!("fivex-fleet-usage-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad_box = dir.join("flat.json");
    std::fs::write(&bad_box, r#"{"boxes": [{"min": [0, 0, 0], "max": [10, 10, 0]}]}"#).unwrap();
    let not_json = dir.join("tools.json");
    std::fs::write(&not_json, r#"{"1": {"length": 100, "radius": 5}}"#).unwrap();
    let (bad_box, not_json) = (bad_box.display().to_string(), not_json.display().to_string());
    for args in [
        vec!["fleet", p.as_str()],
        vec!["fleet", p.as_str(), "--preset", "nope"],
        vec!["fleet", p.as_str(), "--library", "nope"],
        vec!["fleet", p.as_str(), "--machine", "/nonexistent.json"],
        vec!["fleet", "/nonexistent.nc", "--preset", "mill3"],
        vec!["fleet", p.as_str(), "--preset", "mill3", "--workpiece", "/nonexistent.json"],
        vec!["fleet", p.as_str(), "--preset", "mill3", "--workpiece", bad_box.as_str()],
        vec!["fleet", p.as_str(), "--preset", "mill3", "--workpiece", not_json.as_str()],
    ] {
        let out = fivex(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
        assert!(stdout(&out).is_empty());
        assert!(stderr(&out).starts_with("fivex: "), "{}", stderr(&out));
    }
    let out = fivex(&["fleet", p.as_str(), "--preset", "mill3", "--workpiece", bad_box.as_str()]);
    assert!(stderr(&out).contains("box 0: min must be less than max"), "{}", stderr(&out));
    let _ = std::fs::remove_dir_all(&dir);
}
