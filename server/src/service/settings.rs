//! What an operator sets on a controller that the database keeps: macro variables (the
//! retained ones), tool offsets and work offsets.
//!
//! Each is stored first, then set in the controller, so a refusal of the database changes
//! nothing. But the controller's worker may have queued records of older values for the writer
//! (a program's `#500=…` or G10 saved at its run's end), which the writer may store after the
//! request's own write: the old value would come back after a restart while the controller
//! shows the new one. So the change is also handed to the writer, while the controller is
//! locked — after every record of an older value, before any of a newer one — and the answer
//! waits until the writer has stored it (`stored`). *Decision*: the value is written twice
//! (in the request, then by the writer) rather than only by the writer, since the writer's
//! batches cannot tell the request that its record failed (docs/api.md, "The database").

use std::sync::MutexGuard;

use fivex_engine::controller::RunState;
use fivex_engine::interp::{work_value_fits, work_value_limit};
use serde_json::{Map, Value};

use super::ServiceError;
use crate::db::{self, Record, ToolRow};
use crate::host::station::{run_state, tool_row};
use crate::host::stream::Message;
use crate::host::{Host, Hosted, Station};

/// The controller's station, locked, unless the controller left this host while the request
/// waited (deleted, or handed to another node, which loaded it from the database before this
/// change: acting on this copy would lose it, as `panel::execute` says).
fn station(hosted: &Hosted) -> Result<MutexGuard<'_, Station>, ServiceError> {
    let station = hosted.station();
    if hosted.is_removed() {
        return Err(ServiceError::Unavailable(format!(
            "controller {} is no longer hosted here (deleted, or moving to another node): retry in a few seconds",
            hosted.id
        )));
    }
    Ok(station)
}

/// Waits until the writer has stored the record numbered `sent` (`Host::record`), and so every
/// one of the controller's records sent before it: then the database holds the request's
/// value, or a newer one.
async fn stored(db: &db::Db, sent: Option<u64>) -> Result<(), ServiceError> {
    let Some(sent) = sent else {
        return Err(ServiceError::Unavailable("the service is stopping: the change may not be kept".into()));
    };
    if db.records_written(sent).await {
        Ok(())
    } else {
        Err(ServiceError::Unavailable("the database writer is behind: the change may not be kept yet".into()))
    }
}

/// Sets macro variable `number` (`None`: vacant) or input signal #1000–#1035 (never vacant),
/// and tells the controller's subscribers.
pub async fn set_variable(
    db: &db::Db,
    host: &Host,
    hosted: &Hosted,
    number: u32,
    value: Option<f64>,
) -> Result<(), ServiceError> {
    let signal = (1000..=1035).contains(&number);
    if !signal && !matches!(number, 100..=199 | 500..=999 | 100_000..=199_999 | 500_000..=999_999) {
        return Err(ServiceError::invalid(format!(
            "#{number} is not writable here (#100–#199, #500–#999, #100000–#199999, #500000–#999999, \
             input signals #1000–#1035)"
        )));
    }
    // Syntec: #100–#199 are a program's local variables there, vacant at each cycle start, so a
    // value set now would be wiped before any program read it; the extended numbers are no
    // Syntec program's, and #1000… are Syntec's modal state, which its programs read as such (a
    // FANUC input signal there is refused, COR-016): a value set there would reach nothing
    // (`docs/dialects.md`, "The Syntec macro language").
    if hosted.dialect == fivex_engine::Dialect::Syntec && !matches!(number, 500..=999) {
        return Err(ServiceError::invalid(format!(
            "#{number} is not writable in the Syntec dialect: #100–#199 are a Syntec program's local \
             variables, vacant at each cycle start, #1000… its modal state (no input signals), and \
             #100000… are no Syntec variables (#500–#999 are writable)"
        )));
    }
    if value.is_some_and(|v| !v.is_finite()) {
        return Err(ServiceError::invalid("the value must be a finite number or null"));
    }
    // An input signal is never vacant (a program reads it as 0 or 1, or a group's number): a
    // `null` answered 200 and read back `null` while programs read 0.
    if signal && value.is_none() {
        return Err(ServiceError::invalid(format!(
            "#{number} is an input signal: 0 or 1 (a group: 0…2³²−1), not null"
        )));
    }
    let retained = fivex_engine::interp::State::is_retained(number);
    if retained {
        db::save_variables(db, &hosted.id, &[(number, value)]).await?;
    }
    let sent = {
        let mut station = station(hosted)?;
        let state = &mut station.controller.interpreter_mut().state;
        let set = if signal {
            state.signals.set_input(number, value.unwrap_or(0.0))
        } else {
            state.set_common_variable(number, value)
        };
        set.map_err(|_| ServiceError::invalid(format!("#{number}: not a value it can take")))?;
        station.variable_saved(number, value);
        // Sent before the station is let go (the module's comment): ordered with the worker's.
        let sent = retained
            .then(|| host.record(Record::Variables { controller: hosted.id.clone(), values: vec![(number, value)] }));
        hosted.publish(vec![Message::variables(&[(number, value)])]);
        sent
    };
    match sent {
        Some(sent) => stored(db, sent).await,
        None => Ok(()),
    }
}

/// A work offset value, mm: within the range G10 takes (`work_value_limit`), so that no
/// workpiece zero a program could not set reaches a run.
fn work_value(v: f64, what: &str) -> Result<f64, ServiceError> {
    if work_value_fits(v, false) {
        Ok(v)
    } else {
        let limit = work_value_limit(false);
        Err(ServiceError::invalid(format!(
            "{what} {v} is outside ±{limit} mm (the range of a work offset value, as G10 takes it)"
        )))
    }
}

/// Tool offset `number` (1–999) as it is now.
pub fn tool_offset(hosted: &Hosted, number: u32) -> Result<ToolRow, ServiceError> {
    hosted
        .station()
        .controller
        .interpreter()
        .state
        .offsets
        .tool(number)
        .filter(|_| number >= 1)
        .map(|t| tool_row(number, t))
        .ok_or_else(|| ServiceError::invalid(format!("tool offset number {number} is outside 1–999")))
}

/// A change of a tool offset: the values given, the others as they are (the values a tool
/// table's entry sets too, with the same ranges: `tools::ToolValues`).
pub type ToolChange = crate::tools::ToolValues;

/// Changes tool offset `number`; the offset after the change.
///
/// A read-modify-write: the values left out are kept as they are *at the change*. Changes
/// through the API take their turn (`Hosted::editing`, held to the end), so the row stored
/// first never carries a value an earlier answered change has replaced; the values given are
/// set in the controller under its lock, so a program's G10 of the other values meanwhile is
/// kept too, and the writer then stores the offset as the controller holds it.
pub async fn set_tool_offset(
    db: &db::Db,
    host: &Host,
    hosted: &Hosted,
    number: u32,
    change: ToolChange,
) -> Result<ToolRow, ServiceError> {
    let change = change.checked().map_err(ServiceError::invalid)?;
    let _editing = hosted.editing().await;
    let stored_first = change.applied_to(tool_offset(hosted, number)?);
    db::save_tool_offsets(db, &hosted.id, &[stored_first]).await?;
    let (row, sent) = {
        let mut station = station(hosted)?;
        let t = station.controller.interpreter_mut().state.offsets.tool_mut(number);
        let Some(t) = t else {
            return Err(ServiceError::invalid(format!("tool offset number {number} is outside 1–999")));
        };
        change.apply(t);
        let row = tool_row(number, t);
        (row, save_offsets(host, hosted, &mut station))
    };
    stored(db, sent).await?;
    Ok(row)
}

impl ToolChange {
    /// `row` with the values this change gives.
    fn applied_to(self, row: ToolRow) -> ToolRow {
        ToolRow {
            number: row.number,
            length: self.length.unwrap_or(row.length),
            length_wear: self.length_wear.unwrap_or(row.length_wear),
            radius: self.radius.unwrap_or(row.radius),
            radius_wear: self.radius_wear.unwrap_or(row.radius_wear),
            corner_radius: self.corner_radius.unwrap_or(row.corner_radius),
        }
    }
}

/// Hands the offsets written since they were last saved to the writer, the station still
/// locked: this one, and those a running program's G10 wrote, which its run's next state change
/// would have saved (counting only this one as saved would lose them). The last record's number.
fn save_offsets(host: &Host, hosted: &Hosted, station: &mut Station) -> Option<u64> {
    let mut sent = None;
    for record in station.offset_records(&hosted.id) {
        sent = host.record(record);
    }
    sent
}

/// Changes the axes `axes` names (letter: number) of work offset `slot`, only while nothing
/// runs; the offset after the change, per axis letter, once the writer has stored it (in order
/// with what a program's G10 wrote). Only the axes named are set, under the controller's lock:
/// two changes of other axes of one offset at once both stay.
pub async fn set_work_offset(
    db: &db::Db,
    host: &Host,
    hosted: &Hosted,
    slot: usize,
    axes: &Map<String, Value>,
) -> Result<Map<String, Value>, ServiceError> {
    let (shown, sent) = {
        let mut station = station(hosted)?;
        // The axes read on the machine the change is made on (a parameter change may have
        // given the controller another one while the request waited).
        let machine = station.machine.clone();
        let mut given = Vec::with_capacity(axes.len());
        for (letter, value) in axes {
            let index = machine
                .axes
                .iter()
                .position(|a| a.name.to_string().eq_ignore_ascii_case(letter))
                .ok_or_else(|| ServiceError::invalid(format!("the machine has no axis {letter}")))?;
            let v = value.as_f64().ok_or_else(|| ServiceError::invalid(format!("{letter} must be a number")))?;
            given.push((index, work_value(v, letter)?));
        }
        // The check and the change under one lock: checked before the database write, as it
        // was, a cycle start in between ran a program whose offset then changed under it.
        if run_state(&station.controller) != RunState::Idle {
            return Err(ServiceError::Conflict("work offsets change only while nothing runs".into()));
        }
        let work = station.controller.interpreter_mut().state.offsets.work_mut(slot);
        for (index, v) in given {
            work[index] = v;
        }
        let shown = crate::host::stream::axes(&machine, work);
        station.controller.offsets_changed();
        (shown, save_offsets(host, hosted, &mut station))
    };
    stored(db, sent).await?;
    Ok(shown)
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::host::Host;
    use crate::service::controllers::{self, NewController};
    use crate::service::panel::{self, PanelCommand};
    use fivex_engine::interp::expr::Variables;
    use std::sync::Arc;
    use std::time::{Duration, Instant};

    /// A service over a fresh database whose writer is behind: what the host sends is held back
    /// until a record `release` picks arrives (or the host closes the channel), then written in
    /// the order it was sent. (A busy writer, or one writing a large batch, is behind so.)
    struct Service {
        db: db::Db,
        host: Host,
        writer: Option<tokio::task::JoinHandle<()>>,
        _dir: tempfile::TempDir,
    }

    async fn service(release: impl Fn(&Record) -> bool + Send + 'static) -> Service {
        let dir = tempfile::tempdir().unwrap();
        let db = db::open(&dir.path().join("fivex.db")).await.unwrap();
        let (to_gate, mut gate) = tokio::sync::mpsc::unbounded_channel::<Record>();
        let (to_writer, incoming) = tokio::sync::mpsc::unbounded_channel();
        let writer = tokio::spawn(db::write_records(db.clone(), incoming));
        tokio::spawn(async move {
            let mut held = Vec::new();
            while let Some(record) = gate.recv().await {
                let go = release(&record);
                held.push(record);
                if go {
                    break;
                }
            }
            for record in held {
                let _ = to_writer.send(record);
            }
            while let Some(record) = gate.recv().await {
                let _ = to_writer.send(record);
            }
        });
        Service { db, host: Host::new(1, to_gate), writer: Some(writer), _dir: dir }
    }

    impl Service {
        async fn controller(&self, speed: f64) -> Arc<Hosted> {
            let request = NewController {
                name: "c".into(),
                preset: Some("mill3".into()),
                machine: None,
                dialect: None,
                speed: Some(speed),
                workpiece: None,
            };
            controllers::create(&self.db, &self.host, request).await.unwrap()
        }

        /// The service stops (the writer writes everything it was sent) and the controller is
        /// loaded again from the database, as a restart does.
        async fn restart(&mut self, id: &str) -> Hosted {
            self.host.shutdown();
            self.writer.take().unwrap().await.unwrap();
            let row = db::controller(&self.db, id).await.unwrap().unwrap();
            let settings = db::controller_settings(&self.db).await.unwrap();
            controllers::load(&self.db, row, &settings).await.unwrap().unwrap()
        }
    }

    fn command(host: &Host, hosted: &Hosted, command: PanelCommand) {
        panel::execute(host, hosted, command, |_, _| ()).unwrap();
    }

    async fn until(hosted: &Hosted, what: &str, done: impl Fn(&crate::host::Station) -> bool) {
        let deadline = Instant::now() + Duration::from_secs(20);
        while !done(&hosted.station()) {
            assert!(Instant::now() < deadline, "never {what}");
            tokio::time::sleep(Duration::from_millis(5)).await;
        }
    }

    fn run(host: &Host, hosted: &Hosted, text: &str) {
        command(host, hosted, PanelCommand::CycleStart { program: Some((1, text.into())) });
    }

    async fn run_to_end(host: &Host, hosted: &Hosted, text: &str) {
        run(host, hosted, text);
        until(hosted, "idle", |s| s.controller.run_state() == RunState::Idle).await;
    }

    fn variable(hosted: &Hosted, number: u32) -> Option<f64> {
        hosted.station().controller.interpreter().state.read(number).unwrap()
    }

    /// A program's `#500=1` is queued for the writer at the run's end; the API then sets
    /// #500 = 2. The older record must not overwrite the API's value in the database.
    #[tokio::test]
    async fn an_api_write_of_a_variable_is_not_overwritten_by_a_programs_queued_record() {
        let api = |r: &Record| matches!(r, Record::Variables { values, .. } if values.contains(&(500, Some(2.0))));
        let mut s = service(api).await;
        let hosted = s.controller(1000.0).await;
        run_to_end(&s.host, &hosted, "#500=1.\nM30\n").await;
        assert_eq!(variable(&hosted, 500), Some(1.0));
        set_variable(&s.db, &s.host, &hosted, 500, Some(2.0)).await.unwrap();
        assert_eq!(variable(&hosted, 500), Some(2.0));
        let again = s.restart(&hosted.id).await;
        let stored = db::retained_variables(&s.db, &hosted.id).await.unwrap();
        assert!(stored.contains(&(500, 2.0)), "stored: {stored:?}");
        assert_eq!(variable(&again, 500), Some(2.0), "#500 after the restart");
    }

    /// The same for a tool offset a program's G10 set (saved at the run's end) and the API
    /// changes right after.
    #[tokio::test]
    async fn an_api_write_of_a_tool_offset_is_not_overwritten_by_a_programs_queued_record() {
        let api = |r: &Record| matches!(r, Record::ToolOffsets { rows, .. } if rows.iter().any(|t| t.number == 5 && t.length == 3.0));
        let mut s = service(api).await;
        let hosted = s.controller(1000.0).await;
        run_to_end(&s.host, &hosted, "G10 L10 P5 R12.5\nM30\n").await;
        let change = ToolChange { length: Some(3.0), ..ToolChange::default() };
        set_tool_offset(&s.db, &s.host, &hosted, 5, change).await.unwrap();
        let again = s.restart(&hosted.id).await;
        let stored = db::tool_offsets(&s.db, &hosted.id).await.unwrap();
        assert_eq!(stored.iter().find(|t| t.number == 5).map(|t| t.length), Some(3.0), "{stored:?}");
        assert_eq!(tool_offset(&again, 5).unwrap().length, 3.0, "H5 after the restart");
    }

    /// The same for a work offset (G10 L2 P1: G54).
    #[tokio::test]
    async fn an_api_write_of_a_work_offset_is_not_overwritten_by_a_programs_queued_record() {
        let api = |r: &Record| matches!(r, Record::WorkOffsets { rows, .. } if rows.iter().any(|(slot, axes)| *slot == 1 && axes[0] == 7.0));
        let mut s = service(api).await;
        let hosted = s.controller(1000.0).await;
        run_to_end(&s.host, &hosted, "G10 L2 P1 X5.\nM30\n").await;
        let axes: Map<String, Value> = serde_json::from_str(r#"{"X": 7.0}"#).unwrap();
        set_work_offset(&s.db, &s.host, &hosted, 1, &axes).await.unwrap();
        let again = s.restart(&hosted.id).await;
        let stored = db::work_offsets(&s.db, &hosted.id).await.unwrap();
        assert_eq!(stored.iter().find(|(slot, _)| *slot == 1).map(|(_, axes)| axes[0]), Some(7.0), "{stored:?}");
        assert_eq!(again.station().controller.interpreter().state.offsets.work(1)[0], 7.0, "G54 X after the restart");
    }

    /// While a program runs a work offset does not change (409): not in the controller, not in
    /// the database.
    #[tokio::test]
    async fn a_work_offset_does_not_change_while_a_program_runs() {
        let mut s = service(|_| true).await;
        let hosted = s.controller(1.0).await;
        run(&s.host, &hosted, "G04 X100.\nM30\n");
        until(&hosted, "running", |s| s.controller.run_state() == RunState::Running).await;
        let axes: Map<String, Value> = serde_json::from_str(r#"{"X": 7.0}"#).unwrap();
        let refused = set_work_offset(&s.db, &s.host, &hosted, 1, &axes).await;
        assert!(matches!(refused, Err(ServiceError::Conflict(_))), "{refused:?}");
        assert_eq!(hosted.station().controller.interpreter().state.offsets.work(1)[0], 0.0);
        command(&s.host, &hosted, PanelCommand::Reset);
        let again = s.restart(&hosted.id).await;
        assert_eq!(again.station().controller.interpreter().state.offsets.work(1)[0], 0.0, "G54 X after a restart");
    }

    /// A program's G10 is saved when the run state changes; an API write of another tool
    /// offset while the program runs must not count it as saved.
    #[tokio::test]
    async fn an_api_write_of_a_tool_offset_keeps_a_programs_unsaved_g10() {
        let mut s = service(|_| true).await;
        let hosted = s.controller(1.0).await;
        // The dwell keeps the run going (no run state change, so nothing is saved yet).
        run(&s.host, &hosted, "G10 L10 P5 R12.5\nG04 X100.\nM30\n");
        until(&hosted, "G10 done", |s| s.controller.interpreter().state.offsets.length(5) == 12.5).await;
        assert_eq!(hosted.station().controller.run_state(), RunState::Running);
        let change = ToolChange { length: Some(3.0), ..ToolChange::default() };
        set_tool_offset(&s.db, &s.host, &hosted, 7, change).await.unwrap();
        command(&s.host, &hosted, PanelCommand::Reset);
        let again = s.restart(&hosted.id).await;
        let stored = db::tool_offsets(&s.db, &hosted.id).await.unwrap();
        let length = |n: u32| stored.iter().find(|t| t.number == n).map(|t| t.length);
        assert_eq!((length(5), length(7)), (Some(12.5), Some(3.0)), "{stored:?}");
        assert_eq!((tool_offset(&again, 5).unwrap().length, tool_offset(&again, 7).unwrap().length), (12.5, 3.0));
    }
}
