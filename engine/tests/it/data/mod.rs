//! The data-driven harness: every `tests/data/<topic>/**/*.nc` is one program with a header
//! (`header.rs`; the format is in `tests/README.md`, "Data fixtures"). For each dialect the
//! header names, the interpreter's canonical commands are pretty-printed (`pretty.rs`) into one
//! insta snapshot per fixture (`tests/data/<topic>/snapshots/<name>.snap`, all dialects in
//! it), the program is run through the motion at a 2 ms period, its `(expect: …)` are checked
//! against the run, and the invariants of `invariants.rs` against every sample. The programs of
//! `tests/fixtures/` (the e2e harness's) are held to the same invariants.
//!
//! A topic folder without fixtures, a folder without its test here, a snapshot without its
//! fixture, a fixture that expects nothing in a dialect it runs in, a run where an invariant
//! compared nothing without a `(skip: …)` saying why, and a `(skip: …)` the invariant holds
//! without all fail.

mod header;
mod invariants;
mod pretty;

use fivex_engine::canon::Canon;
use fivex_engine::interp::expr::Variables;
use fivex_engine::interp::{Config, Interpreter};
use fivex_engine::lang::parse_file;
use fivex_engine::machine::MachineConfig;
use fivex_engine::run::{run, RunOptions, RunResult, Sample};
use fivex_engine::Dialect;
use header::{Expect, Header, Skip};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/data");
const FIXTURES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/fixtures");

/// The topics, one test each (below).
const TOPICS: &[&str] = &["alarms", "macro", "frames", "modes", "cycles", "five-axis", "probing"];

macro_rules! topics {
    ($($test:ident => $dir:literal),* $(,)?) => {
        $(#[test] fn $test() { topic($dir) })*
    };
}

topics! {
    data_alarms => "alarms",
    data_macro => "macro",
    data_frames => "frames",
    data_modes => "modes",
    data_cycles => "cycles",
    data_five_axis => "five-axis",
    data_probing => "probing",
}

#[test]
fn every_topic_folder_has_its_test() {
    let mut dirs: Vec<String> = std::fs::read_dir(DATA)
        .expect("tests/data")
        .map(|e| e.unwrap())
        .filter(|e| e.path().is_dir())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    dirs.sort();
    let mut known: Vec<String> = TOPICS.iter().map(|s| s.to_string()).collect();
    known.sort();
    assert_eq!(dirs, known, "tests/data's folders and the topics of engine/tests/it/data/mod.rs");
}

/// The `tests/fixtures/*.nc` of the e2e harness: the same invariants (their expectations and
/// snapshots are the e2e harness's, through the binary).
#[test]
fn e2e_fixtures_keep_the_invariants() {
    let files = nc_files(Path::new(FIXTURES));
    assert!(files.len() >= 40, "the e2e fixtures: found {}", files.len());
    let failures: Vec<String> = files.iter().filter_map(|f| guarded(f, invariants_only)).collect();
    assert!(failures.is_empty(), "{} of {} fixtures fail:\n{}", failures.len(), files.len(), failures.join("\n"));
}

fn nc_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
        let path = entry.unwrap().path();
        if path.is_dir() && path.file_name().is_some_and(|n| n != "snapshots") {
            out.extend(nc_files(&path));
        } else if path.extension().is_some_and(|e| e == "nc") {
            out.push(path);
        }
    }
    out.sort();
    out
}

fn topic(name: &str) {
    let dir = Path::new(DATA).join(name);
    let files = nc_files(&dir);
    assert!(!files.is_empty(), "tests/data/{name} holds no fixture");
    let failures: Vec<String> = files.iter().filter_map(|f| guarded(f, |f| fixture(&dir, f))).collect();
    assert!(failures.is_empty(), "{} of {} fixtures fail:\n{}", failures.len(), files.len(), failures.join("\n\n"));
    // A snapshot whose fixture was renamed or removed would pin nothing.
    let snapshots = dir.join("snapshots");
    for entry in std::fs::read_dir(&snapshots).unwrap_or_else(|e| panic!("{}: {e}", snapshots.display())) {
        let snap = entry.unwrap().path();
        if snap.extension().is_some_and(|e| e == "snap") {
            let stem = snap.file_stem().unwrap().to_string_lossy().into_owned();
            assert!(
                files.iter().any(|f| f.file_stem().is_some_and(|s| *s == *stem)),
                "{} has no fixture",
                snap.display()
            );
        }
    }
}

/// Runs `check` on one file; its failures (or its panic: an insta mismatch, an engine panic)
/// as one message.
fn guarded(file: &Path, check: impl Fn(&Path) -> Result<(), String>) -> Option<String> {
    let res = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| check(file)));
    let err = match res {
        Ok(Ok(())) => return None,
        Ok(Err(e)) => e,
        Err(p) => p
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_else(|| "panicked".into()),
    };
    Some(format!("{}: {err}", file.display()))
}

/// The fixture's machine: its `--machine` file (relative to `dir`), or its preset.
fn machine_of(h: &Header, dir: &Path) -> Result<MachineConfig, String> {
    match &h.machine {
        Some(file) => {
            let text = std::fs::read_to_string(dir.join(file)).map_err(|e| format!("{file}: {e}"))?;
            fivex_engine::machine_file::parse(&text).map_err(|e| format!("{file}: {e}"))
        }
        None => MachineConfig::preset(&h.preset).ok_or(format!("no preset {:?}", h.preset)),
    }
}

fn interpreter(text: &str, h: &Header, dialect: Dialect, dir: &Path) -> Result<Interpreter, String> {
    let machine = machine_of(h, dir)?;
    let mut cfg = Config::new(machine, dialect);
    cfg.max_blocks = h.max_blocks.unwrap_or(1_000_000);
    cfg.block_delete = h.block_delete;
    cfg.optional_stop = h.optional_stop;
    cfg.nat = h.nat;
    cfg.refuse_unbuilt = !h.allow_unbuilt;
    if let Some(f) = &h.workpiece {
        let json = std::fs::read_to_string(dir.join(f)).map_err(|e| format!("{f}: {e}"))?;
        let workpiece: fivex_engine::workpiece::Workpiece =
            serde_json::from_str(&json).map_err(|e| format!("{f}: {e}"))?;
        workpiece.check().map_err(|e| format!("{f}: {e}"))?;
        cfg.workpiece = workpiece.into();
    }
    let mut interp = Interpreter::new(parse_file(text), cfg);
    // The CLI's tools: the file's, or 1–99 with length 100 and radius 5.
    let tools: Vec<(u32, f64, f64)> = match &h.tools {
        Some(f) => {
            let json = std::fs::read_to_string(dir.join(f)).map_err(|e| format!("{f}: {e}"))?;
            let v: serde_json::Value = serde_json::from_str(&json).map_err(|e| format!("{f}: {e}"))?;
            let obj = v.as_object().ok_or(format!("{f}: not an object"))?;
            obj.iter()
                .map(|(n, t)| (n.parse().unwrap(), t["length"].as_f64().unwrap(), t["radius"].as_f64().unwrap()))
                .collect()
        }
        None => (1..=99).map(|n| (n, 100.0, 5.0)).collect(),
    };
    for (n, length, radius) in tools {
        let t = interp.state.offsets.tool_mut(n).ok_or(format!("tool {n}"))?;
        (t.h_geometry, t.d_geometry) = (length, radius);
    }
    Ok(interp)
}

/// What one dialect's run gave.
struct Outcome {
    canon: Vec<Canon>,
    /// The interpreter's alarm, if it ends in one.
    interp_alarm: Option<String>,
    result: RunResult,
    samples: Vec<Sample>,
    interp: Interpreter,
}

fn execute(text: &str, h: &Header, dialect: Dialect, dir: &Path) -> Result<Outcome, String> {
    let mut canon = Vec::new();
    let interp_alarm = match interpreter(text, h, dialect, dir)?.run(|c| canon.push(c)) {
        Ok(()) => None,
        Err(a) => Some(format!("alarm {} line {}", a.code, a.line)),
    };
    let mut interp = interpreter(text, h, dialect, dir)?;
    let mut samples = Vec::new();
    let opts = RunOptions { period_s: invariants::PERIOD, ..RunOptions::default() };
    let result = run(&mut interp, &opts, |s| samples.push(*s));
    Ok(Outcome { canon, interp_alarm, result, samples, interp })
}

fn invariants(skips: &[Skip], o: &Outcome, machine: &MachineConfig) -> Result<(), String> {
    if !header::skips_all(skips, "limits") {
        invariants::limits(&o.samples, machine, &header::skipped_lines(skips, "limits"))
            .map_err(|e| format!("limits: {e}"))?;
    }
    if !header::skips_all(skips, "tip") {
        invariants::tip_is_fk(&o.samples, &o.canon, &o.interp.config().machine).map_err(|e| format!("tip: {e}"))?;
        let changes = invariants::length_changes(&o.canon);
        let compared = invariants::tip(&o.samples, machine, &header::skipped_lines(skips, "tip"), &changes)
            .map_err(|e| format!("tip: {e}"))?;
        // A program that never moves has no sample, nor has one whose only moves change the
        // tool length where the systems differ; any other must compare some.
        if compared == 0 && o.samples.iter().any(|s| !changes.contains(&s.line)) {
            return Err("tip: no sample compared (say why with (skip: tip …))".into());
        }
    }
    Ok(())
}

/// Marks in `needed` the skips without which this run breaks its invariant.
fn mark_needed(skips: &[Skip], o: &Outcome, machine: &MachineConfig, needed: &mut [bool]) {
    for (i, flag) in needed.iter_mut().enumerate() {
        let rest: Vec<Skip> = skips.iter().enumerate().filter(|(k, _)| *k != i).map(|(_, s)| s.clone()).collect();
        if invariants(&rest, o, machine).is_err() {
            *flag = true;
        }
    }
}

/// The skips that no dialect needed: a stale exemption would hide a regression.
fn unneeded(skips: &[Skip], needed: &[bool]) -> Result<(), String> {
    let stale: Vec<String> =
        skips.iter().zip(needed).filter(|(_, n)| !**n).map(|(s, _)| format!("(skip: {})", s.text)).collect();
    if stale.is_empty() {
        Ok(())
    } else {
        Err(format!("not needed, the invariant holds without: {}", stale.join(" ")))
    }
}

fn fixture(dir: &Path, file: &Path) -> Result<(), String> {
    let text = std::fs::read_to_string(file).map_err(|e| e.to_string())?;
    let h = header::parse(&text)?;
    let machine = machine_of(&h, file.parent().unwrap())?;
    let mut snapshot = String::new();
    let mut printed: Vec<(String, Vec<Dialect>)> = Vec::new();
    let mut errs = Vec::new();
    let mut needed = vec![false; h.skips.len()];
    for &dialect in &h.dialects {
        let wanted: Vec<&Expect> = h.expects.iter().filter(|e| e.applies_to(dialect)).collect();
        if wanted.is_empty() {
            errs.push(format!("{}: no expectation", dialect.name()));
        }
        let o = execute(&text, &h, dialect, file.parent().unwrap())?;
        let mut body = pretty::canon(&machine, &o.canon);
        if let Some(a) = &o.interp_alarm {
            let _ = writeln!(body, "{a}");
        }
        match printed.iter_mut().find(|(b, _)| *b == body) {
            Some((_, ds)) => ds.push(dialect),
            None => printed.push((body, vec![dialect])),
        }
        errs.extend(expectations(&wanted, &o).into_iter().map(|e| format!("{}: {e}", dialect.name())));
        if let Err(e) = invariants(&h.skips, &o, &machine) {
            errs.push(format!("{}: {e}", dialect.name()));
        }
        mark_needed(&h.skips, &o, &machine, &mut needed);
    }
    if let Err(e) = unneeded(&h.skips, &needed) {
        errs.push(e);
    }
    for (body, ds) in &printed {
        let names: Vec<&str> = ds.iter().map(|d| d.name()).collect();
        let _ = write!(snapshot, "--- {}\n{body}", names.join(", "));
    }
    // The hand-written expectations first, so that a wrong snapshot is never accepted by accident.
    if !errs.is_empty() {
        return Err(errs.join("\n  "));
    }
    let name = file.file_stem().unwrap().to_string_lossy().into_owned();
    let rel = file.parent().unwrap().strip_prefix(dir).unwrap();
    let mut settings = insta::Settings::clone_current();
    settings.set_snapshot_path(dir.join("snapshots").join(rel));
    settings.set_prepend_module_to_snapshot(false);
    settings.set_omit_expression(true);
    settings.set_input_file(file);
    settings.bind(|| insta::assert_snapshot!(name, snapshot));
    Ok(())
}

fn invariants_only(file: &Path) -> Result<(), String> {
    let text = std::fs::read_to_string(file).map_err(|e| e.to_string())?;
    let h = header::parse(&text)?;
    let machine = machine_of(&h, file.parent().unwrap())?;
    let mut needed = vec![false; h.skips.len()];
    for &dialect in &h.dialects {
        let o = execute(&text, &h, dialect, file.parent().unwrap())?;
        invariants(&h.skips, &o, &machine).map_err(|e| format!("{}: {e}", dialect.name()))?;
        mark_needed(&h.skips, &o, &machine, &mut needed);
    }
    unneeded(&h.skips, &needed)
}

/// Equal to 1e-9 (a hand-computed value written to fewer places says `~TOL`).
fn close(got: f64, want: (f64, f64)) -> bool {
    (got - want.0).abs() <= want.1
}

/// `V` or `V~TOL`.
fn number(v: &str) -> Result<(f64, f64), String> {
    let bad = || format!("expectation value {v:?} is not a number");
    let (x, tol) = v.split_once('~').unwrap_or((v, "1e-9"));
    Ok((x.parse().map_err(|_| bad())?, tol.parse().map_err(|_| bad())?))
}

/// `X1,Y2`: the motion's target on the axes named.
fn target_mismatches(k: &str, m: &fivex_engine::canon::Motion, v: &str, machine: &MachineConfig) -> Vec<String> {
    let mut errs = Vec::new();
    for word in v.split(',') {
        let letter = word.chars().next().unwrap_or(' ');
        let Some(i) = machine.axes.iter().position(|a| a.name == letter) else {
            errs.push(format!("{k}: no axis {letter}"));
            continue;
        };
        match number(&word[1..]) {
            Ok(w) if close(m.target[i], w) => {}
            Ok(_) => errs.push(format!("{k}: {letter} expected {}, got {}", &word[1..], m.target[i])),
            Err(e) => errs.push(e),
        }
    }
    errs
}

/// The mismatches between the run and the expectations.
fn expectations(wanted: &[&Expect], o: &Outcome) -> Vec<String> {
    let mut errs = Vec::new();
    let r = &o.result;
    let machine = &o.interp.config().machine;
    let motions: Vec<&fivex_engine::canon::Motion> = o
        .canon
        .iter()
        .filter_map(|c| match &c.kind {
            fivex_engine::canon::CanonKind::Motion(m) => Some(m),
            _ => None,
        })
        .collect();
    let mut msgs: Option<Vec<String>> = None;
    for e in wanted {
        let (k, v) = (e.key.as_str(), e.value.as_str());
        let mut num = |what: &str, got: Option<f64>| match (number(v), got) {
            (Ok(w), Some(g)) if close(g, w) => {}
            (Err(m), _) => errs.push(m),
            (_, g) => errs.push(format!("{what}: expected {v}, got {g:?}")),
        };
        match k {
            "status" => {
                let got = if r.completed() { "completed" } else { "alarm" };
                if got != v {
                    errs.push(format!("status: expected {v}, got {got} {:?}", r.alarms));
                }
            }
            "alarm" => {
                let got: Vec<&str> = r.alarms.iter().map(|a| a.code.as_str()).collect();
                if got != [v] {
                    errs.push(format!("alarm: expected exactly {v}, got {got:?}"));
                }
            }
            "alarm_line" => num("alarm line", r.alarms.first().map(|a| a.line as f64)),
            "alarm_n" => {
                let got = r.alarms.first().map(|a| a.n);
                let ok = match got {
                    Some(None) => v == "null",
                    Some(Some(n)) => number(v).is_ok_and(|w| close(f64::from(n), w)),
                    None => false,
                };
                if !ok {
                    errs.push(format!("alarm n: expected {v}, got {got:?}"));
                }
            }
            "blocks" => num("blocks", Some(r.blocks as f64)),
            "canon" => num("canonical commands", Some(o.canon.len() as f64)),
            "motions" => num("motions", Some(motions.len() as f64)),
            "msg" => msgs.get_or_insert_with(Vec::new).push(v.to_string()),
            k if k.starts_with('#') => {
                let n: u32 = match k[1..].parse() {
                    Ok(n) => n,
                    Err(_) => {
                        errs.push(format!("{k}: not a variable"));
                        continue;
                    }
                };
                match o.interp.state.read(n) {
                    Err(a) => errs.push(format!("{k}: not readable ({a:?})")),
                    Ok(got) if v == "vacant" => {
                        if got.is_some() {
                            errs.push(format!("{k}: expected vacant, got {got:?}"));
                        }
                    }
                    Ok(got) => num(k, got),
                }
            }
            "commons" => {
                // commons=100:1,102:6 (or none): the non-vacant common variables, all of them.
                let want: Vec<(u32, (f64, f64))> = if v == "none" {
                    Vec::new()
                } else {
                    match v.split(',').map(|p| p.split_once(':').ok_or(p)).collect::<Result<Vec<_>, _>>() {
                        Ok(pairs) => match pairs
                            .iter()
                            .map(|(n, x)| Ok((n.parse::<u32>().map_err(|e| e.to_string())?, number(x)?)))
                            .collect::<Result<Vec<_>, String>>()
                        {
                            Ok(w) => w,
                            Err(e) => {
                                errs.push(format!("commons: {e}"));
                                continue;
                            }
                        },
                        Err(p) => {
                            errs.push(format!("commons: {p:?} is not N:V"));
                            continue;
                        }
                    }
                };
                let same = want.len() == r.variables.len()
                    && want.iter().zip(&r.variables).all(|((n, w), (gn, g))| n == gn && close(*g, *w));
                if !same {
                    errs.push(format!("commons: expected {v}, got {:?}", r.variables));
                }
            }
            "feeds" => {
                // feeds=X10,Y0,Z-2/X20,Y0,Z-2: every G01 motion's target, in order.
                let got: Vec<&fivex_engine::canon::Motion> =
                    motions.iter().copied().filter(|m| m.kind == fivex_engine::canon::MotionKind::Linear).collect();
                let want: Vec<&str> = v.split('/').collect();
                if got.len() != want.len() {
                    errs.push(format!("feeds: expected {} G01 motions, got {}", want.len(), got.len()));
                    continue;
                }
                for (m, w) in got.iter().zip(want) {
                    errs.extend(target_mismatches(k, m, w, machine));
                }
            }
            k if k.starts_with("motion") => {
                // motionK=X1,Y2: the K-th motion's target (programming coordinates).
                let Some(m) = k[6..].parse::<usize>().ok().and_then(|i| motions.get(i.wrapping_sub(1))) else {
                    errs.push(format!("{k}: no such motion (there are {})", motions.len()));
                    continue;
                };
                errs.extend(target_mismatches(k, m, v, machine));
            }
            k if k.len() == 2 && (k.starts_with('m') || k.starts_with('w')) => {
                let letter = k.chars().nth(1).unwrap();
                let i = machine.axes.iter().position(|a| a.name == letter);
                let pos = if k.starts_with('m') { &r.machine } else { &r.workpiece };
                num(k, i.map(|i| pos[i]));
            }
            _ => errs.push(format!("unknown expectation key {k:?}")),
        }
    }
    if let Some(want) = msgs {
        if r.messages != want {
            errs.push(format!("messages: expected {want:?}, got {:?}", r.messages));
        }
    }
    errs
}
