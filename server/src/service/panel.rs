//! The operator panel as one command type: every button, switch and manual feed the API offers
//! is a [`PanelCommand`], checked ([`PanelCommand::check`]) before the controller is locked and
//! applied in one place ([`apply`]). [`execute`] does both on a hosted controller and sends out
//! what the command caused.

use fivex_engine::controller::{
    Controller, ManualCoordinates, ManualSignals, Mode, Refusal, RestartPhase, RestartType, RunState,
};
use fivex_engine::interp::restart::Target;
use fivex_engine::kin::ManualFeed;
use fivex_engine::Dialect;
use serde::{Deserialize, Serialize};

use super::programs::{Composed, MAX_PROGRAM_BYTES};
use super::ServiceError;
use crate::host::station::run_state;
use crate::host::{Host, Hosted, Record, Station};

/// What a manual move moves: one axis, along a 5-axis manual feed, or the tool tip centre
/// rotation of a rotary axis.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ManualTarget {
    Axis(char),
    Feed(ManualFeed),
    TipRotation(char),
}

impl ManualTarget {
    /// Exactly one of an axis letter, a feed and a rotary axis letter.
    pub fn of(axis: Option<&str>, feed: Option<ManualFeed>, tip_rotation: Option<&str>) -> Result<Self, ServiceError> {
        match (axis, feed, tip_rotation) {
            (Some(a), None, None) => Ok(ManualTarget::Axis(letter(a)?)),
            (None, Some(f), None) => Ok(ManualTarget::Feed(f)),
            (None, None, Some(a)) => Ok(ManualTarget::TipRotation(letter(a)?)),
            _ => Err(ServiceError::invalid("give exactly one of axis, feed and tip_rotation")),
        }
    }
}

/// The white space an axis letter may carry: JSON's four characters, the same set the schemas'
/// pattern ([`AXIS_LETTER_PATTERN`]) names. Written out rather than `\s`, whose set differs
/// between ECMA-262 (what JSON Schema means), Python (what schemathesis runs) and Rust's `trim`.
const LETTER_SPACE: [char; 4] = [' ', '\t', '\n', '\r'];

/// The JSON Schema pattern of an axis letter: exactly what [`letter`] accepts.
pub const AXIS_LETTER_PATTERN: &str = r"^[ \t\n\r]*[A-Za-z][ \t\n\r]*$";

/// An axis letter, upper case.
pub fn letter(s: &str) -> Result<char, ServiceError> {
    let mut chars = s.trim_matches(LETTER_SPACE).chars();
    match (chars.next(), chars.next()) {
        (Some(c), None) if c.is_ascii_alphabetic() => Ok(c.to_ascii_uppercase()),
        _ => Err(ServiceError::invalid(format!("'{s}' is not an axis letter"))),
    }
}

/// A mode by its word, any case.
pub fn mode(word: &str) -> Result<Mode, ServiceError> {
    match word.to_ascii_lowercase().as_str() {
        "auto" => Ok(Mode::Auto),
        "mdi" => Ok(Mode::Mdi),
        "jog" => Ok(Mode::Jog),
        "handle" => Ok(Mode::Handle),
        "ref" => Ok(Mode::Ref),
        "inc" => Ok(Mode::Inc),
        other => Err(ServiceError::invalid(format!("unknown mode '{other}' (auto, mdi, jog, handle, ref, inc)"))),
    }
}

/// The restart block of a program restart: a sequence number or a line, and the how-many-th
/// time execution reaches it (from 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RestartAt {
    Sequence { n: u32, occurrence: u32 },
    Line { line: u32, occurrence: u32 },
}

/// The largest sequence number (FANUC: 8 digits) and pass count a restart takes.
pub const MAX_RESTART_NUMBER: u32 = 99_999_999;

impl RestartAt {
    /// Exactly one of `n` and `line`; `occurrence` 1 when left out.
    pub fn of(n: Option<u32>, line: Option<u32>, occurrence: Option<u32>) -> Result<Self, ServiceError> {
        let occurrence = occurrence.unwrap_or(1);
        match (n, line) {
            (Some(n), None) => Ok(RestartAt::Sequence { n, occurrence }),
            (None, Some(line)) => Ok(RestartAt::Line { line, occurrence }),
            _ => Err(ServiceError::invalid("give exactly one of n and line")),
        }
    }

    fn target(self) -> Target {
        match self {
            RestartAt::Sequence { n, occurrence } => Target::Sequence { n, occurrence },
            RestartAt::Line { line, occurrence } => Target::Line { line, occurrence },
        }
    }
}

/// A restart type by its word, any case.
pub fn restart_type(word: &str) -> Result<RestartType, ServiceError> {
    match word.to_ascii_lowercase().as_str() {
        "p" => Ok(RestartType::P),
        "q" => Ok(RestartType::Q),
        other => Err(ServiceError::invalid(format!("unknown restart type '{other}' (p, q)"))),
    }
}

/// `PUT /switches`.
// (The API's request body and the service's command are this one struct; `None` leaves a switch
// as it is.)
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct Switches {
    pub single_block: Option<bool>,
    pub optional_stop: Option<bool>,
    pub block_delete: Option<bool>,
    /// Dry run (changes only while nothing moves or is queued: idle, a block stop).
    pub dry_run: Option<bool>,
    /// Machine lock, all axes (the same rule).
    pub machine_lock: Option<bool>,
    /// Z-axis neglect, FANUC only (the same rule).
    pub z_neglect: Option<bool>,
    /// Auxiliary function lock (any time).
    pub aux_lock: Option<bool>,
}

/// One action on the operator panel. A field that is `None` leaves that setting as it is.
/// Serialisable both ways, so that a command can be recorded or handed to another process as
/// it is (`{"command": "set_mode", "mode": "jog"}`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "command", rename_all = "snake_case")]
pub enum PanelCommand {
    /// With a program (its number and the text AUTO runs, `programs::composed`): select it and
    /// run it in AUTO; without: resume, or run what is selected.
    CycleStart {
        program: Option<(u32, Composed)>,
    },
    FeedHold,
    /// Stop, abandon the program (recorded as `reset`), clear the alarms.
    Reset,
    /// Switch to MDI (when idle) and run the blocks; `stored`, the stored programs (number,
    /// text), are there for them to call (`programs::compose_mdi`).
    Mdi {
        text: String,
        #[serde(default)]
        stored: Vec<(u32, String)>,
    },
    SetMode {
        mode: Mode,
    },
    /// Percent: feed 0–200, rapid 0–100, spindle 50–120 in steps of 10.
    Overrides {
        feed: Option<f64>,
        rapid: Option<f64>,
        #[serde(default)]
        spindle: Option<f64>,
    },
    /// Dry run, machine lock and Z-axis neglect change only at rest (`Controller::set_dry_run`).
    Switches(Switches),
    /// Pressing it ends the run under way (recorded as `alarm`).
    EmergencyStop {
        pressed: bool,
    },
    Jog {
        target: ManualTarget,
        positive: bool,
    },
    JogStop,
    Handle {
        target: ManualTarget,
        amount: f64,
    },
    ReferenceReturn,
    ManualSettings {
        coordinates: Option<ManualCoordinates>,
        rtcp: Option<bool>,
        jog_feed: Option<f64>,
        manual_absolute: Option<bool>,
        increment: Option<f64>,
    },
    /// FANUC's 5-axis manual feed signals.
    ManualSignals {
        alngh: Option<bool>,
        rghth: Option<bool>,
        rndh: Option<bool>,
        tb_base: Option<bool>,
        handle_select: Option<u8>,
    },
    JogSignal {
        axis: char,
        positive: bool,
    },
    /// Handle pulses while a program waits for them; the distance the controller took.
    HandlePulses {
        amount: f64,
    },
    /// FANUC program restart's search (`docs/dialects.md`, "Program restart"); with a program
    /// (as for cycle start), that program is selected in AUTO first. The next cycle start
    /// returns the axes and goes on from the restart block.
    Restart {
        program: Option<(u32, Composed)>,
        kind: RestartType,
        at: RestartAt,
    },
}

/// What a command gave back besides the controller's new state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Applied {
    Done,
    /// The distance the handle pulses moved.
    Taken(f64),
}

/// Why the controller did not take a command.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refused {
    /// The panel ignores it in this state.
    Panel(Refusal),
    /// A cycle start with a program while another is under way.
    ProgramUnderWay,
    /// A cycle start with a program in alarm (an emergency stop too): only a reset clears it.
    InAlarm,
    /// Z-axis neglect where the dialect or the machine has none.
    NoZNeglect,
    /// A program restart refused: the state that refuses it (`restart_refused`).
    Restart(&'static str),
}

impl From<Refusal> for Refused {
    fn from(r: Refusal) -> Self {
        Refused::Panel(r)
    }
}

impl From<Refused> for ServiceError {
    fn from(r: Refused) -> Self {
        ServiceError::Conflict(
            match r {
                Refused::Panel(Refusal::WrongMode) => "not possible in this mode",
                Refused::Panel(Refusal::Busy) => "not possible while the controller runs, holds or is in alarm",
                Refused::Panel(Refusal::NoProgram) => "there is no program to run",
                Refused::Panel(Refusal::NoAxis) => "no such axis (or no 5-axis mechanism for this feed)",
                Refused::Panel(Refusal::BadValue) => "the value is not a finite number in range",
                Refused::Panel(Refusal::NotInDialect) => "the dialect's manuals describe no such function",
                Refused::ProgramUnderWay => {
                    "a program is under way: resume it with an empty cycle start, or reset first"
                }
                Refused::InAlarm => "the controller is in alarm (or its emergency stop is pressed): reset first",
                Refused::NoZNeglect => "Z-axis neglect needs a FANUC controller and a Z axis",
                Refused::Restart(why) => why,
            }
            .into(),
        )
    }
}

impl PanelCommand {
    /// The checks that need no controller: values in range, so that the controller is locked
    /// only for a command it may take.
    pub fn check(&self) -> Result<(), ServiceError> {
        let invalid = |why: String| Err(ServiceError::invalid(why));
        match self {
            PanelCommand::Mdi { text, .. } if text.len() > MAX_PROGRAM_BYTES => invalid("MDI text too long".into()),
            PanelCommand::Overrides { feed, rapid, spindle } => {
                for (value, max, what) in [(feed, 200.0, "feed"), (rapid, 100.0, "rapid")] {
                    if value.is_some_and(|p: f64| !(p.is_finite() && (0.0..=max).contains(&p))) {
                        return invalid(format!("{what} override must be 0–{max} %"));
                    }
                }
                // The panel's switch: 50–120 % in 10 % steps (SPINDLE_OVERRIDE).
                if spindle.is_some_and(|p| !((50.0..=120.0).contains(&p) && p % 10.0 == 0.0)) {
                    return invalid("spindle override must be 50–120 % in steps of 10".into());
                }
                Ok(())
            }
            PanelCommand::Handle { amount, .. } if !(amount.is_finite() && amount.abs() <= 1.0e5) => {
                invalid("HANDLE needs a finite amount (at most 1e5)".into())
            }
            PanelCommand::ManualSettings { jog_feed, increment, .. } => {
                if jog_feed.is_some_and(|f| !(f.is_finite() && f > 0.0 && f <= 1.0e6)) {
                    return invalid("jog_feed must be above 0 and at most 1e6".into());
                }
                if increment.is_some_and(|f| !(f.is_finite() && f > 0.0 && f <= 1.0e3)) {
                    return invalid("increment must be above 0 and at most 1000".into());
                }
                Ok(())
            }
            PanelCommand::ManualSignals { handle_select: Some(code), .. } if *code > 31 => {
                invalid("handle_select is a 5-bit code (0–31)".into())
            }
            PanelCommand::HandlePulses { amount } if !(amount.is_finite() && amount.abs() <= 1.0e5) => {
                invalid("amount must be finite and at most 1e5".into())
            }
            PanelCommand::Restart { at, .. } => {
                let (RestartAt::Sequence { n: number, occurrence } | RestartAt::Line { line: number, occurrence }) = at;
                if !(1..=MAX_RESTART_NUMBER).contains(number) {
                    return invalid(format!("n and line are 1–{MAX_RESTART_NUMBER}"));
                }
                if !(1..=MAX_RESTART_NUMBER).contains(occurrence) {
                    return invalid(format!("occurrence is 1–{MAX_RESTART_NUMBER}"));
                }
                Ok(())
            }
            _ => Ok(()),
        }
    }
}

/// Applies `command` to the station of controller `id`; the records of a run it ended go to
/// `ended`.
pub fn apply(
    station: &mut Station,
    id: &str,
    command: PanelCommand,
    ended: &mut Vec<Record>,
) -> Result<Applied, Refused> {
    let c: &mut Controller = &mut station.controller;
    match command {
        PanelCommand::CycleStart { program } => {
            let state = run_state(c);
            let fresh = state == RunState::Idle;
            if let Some((n, composed)) = &program {
                if state == RunState::Alarm {
                    return Err(Refused::InAlarm);
                }
                if !fresh {
                    return Err(Refused::ProgramUnderWay);
                }
                if c.mode() != Mode::Auto {
                    c.set_mode(Mode::Auto)?;
                }
                c.select_program(composed.source.clone())?;
                // The inputs of its estimate as they stand before it starts.
                let key = crate::host::estimate::key(&composed.source, c.interpreter());
                c.cycle_start()?;
                station.layouts.auto = composed.layout.clone();
                station.layouts.started(Mode::Auto);
                station.begin_run(Some(*n));
                station.estimate_run(key);
            } else {
                c.cycle_start()?;
                if fresh {
                    station.layouts.started(c.mode());
                    let program = if c.mode() == Mode::Auto { station.program } else { None };
                    station.begin_run(program);
                }
            }
        }
        PanelCommand::FeedHold => c.feed_hold(),
        PanelCommand::Reset => {
            ended.extend(station.end_run(id, "reset"));
            station.controller.reset();
        }
        PanelCommand::Mdi { text, stored } => {
            if c.mode() != Mode::Mdi {
                c.set_mode(Mode::Mdi)?;
            }
            let composed = crate::service::programs::compose_mdi(&text, &stored);
            c.set_mdi(composed.source.clone())?;
            c.cycle_start()?;
            station.layouts.mdi = composed.layout;
            station.layouts.started(Mode::Mdi);
            station.begin_run(None);
        }
        PanelCommand::SetMode { mode } => c.set_mode(mode)?,
        PanelCommand::Overrides { feed, rapid, spindle } => {
            let feed = feed.map_or(c.panel.feed_override, |p| p / 100.0);
            let rapid = rapid.map_or(c.panel.rapid_override, |p| p / 100.0);
            c.set_overrides(feed, rapid);
            if let Some(p) = spindle {
                c.set_spindle_override(p / 100.0);
            }
        }
        PanelCommand::Switches(Switches {
            single_block,
            optional_stop,
            block_delete,
            dry_run,
            machine_lock,
            z_neglect,
            aux_lock,
        }) => {
            // The switches that may be refused first, so that a refusal changes nothing: Z-axis
            // neglect for its dialect, then the three that change only at rest (the same rule).
            if z_neglect == Some(true) && !c.can_neglect_z() {
                return Err(Refused::NoZNeglect);
            }
            let changes = |on: Option<bool>, now: bool| on.is_some_and(|on| on != now);
            let at_rest_only = changes(dry_run, c.panel.dry_run)
                || changes(machine_lock, c.panel.machine_lock)
                || changes(z_neglect, c.panel.z_neglect);
            if at_rest_only && !c.at_block_boundary() {
                return Err(Refused::Panel(Refusal::Busy));
            }
            c.set_dry_run(dry_run.unwrap_or(c.panel.dry_run))?;
            c.set_machine_lock(machine_lock.unwrap_or(c.panel.machine_lock))?;
            c.set_z_neglect(z_neglect.unwrap_or(c.panel.z_neglect))?;
            let p = &mut c.panel;
            p.aux_lock = aux_lock.unwrap_or(p.aux_lock);
            p.single_block = single_block.unwrap_or(p.single_block);
            p.optional_stop = optional_stop.unwrap_or(p.optional_stop);
            p.block_delete = block_delete.unwrap_or(p.block_delete);
        }
        PanelCommand::EmergencyStop { pressed } => {
            if pressed {
                ended.extend(station.end_run(id, "alarm"));
            }
            station.controller.emergency_stop(pressed);
        }
        PanelCommand::Jog { target, positive } => match target {
            ManualTarget::Axis(a) => c.jog_start(a, positive)?,
            ManualTarget::Feed(f) => c.jog_direction(f, positive)?,
            ManualTarget::TipRotation(a) => c.jog_tip_rotation(a, positive)?,
        },
        PanelCommand::JogStop => c.jog_stop(),
        PanelCommand::Handle { target, amount } => match target {
            ManualTarget::Axis(a) => c.handle(a, amount)?,
            ManualTarget::Feed(f) => c.handle_direction(f, amount)?,
            ManualTarget::TipRotation(a) => c.handle_tip_rotation(a, amount)?,
        },
        PanelCommand::ReferenceReturn => c.reference_return()?,
        PanelCommand::ManualSettings { coordinates, rtcp, jog_feed, manual_absolute, increment } => {
            if let Some(choice) = coordinates {
                c.set_manual_coordinates(choice)?;
            }
            if let Some(on) = rtcp {
                c.set_manual_rtcp(on)?;
            }
            if let Some(feed) = jog_feed {
                c.panel.jog_feed = feed;
            }
            if let Some(on) = manual_absolute {
                c.panel.manual_absolute = on;
            }
            if let Some(step) = increment {
                c.set_increment(step)?;
            }
        }
        PanelCommand::ManualSignals { alngh, rghth, rndh, tb_base, handle_select } => {
            let s: ManualSignals = c.panel.manual_signals;
            c.set_manual_signals(ManualSignals {
                alngh: alngh.unwrap_or(s.alngh),
                rghth: rghth.unwrap_or(s.rghth),
                rndh: rndh.unwrap_or(s.rndh),
                tb_base: tb_base.unwrap_or(s.tb_base),
                handle_select: handle_select.unwrap_or(s.handle_select),
            })?;
        }
        PanelCommand::JogSignal { axis, positive } => c.jog_signal(axis, positive)?,
        PanelCommand::HandlePulses { amount } => return Ok(Applied::Taken(c.handle_pulses(amount)?)),
        PanelCommand::Restart { program, kind, at } => {
            let refused = |c: &Controller, r: Refusal| Refused::Restart(restart_refused(c, r));
            if let Some((n, composed)) = &program {
                if run_state(c) != RunState::Idle {
                    return Err(refused(c, Refusal::Busy));
                }
                if c.mode() != Mode::Auto {
                    c.set_mode(Mode::Auto).map_err(|r| refused(c, r))?;
                }
                c.select_program(composed.source.clone()).map_err(|r| refused(c, r))?;
                c.restart(at.target(), kind).map_err(|r| refused(c, r))?;
                station.layouts.auto = composed.layout.clone();
                station.layouts.started(Mode::Auto);
                // The cycle start that returns the axes runs this program (`begin_run`).
                station.program = Some(*n);
            } else {
                c.restart(at.target(), kind).map_err(|r| refused(c, r))?;
            }
        }
    }
    Ok(Applied::Done)
}

/// Why `c` refuses a program restart, named for the operator (`docs/api.md`): the state that
/// refuses it, not only the kind of refusal.
fn restart_refused(c: &Controller, r: Refusal) -> &'static str {
    match r {
        Refusal::NotInDialect if c.interpreter().config().dialect == Dialect::Syntec => {
            "Syntec has no program restart (its manuals describe none)"
        }
        Refusal::NotInDialect => "the Haas NGC has no FANUC program restart (its Setting 36 scan is not built)",
        Refusal::WrongMode => "not in AUTO: a restart without a program is made in AUTO",
        Refusal::NoProgram => "no program selected: name one with \"program\"",
        _ if c.restart_status().is_some_and(|r| r.phase == RestartPhase::Searching) => {
            "searching: a restart's search is under way (a reset stops it)"
        }
        _ if c.emergency_stopped() => "the emergency stop is pressed",
        _ => match run_state(c) {
            RunState::Alarm => "in alarm: reset first",
            RunState::Running => "running: the program or a move is under way",
            RunState::Hold => "holding: a feed hold or a program stop waits for cycle start (reset first)",
            RunState::Idle => "the axes are moving (a manual move or a deceleration)",
        },
    }
}

/// Checks `command`, applies it to `hosted` (locked for as long as that takes), sends out what
/// it caused (also when it was refused), and answers `view` of the controller after it.
pub fn execute<T>(
    host: &Host,
    hosted: &Hosted,
    command: PanelCommand,
    view: impl FnOnce(&Hosted, &Station) -> T,
) -> Result<(Applied, T), ServiceError> {
    command.check()?;
    let mut ended = Vec::new();
    let mut station = hosted.station();
    // Removed while this request waited for the lock (handed to another node, which
    // loads it from the database): acting on this copy would be lost.
    if hosted.is_removed() {
        return Err(ServiceError::Unavailable(format!(
            "controller {} is moving to another node: retry in a few seconds",
            hosted.id
        )));
    }
    let result = apply(&mut station, &hosted.id, command, &mut ended);
    let (messages, records) = station.collect(&hosted.id, 0.0, true);
    // Sent before the lock is let go (neither send blocks): a worker's tick that follows this
    // command sends its records and messages after these. Sent after the unlock, a cycle
    // start's save (#3002 as it stood then) could reach the writer after the run's end had
    // saved the program's #3002 = 1.5, and overwrite it.
    for r in ended.into_iter().chain(records) {
        host.record(r);
    }
    hosted.publish(messages);
    let seen = view(hosted, &station);
    drop(station);
    Ok((result?, seen))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::host::Spec;
    use fivex_engine::machine::MachineConfig;
    use std::sync::Arc;

    fn hosted() -> Hosted {
        Hosted::new(Spec {
            id: "c1".into(),
            name: "test".into(),
            dialect: fivex_engine::Dialect::Fanuc,
            machine: MachineConfig::preset("mill3").expect("the mill3 preset"),
            created_at: "2025-01-01T00:00:00Z".into(),
            speed: 1.0,
        })
    }

    fn refusal(command: PanelCommand) -> String {
        command.check().expect_err("refused").to_string()
    }

    #[test]
    fn values_out_of_range_are_refused_before_the_controller() {
        let overrides = |feed, rapid| PanelCommand::Overrides { feed, rapid, spindle: None };
        assert_eq!(refusal(overrides(Some(201.0), None)), "feed override must be 0–200 %");
        assert_eq!(refusal(overrides(Some(50.0), Some(f64::NAN))), "rapid override must be 0–100 %");
        assert!(overrides(Some(200.0), Some(0.0)).check().is_ok());
        let handle = PanelCommand::Handle { target: ManualTarget::Axis('X'), amount: 2.0e5 };
        assert_eq!(refusal(handle), "HANDLE needs a finite amount (at most 1e5)");
        let signals = PanelCommand::ManualSignals {
            alngh: None,
            rghth: None,
            rndh: None,
            tb_base: None,
            handle_select: Some(32),
        };
        assert_eq!(refusal(signals), "handle_select is a 5-bit code (0–31)");
        assert_eq!(mode("JOG").unwrap(), Mode::Jog);
        assert!(mode("fast").is_err());
        assert_eq!(letter(" b ").unwrap(), 'B');
        assert_eq!(letter("\t\r\nc\n").unwrap(), 'C');
        // What the pattern refuses, the service refuses too: other white space, two letters.
        for refused in ["\u{a0}X", "X\u{85}", "\u{feff}X", "XY", "", "1"] {
            assert!(letter(refused).is_err(), "{refused:?}");
        }
        assert!(ManualTarget::of(Some("X"), None, Some("A")).is_err());
    }

    #[test]
    fn every_command_reads_back_as_it_was_written() {
        let target = ManualTarget::Feed(ManualFeed::ToolAxis);
        let commands = [
            PanelCommand::CycleStart { program: Some((12, "O0012\nM30\n".into())) },
            PanelCommand::CycleStart { program: None },
            PanelCommand::FeedHold,
            PanelCommand::Reset,
            PanelCommand::Mdi { text: "G91 X1.".into(), stored: vec![] },
            PanelCommand::SetMode { mode: Mode::Handle },
            PanelCommand::Overrides { feed: Some(50.0), rapid: None, spindle: None },
            PanelCommand::Switches(Switches {
                single_block: Some(true),
                block_delete: Some(false),
                ..Default::default()
            }),
            PanelCommand::EmergencyStop { pressed: true },
            PanelCommand::Jog { target: ManualTarget::Axis('X'), positive: false },
            PanelCommand::JogStop,
            PanelCommand::Handle { target, amount: -0.25 },
            PanelCommand::Handle { target: ManualTarget::TipRotation('B'), amount: 1.0 },
            PanelCommand::ReferenceReturn,
            PanelCommand::ManualSettings {
                coordinates: Some(ManualCoordinates::Tool),
                rtcp: Some(true),
                jog_feed: Some(500.0),
                manual_absolute: None,
                increment: Some(0.01),
            },
            PanelCommand::ManualSignals {
                alngh: Some(true),
                rghth: None,
                rndh: None,
                tb_base: Some(false),
                handle_select: Some(3),
            },
            PanelCommand::JogSignal { axis: 'Z', positive: true },
            PanelCommand::HandlePulses { amount: 0.1 },
            PanelCommand::Restart {
                program: Some((3, "N10 X1.\nM30\n".into())),
                kind: RestartType::P,
                at: RestartAt::Sequence { n: 10, occurrence: 2 },
            },
            PanelCommand::Restart {
                program: None,
                kind: RestartType::Q,
                at: RestartAt::Line { line: 4, occurrence: 1 },
            },
        ];
        for command in commands {
            let json = serde_json::to_string(&command).unwrap();
            assert_eq!(serde_json::from_str::<PanelCommand>(&json).unwrap(), command, "{json}");
        }
        let read: PanelCommand = serde_json::from_str(r#"{"command": "set_mode", "mode": "jog"}"#).unwrap();
        assert_eq!(read, PanelCommand::SetMode { mode: Mode::Jog });
    }

    /// The #3002 lost over a restart: a cycle start saves #3002 as it stands (its state event);
    /// the worker's tick that ends the run saves the program's #3002 = 1.5. Had the command
    /// sent its record after letting the station go, the worker could send first and the
    /// writer would store the older value last.
    #[test]
    fn a_commands_records_are_sent_before_the_station_is_let_go() {
        let (tx, mut rx) = tokio::sync::mpsc::unbounded_channel();
        let host = Host::new(1, tx);
        let hosted = Arc::new(hosted());
        hosted.set_speed(1000.0);
        // The hour timer is under way before the run (so the cycle start saves a value).
        hosted.station().controller.tick(36.0);
        host.add(hosted.clone());
        let program = "#3002=1.5\nG01 X10. F6000\nM30\n".to_string();
        let start = PanelCommand::CycleStart { program: Some((1, program.into())) };
        // `view` runs while the station is still locked: what the channel holds then was
        // sent before any worker could tick the controller again.
        let (applied, sent_while_locked) =
            execute(&host, &hosted, start, |_, _| std::iter::from_fn(|| rx.try_recv().ok()).collect::<Vec<_>>())
                .unwrap();
        assert_eq!(applied, Applied::Done);
        let hour_timer = |records: &[Record]| {
            records.iter().rev().find_map(|r| match r {
                Record::Variables { values, .. } => values.iter().find(|(n, _)| *n == 3002).and_then(|(_, v)| *v),
                _ => None,
            })
        };
        let at_start = hour_timer(&sent_while_locked).expect("the cycle start saves #3002");
        assert!((0.009..0.011).contains(&at_start), "{sent_while_locked:?}");
        // The worker ends the run; the writer sees the records in the order they were sent:
        // the last #3002 it stores is the program's.
        let mut written = sent_while_locked;
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(10);
        while !written.iter().any(|r| matches!(r, Record::Run { .. })) {
            assert!(std::time::Instant::now() < deadline, "the run did not end: {written:?}");
            match rx.try_recv() {
                Ok(r) => written.push(r),
                Err(_) => std::thread::sleep(std::time::Duration::from_millis(5)),
            }
        }
        host.shutdown();
        written.extend(std::iter::from_fn(|| rx.try_recv().ok()));
        let last = hour_timer(&written).unwrap();
        assert!((1.5..1.6).contains(&last), "#3002 stored last: {last} ({written:?})");
    }

    #[test]
    fn commands_change_the_controller_and_a_reset_ends_the_run() {
        let hosted = hosted();
        let mut station = hosted.station();
        let mut ended = Vec::new();
        let switches = PanelCommand::Switches(Switches { single_block: Some(true), ..Default::default() });
        assert_eq!(apply(&mut station, "c1", switches, &mut ended), Ok(Applied::Done));
        assert!(station.controller.panel.single_block && !station.controller.panel.optional_stop);
        let overrides = PanelCommand::Overrides { feed: Some(50.0), rapid: None, spindle: None };
        apply(&mut station, "c1", overrides, &mut ended).unwrap();
        assert_eq!(station.controller.panel.feed_override, 0.5);
        let mdi = PanelCommand::Mdi { text: "G91 G01 X10. F100".into(), stored: vec![] };
        apply(&mut station, "c1", mdi, &mut ended).unwrap();
        assert_eq!(station.controller.mode(), Mode::Mdi);
        assert_ne!(station.controller.run_state(), RunState::Idle);
        let another = PanelCommand::CycleStart { program: Some((1, "G01 X1.\nM30\n".into())) };
        assert_eq!(apply(&mut station, "c1", another, &mut ended), Err(Refused::ProgramUnderWay));
        assert_eq!(
            apply(&mut station, "c1", PanelCommand::SetMode { mode: Mode::Jog }, &mut ended),
            Err(Refused::Panel(Refusal::Busy))
        );
        assert!(ended.is_empty());
        apply(&mut station, "c1", PanelCommand::Reset, &mut ended).unwrap();
        assert_eq!(station.controller.run_state(), RunState::Idle);
        assert!(matches!(ended.as_slice(), [Record::Run { result, .. }] if *result == "reset"), "{ended:?}");
        // In alarm (here the emergency stop) a program's cycle start says to reset, not to
        // resume (an empty cycle start is refused there too).
        apply(&mut station, "c1", PanelCommand::EmergencyStop { pressed: true }, &mut ended).unwrap();
        let start = PanelCommand::CycleStart { program: Some((1, "G01 X1.\nM30\n".into())) };
        assert_eq!(apply(&mut station, "c1", start, &mut ended), Err(Refused::InAlarm));
    }
}
