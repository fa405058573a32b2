//! JSON forms of the CLI's outputs (`CONTRACTS.md`). Canonical commands and trace samples are
//! written by hand into a buffered writer: they are the hot path of `fivex interp`/`run --trace`.

use fivex_engine::canon::{Canon, CanonKind, Coolant, FeedMode, Motion, MotionKind, Pos, SpindleState};
use fivex_engine::interp::gcode::display;
use fivex_engine::run::{RunResult, Sample};
use serde_json::{json, Map, Value};
use std::io::{self, Write};

fn num(w: &mut impl Write, x: f64) -> io::Result<()> {
    if x.is_finite() {
        // Shortest representation that reads back to the same f64.
        let mut buf = ryu_like(x);
        if buf.ends_with(".0") {
            buf.truncate(buf.len() - 2);
            buf.push_str(".0");
        }
        w.write_all(buf.as_bytes())
    } else {
        w.write_all(b"null")
    }
}

fn ryu_like(x: f64) -> String {
    // `{:?}` is Rust's shortest round-trip form and always has a point or exponent.
    let x = if x == 0.0 { 0.0 } else { x };
    format!("{x:?}")
}

fn axes_map(w: &mut impl Write, p: &Pos, axes: &[char]) -> io::Result<()> {
    w.write_all(b"{")?;
    for (i, a) in axes.iter().enumerate() {
        if i > 0 {
            w.write_all(b",")?;
        }
        write!(w, "\"{a}\":")?;
        num(w, p[i])?;
    }
    w.write_all(b"}")
}

fn opt_u32(w: &mut impl Write, n: Option<u32>) -> io::Result<()> {
    match n {
        Some(n) => write!(w, "{n}"),
        None => w.write_all(b"null"),
    }
}

fn json_string(s: &str) -> String {
    serde_json::to_string(s).unwrap_or_else(|_| "\"\"".into())
}

/// One canonical command as one JSON line.
pub fn write_canon(w: &mut impl Write, c: &Canon, axes: &[char]) -> io::Result<()> {
    let kind = match &c.kind {
        CanonKind::Motion(_) => "motion",
        CanonKind::Dwell { .. } => "dwell",
        CanonKind::ToolSelect { .. } => "tool_select",
        CanonKind::ToolChange { .. } => "tool_change",
        CanonKind::Spindle { .. } => "spindle",
        CanonKind::Coolant(_) => "coolant",
        CanonKind::Aux { .. } => "aux",
        CanonKind::Stop { .. } => "stop",
        CanonKind::Print { .. } => "print",
        CanonKind::ProgramEnd { .. } => "program_end",
    };
    write!(w, "{{\"type\":\"{kind}\",\"line\":{},\"n\":", c.line)?;
    opt_u32(w, c.n)?;
    match &c.kind {
        CanonKind::Motion(m) => motion(w, m, axes)?,
        CanonKind::Dwell { seconds } => {
            w.write_all(b",\"seconds\":")?;
            num(w, *seconds)?;
        }
        CanonKind::ToolSelect { tool } | CanonKind::ToolChange { tool } => write!(w, ",\"tool\":{tool}")?,
        CanonKind::Spindle { state, speed } => {
            let state = match state {
                SpindleState::Cw => "cw",
                SpindleState::Ccw => "ccw",
                SpindleState::Stop => "stop",
            };
            write!(w, ",\"state\":\"{state}\",\"speed\":")?;
            num(w, *speed)?;
        }
        CanonKind::Coolant(c) => {
            let state = match c {
                Coolant::Mist => "mist",
                Coolant::Flood => "flood",
                Coolant::Off => "off",
            };
            write!(w, ",\"state\":\"{state}\"")?;
        }
        CanonKind::Aux { m } => write!(w, ",\"m\":{m}")?,
        CanonKind::Stop { optional, message } => {
            write!(w, ",\"optional\":{optional},\"message\":")?;
            match message {
                Some(m) => w.write_all(json_string(m).as_bytes())?,
                None => w.write_all(b"null")?,
            }
        }
        CanonKind::Print { text } => write!(w, ",\"text\":{}", json_string(text))?,
        CanonKind::ProgramEnd { m } => write!(w, ",\"m\":{m}")?,
    }
    w.write_all(b"}\n")
}

fn motion(w: &mut impl Write, m: &Motion, axes: &[char]) -> io::Result<()> {
    let kind = match m.kind {
        MotionKind::Rapid => "rapid",
        MotionKind::Linear => "linear",
        MotionKind::ArcCw => "arc_cw",
        MotionKind::ArcCcw => "arc_ccw",
        MotionKind::MachineRapid => "machine_rapid",
    };
    let feed_mode = match m.feed_mode {
        FeedMode::InverseTime => "G93",
        FeedMode::PerMinute => "G94",
        FeedMode::PerRevolution => "G95",
    };
    write!(w, ",\"motion\":\"{kind}\",\"target\":")?;
    axes_map(w, &m.target, axes)?;
    w.write_all(b",\"machine\":")?;
    axes_map(w, &m.machine, axes)?;
    w.write_all(b",\"feed\":")?;
    num(w, m.feed)?;
    write!(w, ",\"feed_mode\":\"{feed_mode}\"")?;
    if let Some(arc) = &m.arc {
        w.write_all(b",\"arc\":{\"center\":")?;
        axes_map(w, &arc.center, axes)?;
        w.write_all(b",\"radius\":")?;
        num(w, arc.radius)?;
        w.write_all(b",\"sweep_deg\":")?;
        num(w, arc.sweep_deg)?;
        w.write_all(b"}")?;
    }
    let c = &m.context;
    let wcs = if c.wcs == 541 { format!("G54.1 P{}", c.wcs_p) } else { display(c.wcs) };
    write!(
        w,
        ",\"context\":{{\"plane\":\"{}\",\"wcs\":\"{wcs}\",\"length_comp\":\"{}\",\"h\":{},\"tool_length\":",
        display(c.plane),
        display(c.length_comp),
        c.h
    )?;
    num(w, c.tool_length)?;
    write!(w, ",\"cutter_comp\":\"{}\",\"d\":{},\"cutter_radius\":", display(c.cutter_comp), c.d)?;
    num(w, c.cutter_radius)?;
    write!(w, ",\"path_mode\":\"{}\",\"rotation\":\"{}\"}}", display(c.path_mode), display(c.rotation))
}

/// One trace sample as one JSON line.
pub fn write_sample(w: &mut impl Write, s: &Sample, axes: &[char]) -> io::Result<()> {
    w.write_all(b"{\"t\":")?;
    num(w, s.t)?;
    write!(w, ",\"line\":{},\"n\":", s.line)?;
    opt_u32(w, s.n)?;
    w.write_all(b",\"machine\":")?;
    axes_map(w, &s.machine, axes)?;
    w.write_all(b",\"tip\":[")?;
    for (i, x) in s.tip.iter().enumerate() {
        if i > 0 {
            w.write_all(b",")?;
        }
        num(w, *x)?;
    }
    w.write_all(b"],\"tool\":[")?;
    for (i, x) in s.tool.iter().enumerate() {
        if i > 0 {
            w.write_all(b",")?;
        }
        num(w, *x)?;
    }
    w.write_all(b"],\"feed\":")?;
    num(w, s.feed)?;
    w.write_all(b"}\n")
}

fn position(p: &Pos, axes: &[char]) -> Value {
    let map: Map<String, Value> = axes.iter().enumerate().map(|(i, a)| (a.to_string(), json!(p[i]))).collect();
    Value::Object(map)
}

/// The `fivex run` summary object.
pub fn summary(r: &RunResult, axes: &[char]) -> Value {
    let alarms: Vec<Value> =
        r.alarms.iter().map(|a| json!({"code": a.code, "message": a.message, "line": a.line, "n": a.n})).collect();
    let variables: Map<String, Value> = r.variables.iter().map(|(n, v)| (format!("#{n}"), json!(v))).collect();
    json!({
        "status": if r.completed() { "completed" } else { "alarm" },
        "alarms": alarms,
        "blocks": r.blocks,
        "cycle_time_s": r.cycle_time_s,
        "position": {"machine": position(&r.machine, axes), "workpiece": position(&r.workpiece, axes)},
        "variables": Value::Object(variables),
        "messages": r.messages,
    })
}
