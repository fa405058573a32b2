//! The `fivex` command line contract (`docs/contracts.md`, "CLI"): exit statuses, the `run` summary,
//! `--tools`, `--trace`, `check` and `interp` output formats. Everything goes through the real
//! binary, as a user or a script would drive it.

use crate::common;

use common::*;
use serde_json::Value;
use std::path::{Path, PathBuf};

/// A scratch directory holding `files`; returned with the paths of the files.
fn scratch(files: &[(&str, &str)]) -> (tempfile::TempDir, Vec<PathBuf>) {
    let dir = tempfile::tempdir().expect("tempdir");
    let paths = files
        .iter()
        .map(|(name, text)| {
            let p = dir.path().join(name);
            std::fs::write(&p, text).expect("write");
            p
        })
        .collect();
    (dir, paths)
}

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

/// `fivex run …`: exit status and the parsed summary; asserts stdout is exactly one object.
fn run_json(args: &[&str]) -> (i32, Value) {
    let out = fivex(&[&["run"], args].concat());
    let text = stdout(&out);
    let v: Value = serde_json::from_str(&text).unwrap_or_else(|e| {
        panic!("run stdout is not exactly one JSON value ({e}):\n{text}\nstderr: {}", stderr(&out))
    });
    assert!(v.is_object(), "run stdout is not an object: {text}");
    (out.status.code().expect("exit code"), v)
}

fn num(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

const SQUARE: &str = "G90 G54 G00 X0. Y0. Z10.\nG01 Z0. F600.\nX10.\nY10.\nX0.\nY0.\nG00 Z10.\nM30\n";

// --- exit statuses --------------------------------------------------------------------------

#[test]
fn exit_0_when_completed() {
    let (_d, p) = scratch(&[("ok.nc", SQUARE)]);
    let (code, v) = run_json(&[s(&p[0])]);
    assert_eq!(code, 0);
    assert_eq!(v["status"], "completed");
    assert_eq!(v["alarms"], serde_json::json!([]));
}

/// Syntec audit: a file saved with a UTF-8 byte order mark (Windows Notepad) failed with
/// "unexpected character 'ï'" in `run` and `check`, where the API drops the mark.
#[test]
fn a_byte_order_mark_is_no_character_of_the_program() {
    let (_d, p) = scratch(&[("bom.nc", &format!("\u{FEFF}{SQUARE}"))]);
    let (code, v) = run_json(&[s(&p[0])]);
    assert_eq!((code, &v["status"]), (0, &serde_json::json!("completed")), "{v}");
    let out = fivex(&["check", s(&p[0])]);
    assert_eq!(out.status.code(), Some(0), "{}{}", stdout(&out), stderr(&out));
}

#[test]
fn exit_1_when_alarm() {
    let (_d, p) = scratch(&[("alarm.nc", "G90 G00 X1.\nN70 #3000=1(STOP HERE)\nM30\n")]);
    let (code, v) = run_json(&[s(&p[0])]);
    assert_eq!(code, 1);
    assert_eq!(v["status"], "alarm");
    let a = &v["alarms"][0];
    assert_eq!(a["code"], "MC3001");
    assert_eq!(a["message"], "STOP HERE");
    assert_eq!(a["line"], 2);
    assert_eq!(a["n"], 70);
    // interp: the same alarm is exit 1 too.
    let out = fivex(&["interp", s(&p[0])]);
    assert_eq!(out.status.code(), Some(1), "interp stderr: {}", stderr(&out));
}

#[test]
fn alarm_n_is_null_without_sequence_number() {
    let (_d, p) = scratch(&[("alarm.nc", "#1=0\n#2=1/#1\nM30\n")]);
    let (code, v) = run_json(&[s(&p[0])]);
    assert_eq!(code, 1);
    assert_eq!(v["alarms"][0]["code"], "PS0112");
    assert_eq!(v["alarms"][0]["line"], 2);
    assert!(v["alarms"][0]["n"].is_null());
}

#[test]
fn exit_2_for_a_missing_file() {
    for cmd in ["run", "interp", "check"] {
        let out = fivex(&[cmd, "/nonexistent/dir/no-such-program.nc"]);
        assert_eq!(out.status.code(), Some(2), "{cmd}: stderr {}", stderr(&out));
        assert!(out.stdout.is_empty(), "{cmd} printed on stdout for a missing file: {}", stdout(&out));
        assert!(stderr(&out).contains("no-such-program.nc"), "{cmd}: the error names the file: {}", stderr(&out));
    }
}

#[test]
fn exit_2_for_a_bad_preset() {
    let (_d, p) = scratch(&[("ok.nc", SQUARE)]);
    for cmd in ["run", "interp"] {
        let out = fivex(&[cmd, s(&p[0]), "--preset", "no-such-machine"]);
        assert_eq!(out.status.code(), Some(2), "{cmd}");
        assert!(out.stdout.is_empty());
        assert!(stderr(&out).contains("no-such-machine"), "{}", stderr(&out));
    }
}

#[test]
fn exit_2_for_usage_errors() {
    let (_d, p) = scratch(&[("ok.nc", SQUARE), ("bad.json", "{not json"), ("neg.json", "{\"1\": {\"length\": 1.0}}")]);
    let cases: Vec<Vec<&str>> = vec![
        vec![],
        vec!["frobnicate"],
        vec!["run"],
        vec!["run", s(&p[0]), "--dialect", "heidenhain"],
        vec!["check", s(&p[0]), "--dialect", "heidenhain"],
        vec!["run", s(&p[0]), "--tools", s(&p[1])],
        vec!["run", s(&p[0]), "--tools", s(&p[2])],
        vec!["run", s(&p[0]), "--tools", "/nonexistent/tools.json"],
        vec!["run", s(&p[0]), "--machine", s(&p[1])],
        vec!["run", s(&p[0]), "--preset", "mill3", "--machine", s(&p[1])],
        vec!["run", s(&p[0]), "--period-ms", "0"],
        vec!["run", s(&p[0]), "--period-ms", "-1"],
        vec!["run", s(&p[0]), "--trace", "/nonexistent/dir/trace.jsonl"],
    ];
    for args in cases {
        let out = fivex(&args);
        assert_eq!(out.status.code(), Some(2), "fivex {args:?}: stdout {} stderr {}", stdout(&out), stderr(&out));
    }
}

// --- the run summary ------------------------------------------------------------------------

fn keys(v: &Value) -> Vec<String> {
    let mut k: Vec<String> = v.as_object().expect("object").keys().cloned().collect();
    k.sort();
    k
}

#[test]
fn run_summary_has_the_contract_fields() {
    let (_d, p) = scratch(&[(
        "p.nc",
        "G10 L2 P1 X100.\nG90 G54 G00 X5. Y6. Z7.\n#100=1.5\n#500=6\n#1=3\n#199=2\n#999=-1\nM30\n",
    )]);
    let (code, v) = run_json(&[s(&p[0])]);
    assert_eq!(code, 0);
    for field in ["status", "alarms", "blocks", "cycle_time_s", "position", "variables"] {
        assert!(v.get(field).is_some(), "missing field {field} in {v}");
    }
    assert!(v["status"].is_string());
    assert!(v["alarms"].is_array());
    assert!(v["blocks"].is_u64(), "blocks is an integer: {}", v["blocks"]);
    assert_eq!(v["blocks"], 8);
    assert!(num(&v["cycle_time_s"]) > 0.0);
    let pos = &v["position"];
    assert_eq!(keys(&pos["machine"]), ["X", "Y", "Z"]);
    assert_eq!(keys(&pos["workpiece"]), ["X", "Y", "Z"]);
    assert_eq!(num(&pos["machine"]["X"]), 105.0);
    assert_eq!(num(&pos["workpiece"]["X"]), 5.0);
    assert_eq!(num(&pos["workpiece"]["Z"]), 7.0);
    // Every common variable that is not vacant, keyed "#n"; locals are not listed.
    let vars = &v["variables"];
    assert_eq!(keys(vars), ["#100", "#199", "#500", "#999"]);
    assert_eq!(num(&vars["#100"]), 1.5);
    assert_eq!(num(&vars["#500"]), 6.0);
    assert_eq!(num(&vars["#999"]), -1.0);
}

#[test]
fn position_is_keyed_by_the_machine_axis_letters() {
    let (_d, p) = scratch(&[("p.nc", "G90 G00 X1. Y2. Z3.\nM30\n")]);
    for (preset, axes) in [
        ("mill3", vec!["X", "Y", "Z"]),
        ("head-bc", vec!["B", "C", "X", "Y", "Z"]),
        ("table-ac", vec!["A", "C", "X", "Y", "Z"]),
        ("table-bc", vec!["B", "C", "X", "Y", "Z"]),
        ("mixed-bc", vec!["B", "C", "X", "Y", "Z"]),
    ] {
        let (code, v) = run_json(&[s(&p[0]), "--preset", preset]);
        assert_eq!(code, 0, "{preset}: {v}");
        assert_eq!(keys(&v["position"]["machine"]), axes, "{preset}");
        assert_eq!(keys(&v["position"]["workpiece"]), axes, "{preset}");
    }
}

/// Preset linear axes: 30000 mm/min rapid, 4000 mm/s², 80000 mm/s³.
const JERK: f64 = 80_000.0;

/// Rest-to-rest time of a straight move of `len` mm cruising at `v` mm/s when `v·J ≤ A²` (the
/// speed change is two jerk phases of √(v/J) each, covering v·√(v/J)): cruise time plus one
/// speed change.
fn short_ramp_move(len: f64, v: f64, jerk: f64) -> f64 {
    len / v + 2.0 * (v / jerk).sqrt()
}

#[test]
fn cycle_time_is_simulated_length_over_feed() {
    // 10 mm at F600 (10 mm/s) with a jerk-limited start and stop, then a 2.5 s dwell: however
    // fast the machine running the test.
    let (_d, p) = scratch(&[("p.nc", "G90 G01 X10. F600.\nG04 X2.5\nM30\n")]);
    let (_, v) = run_json(&[s(&p[0])]);
    let expected = short_ramp_move(10.0, 10.0, JERK) + 2.5;
    assert!((num(&v["cycle_time_s"]) - expected).abs() < 1e-9, "{} vs {expected}", v["cycle_time_s"]);
}

#[test]
fn dialect_changes_alarm_codes() {
    let (_d, p) = scratch(&[("p.nc", "#1=0\n#2=1/#1\nM30\n")]);
    let (_, f) = run_json(&[s(&p[0]), "--dialect", "fanuc"]);
    let (_, sy) = run_json(&[s(&p[0]), "--dialect", "syntec"]);
    assert_eq!(f["alarms"][0]["code"], "PS0112");
    assert_eq!(sy["alarms"][0]["code"], "COR-004");
}

/// Syntec audit: a Syntec parameter list given with `--machine` ran its programs as FANUC text
/// (`X[7/2*1.]` reached 3.5 and `X10` 0.010 mm) in `run`, `check` and `interp`, while `fleet`
/// and the API took the list's own dialect. Now the list's dialect is the default there too,
/// and `--dialect` still decides when given.
#[test]
fn a_parameter_list_runs_in_its_own_dialect() {
    let syntec = concat!(env!("CARGO_MANIFEST_DIR"), "/../machines/cradle-bc-110.json");
    let (_d, p) = scratch(&[("p.nc", "G90 G01 X10 F100.\nM30\n")]);
    let p = [p[0].clone(), PathBuf::from(syntec)];
    let (code, v) = run_json(&[s(&p[0]), "--machine", s(&p[1])]);
    assert_eq!((code, v["alarms"][0]["code"].as_str()), (1, Some("COR-048")), "{v}");
    let (code, v) = run_json(&[s(&p[0]), "--machine", s(&p[1]), "--dialect", "fanuc"]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(num(&v["position"]["machine"]["X"]), 0.01);
    let check = fivex(&["check", s(&p[0]), "--machine", s(&p[1])]);
    assert!(stdout(&check).contains("COR-048"), "{}", stdout(&check));
    let interp = fivex(&["interp", s(&p[0]), "--machine", s(&p[1])]);
    assert!(stderr(&interp).contains("COR-048"), "{}{}", stdout(&interp), stderr(&interp));
}

/// Fleet audit: a key given twice in a JSON file was taken silently, the last winning. A
/// machine, workpiece or variables file that does so is a usage error naming the key.
#[test]
fn a_json_file_giving_a_key_twice_is_refused() {
    let machine = r#"{"name": "m", "axes": [{"name": "X", "kind": "linear", "rapid": 6000.0, "rapid": 60.0}]}"#;
    let (_d, p) = scratch(&[
        ("p.nc", "G90 G00 X10.\nM30\n"),
        ("m.json", machine),
        ("w.json", r#"{"boxes": [], "boxes": []}"#),
        ("v.json", r##"{"#500": 1, "#500": 2}"##),
    ]);
    for (flag, file) in [("--machine", &p[1]), ("--workpiece", &p[2]), ("--variables", &p[3])] {
        let out = fivex(&["run", s(&p[0]), flag, s(file)]);
        assert_eq!(out.status.code(), Some(2), "{flag}: {}", stderr(&out));
        assert!(stderr(&out).contains("is given twice"), "{flag}: {}", stderr(&out));
    }
    let out = fivex(&["fleet", s(&p[0]), "--machine", s(&p[1])]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
}

#[test]
fn machine_file_is_accepted() {
    let machine = r#"{"name": "xyzb", "axes": [
        {"name": "X", "kind": "linear", "rapid": 6000.0},
        {"name": "Y", "kind": "linear", "rapid": 6000.0},
        {"name": "Z", "kind": "linear", "rapid": 6000.0},
        {"name": "B", "kind": "rotary", "rapid": 3600.0}]}"#;
    let (_d, p) = scratch(&[("p.nc", "G90 G00 X60. B90.\nM30\n"), ("m.json", machine)]);
    let (code, v) = run_json(&[s(&p[0]), "--machine", s(&p[1])]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(keys(&v["position"]["machine"]), ["B", "X", "Y", "Z"]);
    // A straight line in X-B space: B90 at 3600 deg/min needs 1.5 s, X60 at 6000 mm/min 0.6 s, so
    // B sets the speed, and (defaults: 0.2 s to rapid, 50 ms to full acceleration) B's
    // acceleration 300 deg/s² and jerk 6000 deg/s³ too. Reaching 60 deg/s takes
    // 60/300 + 300/6000 = 0.25 s: 1.5 + 0.25 s.
    assert!((num(&v["cycle_time_s"]) - 1.75).abs() < 1e-9, "{}", v["cycle_time_s"]);
}

/// Issue 17, item 1: what a machine file sets that fivex does not carry out is named on stderr
/// (a parameter the model does not read, a bit it does not read, a field it does not know); the
/// run itself goes on. A file with nothing of the kind warns nothing; STCP's tolerances, once
/// kept without effect, are carried out now and warn nothing.
#[test]
fn run_warns_of_unmodelled_machine_settings() {
    let fanuc = r#"{"name": "f", "dialect": "fanuc", "parameters": {
        "1020": [88, 89, 90], "1006": [0, 0, 0], "1420": [6000, 6000, 6000],
        "8130": 3, "19608": 1}}"#;
    let model = r#"{"name": "m", "axes": [
        {"name": "X", "kind": "linear", "rapid": 6000.0},
        {"name": "Y", "kind": "linear", "rapid": 6000.0},
        {"name": "Z", "kind": "linear", "rapid": 6000.0}],
        "five_axis": {"smooth_tolerance": [0.5, 0.5]}, "spindle_max_rpm": 12000}"#;
    let plain = r#"{"name": "p", "dialect": "fanuc", "parameters": {
        "1020": [88, 89, 90], "1006": [0, 0, 0], "1420": [6000, 6000, 6000]}}"#;
    let (_d, p) = scratch(&[("p.nc", "G90 G00 X10.\nM30\n"), ("f.json", fanuc), ("m.json", model), ("q.json", plain)]);
    let warnings = |file: &Path| {
        let out = fivex(&["run", s(&p[0]), "--machine", s(file)]);
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
        stderr(&out).lines().filter(|l| l.starts_with("warning:")).map(str::to_string).collect::<Vec<_>>()
    };
    let f = warnings(&p[1]);
    assert_eq!(f.len(), 2, "{f:?}");
    assert!(f[0].contains("No.8130 is not modelled") && f[1].contains("No.19608#0 is not modelled"), "{f:?}");
    let m = warnings(&p[2]);
    assert_eq!(m.len(), 1, "{m:?}");
    assert!(m[0].contains("spindle_max_rpm is not modelled"), "{m:?}");
    assert_eq!(warnings(&p[3]), Vec::<String>::new());
}

// --- --tools --------------------------------------------------------------------------------

#[test]
fn tools_file_changes_tool_length() {
    let prog = "G90 G00 G43 H1 Z0.\n#100=#5023\nG43 H2 Z0.\n#101=#5023\nM30\n";
    let (_d, p) = scratch(&[
        ("p.nc", prog),
        ("tools.json", r#"{"1": {"length": 123.4, "radius": 3.0}, "2": {"length": 50.0, "radius": 2.0}}"#),
    ]);
    // Default: every offset 1-99 is 100 mm.
    let (_, v) = run_json(&[s(&p[0])]);
    assert_eq!(num(&v["variables"]["#100"]), 100.0);
    assert_eq!(num(&v["variables"]["#101"]), 100.0);
    let (code, v) = run_json(&[s(&p[0]), "--tools", s(&p[1])]);
    assert_eq!(code, 0);
    assert_eq!(num(&v["variables"]["#100"]), 123.4);
    assert_eq!(num(&v["variables"]["#101"]), 50.0);
    assert_eq!(num(&v["position"]["machine"]["Z"]), 50.0);
    assert_eq!(num(&v["position"]["workpiece"]["Z"]), 0.0);
}

#[test]
fn tools_file_sets_radius_too() {
    let (_d, p) = scratch(&[
        ("p.nc", "#100=#13007\n#101=#11007\nM30\n"),
        ("t.json", r#"{"7": {"length": 90.0, "radius": 4.5}}"#),
    ]);
    let (_, v) = run_json(&[s(&p[0]), "--tools", s(&p[1])]);
    assert_eq!(num(&v["variables"]["#100"]), 4.5, "D geometry #13007");
    assert_eq!(num(&v["variables"]["#101"]), 90.0, "H geometry #11007");
}

#[test]
fn tools_file_may_give_a_corner_radius() {
    let (_d, p) = scratch(&[
        ("p.nc", "G90 G00 G43 H7 Z0.\n#100=#13007\n#101=#11007\nM30\n"),
        ("plain.json", r#"{"7": {"length": 90.0, "radius": 4.5}}"#),
        (
            "corner.json",
            r#"{"7": {"length": 90.0, "radius": 4.5, "corner_radius": 1.0}, "8": {"length": 1.0, "radius": 0.5, "corner_radius": 0}}"#,
        ),
        ("negative.json", r#"{"7": {"length": 90.0, "radius": 4.5, "corner_radius": -1.0}}"#),
        ("text.json", r#"{"7": {"length": 90.0, "radius": 4.5, "corner_radius": "1"}}"#),
    ]);
    // Optional: a table with corner radii runs as the one without (nothing here reads them).
    let (code, plain) = run_json(&[s(&p[0]), "--tools", s(&p[1])]);
    assert_eq!(code, 0);
    let (code, corner) = run_json(&[s(&p[0]), "--tools", s(&p[2])]);
    assert_eq!(code, 0);
    assert_eq!(corner, plain);
    assert_eq!(num(&corner["variables"]["#100"]), 4.5, "D geometry #13007");
    // A negative corner radius: a usage error naming it, no panic; one that is not a number is
    // a usage error as any malformed table is (serde's message, with its line and column).
    for (bad, cmd, says) in [
        (&p[3], "run", "corner_radius"),
        (&p[3], "check", "corner_radius"),
        (&p[3], "interp", "corner_radius"),
        (&p[4], "run", "expected f64"),
    ] {
        // (`check` reads the tools when it runs the program on a machine.)
        let out = fivex(&[cmd, s(&p[0]), "--preset", "mill3", "--tools", s(bad)]);
        assert_eq!(out.status.code(), Some(2), "{cmd} {}: {}", s(bad), stderr(&out));
        assert!(out.stdout.is_empty(), "{cmd}: {}", stdout(&out));
        let err = stderr(&out);
        assert!(err.contains(says) && !err.contains("panicked"), "{cmd}: {err}");
    }
}

#[test]
fn tools_file_values_beyond_the_g10_range_are_usage_errors() {
    // The range G10 takes (geometry ±999.999 mm, `interp::tool_value_limit`): a table beyond it
    // is a bad input file (exit 2, the file, the offset, the value and the range named), not a
    // run with a tool length no program could set. At the limit it runs.
    let (_d, p) = scratch(&[
        ("p.nc", "#100=#11007\nM30\n"),
        ("long.json", r#"{"7": {"length": 1000.0, "radius": 4.5}}"#),
        ("radius.json", r#"{"7": {"length": 90.0, "radius": -999.9991}}"#),
        ("corner.json", r#"{"7": {"length": 90.0, "radius": 4.5, "corner_radius": 1000.0}}"#),
        ("limit.json", r#"{"7": {"length": 999.999, "radius": -999.999, "corner_radius": 999.999}}"#),
    ]);
    for (bad, says) in [
        (&p[1], "tool offset 7: length 1000 is outside ±999.999 mm"),
        (&p[2], "radius -999.9991"),
        (&p[3], "corner_radius 1000"),
    ] {
        tools_file_refused(&p[0], bad, says);
    }
    let (code, v) = run_json(&[s(&p[0]), "--preset", "mill3", "--tools", s(&p[4])]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(num(&v["variables"]["#100"]), 999.999);
}

/// `run`, `check` and `interp` of `program` with the tools file `bad`: a usage error (exit 2,
/// nothing on stdout) whose message names the file and says `says`.
fn tools_file_refused(program: &Path, bad: &Path, says: &str) {
    for cmd in ["run", "check", "interp"] {
        let out = fivex(&[cmd, s(program), "--preset", "mill3", "--tools", s(bad)]);
        assert_eq!(out.status.code(), Some(2), "{cmd} {}: {}", s(bad), stderr(&out));
        assert!(out.stdout.is_empty(), "{cmd}: {}", stdout(&out));
        let err = stderr(&out);
        assert!(err.contains(says) && err.contains(s(bad)) && !err.contains("panicked"), "{cmd}: {err}");
    }
}

/// A tools file takes the values `PUT /controllers/{id}/tool-offsets/{n}` takes: the wears act
/// (G43 H1 with length 100 and wear −0.5 stands 99.5 above zero, #10001 reads the wear, the
/// radius wear is #12001), a wear beyond ±99.999 is refused, and any other field (a misspelled
/// name) or an offset number given twice is a usage error naming the file and the field: they
/// were dropped without a word, and the run cut by the wear off.
#[test]
fn tools_file_takes_the_wears_and_refuses_unknown_fields() {
    let (_d, p) = scratch(&[
        ("p.nc", "G21 G90 G54 G00 X0 Y0\nG43 H1 Z0\n#100=#10001\n#101=#12001\nM30\n"),
        ("wear.json", r#"{"1": {"length": 100, "radius": 5, "length_wear": -0.5, "radius_wear": 0.1}}"#),
        ("misspelled.json", r#"{"1": {"length": 100, "radius": 5, "lenght_wear": -0.5}}"#),
        ("wear_key.json", r#"{"1": {"length": 100, "radius": 5, "wear": 1}}"#),
        ("beyond.json", r#"{"1": {"length": 100, "radius": 5, "length_wear": 100.0}}"#),
        ("twice.json", r#"{"1": {"length": 100, "radius": 5}, "1": {"length": 90, "radius": 5}}"#),
    ]);
    let (code, v) = run_json(&[s(&p[0]), "--preset", "mill3", "--tools", s(&p[1])]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(num(&v["position"]["machine"]["Z"]), 99.5, "{v}");
    assert_eq!((num(&v["variables"]["#100"]), num(&v["variables"]["#101"])), (-0.5, 0.1), "{v}");
    for (bad, says) in [
        (&p[2], "unknown field `lenght_wear`"),
        (&p[3], "unknown field `wear`"),
        (&p[4], "tool offset 1: length_wear 100 is outside ±99.999 mm"),
        (&p[5], "the key \"1\" is given twice"),
    ] {
        tools_file_refused(&p[0], bad, says);
        let out = fivex(&["fleet", s(&p[0]), "--preset", "mill3", "--tools", s(bad)]);
        assert_eq!(out.status.code(), Some(2), "fleet {}: {}", s(bad), stderr(&out));
        assert!(stderr(&out).contains(says), "fleet: {}", stderr(&out));
    }
}

// --- --trace --------------------------------------------------------------------------------

fn read_trace(path: &Path) -> Vec<Value> {
    let text = std::fs::read_to_string(path).expect("trace file written");
    assert!(text.ends_with('\n'), "trace ends with a newline");
    text.lines()
        .enumerate()
        .map(|(i, l)| {
            let v: Value =
                serde_json::from_str(l).unwrap_or_else(|e| panic!("trace line {} is not JSON ({e}): {l}", i + 1));
            assert!(v.is_object(), "trace line {} is not an object", i + 1);
            v
        })
        .collect()
}

#[test]
fn trace_writes_one_object_per_period() {
    // The feed move (see above), 0.5 s of dwell, a 10 mm rapid that never reaches rapid speed:
    // two S-curves to a peak vp with vp·√(vp/J) = 5 mm each, 2√(vp/J) s each.
    let prog = "G90 G01 X10. F600.\nN20 G04 X0.5\nG00 X0.\nM30\n";
    let (d, p) = scratch(&[("p.nc", prog)]);
    let peak = (5.0 * JERK.sqrt()).powf(2.0 / 3.0);
    let total = short_ramp_move(10.0, 10.0, JERK) + 0.5 + 4.0 * (peak / JERK).sqrt();
    for period_ms in [1.0, 10.0, 4.0] {
        let expected = total * 1000.0 / period_ms;
        let trace = d.path().join(format!("t{period_ms}.jsonl"));
        let mut args = vec![s(&p[0]), "--trace", s(&trace)];
        let period_arg = period_ms.to_string();
        args.extend(["--period-ms", period_arg.as_str()]);
        let (code, v) = run_json(&args);
        assert_eq!(code, 0);
        let cycle = num(&v["cycle_time_s"]);
        assert!((cycle - total).abs() < 1e-9, "{cycle} vs {total}");
        let samples = read_trace(&trace);
        let n = samples.len() as f64;
        assert!(
            (n - expected).abs() <= 2.0,
            "period {period_ms} ms: {n} samples for {cycle} s (expected about {expected})"
        );
        let period = period_ms / 1000.0;
        let mut last_t = -1.0;
        for (i, smp) in samples.iter().enumerate() {
            assert_eq!(
                keys(smp),
                ["feed", "line", "machine", "n", "programmed", "programmed_in", "t", "tip", "tool"],
                "sample {i}: {smp}"
            );
            let t = num(&smp["t"]);
            assert!(t > last_t, "t increases: {last_t} then {t}");
            assert!(
                (t - (i as f64 + if num(&samples[0]["t"]) > 0.0 { 1.0 } else { 0.0 }) * period).abs() < 1e-9,
                "sample {i} at {t}"
            );
            last_t = t;
            assert!(smp["line"].is_u64());
            assert!(smp["n"].is_null() || smp["n"].is_u64());
            assert_eq!(keys(&smp["machine"]), ["X", "Y", "Z"]);
            let tip = smp["tip"].as_array().expect("tip array");
            let tool = smp["tool"].as_array().expect("tool array");
            assert_eq!((tip.len(), tool.len()), (3, 3));
            let norm: f64 = tool.iter().map(|x| num(x) * num(x)).sum::<f64>().sqrt();
            assert!((norm - 1.0).abs() < 1e-9, "tool is a unit vector: {tool:?}");
            assert!(num(&smp["feed"]) >= 0.0);
        }
        // Inside the G01 at cruise: feed 600 mm/min, the tip along X at 10 mm/s, behind the
        // ideal position by half the ramp time (the S-curve is symmetric).
        let ramp = 2.0 * (10.0 / JERK).sqrt();
        let mid = samples.iter().find(|s| (num(&s["t"]) - 0.5).abs() < 1e-9).expect("a sample at t=0.5");
        assert_eq!(mid["line"], 1);
        assert!((num(&mid["feed"]) - 600.0).abs() < 1e-6, "{mid}");
        assert!((num(&mid["tip"][0]) - 10.0 * (0.5 - ramp / 2.0)).abs() < 1e-6, "{mid}");
        // Inside the dwell: feed 0, line 2, N20.
        let dwell = samples.iter().find(|s| (num(&s["t"]) - 1.3).abs() < 1e-9).expect("a sample at t=1.3");
        assert_eq!(dwell["line"], 2);
        assert_eq!(dwell["n"], 20);
        assert_eq!(num(&dwell["feed"]), 0.0);
        assert!((num(&dwell["tip"][0]) - 10.0).abs() < 1e-9);
    }
}

#[test]
fn trace_tip_is_in_the_workpiece_system() {
    // The dwell at the end gives samples at the final point (samples are at multiples of the period).
    let prog = "G10 L2 P1 X100. Y50.\nG90 G54 G01 X10. Y0. F6000.\nG43 H1 Z5.\nG04 X0.1\nM30\n";
    let (d, p) = scratch(&[("p.nc", prog)]);
    let trace = d.path().join("t.jsonl");
    let (code, v) = run_json(&[s(&p[0]), "--trace", s(&trace)]);
    assert_eq!(code, 0, "{v}");
    let samples = read_trace(&trace);
    let last = samples.last().expect("samples");
    // Machine: work offset and tool length added; tip: machine − tool length − work offset.
    assert!((num(&last["machine"]["X"]) - 110.0).abs() < 1e-9, "{last}");
    assert!((num(&last["machine"]["Z"]) - 105.0).abs() < 1e-9, "{last}");
    assert!((num(&last["tip"][0]) - 10.0).abs() < 1e-9, "{last}");
    assert!((num(&last["tip"][1]) - 0.0).abs() < 1e-9, "{last}");
    assert!((num(&last["tip"][2]) - 5.0).abs() < 1e-9, "{last}");
    assert_eq!(last["tool"], serde_json::json!([0.0, 0.0, 1.0]));
    assert_eq!(
        (&last["programmed"], &last["programmed_in"]),
        (&serde_json::json!([10.0, 0.0, 5.0]), &"workpiece".into())
    );
    let pos = &v["position"];
    assert_eq!(
        (&pos["tip"], &pos["tool"]),
        (&serde_json::json!([10.0, 0.0, 5.0]), &serde_json::json!([0.0, 0.0, 1.0]))
    );
    assert_eq!(
        (&pos["programmed"], &pos["programmed_in"]),
        (&serde_json::json!([10.0, 0.0, 5.0]), &"workpiece".into())
    );
}

/// On a table machine under G43.4 started with the table turned, the trace's `tip` is what
/// `fivex kin fk` gives for the sampled axes and the 100 mm tool, less the work offset (the
/// workpiece system fixed on the table), and `programmed` is the point in Π.
#[test]
fn trace_tip_is_fivex_kin_fk_of_the_sampled_axes() {
    let prog = "G10 L2 P1 X20. Y-10. Z-50.\nG90 G54 G00 X0 Y0 Z100. A30. C0\nG43.4 H1\n\
                G01 X10. Y10. Z10. A45. C30. F3000.\nG49\nM30\n";
    let (d, p) = scratch(&[("p.nc", prog)]);
    let trace = d.path().join("t.jsonl");
    let (code, v) = run_json(&[s(&p[0]), "--preset", "table-ac", "--trace", s(&trace)]);
    assert_eq!(code, 0, "{v}");
    let samples = read_trace(&trace);
    let moving: Vec<&Value> = samples.iter().filter(|x| x["line"] == 4).collect();
    assert!(moving.len() > 20, "{} samples on the G43.4 move", moving.len());
    for smp in [moving[0], moving[moving.len() / 2], moving[moving.len() - 1]] {
        let m = &smp["machine"];
        let axes =
            format!("X={},Y={},Z={},A={},C={}", num(&m["X"]), num(&m["Y"]), num(&m["Z"]), num(&m["A"]), num(&m["C"]));
        let out = fivex(&["kin", "fk", "--preset", "table-ac", "--axes", &axes, "--tool-length", "100"]);
        let fk: Value = serde_json::from_str(&stdout(&out)).expect("fk JSON");
        for (k, offset) in [20.0, -10.0, -50.0].into_iter().enumerate() {
            let expected = num(&fk["tip"][k]) - offset;
            assert!((num(&smp["tip"][k]) - expected).abs() < 1e-9, "{smp}\nfk {fk}");
            assert!((num(&smp["tool"][k]) - num(&fk["tool"][k])).abs() < 1e-12, "{smp}\nfk {fk}");
        }
        assert_eq!(smp["programmed_in"], "programming");
    }
    // Π was fixed on the table at A30: the programmed end (10, 10, 10) is not the tip's.
    let last = moving[moving.len() - 1];
    let apart: f64 = (0..3).map(|k| (num(&last["tip"][k]) - num(&last["programmed"][k])).powi(2)).sum::<f64>().sqrt();
    assert!(apart > 1.0, "{last}");
}

#[test]
fn trace_follows_the_arc() {
    // A half circle of radius 10 about (0,0) from (10,0) to (-10,0), CCW: every sample is on it.
    let prog = "G90 G00 X10. Y0.\nG03 X-10. Y0. R10. F1000.\nM30\n";
    let (d, p) = scratch(&[("p.nc", prog)]);
    let trace = d.path().join("t.jsonl");
    let (_, v) = run_json(&[s(&p[0]), "--trace", s(&trace)]);
    // The rapid: 10 mm as in trace_writes_one_object_per_period. The arc at 1000 mm/min
    // (docs/motion.md, "Limits", on an arc): the turning at the top speed w takes half the axes'
    // acceleration A = 4000 (w = √(A·r/2) = 141.42 mm/s, below ∛(J·r²/2) = 158.74; half is the
    // faster of the two shares here), the speed changes what is left at w: acceleration
    // min(√(A² − (w²/r)²), ½·√(J² − (w³/r²)²)·r/(3w)) = 881.92, jerk √(J² − (3wa/r)²) − w³/r²
    // = 42426.4. At 16.67 mm/s the ramp is jerk-limited (v·j ≤ a²).
    let peak = (5.0 * JERK.sqrt()).powf(2.0 / 3.0);
    let rapid = 4.0 * (peak / JERK).sqrt();
    let (accel, r) = (4000.0f64, 10.0f64);
    let w = (accel * r / 2.0).sqrt();
    let (pull, turn) = (w * w / r, w.powi(3) / (r * r));
    let a = (accel * accel - pull * pull).sqrt().min(0.5 * (JERK * JERK - turn * turn).sqrt() * r / (3.0 * w));
    let j = (JERK * JERK - (3.0 * w * a / r).powi(2)).sqrt() - turn;
    assert!((1000.0 / 60.0) * j <= a * a);
    let t_arc = short_ramp_move(10.0 * std::f64::consts::PI, 1000.0 / 60.0, j);
    assert!((num(&v["cycle_time_s"]) - (rapid + t_arc)).abs() < 1e-9, "{}", v["cycle_time_s"]);
    let samples = read_trace(&trace);
    let on_arc: Vec<&Value> = samples.iter().filter(|s| s["line"] == 2).collect();
    assert!(on_arc.len() > 1000);
    for smp in on_arc {
        let (x, y) = (num(&smp["tip"][0]), num(&smp["tip"][1]));
        assert!(((x * x + y * y).sqrt() - 10.0).abs() < 1e-6, "off the arc: {smp}");
        assert!(y >= -1e-9, "CCW from +X to -X stays in y >= 0: {smp}");
        assert!(num(&smp["feed"]) <= 1000.0 + 1e-6, "{smp}");
    }
    // Past the speed-up, the programmed feed.
    let middle = samples.iter().filter(|s| s["line"] == 2).nth(900).expect("a sample mid-arc");
    assert!((num(&middle["feed"]) - 1000.0).abs() < 1e-6, "{middle}");
}

// --- check ----------------------------------------------------------------------------------

/// `PROGRAM:LINE:COL: CODE message` → (line, col, code).
fn parse_diag<'a>(line: &'a str, program: &str) -> (u32, u32, &'a str) {
    let rest = line
        .strip_prefix(program)
        .unwrap_or_else(|| panic!("diagnostic does not start with the program path {program}: {line}"));
    let rest = rest.strip_prefix(':').unwrap_or_else(|| panic!("no ':' after the program: {line}"));
    let mut parts = rest.splitn(3, ':');
    let l: u32 = parts.next().and_then(|x| x.parse().ok()).unwrap_or_else(|| panic!("no LINE: {line}"));
    let c: u32 = parts.next().and_then(|x| x.parse().ok()).unwrap_or_else(|| panic!("no COL: {line}"));
    let tail = parts.next().unwrap_or_else(|| panic!("no message: {line}"));
    let tail = tail.strip_prefix(' ').unwrap_or_else(|| panic!("no space after COL: {line}"));
    let (code, message) = tail.split_once(' ').unwrap_or_else(|| panic!("no message after the code: {line}"));
    assert!(
        code.chars().all(|ch| ch.is_ascii_uppercase() || ch.is_ascii_digit() || ch == '-'),
        "code {code:?}: {line}"
    );
    assert!(code.chars().any(|ch| ch.is_ascii_digit()), "code {code:?}: {line}");
    assert!(!message.trim().is_empty(), "empty message: {line}");
    assert!(l >= 1 && c >= 1, "1-based: {line}");
    (l, c, code)
}

#[test]
fn check_is_silent_and_exit_0_on_a_clean_program() {
    let (_d, p) = scratch(&[("ok.nc", SQUARE)]);
    let out = fivex(&["check", s(&p[0])]);
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(stdout(&out), "");
}

#[test]
fn check_collects_every_diagnostic() {
    let prog = "\
O0001
G90 G00 X0 Y0
G12.3 X1
#1=[1+
GOTO 999
M98 P4242
G01 X1 Y2 F100 $
WHILE[#1LT3]DO1
G77.7
M30
";
    let (_d, p) = scratch(&[("many.nc", prog)]);
    let program = s(&p[0]);
    let out = fivex(&["check", program]);
    assert_eq!(out.status.code(), Some(1), "stderr: {}", stderr(&out));
    let text = stdout(&out);
    let diags: Vec<(u32, u32, &str)> = text.lines().map(|l| parse_diag(l, program)).collect();
    let lines: Vec<u32> = diags.iter().map(|d| d.0).collect();
    assert_eq!(lines, [3, 4, 5, 6, 7, 8, 9], "one diagnostic per bad line, in order:\n{text}");
    let codes: Vec<&str> = diags.iter().map(|d| d.2).collect();
    assert_eq!(codes[0], "PS0010", "{text}");
    assert_eq!(codes[2], "PS0128", "{text}");
    assert_eq!(codes[3], "PS0078", "{text}");
    assert_eq!(codes[6], "PS0010", "{text}");
    // The column points at the culprit: G12.3 at column 1, '$' at column 16.
    assert_eq!(diags[0].1, 1);
    assert_eq!(diags[4].1, 16, "{text}");
}

#[test]
fn check_uses_the_dialect_codes() {
    let (_d, p) = scratch(&[("p.nc", "G12.3\nG53.3\nM30\n")]);
    let fanuc = stdout(&fivex(&["check", s(&p[0])]));
    let syntec = stdout(&fivex(&["check", s(&p[0]), "--dialect", "syntec"]));
    let codes = |t: &str| t.lines().map(|l| parse_diag(l, s(&p[0])).2.to_string()).collect::<Vec<_>>();
    assert_eq!(codes(&fanuc), ["PS0010", "PS0010"], "{fanuc}");
    // G53.3 is a Syntec code: only G12.3 is wrong there.
    assert_eq!(codes(&syntec), ["COR-070"], "{syntec}");
}

#[test]
fn check_on_a_machine_reports_what_only_that_machine_refuses() {
    // B is an axis of head-bc, not of mill3; G43.4 is refused on a machine without rotary axes.
    let prog = "G90 G00 X10. Y5.\nG43.4 H1\nG01 X20. B30. F500.\nM98 P4242\nM30\n";
    let (_d, p) = scratch(&[("b.nc", prog)]);
    let program = s(&p[0]);
    let plain = stdout(&fivex(&["check", program]));
    let codes = |t: &str| {
        t.lines().map(|l| (parse_diag(l, program).0, parse_diag(l, program).2.to_string())).collect::<Vec<_>>()
    };
    assert_eq!(codes(&plain), [(4, "PS0078".to_string())], "without a machine only the text is checked:\n{plain}");
    let out = fivex(&["check", program, "--preset", "mill3"]);
    assert_eq!(out.status.code(), Some(1));
    let mill3 = stdout(&out);
    let found = codes(&mill3);
    assert_eq!(found.len(), 2, "{mill3}");
    assert!(found[0].0 == 2 || found[0].0 == 3, "the machine's alarm comes first, at its line:\n{mill3}");
    assert!(found[0].1.starts_with("PS"), "{mill3}");
    assert!(mill3.lines().next().unwrap().ends_with("when run on mill3"), "{mill3}");
    assert_eq!(found[1], (4, "PS0078".to_string()), "{mill3}");
    // On head-bc the program is fine but for the missing subprogram of the static check.
    let head = stdout(&fivex(&["check", program, "--preset", "head-bc"]));
    assert_eq!(codes(&head), [(4, "PS0078".to_string())], "{head}");
}

/// Without a machine, a program the default machine stops early (a 5-axis program on mill3,
/// at its first B word) was checked from the text only after that point, and check said nothing
/// of it: exit 0, as for a program run to its end. stderr now says where the run stopped and
/// why; the exit stays 0 (mill3's alarm is not the text's).
#[test]
fn check_without_a_machine_says_where_the_default_machines_run_stopped() {
    let five_axis = "G90 G00 X0 Y0 Z50. B0 C0\nG43.4 H1\nG01 X10. B30. F1000.\nM30\n";
    let (_d, p) = scratch(&[("five.nc", five_axis)]);
    let out = fivex(&["check", s(&p[0])]);
    assert_eq!(out.status.code(), Some(0), "{}", stdout(&out));
    let err = stderr(&out);
    assert!(err.contains(":1: the run on mill3 (the default machine) stopped here"), "{err}");
    assert!(err.contains("--preset") && err.contains("--machine"), "{err}");
    // On a machine it runs to its end: nothing to say.
    let out = fivex(&["check", s(&p[0]), "--preset", "head-bc"]);
    assert_eq!((out.status.code(), stderr(&out)), (Some(0), String::new()), "{}", stdout(&out));
}

/// A groove 4 wide, cut with the default tool (radius 5) under G41: the interference check's
/// PS0041 at line 6, where the compensated block would run backwards.
#[test]
fn check_on_a_machine_passes_over_only_a_program_the_file_lacks() {
    // PS0078 has several causes: a call of O4242 may be a program the control holds, but a
    // return to a sequence number the caller lacks (`M99 P77`) and a call without P are errors
    // of the file itself, which a run on the machine stops with.
    let missing_line = "G90 G00 X0 Y0 Z50.\nM98 P20\nM30\nO0020\nG01 X10. F100.\nM99 P77\n";
    let no_p = "G90 G00 X0 Y0 Z50.\nG65 A1. B2.\nM30\n";
    let other_program = "G90 G00 X0 Y0 Z50.\nM98 P4242\nM30\n";
    let (_d, p) = scratch(&[("line.nc", missing_line), ("nop.nc", no_p), ("other.nc", other_program)]);
    for dialect in ["fanuc", "syntec"] {
        let first = |i: usize| {
            let out = fivex(&["check", s(&p[i]), "--preset", "mill3", "--dialect", dialect]);
            stdout(&out).lines().next().map(|l| parse_diag(l, s(&p[i])).0)
        };
        assert_eq!(first(0), Some(6), "{dialect}: M99 P77 without N77");
        assert_eq!(first(1), Some(2), "{dialect}: G65 without P");
        let out = fivex(&["check", s(&p[2]), "--preset", "mill3", "--dialect", dialect]);
        let lines: Vec<String> = stdout(&out).lines().map(str::to_string).collect();
        assert!(lines.iter().all(|l| !l.ends_with("when run on mill3")), "{dialect}: {lines:?}");
        // The run ends at that call: the check says the blocks after it were not run.
        assert!(stderr(&out).contains(":2: the run on mill3 ends at this call"), "{dialect}: {}", stderr(&out));
    }
}

#[test]
fn check_reports_a_block_over_the_interpreters_limits_without_looking_at_each_word() {
    // 13 G codes, 4 M codes, 49 words: the run refuses each block as it reads it.
    let g13 = "G00 G17 G21 G40 G49 G80 G90 G94 G54 G64 G69 G15 G50\nM30\n";
    let m4 = "M08 M03 M07 M09 S1000\nM30\n";
    let words49 = format!("G01 {}F100.\nM30\n", "X1. ".repeat(48));
    // A line of 40,000 G words is answered at once (the check was quadratic in them).
    let long = format!("{}\nM30\n", "G01 ".repeat(40_000));
    let (_d, p) = scratch(&[("g.nc", g13), ("m.nc", m4), ("w.nc", &words49), ("long.nc", &long)]);
    let code_of = |i: usize| {
        let out = fivex(&["check", s(&p[i])]);
        stdout(&out).lines().next().map(|l| parse_diag(l, s(&p[i])).2.to_string())
    };
    assert_eq!(code_of(0).as_deref(), Some("PS0010"));
    assert_eq!(code_of(1).as_deref(), Some("PS0009"));
    assert_eq!(code_of(2).as_deref(), Some("PS0009"));
    assert_eq!(code_of(3).as_deref(), Some("PS0010"));
    for program in &p[..3] {
        let run = fivex(&["run", s(program)]);
        assert!(stdout(&run).contains("\"alarm\""), "the run refuses it too: {}", stdout(&run));
    }
}

const CRC_GROOVE: &str = "\
G21 G17 G40 G90 G94
G00 X-10. Y0. Z0.
G41 D1 G01 X0. F1000.
X20.
Y-2.
X24.
Y0.
X40.
G40 X50.
M30
";

#[test]
fn check_runs_cutter_compensation_and_reports_its_alarms() {
    let startup_arc = "G21 G17 G40 G90\nG00 X-10. Y0.\nG41 D1 G02 X0. Y10. R10. F1000.\nG01 X20.\nG40 X30.\nM30\n";
    let square =
        "G21 G17 G40 G90\nG00 X-10. Y-10.\nG41 D1 G01 X0. Y0. F500.\nX40.\nY40.\nX0.\nY0.\nG40 X-10. Y-10.\nM30\n";
    let (_d, p) = scratch(&[("groove.nc", CRC_GROOVE), ("arc.nc", startup_arc), ("square.nc", square)]);
    let codes = |out: &std::process::Output, program: &str| {
        stdout(out)
            .lines()
            .map(|l| {
                let (line, _, code) = parse_diag(l, program);
                (line, code.to_string())
            })
            .collect::<Vec<_>>()
    };
    // Without a machine a program with G41/G42 runs on the default machine, the default tools.
    let out = fivex(&["check", s(&p[0])]);
    assert_eq!(out.status.code(), Some(1), "stderr: {}", stderr(&out));
    assert_eq!(codes(&out, s(&p[0])), [(6, "PS0041".to_string())], "{}", stdout(&out));
    assert!(stdout(&out).trim_end().ends_with("INTERFERENCE IN CRC: when run on mill3 (the default machine)"));
    let out = fivex(&["check", s(&p[0]), "--preset", "head-bc"]);
    assert_eq!(codes(&out, s(&p[0])), [(6, "PS0041".to_string())], "{}", stdout(&out));
    assert!(stdout(&out).trim_end().ends_with("when run on head-bc"), "{}", stdout(&out));
    let syntec = fivex(&["check", s(&p[0]), "--dialect", "syntec"]);
    assert_eq!(codes(&syntec, s(&p[0])), [(6, "COR-100".to_string())], "{}", stdout(&syntec));
    // A tool that fits the groove: no interference.
    let (_t, tools) = scratch(&[("tools.json", r#"{"1": {"length": 100.0, "radius": 1.5}}"#)]);
    let out = fivex(&["check", s(&p[0]), "--tools", s(&tools[0])]);
    assert_eq!((out.status.code(), stdout(&out)), (Some(0), String::new()));
    // G02 as the start-up block.
    let out = fivex(&["check", s(&p[1])]);
    assert_eq!(codes(&out, s(&p[1])), [(3, "PS0034".to_string())], "{}", stdout(&out));
    // A correct G41 contour: nothing, with or without a machine.
    for args in [&["check", s(&p[2])][..], &["check", s(&p[2]), "--preset", "mill3"]] {
        let out = fivex(args);
        assert_eq!((out.status.code(), stdout(&out)), (Some(0), String::new()), "{args:?}");
    }
}

#[test]
fn check_without_a_machine_reports_only_the_compensations_alarms() {
    // Line 3 needs a B axis mill3 lacks: the machine's alarm, not a compensation one, so a check
    // without a machine stays silent (it is not the text's fault); G41 is in the text.
    let prog = "G21 G17 G90\nG00 X0. Y0.\nG01 B30. F500.\nG41 D1 X10.\nG40 X0.\nM30\n";
    let (_d, p) = scratch(&[("b.nc", prog)]);
    let out = fivex(&["check", s(&p[0])]);
    assert_eq!((out.status.code(), stdout(&out)), (Some(0), String::new()));
    let out = fivex(&["check", s(&p[0]), "--preset", "mill3"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stdout(&out).contains(":3:1: "), "{}", stdout(&out));
}

#[test]
fn check_on_a_machine_reports_the_over_travel_the_run_stops_with() {
    // The audit's ot.nc: mill3's X stroke is ±600; the run stops with OT0510 at line 2.
    let (_d, p) = scratch(&[("ot.nc", "O1\nG90 G00 X5000.\nM30\n")]);
    let out = fivex(&["check", s(&p[0]), "--preset", "mill3"]);
    assert_eq!(out.status.code(), Some(1));
    let text = stdout(&out);
    assert_eq!(parse_diag(text.trim_end(), s(&p[0])).0, 2, "{text}");
    assert!(text.contains("OT0510 + OVERTRAVEL ( PRE-CHECK ) X: when run on mill3"), "{text}");
    // Without a machine the strokes are mill3's, not the text's: nothing to report.
    let out = fivex(&["check", s(&p[0])]);
    assert_eq!((out.status.code(), stdout(&out)), (Some(0), String::new()));
}

#[test]
fn check_shows_the_text_and_the_run_alarms_of_one_line() {
    // Line 2: the text's P beside G55 (PS0009, not built) and the run's division by zero in
    // X (PS0112), which stops the run on that line first. Both are shown: the run's alarm
    // was dropped because the text had a diagnostic on its line.
    let (_d, p) = scratch(&[("two.nc", "#1=0\nG90 G55 P1 X[1/#1]\nM30\n")]);
    let program = s(&p[0]);
    let out = fivex(&["check", program, "--preset", "mill3"]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let text = stdout(&out);
    let found: Vec<(u32, String)> =
        text.lines().map(|l| (parse_diag(l, program).0, parse_diag(l, program).2.into())).collect();
    assert_eq!(found.len(), 2, "{text}");
    assert!(found.contains(&(2, "PS0009".into())), "the text's: {text}");
    assert!(found.contains(&(2, "PS0112".into())), "the run's: {text}");
    assert!(text.contains("PS0112 ZERO DIVIDE: when run on mill3"), "{text}");
    // The same alarm from both on one line is shown once (the text says it already).
    let (_e, q) = scratch(&[("same.nc", "G90 G55 P1 X1.\nM30\n")]);
    let out = fivex(&["check", s(&q[0]), "--preset", "mill3"]);
    let text = stdout(&out);
    assert_eq!(text.lines().count(), 1, "{text}");
    assert_eq!(parse_diag(text.trim_end(), s(&q[0])), (1, 9, "PS0009"), "{text}");
}

/// `fivex args…` (a check of `program`) finding one problem, at `(line, col, code)`: exit 1
/// and that one line, returned.
fn the_one_diagnostic(args: &[&str], program: &str, at: (u32, u32, &str)) -> String {
    let out = fivex(args);
    assert_eq!(out.status.code(), Some(1), "{args:?}: {}", stderr(&out));
    let text = stdout(&out);
    assert_eq!(text.lines().count(), 1, "{args:?}: {text}");
    assert_eq!(parse_diag(text.trim_end(), program), at, "{args:?}: {text}");
    text
}

#[test]
fn check_reports_a_run_that_never_ends() {
    // The loop after the compensation: the check runs the program (it has G41) and its block
    // budget runs out at line 5. It was left out as no compensation alarm (G40 is in force),
    // and check answered 0, a program that never ends reported clean.
    let prog = "G21 G17 G40 G90\nG41 D1 G01 X0. Y0. F500.\nX10.\nG40 X20.\nN10 GOTO10\nM30\n";
    let (_d, p) = scratch(&[("loop.nc", prog)]);
    let program = s(&p[0]);
    for args in [&["check", program][..], &["check", program, "--preset", "mill3"]] {
        let text = the_one_diagnostic(args, program, (5, 1, "FX0001"));
        // What happened, the budget, why, and what to do.
        for says in ["5000000 BLOCKS RUN, PROGRAM NOT ENDED", "may loop without end", "fivex run --max-blocks"] {
            assert!(text.contains(says), "{args:?}: {says}: {text}");
        }
    }
}

/// A FANUC program whose text ends without M02/M30 stops with PS5010 END OF RECORD on the
/// control (`docs/dialects.md`, "The end of the program's text"): check reports it at the last
/// line, with or without a machine. Not after M30 or M02, nor in Syntec or Haas.
#[test]
fn check_reports_the_end_of_record() {
    let open = "G90 G01 X10. F1000.\n";
    let (_d, p) = scratch(&[
        ("open.nc", open),
        ("m30.nc", "G90 G01 X10. F1000.\nM30\n"),
        ("m02.nc", "G90 G01 X10. F1000.\nM02\n%\n"),
    ]);
    let program = s(&p[0]);
    for args in [&["check", program][..], &["check", program, "--preset", "mill3"]] {
        let text = the_one_diagnostic(args, program, (1, 1, "PS5010"));
        assert!(text.contains("PS5010 END OF RECORD"), "{args:?}: {text}");
    }
    let clean = [
        vec!["check", s(&p[1])],
        vec!["check", s(&p[2])],
        vec!["check", program, "--dialect", "syntec"],
        vec!["check", program, "--dialect", "haas"],
    ];
    for args in clean {
        let out = fivex(&args);
        assert_eq!((out.status.code(), stdout(&out)), (Some(0), String::new()), "{args:?}: {}", stderr(&out));
    }
}

// --- interp ---------------------------------------------------------------------------------

fn json_lines(text: &str) -> Vec<Value> {
    assert!(text.is_empty() || text.ends_with('\n'), "output ends with a newline");
    text.lines()
        .enumerate()
        .map(|(i, l)| {
            let v: Value =
                serde_json::from_str(l).unwrap_or_else(|e| panic!("line {} is not one JSON value ({e}): {l:?}", i + 1));
            assert!(v.is_object(), "line {} is not an object: {l}", i + 1);
            assert!(v["type"].is_string(), "line {} has no type: {l}", i + 1);
            v
        })
        .collect()
}

#[test]
fn interp_prints_one_json_object_per_line_and_nothing_else() {
    let prog = "\
O0001
G90 G54 G00 X0. Y0. Z10. S1000 M03
T1 M06
G43 H1 Z5.
G01 Z-1. F100.
G02 X10. Y0. R5.
G04 P500
#100=1
DPRNT[DONE#100[10]]
#3006=1(LOOK)
M08
M09
M05
M30
";
    let (_d, p) = scratch(&[("p.nc", prog)]);
    let out = fivex(&["interp", s(&p[0])]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let canon = json_lines(&stdout(&out));
    let types: Vec<&str> = canon.iter().map(|c| c["type"].as_str().unwrap()).collect();
    for t in ["motion", "spindle", "tool_change", "dwell", "coolant", "print", "stop", "program_end"] {
        assert!(types.contains(&t), "no {t} in {types:?}");
    }
    assert_eq!(*types.last().unwrap(), "program_end");
    // Program order: lines never go backwards in a program without jumps.
    let lines: Vec<u64> = canon.iter().map(|c| c["line"].as_u64().expect("line")).collect();
    assert!(lines.windows(2).all(|w| w[0] <= w[1]), "{lines:?}");
}

#[test]
fn interp_stdout_stays_json_when_the_program_alarms() {
    let (_d, p) = scratch(&[("p.nc", "G90 G00 X1.\nG01 X2.\nM30\n")]);
    let out = fivex(&["interp", s(&p[0])]);
    assert_eq!(out.status.code(), Some(1));
    let canon = json_lines(&stdout(&out));
    assert_eq!(canon.len(), 1, "the rapid before the alarm");
    assert!(stderr(&out).contains("PS0011"), "feed zero alarm reported on stderr: {}", stderr(&out));
}

/// The (X, Y) end points of the motions `fivex interp` printed.
fn motion_ends(canon: &[Value]) -> Vec<(f64, f64)> {
    canon.iter().filter(|c| c["type"] == "motion").map(|c| (num(&c["target"]["X"]), num(&c["target"]["Y"]))).collect()
}

#[test]
fn interp_with_stages_prints_the_tool_centre_path() {
    // A 40 mm pocket cut inside with G41 and radius 5 (the default tool table): the start-up
    // and every corner at the offset paths' intersections, FANUC's type A cancel (the block
    // before G40 ends where its offset meets the cancel block's). Without --stages: as programmed.
    let prog = "G90 G00 X20. Y20. Z0.\nG41 D1 G01 Y0. F1000.\nX40.\nY40.\nX0.\nY0.\nX20.\nG40 Y20.\nM30\n";
    let (_d, p) = scratch(&[("p.nc", prog)]);
    let out = fivex(&["interp", "--stages", s(&p[0])]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let centre =
        [(20.0, 20.0), (25.0, 5.0), (35.0, 5.0), (35.0, 35.0), (5.0, 35.0), (5.0, 5.0), (15.0, 5.0), (20.0, 20.0)];
    assert_eq!(motion_ends(&json_lines(&stdout(&out))), centre);
    let out = fivex(&["interp", s(&p[0])]);
    let programmed =
        [(20.0, 20.0), (20.0, 0.0), (40.0, 0.0), (40.0, 40.0), (0.0, 40.0), (0.0, 0.0), (20.0, 0.0), (20.0, 20.0)];
    assert_eq!(motion_ends(&json_lines(&stdout(&out))), programmed);
    // A compensation alarm (an arc as the start-up block, PS0034) ends the output with exit 1.
    let (_d, p) = scratch(&[("p.nc", "G90 G00 X0. Y0.\nG01 X10. F500.\nG41 D1 G02 X20. Y0. R5.\nM30\n")]);
    let out = fivex(&["interp", "--stages", s(&p[0])]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("PS0034"), "{}", stderr(&out));
    assert_eq!(motion_ends(&json_lines(&stdout(&out))), [(0.0, 0.0), (10.0, 0.0)]);
}

#[test]
fn odd_bytes_do_not_break_the_cli() {
    let (_d, _) = scratch(&[]);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bin.nc");
    std::fs::write(&path, b"G90 G00 X1.\xff\xfe(\xc3\x28)\nG01 X\x00 F100\n\x1b[2J#100=1\nM30\n").unwrap();
    for cmd in ["run", "interp", "check"] {
        let out = fivex(&[cmd, s(&path)]);
        let code = out.status.code().expect("not killed by a signal");
        assert!(code == 0 || code == 1, "{cmd}: exit {code}, stderr {}", stderr(&out));
        assert!(!stderr(&out).contains("panicked"), "{cmd} panicked: {}", stderr(&out));
    }
    let (code, v) = run_json(&[s(&path)]);
    assert!(code == 0 || code == 1, "{v}");
}

#[test]
fn time_budget_alarm_names_a_program_line() {
    // 500 mm at F100 = 300 s of simulated time, past a 10 s budget: FX0002. The contract says
    // every alarm's `line` is a 1-based line of PROGRAM: here the block that ran past the budget.
    let (_d, p) = scratch(&[("p.nc", "G90 G00 X0.\nN20 G01 X500. F100.\nM30\n")]);
    let (code, v) = run_json(&[s(&p[0]), "--max-time-s", "10"]);
    assert_eq!(code, 1, "{v}");
    let a = &v["alarms"][0];
    assert_eq!(a["code"], "FX0002", "{v}");
    assert_eq!(a["line"], 2, "the alarm points at the block that used up the budget: {a}");
    assert_eq!(a["n"], 20, "{a}");
}

/// Run with a wall-clock limit; `None` if it had to be killed.
fn fivex_with_timeout(args: &[&str], limit: std::time::Duration) -> Option<std::process::Output> {
    use std::process::{Command, Stdio};
    let mut child = Command::new(fivex_bin())
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn");
    let start = std::time::Instant::now();
    loop {
        if child.try_wait().expect("wait").is_some() {
            return Some(child.wait_with_output().expect("output"));
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            return None;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

#[test]
fn deep_expressions_do_not_crash() {
    // Long but legal-looking expressions: the parser and the evaluator recurse once per operator,
    // so these overflowed the stack (SIGABRT, exit 134) instead of giving a result or an alarm.
    // On the server the same text arrives by `PUT /programs/{n}` and would take down the process.
    let cases = [
        ("minus.nc", format!("#1={}1\n#100=#1\nM30\n", "-".repeat(100_000))),
        ("sum.nc", format!("#100=1{}\nM30\n", "+1".repeat(100_000))),
        ("product.nc", format!("#100=1{}\nM30\n", "*1".repeat(100_000))),
        ("word.nc", format!("G90 G00 X[1{}]\nM30\n", "+0".repeat(100_000))),
    ];
    let dir = tempfile::tempdir().unwrap();
    let mut crashes = Vec::new();
    for (name, text) in &cases {
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        for cmd in ["check", "run"] {
            let out = fivex_with_timeout(&[cmd, s(&path)], std::time::Duration::from_secs(60))
                .unwrap_or_else(|| panic!("{cmd} {name} hung"));
            let code = out.status.code();
            if !matches!(code, Some(0) | Some(1)) {
                crashes.push(format!("fivex {cmd} {name}: exit {code:?}, stderr: {}", stderr(&out).trim()));
            }
        }
    }
    assert!(crashes.is_empty(), "crashes:\n{}", crashes.join("\n"));
}

#[test]
fn a_closed_stdout_is_not_a_panic() {
    // `fivex interp big.nc | head -1`: once the reader has gone, writing fails with EPIPE. The
    // CLI must stop quietly (any exit status), not panic with "failed printing to stdout".
    use std::process::{Command, Stdio};
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("big.nc");
    let mut prog = String::from("#1=0\nWHILE[#1LT20000]DO1\nG91 G01 X0.001 F1000.\n#1=#1+1\nEND1\nM30\n");
    prog.push('\n');
    std::fs::write(&path, prog).unwrap();
    let mut panics = Vec::new();
    for cmd in ["interp", "run"] {
        let mut child = Command::new(fivex_bin())
            .args([cmd, s(&path)])
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("spawn");
        // Close the read end at once, like `| head -0`.
        drop(child.stdout.take());
        let out = child.wait_with_output().expect("wait");
        let err = stderr(&out);
        if err.contains("panicked") {
            panics.push(format!("fivex {cmd}: {}", err.lines().take(2).collect::<Vec<_>>().join(" / ")));
        }
    }
    assert!(panics.is_empty(), "panics on a closed stdout:\n{}", panics.join("\n"));
}

#[test]
fn trace_tool_vector_follows_the_rotary_axes() {
    // docs/contracts.md: `tool` is the unit tool vector (tip toward holder) in the active workpiece
    // system. Whatever the rotation senses, a head B axis at 90 degrees lays the tool flat
    // (no Z component, along X), and a table A axis at 90 degrees stands the part up so the
    // tool, seen from the part, lies along its Y axis.
    let (d, p) = scratch(&[("p.nc", "G90 G00 B90.\nG04 X0.1\nM30\n"), ("a.nc", "G90 G00 A90.\nG04 X0.1\nM30\n")]);
    let mut wrong = Vec::new();
    for (preset, file, axis) in [("head-bc", &p[0], 0usize), ("table-ac", &p[1], 1usize)] {
        let trace = d.path().join(format!("{preset}.jsonl"));
        let (code, v) = run_json(&[s(file), "--preset", preset, "--trace", s(&trace)]);
        assert_eq!(code, 0, "{v}");
        let last = read_trace(&trace).pop().expect("samples");
        let tool: Vec<f64> = last["tool"].as_array().expect("tool").iter().map(num).collect();
        if tool[2].abs() > 1e-9 || (tool[axis].abs() - 1.0).abs() > 1e-9 {
            wrong.push(format!("{preset}: tool {tool:?} at {}", last["machine"]));
        }
    }
    assert!(wrong.is_empty(), "tool vector ignores the rotary axes:\n{}", wrong.join("\n"));
}
