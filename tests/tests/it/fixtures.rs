//! Data-driven end-to-end tests: every `tests/fixtures/*.nc` is run through the real `fivex`
//! binary with `run`, `interp` and `check`, and once more with `--trace`; each output is an
//! insta snapshot (`tests/tests/snapshots/fixtures__{run,interp,check,trace}@NAME.nc.snap`; the
//! trace decimated to 40 samples, rounded to 0.1 µm, with the programmed point and its system,
//! and the cutting point where there is one).
//!
//! A fixture's first line may select options: `(fivex: --preset table-ac --dialect syntec)`.
//! `run` gets all of them; `interp` all but the trace/timing ones; `check` only `--dialect`.
//!
//! Fixtures also carry hand-computed expectations, checked before the snapshots so that a wrong
//! snapshot cannot be accepted silently: `(expect: key=value …)` comments anywhere in the file
//! (put them after the program end so they are not executed). Keys:
//!
//! | key | meaning (for `fivex run` unless said) |
//! |---|---|
//! | `exit=N` | exit status of `run` (and of `interp`, unless `interp_exit=N` says otherwise) |
//! | `status=completed\|alarm` | the summary's status |
//! | `alarm=CODE`, `alarm_line=N`, `alarm_n=N\|null` | the first alarm |
//! | `blocks=N` | executed blocks |
//! | `time=S` | `cycle_time_s` exactly (±1e-6), worked out by hand with the S-curve times of `docs/motion.md` |
//! | `ideal=S` | the cycle time without acceleration (path length / feed, rapids at the slowest axis's rate, dwells): `cycle_time_s` is at least that and at most 0.4 s more per motion (`interp` motion lines; the presets' slowest full speed change takes 0.175 s, and a motion has two) — the exact times are pinned by the snapshot and by the analytic tests of `cli.rs` and `engine::motion` |
//! | `#N=V` / `#N=vacant` | a common variable at the end (±1e-6) |
//! | `mX=V` / `wX=V` | machine / workpiece position of axis X (±1e-6) |
//! | `msg="TEXT"` | the `messages` list, in order (all of them when any is given) |
//! | `canon=N` | number of `interp` lines |
//! | `notice=CODE:LINE` | the summary's `notices`, all of them in order (none given = none expected) |
//! | `diag=LINE:CODE` | `check` diagnostics, all of them in order (none given = none expected) |
//! | `stand=X:Y` | the machine's X and Y axes stand still at X, Y (±1e-6) in two consecutive samples of `run --trace` (a dwell or the end: where the tool centre stops) |

use crate::common;

use common::*;
use serde_json::Value;
use std::fmt::Write as _;
use std::path::Path;

/// Options that take a value, and which commands accept them.
const VALUE_OPTS: &[(&str, &[&str])] = &[
    ("--preset", &["run", "interp"]),
    ("--machine", &["run", "interp"]),
    ("--dialect", &["run", "interp", "check"]),
    ("--tools", &["run", "interp"]),
    ("--workpiece", &["run", "interp"]),
    ("--max-blocks", &["run", "interp"]),
    ("--trace", &["run"]),
    ("--period-ms", &["run"]),
    ("--max-time-s", &["run"]),
];
const FLAG_OPTS: &[(&str, &[&str])] =
    &[("--block-delete", &["run", "interp"]), ("--optional-stop", &["run", "interp"])];

/// The options of the first line's `(fivex: …)` comment that `command` accepts.
fn options_for(text: &str, command: &str) -> Vec<String> {
    let first = text.lines().next().unwrap_or("");
    let Some(opts) = tagged_comments(first, "fivex").into_iter().next() else { return vec![] };
    let words = split_words(opts);
    let mut out = Vec::new();
    let mut i = 0;
    while i < words.len() {
        let w = words[i].as_str();
        if let Some((_, cmds)) = VALUE_OPTS.iter().find(|(o, _)| *o == w) {
            let v = words.get(i + 1).unwrap_or_else(|| panic!("option {w} needs a value"));
            if cmds.contains(&command) {
                out.push(w.to_string());
                out.push(v.clone());
            }
            i += 2;
        } else if let Some((_, cmds)) = FLAG_OPTS.iter().find(|(o, _)| *o == w) {
            if cmds.contains(&command) {
                out.push(w.to_string());
            }
            i += 1;
        } else {
            panic!("unknown fixture option {w:?}");
        }
    }
    out
}

struct Ran {
    exit: i32,
    stdout: String,
    stderr: String,
    /// The snapshot text.
    snapshot: String,
}

fn run_cmd(dir: &Path, command: &str, file: &str, opts: &[String]) -> Ran {
    let mut args: Vec<&str> = vec![command, file];
    args.extend(opts.iter().map(String::as_str));
    let out = fivex_in(dir, &args);
    let exit = out.status.code().expect("fivex was killed by a signal");
    let (stdout, stderr) = (stdout(&out), stderr(&out));
    let mut snapshot = format!("$ fivex {}\nexit: {exit}\n--- stdout\n{stdout}", args.join(" "));
    if !stdout.is_empty() && !stdout.ends_with('\n') {
        snapshot.push('\n');
    }
    if !stderr.is_empty() {
        let _ = write!(snapshot, "--- stderr\n{stderr}");
    }
    Ran { exit, stdout, stderr, snapshot }
}

fn close(got: f64, want: f64) -> bool {
    (got - want).abs() <= 1e-6
}

fn parse_num(v: &str) -> f64 {
    v.parse().unwrap_or_else(|_| panic!("expectation value {v:?} is not a number"))
}

/// Check the `(expect: …)` comments; returns the list of mismatches.
fn check_expectations(text: &str, run: &Ran, interp: &Ran, check: &Ran, trace: &str) -> Vec<String> {
    let mut errs = Vec::new();
    let summary: Value = match serde_json::from_str(&run.stdout) {
        Ok(v) => v,
        Err(e) => return vec![format!("run stdout is not one JSON object ({e}): {}", run.stdout)],
    };
    let mut run_exit = None;
    let mut interp_exit = None;
    let mut msgs: Option<Vec<String>> = None;
    let mut diags: Vec<String> = Vec::new();
    let mut notices: Vec<String> = Vec::new();
    for body in tagged_comments(text, "expect") {
        for item in split_words(body) {
            let (k, v) = item.split_once('=').unwrap_or_else(|| panic!("expectation {item:?} is not key=value"));
            let num = |path: &[&str]| -> Option<f64> {
                let mut x = &summary;
                for p in path {
                    x = x.get(p)?;
                }
                x.as_f64()
            };
            let mut want_num = |what: String, got: Option<f64>| match got {
                Some(g) if close(g, parse_num(v)) => {}
                other => errs.push(format!("{what}: expected {v}, got {other:?}")),
            };
            match k {
                "exit" => run_exit = Some(parse_num(v) as i32),
                "interp_exit" => interp_exit = Some(parse_num(v) as i32),
                "status" => {
                    if summary["status"] != v {
                        errs.push(format!("status: expected {v}, got {}", summary["status"]));
                    }
                }
                "alarm" => {
                    let got = &summary["alarms"][0]["code"];
                    if got != v {
                        errs.push(format!("alarm: expected {v}, got {got} ({})", summary["alarms"]));
                    }
                }
                "alarm_line" => want_num("alarm line".into(), summary["alarms"][0]["line"].as_f64()),
                "alarm_n" => {
                    let got = &summary["alarms"][0]["n"];
                    let ok =
                        if v == "null" { got.is_null() } else { got.as_f64().is_some_and(|g| close(g, parse_num(v))) };
                    if !ok {
                        errs.push(format!("alarm n: expected {v}, got {got}"));
                    }
                }
                "blocks" => want_num("blocks".into(), num(&["blocks"])),
                "time" => want_num("cycle_time_s".into(), num(&["cycle_time_s"])),
                "ideal" => {
                    let ideal = parse_num(v);
                    let motions = interp.stdout.lines().filter(|l| l.starts_with("{\"type\":\"motion\"")).count();
                    let slack = 0.4 * motions as f64;
                    match num(&["cycle_time_s"]) {
                        Some(t) if t >= ideal - 1e-6 && t <= ideal + slack => {}
                        other => errs.push(format!(
                            "cycle_time_s: expected {ideal} without acceleration, at most {slack} s more; got {other:?}"
                        )),
                    }
                }
                "canon" => {
                    let n = interp.stdout.lines().count() as f64;
                    want_num("interp lines".into(), Some(n));
                }
                "msg" => msgs.get_or_insert_with(Vec::new).push(v.to_string()),
                "diag" => diags.push(v.to_string()),
                "notice" => notices.push(v.to_string()),
                "stand" => {
                    let (x, y) = v.split_once(':').unwrap_or_else(|| panic!("stand={v}: not X:Y"));
                    let (x, y) = (parse_num(x), parse_num(y));
                    let at = |line: &str| -> Option<(f64, f64)> {
                        let s: Value = serde_json::from_str(line).ok()?;
                        Some((s["machine"]["X"].as_f64()?, s["machine"]["Y"].as_f64()?))
                    };
                    let points: Vec<Option<(f64, f64)>> = trace.lines().map(at).collect();
                    let here = |p: &Option<(f64, f64)>| p.is_some_and(|(px, py)| close(px, x) && close(py, y));
                    if !points.windows(2).any(|w| here(&w[0]) && here(&w[1])) {
                        errs.push(format!("stand: the machine never stands at X{x} Y{y}"));
                    }
                }
                k if k.starts_with('#') => {
                    let got = &summary["variables"][k];
                    if v == "vacant" {
                        if !got.is_null() {
                            errs.push(format!("{k}: expected vacant, got {got}"));
                        }
                    } else {
                        want_num(k.to_string(), got.as_f64());
                    }
                }
                k if k.len() == 2 && (k.starts_with('m') || k.starts_with('w')) => {
                    let frame = if k.starts_with('m') { "machine" } else { "workpiece" };
                    want_num(format!("{frame} {}", &k[1..]), num(&["position", frame, &k[1..]]));
                }
                _ => panic!("unknown expectation key {k:?}"),
            }
        }
    }
    let run_exit = run_exit.unwrap_or(0);
    if run.exit != run_exit {
        errs.push(format!("run exit: expected {run_exit}, got {} (stderr: {})", run.exit, run.stderr.trim()));
    }
    let interp_exit = interp_exit.unwrap_or(run_exit);
    if interp.exit != interp_exit {
        errs.push(format!(
            "interp exit: expected {interp_exit}, got {} (stderr: {})",
            interp.exit,
            interp.stderr.trim()
        ));
    }
    for (i, line) in interp.stdout.lines().enumerate() {
        match serde_json::from_str::<Value>(line) {
            Ok(v) if v.is_object() && v.get("type").is_some() => {}
            _ => errs.push(format!("interp stdout line {} is not a JSON object with a type: {line}", i + 1)),
        }
    }
    if let Some(want) = msgs {
        let got: Vec<String> = summary["messages"]
            .as_array()
            .map(|a| a.iter().map(|m| m.as_str().unwrap_or("").to_string()).collect())
            .unwrap_or_default();
        if got != want {
            errs.push(format!("messages: expected {want:?}, got {got:?}"));
        }
    }
    let got_notices: Vec<String> = summary["notices"]
        .as_array()
        .map(|a| a.iter().map(|n| format!("{}:{}", n["code"].as_str().unwrap_or(""), n["line"])).collect())
        .unwrap_or_default();
    if got_notices != notices {
        errs.push(format!("notices: expected {notices:?}, got {got_notices:?}"));
    }
    // check: `FILE:LINE:COL: CODE message` lines.
    let got_diags: Vec<String> = check
        .stdout
        .lines()
        .map(|l| {
            let mut parts = l.splitn(4, ':');
            let (_file, line, _col, rest) = (parts.next(), parts.next(), parts.next(), parts.next().unwrap_or(""));
            let code = rest.split_whitespace().next().unwrap_or("");
            format!("{}:{code}", line.unwrap_or("?"))
        })
        .collect();
    if got_diags != diags {
        errs.push(format!("check diagnostics: expected {diags:?}, got {got_diags:?}\n{}", check.stdout));
    }
    let check_exit = if diags.is_empty() { 0 } else { 1 };
    if check.exit != check_exit {
        errs.push(format!("check exit: expected {check_exit}, got {}", check.exit));
    }
    errs
}

/// Samples kept in a trace snapshot (evenly spread, the last one always).
const TRACE_SAMPLES: usize = 40;

/// `fivex run --trace` decimated to [`TRACE_SAMPLES`] lines, numbers rounded to 0.1 µm so that
/// the snapshot pins the motion, not the last bits of a libm.
fn run_trace(dir: &Path, file: &str, opts: &[String], scratch: &Path) -> (Ran, String) {
    let trace = scratch.join(format!("{file}.jsonl"));
    let mut opts = opts.to_vec();
    opts.extend(["--trace".to_string(), trace.display().to_string()]);
    let ran = run_cmd(dir, "run", file, &opts);
    (ran, std::fs::read_to_string(&trace).unwrap_or_default())
}

fn trace_snapshot(ran: &Ran, text: &str) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let n = lines.len();
    let mut picks: Vec<usize> = (0..TRACE_SAMPLES.min(n)).map(|k| k * (n - 1) / (TRACE_SAMPLES - 1).max(1)).collect();
    picks.dedup();
    let round = |v: &Value| {
        let x = (v.as_f64().unwrap_or(f64::NAN) * 1e4).round() / 1e4;
        format!("{}", if x == 0.0 { 0.0 } else { x })
    };
    let mut out = format!("exit {} · {n} samples · showing {}\n", ran.exit, picks.len());
    for i in picks {
        let s: Value = serde_json::from_str(lines[i]).expect("trace line is JSON");
        let axes: Vec<String> = s["machine"]
            .as_object()
            .map(|m| m.iter().map(|(k, v)| format!("{k}{}", round(v))).collect())
            .unwrap_or_default();
        let vec3 =
            |v: &Value| v.as_array().map(|a| a.iter().map(round).collect::<Vec<_>>().join(",")).unwrap_or_default();
        let _ = writeln!(
            out,
            "t{} L{} N{} | {} | tip {} | tool {} | F{} | {} {}",
            round(&s["t"]),
            s["line"],
            s["n"],
            axes.join(" "),
            vec3(&s["tip"]),
            vec3(&s["tool"]),
            round(&s["feed"]),
            s["programmed_in"].as_str().unwrap_or("?"),
            vec3(&s["programmed"]),
        );
        // Under cutting point control or cutter compensation: where the tool touches.
        if let Some(c) = s.get("cutting") {
            out.pop();
            let _ = writeln!(out, " | cutting {}", vec3(c));
        }
    }
    out
}

#[test]
fn fixtures() {
    let dir = fixtures_dir();
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let mut failures = Vec::new();
    let mut count = 0;
    insta::glob!("../../fixtures", "*.nc", |path| {
        count += 1;
        let file = path.file_name().unwrap().to_str().unwrap();
        let text = std::fs::read_to_string(path).unwrap();
        let run = run_cmd(&dir, "run", file, &options_for(&text, "run"));
        let interp = run_cmd(&dir, "interp", file, &options_for(&text, "interp"));
        let check = run_cmd(&dir, "check", file, &options_for(&text, "check"));
        let (traced, trace) = run_trace(&dir, file, &options_for(&text, "run"), scratch.path());
        for e in check_expectations(&text, &run, &interp, &check, &trace) {
            // Printed at once too: a snapshot failure below ends the test before the summary.
            eprintln!("EXPECTATION FAILED {file}: {e}");
            failures.push(format!("{file}: {e}"));
        }
        insta::assert_snapshot!("run", run.snapshot);
        insta::assert_snapshot!("interp", interp.snapshot);
        insta::assert_snapshot!("check", check.snapshot);
        insta::assert_snapshot!("trace", trace_snapshot(&traced, &trace));
    });
    assert!(count >= 30, "expected at least 30 fixtures, found {count}");
    assert!(failures.is_empty(), "{} hand-computed expectation(s) failed:\n{}", failures.len(), failures.join("\n"));
}
