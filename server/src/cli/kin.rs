//! `fivex kin fk` / `fivex kin ik` (docs/contracts.md): the machine's kinematics by hand.

use super::{load_machine, Fail, MachineArgs};
use crate::wire::{axis_values, AlarmCode, ForwardKinematics, InverseKinematics, SingularityInfo};
use clap::{Args, Subcommand};
use fivex_engine::kin::{Kinematics, Selection, Vec3};
use fivex_engine::machine::{Chain, MachineConfig};
use fivex_engine::Dialect;
use serde::Serialize;

#[derive(Subcommand, Debug)]
pub enum KinCommand {
    /// Forward kinematics: axis positions → tool tip and direction.
    Fk(FkArgs),
    /// Inverse kinematics: tool tip and direction → every axis solution and the chosen one.
    Ik(IkArgs),
}

#[derive(Args, Debug)]
pub struct FkArgs {
    #[command(flatten)]
    machine: MachineArgs,
    /// Axis positions, e.g. X=0,Y=0,Z=0,B=0,C=0 (missing axes are 0).
    #[arg(long, default_value = "", allow_hyphen_values = true)]
    axes: String,
    /// Tool length, mm.
    #[arg(long, default_value_t = 0.0)]
    tool_length: f64,
    /// Whose alarm a machine that cannot work raises: fanuc, syntec or haas [default: a
    /// parameter list's own dialect, else fanuc].
    #[arg(long)]
    dialect: Option<Dialect>,
    /// The mechanism chain, as Syntec's G10 L5000 P_ Q_ selects it: SET or SET,SUB (default 1).
    #[arg(long)]
    chain: Option<String>,
}

#[derive(Args, Debug)]
pub struct IkArgs {
    #[command(flatten)]
    machine: MachineArgs,
    /// Tool tip X,Y,Z in the table frame.
    #[arg(long, allow_hyphen_values = true)]
    tip: String,
    /// Tool direction I,J,K (tip → holder) in the table frame.
    #[arg(long, allow_hyphen_values = true)]
    tool: String,
    /// Current axis positions the choice starts from, e.g. B=-70,C=30 (missing axes are 0).
    #[arg(long, default_value = "", allow_hyphen_values = true)]
    from: String,
    /// Tool length, mm.
    #[arg(long, default_value_t = 0.0)]
    tool_length: f64,
    /// Syntec G53.1 P: 0 shortest master path, 1 master positive, 2 master negative.
    #[arg(long, default_value_t = 0)]
    p: u8,
    /// FANUC No.19608#5 PRI: judge the second rotary axis's movement first.
    #[arg(long)]
    pri: bool,
    /// Whose selection rules: fanuc, syntec or haas (Haas: FANUC's) [default: a parameter
    /// list's own dialect, else fanuc].
    #[arg(long)]
    dialect: Option<Dialect>,
    /// The mechanism chain, as Syntec's G10 L5000 P_ Q_ selects it: SET or SET,SUB (default 1).
    #[arg(long)]
    chain: Option<String>,
}

pub fn run(command: KinCommand) -> Result<i32, Fail> {
    match command {
        KinCommand::Fk(a) => fk(a),
        KinCommand::Ik(a) => ik(a),
    }
}

/// The machine (as `chain` sees it) and its kinematics; a mechanism that cannot work fails with
/// the dialect's alarm. The dialect is `given` or the machine file's (`load_machine`).
fn model(
    args: &MachineArgs,
    given: Option<Dialect>,
    chain: Option<&str>,
) -> Result<(MachineConfig, Kinematics, Dialect), Fail> {
    let (mut m, dialect) = load_machine(args, given)?;
    if let Some(text) = chain {
        let numbers: Vec<u8> = text
            .split(',')
            .map(|n| n.trim().parse())
            .collect::<Result<_, _>>()
            .map_err(|_| Fail(format!("--chain '{text}': expected SET or SET,SUB (whole numbers)")))?;
        let chain = match numbers[..] {
            [set] => Chain { set, sub: 1 },
            [set, sub] => Chain { set, sub: sub.max(1) },
            _ => return Err(Fail(format!("--chain '{text}': expected SET or SET,SUB"))),
        };
        m = m.chain_view(chain).ok_or_else(|| Fail(format!("--chain '{text}': the machine has no such chain")))?;
    }
    let k = Kinematics::new(&m).map_err(|e| Fail(e.describe(dialect)))?;
    Ok((m, k, dialect))
}

/// `X=1,B=-70` → positions in axis order (others 0).
fn positions(m: &MachineConfig, text: &str) -> Result<Vec<f64>, Fail> {
    let mut pos = vec![0.0; m.axes.len()];
    for item in text.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let (name, value) = item.split_once('=').ok_or_else(|| Fail(format!("'{item}': expected AXIS=VALUE")))?;
        let i = m
            .axes
            .iter()
            .position(|a| a.name.to_string().eq_ignore_ascii_case(name.trim()))
            .ok_or_else(|| Fail(format!("'{name}': the machine has no such axis")))?;
        pos[i] = number(value)?;
    }
    Ok(pos)
}

fn number(text: &str) -> Result<f64, Fail> {
    let v: f64 = text.trim().parse().map_err(|_| Fail(format!("'{text}': not a number")))?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(Fail(format!("'{text}': not a finite number")))
    }
}

fn triple(text: &str) -> Result<Vec3, Fail> {
    let v: Vec<f64> = text.split(',').map(number).collect::<Result<_, _>>()?;
    match v[..] {
        [x, y, z] => Ok(Vec3::new(x, y, z)),
        _ => Err(Fail(format!("'{text}': expected three numbers X,Y,Z"))),
    }
}

fn array(v: Vec3) -> [f64; 3] {
    [v.x, v.y, v.z]
}

fn print(value: &impl Serialize) -> Result<(), Fail> {
    println!("{}", serde_json::to_string(value)?);
    Ok(())
}

fn fk(a: FkArgs) -> Result<i32, Fail> {
    let (m, k, _) = model(&a.machine, a.dialect, a.chain.as_deref())?;
    let pos = positions(&m, &a.axes)?;
    let p = k.forward(&pos, a.tool_length);
    print(&ForwardKinematics {
        tip: array(p.tip),
        tool: array(p.tool),
        tip_machine: array(p.tip_machine),
        tool_machine: array(p.tool_machine),
        singularity: k.singularity(&pos).map(|s| SingularityInfo { axis: s.axis.to_string(), angle: s.angle }),
    })?;
    Ok(0)
}

fn ik(a: IkArgs) -> Result<i32, Fail> {
    let (m, k, dialect) = model(&a.machine, a.dialect, a.chain.as_deref())?;
    let from = positions(&m, &a.from)?;
    let tool = triple(&a.tool)?;
    if tool.norm() < 1e-12 {
        return Err(Fail("--tool: the direction must not be zero".into()));
    }
    let candidates = k.inverse(triple(&a.tip)?, tool, a.tool_length, &from);
    let how = Selection { dialect, pri: a.pri, p: a.p };
    let choice = k.select(&candidates, &from, how);
    let names: Vec<char> = m.axes.iter().map(|a| a.name).collect();
    let (chosen, alarm) = match &choice {
        Ok(c) => (Some(axis_values(&c.pos, &names)), None),
        Err(id) => {
            let (code, message) = dialect.describe(id);
            (None, Some(AlarmCode { code: code.to_string(), message: message.to_string() }))
        }
    };
    // Axes a singular posture leaves free (kept at their --from angle).
    let joints = k.joints();
    let free: Vec<String> = candidates
        .first()
        .map(|c| joints.iter().zip(&c.free).filter(|(_, f)| **f).map(|(j, _)| j.name.to_string()).collect())
        .unwrap_or_default();
    print(&InverseKinematics {
        candidates: candidates.iter().map(|c| axis_values(&c.pos, &names)).collect(),
        chosen,
        alarm,
        singular: free,
    })?;
    Ok(if choice.is_ok() { 0 } else { 1 })
}
