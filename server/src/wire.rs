//! The typed wire formats the command line and the service share (`docs/contracts.md`,
//! `docs/api.md`): the `fivex run` summary, one machine's result of a fleet run, the answers of
//! `fivex kin fk`/`ik`, and the schemas
//! of what the document describes but no single Rust type is — a machine document (a model or
//! a vendor parameter list), the words of the enums the engine has no schema for, and the
//! websocket messages of each stream. The engine's own wire types (the machine model, the run
//! report) get their schemas from its `schema` feature.
//!
//! The JSON is written through these types, field by field in the order the contract prints
//! them (`serde_json`'s `preserve_order`): what `fivex run`, `fivex fleet` and `POST
//! /fleet/runs` print is unchanged byte for byte (the e2e fixture snapshots hold it).

use std::borrow::Cow;

use fivex_engine::machine::MachineConfig;
use fivex_engine::report::Report;
use fivex_engine::run::RunResult;
use fivex_engine::vendor::ParamFile;
use fivex_engine::Dialect;
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};
use utoipa::openapi::schema::{AnyOfBuilder, OneOfBuilder, Schema};
use utoipa::openapi::{Ref, RefOr};
use utoipa::{PartialSchema, ToSchema};

use crate::api::Position;
use crate::host::stream::AlarmInfo;

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, ToSchema)]
#[serde(rename_all = "lowercase")]
pub enum RunStatus {
    Completed,
    Alarm,
}

/// The `fivex run` summary (`docs/contracts.md`): one JSON object.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct RunSummary {
    pub status: RunStatus,
    /// The alarm the run ended in (at most one).
    pub alarms: Vec<AlarmInfo>,
    /// Blocks executed.
    pub blocks: u64,
    /// Simulated seconds, not wall time.
    pub cycle_time_s: f64,
    /// Where the machine ends.
    pub position: Position,
    /// The common variables (#100–#199, #500–#999, #100000–#199999, #500000–#999999) that are not
    /// vacant at the end: `{"#100": 1.5}`.
    #[schema(value_type = std::collections::HashMap<String, f64>)]
    pub variables: Map<String, Value>,
    /// DPRNT output and stop messages, in order.
    pub messages: Vec<String>,
    /// Blocks run by a rule of fivex's own where the manuals do not say what the control does
    /// (`FX1…`), in order; left out when there is none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub notices: Vec<fivex_engine::notice::Notice>,
}

/// `fivex kin fk`: the tool tip and direction of axis positions, in the table frame and in the
/// machine frame, and how near the posture is to a singularity.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ForwardKinematics {
    pub tip: [f64; 3],
    pub tool: [f64; 3],
    pub tip_machine: [f64; 3],
    pub tool_machine: [f64; 3],
    pub singularity: Option<SingularityInfo>,
}

/// The axis a singular posture leaves free and the tool's angle to it (degrees, 0: singular).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SingularityInfo {
    pub axis: String,
    pub angle: f64,
}

/// `fivex kin ik`: every axis solution, the one the dialect's rules choose (or the alarm
/// they raise), and the axes a singular posture leaves at their `--from` angle.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct InverseKinematics {
    pub candidates: Vec<Map<String, Value>>,
    pub chosen: Option<Map<String, Value>>,
    pub alarm: Option<AlarmCode>,
    pub singular: Vec<String>,
}

/// An alarm without a place in a program: the dialect's code and message.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AlarmCode {
    pub code: String,
    pub message: String,
}

/// Axis values keyed by axis letter, in axis order (`{"X": 0.0, "B": 30.0}`).
pub fn axis_values(p: &[f64], axes: &[char]) -> Map<String, Value> {
    axes.iter().zip(p).map(|(a, v)| (a.to_string(), Value::from(*v))).collect()
}

impl RunSummary {
    pub fn of(r: &RunResult, axis_names: &[char]) -> RunSummary {
        RunSummary {
            status: if r.completed() { RunStatus::Completed } else { RunStatus::Alarm },
            alarms: r.alarms.iter().map(AlarmInfo::from).collect(),
            blocks: r.blocks,
            cycle_time_s: r.cycle_time_s,
            position: Position {
                machine: axis_values(&r.machine, axis_names),
                workpiece: axis_values(&r.workpiece, axis_names),
                tip: r.tip.tip,
                tool: r.tip.tool,
                programmed: r.programmed,
                programmed_in: r.programmed_in.name().to_string(),
            },
            variables: r.variables.iter().map(|(n, v)| (format!("#{n}"), Value::from(*v))).collect(),
            messages: r.messages.clone(),
            notices: r.notices.clone(),
        }
    }
}

/// One machine's result of a fleet run (`fivex fleet`, `POST /fleet/runs`): its name and
/// dialect, then the `fivex run` summary, then the run report when asked for.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct FleetResult {
    /// The preset or library name, the machine document's `name`, or the controller's name.
    pub machine: String,
    pub dialect: Dialect,
    #[serde(flatten)]
    pub summary: RunSummary,
    /// The run report (`docs/fleet.md`), with `"report": true`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub report: Option<Report>,
}

/// A machine document as `--machine FILE.json`, `POST /controllers` and fleet runs take it
/// (`docs/machine-config.md`): the model, or a vendor parameter list. (`anyOf`: a model may carry
/// fields it does not know, so a document is told apart by what the engine reads, not here.)
pub struct MachineDocument;

impl PartialSchema for MachineDocument {
    fn schema() -> RefOr<Schema> {
        AnyOfBuilder::new()
            .item(Ref::from_schema_name(MachineConfig::name()))
            .item(Ref::from_schema_name(ParamFile::name()))
            .description(Some("A machine model or a vendor parameter list (`docs/machine-config.md`)"))
            .into()
    }
}

impl ToSchema for MachineDocument {
    fn schemas(schemas: &mut Vec<(String, RefOr<Schema>)>) {
        schemas.push((MachineConfig::name().into(), MachineConfig::schema()));
        MachineConfig::schemas(schemas);
        schemas.push((ParamFile::name().into(), ParamFile::schema()));
        ParamFile::schemas(schemas);
    }
}

/// A `oneOf` of the named schemas, each message told apart by its `type`.
fn messages(names: &[Cow<'static, str>], description: &str) -> RefOr<Schema> {
    names
        .iter()
        .fold(OneOfBuilder::new(), |b, name| b.item(Ref::from_schema_name(name.clone())))
        .description(Some(description))
        .into()
}

/// Every message of `GET /controllers/{id}/stream` (`docs/api.md`, "Websocket streams").
pub struct ControllerMessage;

impl PartialSchema for ControllerMessage {
    fn schema() -> RefOr<Schema> {
        use crate::api::stream::Snapshot;
        use crate::host::stream::{Message, PositionFrame};
        messages(
            &[Snapshot::name(), PositionFrame::name(), Message::name()],
            "A message of a controller's stream: `snapshot`, `position`, `state`, `alarm`, `variables`, `message` or `workpiece`",
        )
    }
}

impl ToSchema for ControllerMessage {}

/// Every message of `GET /stream`, the fleet's stream.
pub struct FleetMessage;

impl PartialSchema for FleetMessage {
    fn schema() -> RefOr<Schema> {
        use crate::api::stream::{Fleet, FleetDelta};
        messages(&[Fleet::name(), FleetDelta::name()], "A message of the fleet stream: `fleet` or `fleet_delta`")
    }
}

impl ToSchema for FleetMessage {}

/// Schemas of words the engine writes from enums that have no schema of their own.
pub mod words {
    #![allow(dead_code)]
    use utoipa::ToSchema;

    /// The mechanism a machine's rotary axes are on (`unknown`: the kinematics refuses it).
    #[derive(ToSchema)]
    #[serde(rename_all = "kebab-case")]
    pub enum MechanismName {
        ThreeAxis,
        HeadHead,
        TableTable,
        HeadTable,
        Head,
        Table,
        Unknown,
    }

    /// The coordinate system of a programmed point (`docs/api.md`, Positions).
    #[derive(ToSchema)]
    #[serde(rename_all = "snake_case")]
    pub enum SystemName {
        Workpiece,
        WorkpieceMachineAxes,
        Programming,
        Feature,
        Wscs,
    }

    // The `type` of each stream message: one word each.
    #[derive(ToSchema)]
    #[serde(rename_all = "snake_case")]
    pub enum SnapshotType {
        Snapshot,
    }

    #[derive(ToSchema)]
    #[serde(rename_all = "snake_case")]
    pub enum PositionType {
        Position,
    }

    #[derive(ToSchema)]
    #[serde(rename_all = "snake_case")]
    pub enum FleetType {
        Fleet,
    }

    #[derive(ToSchema)]
    #[serde(rename_all = "snake_case")]
    pub enum FleetDeltaType {
        FleetDelta,
    }

    #[derive(ToSchema)]
    #[serde(rename_all = "snake_case")]
    pub enum ProgressType {
        Progress,
    }

    /// What an `alarm` message says happened.
    #[derive(ToSchema)]
    #[serde(rename_all = "snake_case")]
    pub enum AlarmEvent {
        Raised,
        Cleared,
    }

    /// A fleet run's status.
    #[derive(ToSchema)]
    #[serde(rename_all = "snake_case")]
    pub enum FleetRunStatus {
        Queued,
        Running,
        Done,
        Cancelled,
        Interrupted,
    }

    /// How a run in a controller's history ended.
    #[derive(ToSchema)]
    #[serde(rename_all = "snake_case")]
    pub enum RunEnd {
        Completed,
        Alarm,
        Reset,
        // The service stopped while it ran (a graceful stop; `kill -9` leaves no record).
        Interrupted,
    }

    /// One machine's state in a fleet run's progress.
    #[derive(ToSchema)]
    #[serde(rename_all = "snake_case")]
    pub enum MachineState {
        Queued,
        Running,
        Completed,
        Alarm,
        Cancelled,
    }
}
