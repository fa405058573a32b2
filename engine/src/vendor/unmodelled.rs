//! What of a machine description fivex keeps but does not carry out, reported when a machine
//! is loaded (`docs/machine-config.md`, "Settings fivex does not model"): a confident answer on a
//! machine whose parameters fivex silently ignored would be wrong.
//!
//! A vendor parameter is *unmodelled* when nothing about it reaches the model: removing it,
//! changing its value by one, or (FANUC, values 0–255) flipping any of its bits leaves the
//! machine the list describes unchanged. A FANUC bit that is set while the rest of its parameter
//! is read is reported alone (`No.19608#0`). Known display-only parameters are not reported.
//! Settings the model would keep without acting on them are reported from the model, whatever
//! form it was given in (none today).

use super::{machine_from, Params, Value};
use crate::machine::MachineConfig;
use crate::Dialect;

/// One setting fivex does not carry out.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct Unmodelled {
    /// As the vendor numbers it (`No.8130`, `No.19608#0`, `Pr3052`) or the model field
    /// (`five_axis.smooth_tolerance`).
    pub parameter: String,
    /// What fivex does instead.
    pub reason: String,
}

/// Parameters that change nothing a program does (display only): accepted without a report.
const DISPLAY_ONLY: &[(Dialect, u32)] = &[(Dialect::Fanuc, 3281)];

/// Why a parameter that is not read is reported, where fivex knows more than "not read": the
/// FANUC 16i's own description of the tool's rotation axes for 3-D cutter compensation.
fn not_read_reason(dialect: Dialect, n: u32) -> String {
    match (dialect, n) {
        (Dialect::Fanuc, 19610..=19623) => "the 16i's description of the tool's rotation axes for 3-D cutter \
            compensation (A-78438E) is not read: fivex takes the tool from the machine's kinematics \
            (No.19680–19699), docs/cutter-compensation.md, \"16i variant\""
            .into(),
        _ => "not read by fivex's model: the machine behaves as without it".into(),
    }
}

/// The model's settings fivex keeps without carrying them out: none today (Syntec STCP's
/// smoothing, the last, is performed); a setting the model gains before its function is built
/// is reported here.
pub fn of_model(_m: &MachineConfig) -> Vec<Unmodelled> {
    Vec::new()
}

/// What of the parameter list `given` fivex does not carry out (nothing when the list
/// describes no machine: loading it fails with the reason instead).
pub fn of_params(dialect: Dialect, given: &Params) -> Vec<Unmodelled> {
    let Ok(base) = machine_from(dialect, "m", given) else { return Vec::new() };
    let name = |n: u32| match dialect {
        Dialect::Fanuc => format!("No.{n}"),
        Dialect::Haas => format!("Setting {n}"),
        Dialect::Syntec => format!("Pr{n}"),
    };
    // Whether the list with `n` set to `value` (`None`: removed) describes another machine (or
    // none).
    // What the list with `n` set to `value` (`None`: removed) describes: the same machine
    // (`Some(true)`), another one (`Some(false)`), or none.
    let same = |n: u32, value: Option<Value>| {
        let mut p = given.clone();
        match value {
            Some(v) => p.0.insert(n, v),
            None => p.0.remove(&n),
        };
        machine_from(dialect, "m", &p).ok().map(|m| m == base)
    };
    let mut out = Vec::new();
    for (&n, value) in &given.0 {
        if DISPLAY_ONLY.contains(&(dialect, n)) {
            continue;
        }
        let values: Vec<f64> = match value {
            Value::One(x) => vec![*x],
            Value::PerAxis(v) => v.clone(),
        };
        // 0 is every parameter's value when not set: a parameter left there changes nothing —
        // except the 16i's tool description, where 0 says something (axis numbers, reference
        // angles RA/RB 0°: the tool along linear axis 3) that fivex takes from elsewhere.
        let sixteen_i_tool = dialect == Dialect::Fanuc && (19610..=19623).contains(&n);
        if values.iter().all(|x| *x == 0.0) && !sixteen_i_tool {
            continue;
        }
        let with = |values: Vec<f64>| match value {
            Value::One(_) => Value::One(values[0]),
            Value::PerAxis(_) => Value::PerAxis(values),
        };
        let shifted = |d: f64| with(values.iter().map(|x| x + d).collect());
        let read = [None, Some(shifted(1.0)), Some(shifted(-1.0))].into_iter().any(|v| same(n, v) != Some(true));
        // FANUC bit parameters (element values 0–255): each bit of each element flipped.
        let bits = dialect == Dialect::Fanuc && values.iter().all(|x| x.fract() == 0.0 && (0.0..=255.0).contains(x));
        let flips: Vec<(usize, u32, Option<bool>)> = if bits {
            (0..values.len())
                .flat_map(|k| (0..8).map(move |b| (k, b)))
                .map(|(k, b)| {
                    let mut v = values.clone();
                    v[k] = ((v[k] as u32) ^ (1 << b)) as f64;
                    (k, b, same(n, Some(with(v))))
                })
                .collect()
        } else {
            Vec::new()
        };
        // A bit parameter at its default is read when flipping one of its bits matters.
        if !read && flips.iter().all(|f| f.2 == Some(true)) {
            out.push(Unmodelled { parameter: name(n), reason: not_read_reason(dialect, n) });
            continue;
        }
        // Bit by bit only where bits are what the model reads: some bit's flip gives another
        // working machine, or the same machine with the element still set (No.1006#1 ROS
        // beside #0 ROT, whose own flip a rotary link refuses: No.1006 = 3 → 1). A checked
        // code (No.1022's one legal value per axis) flips only into refusals or to 0, unset.
        let bitwise = flips.iter().any(|&(k, b, same)| match same {
            Some(false) => true,
            Some(true) => (values[k] as u32) ^ (1 << b) != 0,
            None => false,
        });
        if bitwise {
            for &(k, b, _) in flips.iter().filter(|f| f.2 == Some(true) && (values[f.0] as u32) & (1 << f.1) != 0) {
                let axis = if values.len() > 1 { format!(" (axis {})", k + 1) } else { String::new() };
                out.push(Unmodelled {
                    parameter: format!("No.{n}#{b}{axis}"),
                    reason: "bit not read by fivex's model: the machine behaves as with it 0".into(),
                });
            }
        }
    }
    if dialect == Dialect::Haas {
        // Not a setting ignored but one missing: loading goes on with the centre at machine
        // zero, so it is said (a UMC program would otherwise run about a pivot far off).
        out.extend(super::haas::missing_mrzp(given).into_iter().map(|n| Unmodelled {
            parameter: name(n),
            reason:
                "not given: the MRZP offset is 0 (machine zero), no real rotary centre; set it to the machine's".into(),
        }));
    }
    out.extend(of_model(&base));
    out
}
