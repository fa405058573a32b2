//! The compact pretty-print of canonical commands a data fixture's snapshot holds: one line per
//! command, `LINE [Nn] what`, numbers rounded to 1 nm / 1 µdeg so that the snapshot pins the
//! program's meaning, not the last bits of the arithmetic.

use fivex_engine::canon::{Canon, CanonKind, Coolant, CutterWord, FeedMode, Motion, MotionKind, Pos, SpindleState};
use fivex_engine::kin::Vec3;
use fivex_engine::machine::MachineConfig;
use std::fmt::Write as _;

/// A number rounded to 6 decimals in its shortest form (no `-0`).
pub fn num(x: f64) -> String {
    let r = (x * 1e6).round() / 1e6;
    if r == 0.0 {
        "0".into()
    } else {
        format!("{r}")
    }
}

fn axes(m: &MachineConfig, p: &Pos) -> String {
    let words: Vec<String> = m.axes.iter().enumerate().map(|(i, a)| format!("{}{}", a.name, num(p[i]))).collect();
    words.join(" ")
}

fn vec3(v: Vec3) -> String {
    format!("({} {} {})", num(v.x), num(v.y), num(v.z))
}

fn motion(m: &MachineConfig, mo: &Motion) -> String {
    let code = match mo.kind {
        MotionKind::Rapid => "G00",
        MotionKind::Linear => "G01",
        MotionKind::ArcCw => "G02",
        MotionKind::ArcCcw => "G03",
        MotionKind::MachineRapid => "G53",
    };
    let mut s = format!("{code} {} @ {}", axes(m, &mo.target), axes(m, &mo.machine));
    if !matches!(mo.kind, MotionKind::Rapid | MotionKind::MachineRapid) {
        let unit = match mo.feed_mode {
            FeedMode::PerMinute => "",
            FeedMode::PerRevolution => "/rev",
            FeedMode::InverseTime => " 1/min",
        };
        let _ = write!(s, " F{}{unit}", num(mo.feed));
    }
    if let Some(a) = &mo.arc {
        let (i, j, _) = a.plane_axes;
        let _ = write!(
            s,
            " arc c=({} {}) r={} sweep={}",
            num(a.center[i]),
            num(a.center[j]),
            num(a.radius),
            num(a.sweep_deg)
        );
    }
    if let Some(t) = &mo.tip {
        let _ = write!(s, " tip {}→{} L={}", vec3(t.from), vec3(t.to), num(t.tool_length));
        if let Some(a) = &t.arc {
            let _ = write!(s, " arc c={} n={} sweep={}", vec3(a.center), vec3(a.normal), num(a.sweep_deg));
        }
        if t.posture.is_some() {
            s.push_str(" posture");
        }
    }
    if mo.context.exact_stop {
        s.push_str(" exact");
    }
    s
}

fn kind(m: &MachineConfig, k: &CanonKind) -> String {
    match k {
        CanonKind::Motion(mo) => motion(m, mo),
        CanonKind::Dwell { seconds } => format!("dwell {}", num(*seconds)),
        CanonKind::ToolSelect { tool } => format!("tool select T{tool}"),
        CanonKind::ToolChange { tool } => format!("tool change T{tool}"),
        CanonKind::Spindle { state, speed } => {
            let st = match state {
                SpindleState::Cw => "cw",
                SpindleState::Ccw => "ccw",
                SpindleState::Stop => "stop",
            };
            format!("spindle {st} S{}", num(*speed))
        }
        CanonKind::Coolant(c) => {
            let c = match c {
                Coolant::Mist => "mist",
                Coolant::Flood => "flood",
                Coolant::Off => "off",
            };
            format!("coolant {c}")
        }
        CanonKind::Aux { m } => format!("M{m}"),
        CanonKind::Stop { optional, message } => {
            let mut s = if *optional { "optional stop".to_string() } else { "stop".to_string() };
            if let Some(msg) = message {
                let _ = write!(s, " {msg:?}");
            }
            s
        }
        CanonKind::Print { text } => format!("print {text:?}"),
        CanonKind::ProgramEnd { m } => format!("end M{m}"),
        CanonKind::Chain(c) => format!("chain P{} Q{}", c.set, c.sub),
        CanonKind::Cutter(CutterWord::CornerArc(d)) => match d {
            Some(d) => format!("corner arc I{} J{} K{}", num(d[0]), num(d[1]), num(d[2])),
            None => "corner arc".to_string(),
        },
        CanonKind::Cutter(CutterWord::CancelDirection(d)) => {
            format!("cancel toward I{} J{} K{}", num(d[0]), num(d[1]), num(d[2]))
        }
        CanonKind::Cutter(CutterWord::VectorHold(d)) => match d {
            Some(d) => format!("vector hold I{} J{} K{}", num(d[0]), num(d[1]), num(d[2])),
            None => "vector hold".to_string(),
        },
        CanonKind::Cutter(CutterWord::PlaneChange(q)) => format!("plane change Q{q}"),
        CanonKind::Cutter(CutterWord::Perpendicular) => "perpendicular".to_string(),
        CanonKind::Cutter(CutterWord::WithoutMotion) => "without motion".to_string(),
    }
}

/// Commands printed at most: the first `HEAD` and the last `TAIL` of a longer list (a program
/// that expands without bound until its alarm).
const HEAD: usize = 200;
const TAIL: usize = 20;

/// One line per command.
pub fn canon(m: &MachineConfig, cmds: &[Canon]) -> String {
    let mut out = String::new();
    let line = |out: &mut String, c: &Canon| {
        let n = c.n.map(|n| format!(" N{n}")).unwrap_or_default();
        let _ = writeln!(out, "{}{n} {}", c.line, kind(m, &c.kind));
    };
    if cmds.len() <= HEAD + TAIL {
        cmds.iter().for_each(|c| line(&mut out, c));
    } else {
        cmds[..HEAD].iter().for_each(|c| line(&mut out, c));
        let _ = writeln!(out, "… {} commands …", cmds.len() - HEAD - TAIL);
        cmds[cmds.len() - TAIL..].iter().for_each(|c| line(&mut out, c));
    }
    out
}
