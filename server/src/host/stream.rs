//! What a controller's websocket stream carries (besides the snapshot the API sends first):
//! position frames and event messages, each a JSON object with a `"type"`.

use std::sync::{Arc, OnceLock};

use axum::extract::ws::Utf8Bytes;
use serde::Serialize;
use serde_json::{Map, Value};
use utoipa::ToSchema;

use fivex_engine::canon::Pos;
use fivex_engine::controller::{Mode, RunState};
use fivex_engine::interp::gcode::display;
use fivex_engine::interp::TiltedPlane;
use fivex_engine::machine::{Chain, Machine, MachineConfig};
use fivex_engine::motion::Sample;
use fivex_engine::workpiece::{Cuboid, Workpiece};
use fivex_engine::Alarm;

use super::{now_unix_ms, Station};

/// `{"type": "position", …}`: where the machine is.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct PositionFrame {
    /// Always `"position"`.
    #[serde(rename = "type")]
    #[schema(value_type = crate::wire::words::PositionType, inline)]
    pub kind: &'static str,
    /// Simulated seconds since the controller was created (or the service started).
    pub t: f64,
    /// The server's wall clock when the frame was made, Unix milliseconds (to measure lag).
    pub wall_ms: f64,
    /// Machine coordinates per axis letter, in axis order.
    #[schema(value_type = std::collections::HashMap<String, f64>)]
    pub machine: Map<String, Value>,
    /// Workpiece (programming) coordinates per axis letter.
    #[schema(value_type = std::collections::HashMap<String, f64>)]
    pub workpiece: Map<String, Value>,
    /// Tool tip in the active workpiece system (G54…, after G52/G92, before any tilted working
    /// plane; fixed on the table of a table machine), from the machine axes and the tool length
    /// in effect by forward kinematics: where the machine puts it.
    pub tip: [f64; 3],
    /// Unit tool vector, tip toward holder, in the workpiece system.
    pub tool: [f64; 3],
    /// The commanded point (X, Y, Z) of the block moving now, in the system `programmed_in`
    /// names.
    pub programmed: [f64; 3],
    /// `workpiece`, `workpiece_machine_axes` (FANUC DET under tool centre point control or in
    /// the table system of 5-axis cutter compensation), `programming` (tool centre point
    /// control, the table system of 5-axis cutter compensation), `feature` (tilted working
    /// plane) or `wscs` (G54.4).
    #[schema(value_type = crate::wire::words::SystemName)]
    pub programmed_in: &'static str,
    /// 1-based program line of the block moving now (0 before any), in the program `program`.
    pub line: u32,
    /// The O number of the stored program `line` is in: the selected one or one it called
    /// (M98/G65/G66…); null for MDI's own blocks.
    pub program: Option<u32>,
    /// Its sequence number.
    pub n: Option<u32>,
    /// Tool tip speed relative to the workpiece, mm/min.
    pub feed: f64,
    /// Distance to go to the end of the block moving now, workpiece coordinates per axis letter.
    #[schema(value_type = std::collections::HashMap<String, f64>)]
    pub to_go: Map<String, Value>,
    /// Spindle speed, 1/min (negative: M04; 0: stopped).
    pub spindle: f64,
    /// The tool length offset in force, mm.
    pub tool_length: f64,
    /// Tool tip in the table frame (`docs/machine-config.md`): where the tip is relative to
    /// the part on its table, from the machine axes, the mechanism and the tool length in effect (for a
    /// machine without table axes, machine coordinates). The 3D view draws the trace with it.
    pub tip_table: [f64; 3],
    /// Under cutting point control (G43.8/G43.9) or a cutter compensation (G41/G42,
    /// G41.2…G42.6, G41.3): where the tool touches the surface or the programmed contour, in the
    /// workpiece system as `tip`, on the tool placed by the machine axes (`docs/api.md`,
    /// "Positions"); absent otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cutting: Option<[f64; 3]>,
    /// The mechanism chain the machine executes in (Syntec `G10 L5000 P_ Q_`), as the status's
    /// `chain`: carried by every frame so the 3D view turns the head this frame's axes belong to
    /// (a switch takes effect between motions, so no frame mixes two chains).
    pub chain: Chain,
    /// The tilted working plane of the block moving now (G68.2…G68.4, Syntec G68.2), in the
    /// workpiece system as `tip`; absent when none is in force. The 3D view draws its frame.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub plane: Option<WorkingPlane>,
}

/// A tilted working plane: its feature coordinate system in the workpiece system.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct WorkingPlane {
    /// The G code that defined it, e.g. `G68.2`.
    #[schema(example = "G68.2")]
    pub code: String,
    /// The feature coordinate system's origin, mm.
    pub origin: [f64; 3],
    /// Its X, Y and Z axes, unit vectors.
    pub axes: [[f64; 3]; 3],
}

impl From<&TiltedPlane> for WorkingPlane {
    fn from(p: &TiltedPlane) -> Self {
        WorkingPlane { code: display(p.code), origin: p.origin, axes: p.axes }
    }
}

/// What a worker reads every tick for a watched controller: plain numbers, no allocation. It is
/// published (as a [`Published`]) only when it differs from the last one in more than its clock.
#[derive(Debug, Clone)]
pub struct Reading {
    machine_config: Arc<Machine>,
    wall_ms: f64,
    sample: Sample,
    /// The programmed position of every axis (the sample holds X, Y, Z).
    work: Pos,
    to_go: Pos,
    spindle: f64,
    tool_length: f64,
    chain: Chain,
    plane: Option<TiltedPlane>,
    /// The sample's line in the program it is in, and that program (`Layouts::locate`).
    line: (Option<u32>, u32),
}

impl Reading {
    pub fn of(station: &Station) -> Reading {
        let c = &station.controller;
        let sample = c.sample();
        Reading {
            machine_config: station.machine.clone(),
            wall_ms: now_unix_ms(),
            line: station.layouts.locate(sample.line),
            sample,
            work: c.point().work,
            to_go: c.to_go(),
            spindle: c.spindle(),
            tool_length: c.tool_length(),
            chain: c.chain(),
            plane: c.plane(),
        }
    }

    /// The server's wall clock when the worker read it, Unix ms (the frame's `wall_ms`).
    pub fn wall_ms(&self) -> f64 {
        self.wall_ms
    }

    /// Whether a frame of `self` would say the same as one of `other` but for `t` and
    /// `wall_ms`: then nothing moved and nothing is sent. Bit-wise, so a NaN does not count as
    /// a change on every tick.
    pub fn same_frame(&self, other: &Reading) -> bool {
        fn same(a: &[f64], b: &[f64]) -> bool {
            a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
        }
        let (a, b) = (&self.sample, &other.sample);
        Arc::ptr_eq(&self.machine_config, &other.machine_config)
            && same(&a.machine, &b.machine)
            && same(&self.work, &other.work)
            && same(&a.tip, &b.tip)
            && same(&a.tool, &b.tool)
            && a.programmed_in == b.programmed_in
            && a.line == b.line
            && a.n == b.n
            && same(&[a.feed, self.spindle, self.tool_length], &[b.feed, other.spindle, other.tool_length])
            && same(&self.to_go, &other.to_go)
            && same(&a.tip_table, &b.tip_table)
            && self.chain == other.chain
            && self.plane == other.plane
            && same(a.cutting.as_ref().map_or(&[], |c| &c[..]), b.cutting.as_ref().map_or(&[], |c| &c[..]))
    }

    pub fn frame(&self) -> PositionFrame {
        let s = &self.sample;
        PositionFrame {
            kind: "position",
            t: s.t,
            wall_ms: self.wall_ms,
            machine: axes(&self.machine_config, &s.machine),
            workpiece: axes(&self.machine_config, &self.work),
            tip: s.tip,
            tool: s.tool,
            programmed: s.programmed,
            programmed_in: s.programmed_in.name(),
            line: self.line.1,
            program: self.line.0,
            n: s.n,
            feed: s.feed,
            to_go: axes(&self.machine_config, &self.to_go),
            spindle: self.spindle,
            tool_length: self.tool_length,
            tip_table: s.tip_table,
            cutting: s.cutting,
            chain: self.chain,
            plane: self.plane.as_ref().map(WorkingPlane::from),
        }
    }
}

/// A position as it leaves the controller: the sample, and its frame encoded at most once, by
/// the first subscriber that sends it, then shared by every other (a cheap clone of the bytes).
#[derive(Debug)]
pub struct Published {
    pub reading: Reading,
    text: OnceLock<Utf8Bytes>,
}

impl Published {
    pub fn new(reading: Reading) -> Published {
        Published { reading, text: OnceLock::new() }
    }

    /// The `position` message as JSON text.
    pub fn text(&self) -> Utf8Bytes {
        self.text
            .get_or_init(|| Utf8Bytes::from(serde_json::to_string(&self.reading.frame()).unwrap_or_default()))
            .clone()
    }
}

/// Axis values keyed by axis letter, in the machine's axis order.
pub fn axes(machine: &MachineConfig, pos: &Pos) -> Map<String, Value> {
    machine.axes.iter().zip(pos).map(|(a, v)| (a.name.to_string(), finite(*v))).collect()
}

fn finite(v: f64) -> Value {
    serde_json::Number::from_f64(v).map_or(Value::Null, Value::Number)
}

/// An alarm as clients see it.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize, ToSchema)]
pub struct AlarmInfo {
    /// The dialect's code, e.g. `PS5421` or `COR-153`.
    #[schema(example = "PS5421")]
    pub code: String,
    pub message: String,
    /// 1-based line in the program `program` (for a stored program run, the program it
    /// occurred in: the selected one or one it called).
    pub line: u32,
    /// Sequence number of the block, if it has one.
    pub n: Option<u32>,
    /// The O number of the stored program `line` is in; null for a text of its own (MDI's
    /// blocks, a fleet run's program, an alarm recorded before this was kept).
    #[serde(default)]
    pub program: Option<u32>,
}

impl From<&Alarm> for AlarmInfo {
    fn from(a: &Alarm) -> Self {
        AlarmInfo { code: a.code.clone(), message: a.message.clone(), line: a.line, n: a.n, program: None }
    }
}

impl AlarmInfo {
    /// `a`, raised in a text composed of stored programs: its line in the program it is in.
    pub fn located(a: &Alarm, layout: &crate::service::programs::Layout) -> AlarmInfo {
        layout.relocate(AlarmInfo::from(a))
    }
}

/// An event message of the stream.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum Message {
    /// The run state changed (`idle`, `running`, `hold`, `alarm`).
    State {
        #[schema(value_type = fivex_engine::controller::RunState)]
        run_state: RunState,
        #[schema(value_type = fivex_engine::controller::Mode)]
        mode: Mode,
        /// The stored program AUTO runs, if one was started.
        program: Option<u32>,
    },
    /// An alarm was raised (`event: "raised"`, with the alarm) or every alarm was cleared
    /// (`event: "cleared"`); `active` lists the alarms in force after the change.
    Alarm {
        #[schema(value_type = crate::wire::words::AlarmEvent)]
        event: &'static str,
        raised: Option<AlarmInfo>,
        active: Vec<AlarmInfo>,
    },
    /// Macro variables changed: `{"#500": 1.5, "#101": null}` (null: vacant).
    Variables {
        #[schema(value_type = std::collections::HashMap<String, Option<f64>>)]
        changes: Map<String, Value>,
    },
    /// An operator message (`#3006`, `(MSG…)`).
    Message { text: String },
    /// A block queued to run by a rule of fivex's own where the manuals do not say what the
    /// control does (`FX1…`: code, message, line, n, program).
    Notice {
        /// Its `line` is in the program `program`, as an alarm's.
        #[serde(flatten)]
        notice: fivex_engine::notice::Notice,
        /// The O number of the stored program the line is in; null for MDI's own blocks.
        program: Option<u32>,
    },
    /// What is clamped on the table changed (`PUT …/workpiece`): every box on it now, in the
    /// table frame, mm (`[]`: nothing). The snapshot's `workpiece` gives it to start with.
    Workpiece { boxes: Vec<Cuboid> },
}

impl Message {
    pub fn state(station: &Station) -> Message {
        let c = &station.controller;
        Message::State { run_state: super::station::run_state(c), mode: c.mode(), program: station.program }
    }

    pub fn workpiece(workpiece: &Workpiece) -> Message {
        Message::Workpiece { boxes: workpiece.boxes.clone() }
    }

    pub fn variables(changes: &[(u32, Option<f64>)]) -> Message {
        let changes = changes.iter().map(|(n, v)| (format!("#{n}"), v.map_or(Value::Null, finite))).collect();
        Message::Variables { changes }
    }
}
