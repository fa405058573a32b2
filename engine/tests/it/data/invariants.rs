//! The invariants every data fixture's run is held to, sample by sample (every [`PERIOD`]):
//!
//! - `limits`: each axis's speed, acceleration and jerk by finite differences within its limits
//!   (`common::check_limits_every`, corners allowed the speed step), and every sample within the
//!   stored stroke (`common::check_strokes`).
//! - `tip`: the sample's tip is the forward kinematics of its axes (`tip_is_fk`, read
//!   independently of the run through `fivex_engine::tip::locate`), and that tip
//!   (`Sample::tip`) is held against the commanded point (`Sample::programmed`). Where the two
//!   systems coincide — the commanded point is in the workpiece system and every rotary axis
//!   stands at 0 — they are the same point (1 nm). In every other case (rotaries turned with
//!   plain G43, TCP in Π, a tilted plane's feature system, G54.4's WSCS) the commanded point's
//!   system is fixed to the tip's while a block runs, so the tip's path is the commanded path
//!   carried rigidly: within each block, every sample is as far from the block's first sample on
//!   the tip path as on the commanded path (1 µm, the kinematic paths' tolerance). A block that
//!   changes the tool length in effect (G43/G44/G49, TCP on or off, found from the canonical
//!   commands' `tip_basis`) moves the machine by the change while the commanded point moves from
//!   where it was (FANUC type A): the tip meets the commanded path only at the block's end, so
//!   there the harness checks only that the tip ends no farther from the commanded point than it
//!   started. What else breaks it — a rotary move without TCP swings the tip off the commanded
//!   line; a display in machine directions (FANUC DET) under a turning table — is named by the
//!   fixture's `(skip: tip@LINE …)`.

use crate::common;
use fivex_engine::canon::Canon;
use fivex_engine::machine::{AxisKind, Machine, MachineConfig};
use fivex_engine::run::Sample;
use fivex_engine::tip::{self, Basis};
use std::collections::HashMap;

/// The sampling period, s: 2 ms halves the cost of a 1 ms trace (most of the harness's time
/// is the run itself), and a finite difference over it bounds the derivatives as well.
pub const PERIOD: f64 = 0.002;

/// Where the tip and the commanded point coincide, mm.
const SAME: f64 = 1e-6;
/// How far the rigid copy may be off, mm.
const RIGID: f64 = 1e-3;

/// The `limits` invariant on the samples outside the `skipped` lines (each stretch between them
/// apart, so that no finite difference spans a gap).
pub fn limits(samples: &[Sample], m: &MachineConfig, skipped: &[u32]) -> Result<(), String> {
    for stretch in samples.split(|s| skipped.contains(&s.line)) {
        common::check_limits_every(stretch, m, false, PERIOD).map_err(|e| e.to_string())?;
        common::check_strokes(stretch, m).map_err(|e| e.to_string())?;
    }
    Ok(())
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Every rotary axis at 0 (the shown position is kept in [0, 360) on rollover axes).
fn rotaries_at_zero(s: &Sample, m: &MachineConfig) -> bool {
    m.axes.iter().enumerate().all(|(i, a)| {
        let x = s.machine[i].rem_euclid(360.0);
        a.kind != AxisKind::Rotary || !(1e-9..=360.0 - 1e-9).contains(&x)
    })
}

/// Every sample's `tip` and `tool` are the forward kinematics of its axes with the tool length
/// and workpiece origin of its block (the `tip_basis` of the canonical commands of its line,
/// where that line has one; a line run with different bases, as a loop over G43 H#1 can, is
/// left out), read here through `fivex_engine::tip::locate` with the mechanism of the basis's
/// chain (Syntec G10 L5000). Returns how many were compared.
pub fn tip_is_fk(samples: &[Sample], canon: &[Canon], machine: &Machine) -> Result<usize, String> {
    let mut bases: HashMap<u32, Option<Basis>> = HashMap::new();
    for c in canon {
        let b = bases.entry(c.line).or_insert(Some(c.tip_basis));
        if *b != Some(c.tip_basis) {
            *b = None;
        }
    }
    let mut compared = 0;
    for s in samples {
        let Some(Some(basis)) = bases.get(&s.line) else { continue };
        let fk = tip::locate(machine.kinematics_of(basis.chain).map(|k| &**k), &s.machine, basis);
        if dist(fk.tip, s.tip) > SAME || dist(fk.tool, s.tool) > 1e-9 {
            return Err(format!(
                "line {} t={}: the sample's tip {:?} (tool {:?}) is not the forward kinematics {:?} ({:?})",
                s.line, s.t, s.tip, s.tool, fk.tip, fk.tool
            ));
        }
        compared += 1;
    }
    Ok(compared)
}

/// The lines whose commands change the tool length the tip is read with.
pub fn length_changes(canon: &[Canon]) -> Vec<u32> {
    let mut length = 0.0;
    let mut lines = Vec::new();
    for c in canon {
        if c.tip_basis.tool_length != length {
            length = c.tip_basis.tool_length;
            lines.push(c.line);
        }
    }
    lines
}

/// The `tip` invariant; `skipped` lines are not checked, on `length_changed` lines only the
/// approach. Returns how many samples were compared, so that a fixture where it checks nothing
/// is seen.
pub fn tip(samples: &[Sample], m: &MachineConfig, skipped: &[u32], length_changed: &[u32]) -> Result<usize, String> {
    let mut compared = 0;
    let mut errs = Vec::new();
    for block in samples.chunk_by(|a, b| a.line == b.line) {
        let first = &block[0];
        if skipped.contains(&first.line) {
            continue;
        }
        if length_changed.contains(&first.line) {
            // Comparable only where the two systems coincide at both ends.
            let last = &block[block.len() - 1];
            let same = |s: &Sample| s.programmed_in == tip::System::Workpiece && rotaries_at_zero(s, m);
            if same(first) && same(last) {
                let (from, to) = (dist(first.tip, first.programmed), dist(last.tip, last.programmed));
                if to > from + RIGID {
                    errs.push(format!(
                        "line {} (the tool length changes): the tip ends {to} mm from the commanded point, started {from} mm",
                        first.line
                    ));
                }
                compared += 1;
            }
            continue;
        }
        for s in block {
            if s.programmed_in == tip::System::Workpiece && rotaries_at_zero(s, m) {
                let d = dist(s.tip, s.programmed);
                if d > SAME {
                    errs.push(format!(
                        "line {} t={}: tip {:?} is {d} mm from the commanded point {:?} (workpiece system, rotaries at 0)",
                        s.line, s.t, s.tip, s.programmed
                    ));
                    break;
                }
            }
            let on_tip = dist(s.tip, first.tip);
            let on_path = dist(s.programmed, first.programmed);
            if (on_tip - on_path).abs() > RIGID {
                errs.push(format!(
                    "line {} t={}: the tip moved {on_tip} mm since t={} but the commanded point ({}) {on_path} mm",
                    s.line,
                    s.t,
                    first.t,
                    s.programmed_in.name()
                ));
                break;
            }
            compared += 1;
        }
    }
    if errs.is_empty() {
        Ok(compared)
    } else {
        Err(errs.join("; "))
    }
}
