//! A hosted controller's mutable side: the engine [`Controller`] and what the service keeps
//! beside it (the stored program it runs, the run under way, what was last saved and streamed),
//! and the translation of the controller's events into stream messages and database records.

use std::collections::BTreeMap;

use fivex_engine::controller::{Controller, Event, RunState};

use super::stream::{AlarmInfo, Message};
use super::{now_rfc3339, Record};

/// Retained variables #500–#999.
const RETAINED: usize = 500;

/// How often, in real seconds, a running controller's variables are compared with what was
/// streamed, and its retained variables with what was saved.
const STREAM_VARIABLES_EVERY: f64 = 0.1;
const SAVE_VARIABLES_EVERY: f64 = 1.0;

pub struct Station {
    pub controller: Controller,
    /// The stored program (O number) AUTO runs, once one was started.
    pub program: Option<u32>,
    run: Option<RunStart>,
    /// #500–#999 as last saved.
    saved: Box<[Option<f64>; RETAINED]>,
    /// Common variables as last streamed.
    streamed: BTreeMap<u32, f64>,
    since_streamed: f64,
    since_saved: f64,
}

/// A program run under way.
struct RunStart {
    program: Option<u32>,
    started_at: String,
    sim_start: f64,
}

impl Station {
    pub fn new(controller: Controller) -> Station {
        let saved = Box::new(*controller.interpreter().state.persistent());
        let streamed = controller.interpreter().state.common_variables().into_iter().collect();
        Station { controller, program: None, run: None, saved, streamed, since_streamed: 0.0, since_saved: 0.0 }
    }

    /// Retained values read from the database: they count as saved.
    pub fn load_retained(&mut self, values: &[Option<f64>; RETAINED]) {
        self.controller.interpreter_mut().state.load_persistent(values);
        *self.saved = *values;
        self.streamed = self.controller.interpreter().state.common_variables().into_iter().collect();
    }

    /// A variable was set from outside (the API wrote it to the database already).
    pub fn variable_saved(&mut self, number: u32, value: Option<f64>) {
        if (500..1000).contains(&number) {
            self.saved[number as usize - 500] = value;
        }
    }

    /// A program run begins (cycle start from idle): remembered for the run history.
    pub fn begin_run(&mut self, program: Option<u32>) {
        self.program = program;
        self.run = Some(RunStart { program, started_at: now_rfc3339(), sim_start: self.controller.time() });
    }

    /// The run under way ends with `result`.
    pub fn end_run(&mut self, controller: &str, result: &'static str) -> Option<Record> {
        let run = self.run.take()?;
        Some(Record::Run {
            controller: controller.to_string(),
            program: run.program,
            started_at: run.started_at,
            ended_at: now_rfc3339(),
            cycle_time_s: self.controller.time() - run.sim_start,
            result,
        })
    }

    /// After a tick of `real_dt` real seconds or an operator action: the controller's events as
    /// stream messages (`watching`: someone listens) and database records.
    pub fn collect(&mut self, controller: &str, real_dt: f64, watching: bool) -> (Vec<Message>, Vec<Record>) {
        let (mut messages, mut records) = (Vec::new(), Vec::new());
        let mut changed = false;
        for event in self.controller.take_events() {
            match event {
                Event::State(state) => {
                    changed = true;
                    messages.push(Message::state(self));
                    let result = match state {
                        RunState::Idle => Some("completed"),
                        RunState::Alarm => Some("alarm"),
                        _ => None,
                    };
                    if let Some(record) = result.and_then(|r| self.end_run(controller, r)) {
                        records.push(record);
                    }
                }
                Event::Alarm(alarm) => {
                    records.push(Record::Alarm {
                        controller: controller.to_string(),
                        at: now_rfc3339(),
                        alarm: alarm.clone(),
                    });
                    messages.push(Message::Alarm {
                        event: "raised",
                        raised: Some(AlarmInfo::from(&alarm)),
                        active: self.controller.alarms().iter().map(AlarmInfo::from).collect(),
                    });
                }
                Event::AlarmsCleared => {
                    messages.push(Message::Alarm { event: "cleared", raised: None, active: Vec::new() });
                }
                Event::Message(text) => messages.push(Message::Message { text }),
            }
        }
        let running = self.controller.run_state() == RunState::Running;
        self.since_streamed += real_dt;
        self.since_saved += real_dt;
        if watching && (changed || running && self.since_streamed >= STREAM_VARIABLES_EVERY) {
            self.since_streamed = 0.0;
            let changes = self.stream_changes();
            if !changes.is_empty() {
                messages.push(Message::variables(&changes));
            }
        }
        if changed || running && self.since_saved >= SAVE_VARIABLES_EVERY {
            self.since_saved = 0.0;
            if let Some(record) = self.save_changes(controller) {
                records.push(record);
            }
        }
        (messages, records)
    }

    /// Common variables that differ from what was streamed last.
    fn stream_changes(&mut self) -> Vec<(u32, Option<f64>)> {
        let now: BTreeMap<u32, f64> = self.controller.interpreter().state.common_variables().into_iter().collect();
        let mut changes: Vec<(u32, Option<f64>)> = now
            .iter()
            .filter(|(n, v)| self.streamed.get(n).is_none_or(|old| old.to_bits() != v.to_bits()))
            .map(|(n, v)| (*n, Some(*v)))
            .collect();
        changes.extend(self.streamed.keys().filter(|n| !now.contains_key(n)).map(|n| (*n, None)));
        changes.sort_by_key(|(n, _)| *n);
        self.streamed = now;
        changes
    }

    /// Retained variables that differ from what was saved last, as a record for the database.
    fn save_changes(&mut self, controller: &str) -> Option<Record> {
        let now = *self.controller.interpreter().state.persistent();
        let values: Vec<(u32, Option<f64>)> = (0..RETAINED)
            .filter(|&i| now[i].map(f64::to_bits) != self.saved[i].map(f64::to_bits))
            .map(|i| (500 + i as u32, now[i]))
            .collect();
        if values.is_empty() {
            return None;
        }
        *self.saved = now;
        Some(Record::Variables { controller: controller.to_string(), values })
    }
}
