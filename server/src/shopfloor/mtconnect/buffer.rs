//! The agent's memory: every observation numbered by one sequence across all devices, the last
//! `capacity` of them kept for `/sample`, and each device's current values for `/current`.
//!
//! An observation is made only when a data item's value changed between two rounds of the
//! observer, so the sequence says what changed and when; a `/sample` client that asks for
//! `from = nextSequence` each time sees every observation once, in order, without gaps.

use std::collections::VecDeque;
use std::sync::Arc;

use super::doc::Text;
use super::model::{Category, Device, Value};
use crate::host::station::{AlarmChange, AlarmLog};
use crate::host::stream::AlarmInfo;
use crate::shopfloor::observe::Round;

/// What one observation says.
#[derive(Debug, Clone, PartialEq)]
pub enum Said {
    Value(Text),
    Unavailable,
    /// A condition's fault came on (nativeCode = the alarm's code, text its message).
    Fault(AlarmInfo),
    /// A condition is normal again: every fault (`None`) or the one with this code.
    Normal(Option<String>),
}

#[derive(Debug, Clone)]
pub struct Observation {
    pub sequence: u64,
    /// RFC 3339 UTC, the observer's round.
    pub at: Arc<str>,
    pub device: Arc<Device>,
    /// Index into the device's items.
    pub item: usize,
    pub said: Said,
}

/// A device as the agent holds it: its model, the values last seen, and what `/current` shows
/// (per item: the last observation; for a condition, every fault in force or one `Normal`).
#[derive(Debug)]
pub struct Held {
    pub model: Arc<Device>,
    /// Per item: the value last observed (`None`: not yet).
    last: Vec<Option<Value>>,
    pub current: Vec<Vec<Observation>>,
    /// The controller's alarm changes read up to (`AlarmLog::next`); `None` before the first
    /// reading. Kept when the model is rebuilt.
    alarms_read: Option<u64>,
}

#[derive(Debug)]
pub struct Buffer {
    capacity: usize,
    kept: VecDeque<Observation>,
    next: u64,
    /// In the order the controllers were first seen.
    pub devices: Vec<Held>,
    /// When the set of devices or one's model last changed (the header's deviceModelChangeTime).
    pub model_changed_at: String,
}

impl Buffer {
    pub fn new(capacity: usize) -> Buffer {
        Buffer {
            capacity: capacity.max(1),
            kept: VecDeque::with_capacity(capacity.clamp(1, 1 << 20)),
            next: 1,
            devices: Vec::new(),
            model_changed_at: crate::host::now_rfc3339(),
        }
    }

    pub fn capacity(&self) -> usize {
        self.capacity
    }

    /// The sequence the next observation gets.
    pub fn next_sequence(&self) -> u64 {
        self.next
    }

    /// The oldest sequence still kept (`next` when none is).
    pub fn first_sequence(&self) -> u64 {
        self.kept.front().map_or(self.next, |o| o.sequence)
    }

    pub fn last_sequence(&self) -> u64 {
        self.next.saturating_sub(1).max(self.first_sequence().saturating_sub(1))
    }

    /// Up to `count` observations from sequence `from` on (`from` must be kept or `next`).
    pub fn range(&self, from: u64, count: usize) -> &[Observation] {
        let first = self.first_sequence();
        let start = usize::try_from(from.saturating_sub(first)).unwrap_or(usize::MAX).min(self.kept.len());
        let (a, b) = self.kept.as_slices();
        // The ring's two halves: a range inside one of them is one slice; one across both is
        // cut at the seam (the caller asks again from the next sequence).
        if start < a.len() {
            &a[start..(start + count).min(a.len())]
        } else {
            let start = start - a.len();
            &b[start..(start + count).min(b.len())]
        }
    }

    /// Takes in a round: observations for what changed, new devices, and devices gone.
    pub fn observe(&mut self, round: &Round) {
        let at: Arc<str> = Arc::from(round.at.as_str());
        let mut seen = vec![false; self.devices.len()];
        let names = super::model::unique_names(&round.controllers);
        for (entry, name) in round.controllers.iter().zip(&names) {
            let index = match self.devices.iter().position(|d| d.model.uuid == entry.id) {
                Some(i) => {
                    seen[i] = true;
                    let held = &self.devices[i];
                    if !Arc::ptr_eq(&held.model.machine, &entry.machine) || held.model.name != *name {
                        // A new machine (or name): the device's model is rebuilt, every value
                        // observed afresh.
                        let alarms_read = held.alarms_read;
                        self.devices[i] = Held::new(Arc::new(Device::of(entry, name)));
                        self.devices[i].alarms_read = alarms_read;
                        self.model_changed_at = round.at.clone();
                    }
                    i
                }
                None => {
                    self.devices.push(Held::new(Arc::new(Device::of(entry, name))));
                    seen.push(true);
                    self.model_changed_at = round.at.clone();
                    self.devices.len() - 1
                }
            };
            self.replay_alarms(index, &entry.observed.alarm_log, &at);
            let values: Vec<Value> = self.devices[index].model.items.iter().map(|i| i.value(&entry.observed)).collect();
            for (item, value) in values.into_iter().enumerate() {
                if self.devices[index].last[item].as_ref() != Some(&value) {
                    self.change(index, item, value, &at);
                }
            }
        }
        // Gone (deleted, or hosted by another node now): said unavailable, then forgotten.
        for i in (0..seen.len()).rev() {
            if !seen[i] {
                let availability = self.devices[i].model.items.iter().position(|it| it.kind == "AVAILABILITY");
                if let Some(item) = availability {
                    self.change(i, item, Value::Unavailable, &at);
                }
                self.devices.remove(i);
                self.model_changed_at = round.at.clone();
            }
        }
    }

    /// The alarm changes of device `index`'s controller since the last round, in order: a
    /// Fault for each alarm raised, a Normal for each reset. Comparing the alarm lists of two
    /// rounds alone missed an alarm raised and reset between them. (What the lists still
    /// differ in afterwards is observed as any value is.)
    fn replay_alarms(&mut self, index: usize, log: &AlarmLog, at: &Arc<str>) {
        let item = self.devices[index].model.items.iter().position(|i| i.is_alarms());
        let read = self.devices[index].alarms_read.replace(log.next());
        // At the first reading the alarms in force are the condition's first value.
        let (Some(read), Some(item)) = (read, item) else {
            return;
        };
        for change in log.since(read) {
            let faults: Vec<AlarmInfo> = match &self.devices[index].last[item] {
                Some(Value::Faults(f)) => f.clone(),
                _ => Vec::new(),
            };
            match change {
                AlarmChange::Raised(alarm) if !faults.contains(alarm) => {
                    let mut now = faults;
                    now.push(alarm.clone());
                    self.change(index, item, Value::Faults(now), at);
                }
                AlarmChange::Cleared if !faults.is_empty() || self.devices[index].last[item].is_none() => {
                    self.change(index, item, Value::Faults(Vec::new()), at);
                }
                _ => {}
            }
        }
    }

    /// Item `item` of device `index` now has `value`: the observations that say so.
    fn change(&mut self, index: usize, item: usize, value: Value, at: &Arc<str>) {
        let held = &self.devices[index];
        let said: Vec<Said> = match (&held.last[item], &value) {
            (_, Value::Text(t)) => vec![Said::Value(t.clone())],
            (_, Value::Unavailable) => vec![Said::Unavailable],
            (before, Value::Faults(now)) => {
                let before: &[AlarmInfo] = match before {
                    Some(Value::Faults(f)) => f,
                    _ => &[],
                };
                if now.is_empty() {
                    vec![Said::Normal(None)]
                } else {
                    let cleared =
                        before.iter().filter(|a| !now.contains(a)).map(|a| Said::Normal(Some(a.code.clone())));
                    let raised = now.iter().filter(|a| !before.contains(a)).map(|a| Said::Fault(a.clone()));
                    cleared.chain(raised).collect()
                }
            }
        };
        let model = held.model.clone();
        for said in said {
            let observation =
                Observation { sequence: self.next, at: at.clone(), device: model.clone(), item, said: said.clone() };
            self.next += 1;
            let current = &mut self.devices[index].current[item];
            if model.items[item].category == Category::Condition {
                match &said {
                    Said::Fault(_) => {
                        current.retain(|o| matches!(o.said, Said::Fault(_)));
                        current.push(observation.clone());
                    }
                    Said::Normal(Some(code)) => {
                        current.retain(|o| !matches!(&o.said, Said::Fault(a) if &a.code == code));
                        if current.is_empty() {
                            current.push(observation.clone());
                        }
                    }
                    _ => *current = vec![observation.clone()],
                }
            } else {
                *current = vec![observation.clone()];
            }
            if self.kept.len() == self.capacity {
                self.kept.pop_front();
            }
            self.kept.push_back(observation);
        }
        self.devices[index].last[item] = Some(value);
    }
}

impl Held {
    fn new(model: Arc<Device>) -> Held {
        let n = model.items.len();
        Held { model, last: vec![None; n], current: vec![Vec::new(); n], alarms_read: None }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shopfloor::observe::{Entry, Observed};
    use fivex_engine::controller::{Mode, RunState};
    use fivex_engine::machine::{Machine, MachineConfig};

    fn entry(machine: &Arc<Machine>, x: f64, alarms: &[&str]) -> Arc<Entry> {
        let observed = Observed {
            emergency_stop: false,
            mode: Mode::Auto,
            run_state: if alarms.is_empty() { RunState::Running } else { RunState::Alarm },
            program_stop: None,
            program: Some(1),
            line: 3,
            line_program: Some(1),
            n: None,
            block: None,
            machine: vec![x, 0.0, 0.0],
            tip: [x, 0.0, 0.0],
            feed: 600.0,
            feed_override: 100.0,
            rapid_override: 100.0,
            spindle: 0.0,
            spindle_override: 100.0,
            tool: 1,
            parts: 0.0,
            parts_required: 0.0,
            alarms: alarms
                .iter()
                .map(|c| AlarmInfo { code: c.to_string(), message: "m".into(), line: 3, n: None, program: Some(1) })
                .collect(),
            alarm_log: Default::default(),
            time_s: 0.0,
        };
        Arc::new(Entry {
            id: "c1".into(),
            name: "one".into(),
            dialect: fivex_engine::Dialect::Fanuc,
            created_at: String::new(),
            machine: machine.clone(),
            observed,
            lag: Default::default(),
        })
    }

    fn round(number: u64, controllers: Vec<Arc<Entry>>) -> Round {
        Round { number, at: format!("2026-01-01T00:00:0{number}Z"), controllers }
    }

    fn condition(b: &Buffer) -> Vec<Said> {
        let held = &b.devices[0];
        let item = held.model.items.iter().position(|i| i.category == Category::Condition).unwrap();
        held.current[item].iter().map(|o| o.said.clone()).collect()
    }

    #[test]
    fn only_changes_are_observed_and_conditions_track_each_fault() {
        let machine = Arc::new(Machine::new(MachineConfig::preset("mill3").unwrap()));
        let mut b = Buffer::new(1000);
        b.observe(&round(1, vec![entry(&machine, 0.0, &[])]));
        let first = b.next_sequence();
        assert_eq!(first - 1, b.devices[0].model.items.len() as u64, "every item once at first");
        assert_eq!(condition(&b), vec![Said::Normal(None)]);

        b.observe(&round(2, vec![entry(&machine, 0.0, &[])]));
        assert_eq!(b.next_sequence(), first, "nothing changed, nothing observed");

        // X moves: its ACTUAL and COMMANDED, and the path position.
        b.observe(&round(3, vec![entry(&machine, 1.0, &[])]));
        assert_eq!(b.next_sequence(), first + 3);

        b.observe(&round(4, vec![entry(&machine, 1.0, &["PS0010", "PS0011"])]));
        let faults = condition(&b);
        assert_eq!(faults.len(), 2, "{faults:?}");
        b.observe(&round(5, vec![entry(&machine, 1.0, &["PS0011"])]));
        assert!(matches!(&condition(&b)[..], [Said::Fault(a)] if a.code == "PS0011"));
        let last = b.range(b.next_sequence() - 1, 1)[0].clone();
        assert_eq!(last.said, Said::Normal(Some("PS0010".into())));
        b.observe(&round(6, vec![entry(&machine, 1.0, &[])]));
        assert_eq!(condition(&b), vec![Said::Normal(None)]);

        // The controller is gone: unavailable, then forgotten.
        b.observe(&round(7, vec![]));
        assert!(b.devices.is_empty());
        let last = b.range(b.next_sequence() - 1, 1)[0].clone();
        assert_eq!(last.said, Said::Unavailable);
    }

    /// A rename rebuilds the device's model: a range across it was two DeviceStreams of one
    /// uuid with the same componentIds (XML IDs). One stream, named as the device is now.
    #[test]
    fn a_range_across_a_rebuilt_model_is_one_device_stream() {
        let machine = Arc::new(Machine::new(MachineConfig::preset("mill3").unwrap()));
        let mut b = Buffer::new(1000);
        b.observe(&round(1, vec![entry(&machine, 0.0, &[])]));
        let mut renamed = (*entry(&machine, 1.0, &[])).clone();
        renamed.name = "two".into();
        b.observe(&round(2, vec![Arc::new(renamed)]));
        let sender = super::super::documents::Sender { sender: "h".into(), instance_id: 1, buffer_size: 1000 };
        let root = super::super::documents::streams(&sender, &b, b.range(1, 1000), b.next_sequence());
        let xml = super::super::doc::xml(&root, "Streams");
        assert_eq!(xml.matches("<DeviceStream ").count(), 1, "{xml}");
        assert!(xml.contains("<DeviceStream name=\"two\" uuid=\"c1\""), "{xml}");
        let ids: Vec<&str> = xml
            .match_indices("componentId=\"")
            .map(|(at, m)| {
                let rest = &xml[at + m.len()..];
                &rest[..rest.find('"').unwrap()]
            })
            .collect();
        let mut unique = ids.clone();
        unique.sort_unstable();
        unique.dedup();
        assert_eq!(ids.len(), unique.len(), "{ids:?}");
        assert_eq!(xml.matches("_avail\"").count(), 2, "both models' observations: {xml}");
    }

    /// An alarm raised and reset between two rounds is in neither round's alarm list: its
    /// Fault and the Normal of the reset come from the controller's alarm changes.
    #[test]
    fn an_alarm_raised_and_reset_between_two_rounds_is_observed() {
        let machine = Arc::new(Machine::new(MachineConfig::preset("mill3").unwrap()));
        let mut b = Buffer::new(1000);
        let mut log = AlarmLog::default();
        let with_log = |log: &AlarmLog| {
            let mut e = (*entry(&machine, 0.0, &[])).clone();
            e.observed.alarm_log = log.clone();
            Arc::new(e)
        };
        b.observe(&round(1, vec![with_log(&log)]));
        let from = b.next_sequence();
        let alarm = entry(&machine, 0.0, &["MC3001"]).observed.alarms[0].clone();
        log.push(AlarmChange::Raised(alarm));
        log.push(AlarmChange::Cleared);
        b.observe(&round(2, vec![with_log(&log)]));
        let said: Vec<Said> = b.range(from, 100).iter().map(|o| o.said.clone()).collect();
        assert!(matches!(&said[..], [Said::Fault(a), Said::Normal(None)] if a.code == "MC3001"), "{said:?}");
        assert_eq!(condition(&b), vec![Said::Normal(None)]);
        b.observe(&round(3, vec![with_log(&log)]));
        assert_eq!(b.next_sequence(), from + 2, "read once");
    }

    /// Two controllers of one name were two devices of that name: `/{name}/current` answered
    /// for the first only. The later one is named with the head of its id, and takes the
    /// plain name when the first is gone.
    #[test]
    fn devices_of_controllers_with_one_name_are_named_apart() {
        let machine = Arc::new(Machine::new(MachineConfig::preset("mill3").unwrap()));
        let with_id = |id: &str| {
            let mut e = (*entry(&machine, 0.0, &[])).clone();
            e.id = id.into();
            Arc::new(e)
        };
        let (first, second) = (with_id("0123456789abcdef"), with_id("fedcba9876543210"));
        let mut b = Buffer::new(1000);
        b.observe(&round(1, vec![first.clone(), second.clone()]));
        let names: Vec<&str> = b.devices.iter().map(|d| d.model.name.as_str()).collect();
        assert_eq!(names, ["one", "one-fedcba98"]);
        assert!(b.devices[1].model.is("one-fedcba98") && !b.devices[1].model.is("one"));
        b.observe(&round(2, vec![second]));
        assert_eq!(b.devices[0].model.name, "one");
    }

    #[test]
    fn a_full_buffer_drops_the_oldest_and_ranges_stay_contiguous_across_its_seam() {
        let machine = Arc::new(Machine::new(MachineConfig::preset("mill3").unwrap()));
        let mut b = Buffer::new(10);
        for k in 0..40 {
            b.observe(&round(k, vec![entry(&machine, k as f64, &[])]));
        }
        assert_eq!(b.next_sequence() - b.first_sequence(), 10);
        let mut at = b.first_sequence();
        let mut seen = Vec::new();
        while at < b.next_sequence() {
            let slice = b.range(at, 4);
            assert!(!slice.is_empty());
            seen.extend(slice.iter().map(|o| o.sequence));
            at = slice.last().unwrap().sequence + 1;
        }
        assert_eq!(seen, (b.first_sequence()..b.next_sequence()).collect::<Vec<_>>());
    }
}
