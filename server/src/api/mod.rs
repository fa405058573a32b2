//! The REST API under `/api/v1` (docs/contracts.md): one module per concept — the controllers
//! themselves, their stored programs, the operator panel, macro variables, history, and the
//! websocket stream. Handlers lock a hosted controller only for as long as a button press takes
//! and never across an `.await`.

pub mod controllers;
pub mod fleet;
pub mod fleet_view;
pub mod health;
pub mod history;
pub mod manual;
pub mod metrics;
pub mod modal;
pub mod offsets;
pub mod panel;
pub mod parameters;
pub mod programs;
pub mod restart;
pub mod stream;
pub mod teach;
pub mod variables;
pub mod workpiece;

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};
use utoipa::ToSchema;
use utoipa_axum::router::OpenApiRouter;
use utoipa_axum::routes;

use crate::host::stream::{axes, AlarmInfo};
use crate::host::{Hosted, Station};
use crate::http::AppState;

/// The `/api/v1` routes, each listed once: `routes!` takes a handler's path and method from its
/// `#[utoipa::path]`, so the router and the OpenAPI document come from the same list (handlers
/// of one path go in one `routes!`).
pub fn routes() -> OpenApiRouter<AppState> {
    OpenApiRouter::new()
        .routes(routes!(controllers::list, controllers::create))
        .routes(routes!(controllers::status, controllers::update, controllers::remove))
        .routes(routes!(controllers::clone))
        .routes(routes!(controllers::machine))
        .routes(routes!(controllers::presets))
        .routes(routes!(modal::modal))
        .routes(routes!(programs::list))
        .routes(routes!(programs::store, programs::text, programs::remove))
        .routes(routes!(programs::tool_path))
        .routes(routes!(programs::estimate))
        .routes(routes!(panel::cycle_start))
        .routes(routes!(panel::feed_hold))
        .routes(routes!(panel::reset))
        .routes(routes!(panel::mdi))
        .routes(routes!(panel::set_mode))
        .routes(routes!(panel::set_overrides))
        .routes(routes!(panel::set_switches))
        .routes(routes!(panel::emergency_stop))
        .routes(routes!(restart::restart))
        .routes(routes!(manual::jog))
        .routes(routes!(manual::jog_stop))
        .routes(routes!(manual::handle))
        .routes(routes!(manual::reference_return))
        .routes(routes!(manual::settings))
        .routes(routes!(manual::set_signals))
        .routes(routes!(manual::jog_signal))
        .routes(routes!(manual::handle_pulses))
        .routes(routes!(variables::list))
        .routes(routes!(variables::read, variables::write))
        .routes(routes!(offsets::tools))
        .routes(routes!(offsets::set_tool))
        .routes(routes!(offsets::works))
        .routes(routes!(offsets::set_work))
        .routes(routes!(parameters::get_all))
        .routes(routes!(parameters::set))
        .routes(routes!(workpiece::get_workpiece, workpiece::put_workpiece))
        .routes(routes!(teach::get))
        .routes(routes!(teach::clear))
        .routes(routes!(teach::latch))
        .routes(routes!(teach::plane))
        .routes(routes!(history::alarms))
        .routes(routes!(history::runs))
        .routes(routes!(stream::stream))
        .routes(routes!(stream::fleet))
        .routes(routes!(fleet::create, fleet::list))
        .routes(routes!(fleet::get))
        .routes(routes!(fleet::cancel))
        .routes(routes!(fleet::stream))
        .routes(routes!(fleet::library))
        .routes(routes!(fleet::library_one))
}

/// A controller as `GET /controllers/{id}` shows it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct ControllerStatus {
    /// Stable identifier used in `/api/v1/controllers/{id}/…` paths.
    pub id: String,
    /// Display name.
    pub name: String,
    /// `fanuc`, `syntec` or `haas`.
    #[schema(value_type = fivex_engine::Dialect)]
    pub dialect: String,
    /// The machine configuration's name (a preset name for a preset).
    #[schema(example = "table-ac")]
    pub machine: String,
    /// The mechanism: `three-axis`, `head-head`, `table-table`, `head-table`, `head`, `table`
    /// (`unknown` when the kinematics refuses the machine).
    #[schema(value_type = crate::wire::words::MechanismName)]
    pub kind: String,
    /// Creation time, RFC 3339 UTC.
    #[schema(example = "2025-01-01T00:00:00Z")]
    pub created_at: String,
    /// Simulated seconds per real second (1 = real time).
    pub speed: f64,
    /// `auto`, `mdi`, `jog`, `handle`, `ref` or `inc`.
    #[schema(value_type = fivex_engine::controller::Mode)]
    pub mode: String,
    /// `idle`, `running`, `hold` or `alarm`.
    #[schema(value_type = fivex_engine::controller::RunState)]
    pub run_state: String,
    /// The stored program AUTO runs (O number), once one was started.
    pub program: Option<u32>,
    /// 1-based line of the block being executed (0 before any) and its sequence number: the
    /// moving block's, or a block without motion (a dwell, a modal change) once reached. The
    /// line is in the program `line_program`.
    pub line: u32,
    pub n: Option<u32>,
    /// The O number of the stored program `line` is in: `program`, or a program it called
    /// (M98/G65/G66…), as stored; null for MDI's own blocks.
    pub line_program: Option<u32>,
    pub position: Position,
    /// Tool tip speed relative to the workpiece, mm/min.
    pub feed: f64,
    /// Simulated seconds since the controller was created (or the service started).
    pub time_s: f64,
    /// Alarms in force.
    pub alarms: Vec<AlarmInfo>,
    /// The operator panel's switches and overrides.
    pub panel: PanelState,
    /// The manual handle interruption's shift per axis (machine = absolute + shift; cleared by
    /// the reference return).
    #[schema(value_type = std::collections::HashMap<String, f64>)]
    pub interrupt_shift: Map<String, Value>,
    /// What the controller's machine description sets that fivex keeps but does not carry out
    /// (`docs/machine-config.md`, "Settings fivex does not model"); empty for most machines.
    pub unmodelled_parameters: Vec<UnmodelledParameter>,
    /// The mechanism chain in force (Syntec `G10 L5000 P_ Q_`, `docs/five-axis.md`): its set
    /// 1–4 and sub-chain 1–4, as the machine executes; set 1, sub-chain 1 on a one-chain machine.
    pub chain: fivex_engine::machine::Chain,
    /// The run of a stored program under way against its estimated cycle time (`docs/api.md`,
    /// "Cycle-time estimate and progress"); absent when no such run is under way.
    #[serde(default)]
    pub progress: Option<crate::host::estimate::RunProgress>,
    /// FANUC program restart under way (`POST /restart`): `null` when none.
    pub restart: Option<restart::RestartInfo>,
    /// Spindle speed, 1/min: the commanded speed times the spindle override (not while a
    /// tapping cycle's tap is in the hole, where the override does not act); positive clockwise
    /// (M03), negative counter-clockwise (M04), 0 stopped.
    pub spindle: f64,
    /// Machine minus the program's machine coordinates per axis after (or during) machine lock
    /// or Z-axis neglect: zero when they agree; the reference return sets them equal
    /// (`docs/dialects.md`, "The operator's switches and counters").
    #[schema(value_type = std::collections::HashMap<String, f64>)]
    pub lock_offset: Map<String, Value>,
    /// The part count and the operating and cutting time.
    pub counters: Counters,
}

/// The part count (#3901, #3902) and FANUC's operating and cutting time (No.6751–6754), in
/// seconds of simulated time since the controller was made or restored.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct Counters {
    /// Parts machined (#3901): one at each M02/M30.
    pub parts: f64,
    /// Parts required (#3902).
    pub parts_required: f64,
    /// Automatic operation running (not held, not stopped).
    pub operating_time_s: f64,
    /// The part of it along cutting feeds.
    pub cutting_time_s: f64,
}

impl Counters {
    fn of(c: &fivex_engine::controller::Controller) -> Counters {
        let (parts, parts_required) = c.interpreter().state.part_count();
        let t = c.times();
        Counters { parts, parts_required, operating_time_s: t.operating_s, cutting_time_s: t.cutting_s }
    }
}

/// A machine setting fivex does not carry out.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct UnmodelledParameter {
    /// The vendor's number (`No.8130`, `No.19608#0`, `Pr3052`) or the model field.
    #[schema(example = "No.8130")]
    pub parameter: String,
    /// What fivex does instead.
    pub reason: String,
}

impl UnmodelledParameter {
    pub fn list(of: &[fivex_engine::vendor::unmodelled::Unmodelled]) -> Vec<UnmodelledParameter> {
        of.iter().map(|u| UnmodelledParameter { parameter: u.parameter.clone(), reason: u.reason.clone() }).collect()
    }
}

/// The switches and overrides of the operator panel, as `PUT /switches`, `/overrides` and
/// `/manual` set them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct PanelState {
    pub single_block: bool,
    pub optional_stop: bool,
    pub block_delete: bool,
    /// Percent.
    pub feed_override: f64,
    pub rapid_override: f64,
    /// JOG and HANDLE feed, mm/min or deg/min.
    pub jog_feed: f64,
    /// INC mode: the distance of one key press.
    pub increment: f64,
    pub manual_absolute: bool,
    /// Syntec R518: `machine`, `program` or `tool`.
    #[schema(value_type = fivex_engine::controller::ManualCoordinates)]
    pub coordinates: String,
    /// Syntec R519 manual RTCP.
    pub rtcp: bool,
    /// FANUC's 5-axis manual feed signals (`PUT /manual-signals`).
    pub signals: manual::PanelSignals,
    /// Dry run: cutting feeds at the dry run rate (FANUC No.1410) with the feed override.
    pub dry_run: bool,
    /// Machine lock (all axes): the program runs, the machine does not move.
    pub machine_lock: bool,
    /// Z-axis neglect (FANUC): machine lock of the Z axis alone.
    pub z_neglect: bool,
    /// Auxiliary function lock: spindle commands and tool changes not carried out.
    pub aux_lock: bool,
    /// Spindle speed override, percent (50–120).
    pub spindle_override: f64,
}

impl PanelState {
    fn of(panel: &fivex_engine::controller::Panel) -> PanelState {
        PanelState {
            single_block: panel.single_block,
            optional_stop: panel.optional_stop,
            block_delete: panel.block_delete,
            feed_override: (panel.feed_override * 100.0).round(),
            rapid_override: (panel.rapid_override * 100.0).round(),
            jog_feed: panel.jog_feed,
            increment: panel.increment,
            manual_absolute: panel.manual_absolute,
            coordinates: word(&panel.manual_coordinates),
            rtcp: panel.manual_rtcp,
            signals: manual::PanelSignals {
                alngh: Some(panel.manual_signals.alngh),
                rghth: Some(panel.manual_signals.rghth),
                rndh: Some(panel.manual_signals.rndh),
                tb_base: Some(panel.manual_signals.tb_base),
                handle_select: Some(panel.manual_signals.handle_select),
            },
            dry_run: panel.dry_run,
            machine_lock: panel.machine_lock,
            z_neglect: panel.z_neglect,
            aux_lock: panel.aux_lock,
            spindle_override: (panel.spindle_override * 100.0).round(),
        }
    }
}

/// Machine and workpiece coordinates per axis letter, in axis order, and, as in the run
/// summary, the tool tip and direction where the machine puts them (forward kinematics of the
/// axes with the tool length in effect, in the active workpiece system) and the programmed
/// point with the name of its system (`docs/api.md`, Positions).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct Position {
    #[schema(value_type = std::collections::HashMap<String, f64>)]
    pub machine: Map<String, Value>,
    #[schema(value_type = std::collections::HashMap<String, f64>)]
    pub workpiece: Map<String, Value>,
    #[serde(default)]
    pub tip: [f64; 3],
    #[serde(default)]
    pub tool: [f64; 3],
    #[serde(default)]
    pub programmed: [f64; 3],
    /// `workpiece`, `workpiece_machine_axes`, `programming`, `feature` or `wscs`.
    #[serde(default)]
    #[schema(value_type = crate::wire::words::SystemName)]
    pub programmed_in: String,
}

/// The kebab-case name of a mechanism kind (`unknown` for none).
fn kind_name(kind: Option<fivex_engine::kin::MachineKind>) -> String {
    kind.and_then(|k| serde_json::to_value(k).ok())
        .and_then(|v| v.as_str().map(str::to_string))
        .unwrap_or_else(|| "unknown".into())
}

/// The mechanism kind of a machine, as [`ControllerStatus::kind`] names it.
pub fn machine_kind(machine: &fivex_engine::machine::MachineConfig) -> String {
    kind_name(fivex_engine::kin::Kinematics::new(machine).ok().map(|k| k.kind))
}

impl ControllerStatus {
    pub fn of(hosted: &Hosted, station: &Station) -> ControllerStatus {
        let c = &station.controller;
        let p = c.point();
        let s = c.sample();
        ControllerStatus {
            id: hosted.id.clone(),
            name: hosted.name(),
            dialect: hosted.dialect.name().to_string(),
            machine: station.machine.name.clone(),
            kind: kind_name(station.machine.kinematics().map(|k| k.kind)),
            created_at: hosted.created_at.clone(),
            speed: hosted.speed(),
            mode: word(&c.mode()),
            run_state: word(&crate::host::station::run_state(c)),
            program: station.program,
            line: station.layouts.locate(p.line).1,
            n: p.n,
            line_program: station.layouts.locate(p.line).0,
            position: Position {
                machine: axes(&station.machine, &p.machine),
                workpiece: axes(&station.machine, &p.work),
                tip: s.tip,
                tool: s.tool,
                programmed: s.programmed,
                programmed_in: s.programmed_in.name().to_string(),
            },
            feed: p.feed,
            time_s: c.time(),
            alarms: station.layouts.alarms(c.alarms()),
            panel: PanelState::of(&c.panel),
            interrupt_shift: axes(&station.machine, &c.interrupt_shift()),
            unmodelled_parameters: UnmodelledParameter::list(&station.unmodelled),
            chain: c.chain(),
            progress: station.progress(),
            restart: restart::RestartInfo::of(station),
            spindle: c.spindle(),
            lock_offset: axes(&station.machine, &c.lock_offset()),
            counters: Counters::of(c),
        }
    }

    /// The status of `hosted` now.
    pub fn now(hosted: &Hosted) -> ControllerStatus {
        let station = hosted.station();
        ControllerStatus::of(hosted, &station)
    }
}

/// The engine's serde name of a unit enum value (a mode, a run state) as a plain word.
pub fn word<T: Serialize>(value: &T) -> String {
    match serde_json::to_value(value) {
        Ok(Value::String(s)) => s,
        _ => String::new(),
    }
}
