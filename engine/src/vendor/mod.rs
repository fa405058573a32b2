//! The vendors' parameter sets: FANUC No.1020… / No.19680…, Syntec Pr21… / Pr3001… and the
//! Haas settings (MRZP Setting 255–257 and a constructed machine description), mapped
//! onto the vendor-neutral [`MachineConfig`] and back (`docs/machine-config.md`, "Parameter
//! sets", lists every number).
//!
//! Reading a set checks it the way the control does: values out of range are refused, and a
//! mechanism that cannot work raises the vendor's alarm (Syntec COR-155/156/157, OP-032; FANUC
//! PS5459). Writing gives the set's *canonical* form — the one spelling of each value the reader
//! gives back unchanged (coordinate-axis directions as codes 1–3, angles in (−180°, 180°], RA in
//! [0°, 180°] with RB 0 when RA is 0) — so vendor → model → vendor is the identity on it.

mod fanuc;
mod haas;
mod params;
mod syntec;
pub mod unmodelled;

pub use params::{ParamFile, Params, Value};

use crate::kin::{vec3, Vec3};
use crate::machine::{ConfigError, MachineConfig, RotaryLink, Side};
use crate::Dialect;

/// The machine a vendor parameter list describes.
pub fn machine_from(dialect: Dialect, name: &str, params: &Params) -> Result<MachineConfig, ConfigError> {
    let m = match dialect {
        Dialect::Fanuc => fanuc::machine(name, params)?,
        Dialect::Haas => haas::machine(name, params)?,
        Dialect::Syntec => syntec::machine(name, params)?,
    };
    // The mechanism checks (parallel axes, axes parallel to the tool) raise the vendor's alarm.
    crate::kin::Kinematics::new(&m)?;
    Ok(m)
}

/// The vendor parameter list of a machine, or why the vendor cannot describe it.
pub fn params_of(dialect: Dialect, m: &MachineConfig) -> Result<Params, ConfigError> {
    crate::kin::Kinematics::new(m)?;
    match dialect {
        Dialect::Fanuc => fanuc::params(m),
        Dialect::Syntec => syntec::params(m),
        Dialect::Haas => haas::params(m),
    }
}

/// The unit vector of coordinate axis `code` (1 X, 2 Y, 3 Z).
fn unit(code: i64) -> Vec3 {
    let mut u = Vec3::zeros();
    u[(code - 1) as usize] = 1.0;
    u
}

/// The reference tool direction of FANUC No.19697–19699 and Syntec Pr3002–3004 (both manuals
/// describe the same construction): the tool along coordinate axis `code` is tilted by RA, then
/// by RB, about fixed axes with the right-hand rule —
/// 3: `Rz(RB)·Ry(RA)·ẑ`, 1: `Rx(RB)·Rz(RA)·x̂`, 2: `Ry(RB)·Rx(RA)·ŷ`.
fn reference_direction(code: i64, ra: f64, rb: f64) -> Vec3 {
    let (sa, ca) = crate::angle::sin_cos_deg(ra);
    let (sb, cb) = crate::angle::sin_cos_deg(rb);
    match code {
        1 => Vec3::new(ca, sa * cb, sa * sb),
        2 => Vec3::new(sa * sb, ca, sa * cb),
        _ => Vec3::new(sa * cb, sa * sb, ca),
    }
}

/// The canonical (code, RA, RB) of a unit tool direction (`kin::reference_angles`, the code
/// counting the axes from 1).
fn reference_angles(t: Vec3) -> (i64, f64, f64) {
    let (k, ra, rb) = crate::kin::reference_angles(t);
    (k as i64 + 1, ra, rb)
}

/// The rotary links in the vendors' order θ1, θ2: master then slave on one side, the head axis
/// then the table axis on a mixed machine.
fn chain(m: &MachineConfig) -> Vec<&RotaryLink> {
    let on = |side: Side| m.rotary.iter().filter(move |l| l.side == side);
    on(Side::Head).chain(on(Side::Table)).collect()
}

/// A machine-file direction as a unit vector.
fn direction(a: [f64; 3]) -> Vec3 {
    vec3(a).normalize()
}

/// Angle `x` (degrees) in (−180°, 180°].
fn half_turn(x: f64) -> f64 {
    let r = x.rem_euclid(360.0);
    if r > 180.0 {
        r - 360.0
    } else {
        r
    }
}

/// A value that cannot be written in the vendor's parameters.
fn unrepresentable(dialect: &str, what: impl std::fmt::Display) -> ConfigError {
    ConfigError::invalid(format!("{dialect} parameters cannot describe this machine: {what}"))
}

#[cfg(test)]
mod tests;
