//! The fleet stream's shared view: one [`FleetEntry`] per hosted controller, each encoded once
//! when it changes, with a version per change, so that every subscriber of `GET /stream` is
//! answered from the same encoded entries — a first snapshot, then only what changed since the
//! version it has (`fleet_delta`). Reading the controllers happens at most [`REFRESH`] apart,
//! however many subscribers ask.

use std::collections::{HashMap, VecDeque};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use super::stream::FleetEntry;
use crate::host::{Host, Hosted};

/// The shortest time between two readings of every controller (the fleet stream's fastest rate).
const REFRESH: Duration = Duration::from_millis(33);

/// Removals remembered for subscribers that have not seen them yet; one further behind gets a
/// snapshot instead.
const REMOVALS_KEPT: usize = 4096;

/// Cheap to clone: a handle on the view every fleet subscriber shares.
#[derive(Clone, Debug, Default)]
pub struct FleetView {
    view: Arc<Mutex<View>>,
    /// When the controllers were last read; held while reading, so one subscriber reads and the
    /// others wait for what it read (rather than answering from an older view).
    reading: Arc<tokio::sync::Mutex<Option<Instant>>>,
}

#[derive(Debug, Default)]
struct View {
    /// Bumped by every reading that changed something.
    version: u64,
    /// In creation order.
    entries: Vec<Entry>,
    /// (version, id) of each removal, oldest first.
    removed: VecDeque<(u64, String)>,
    /// Removals up to this version were forgotten.
    forgotten: u64,
}

#[derive(Debug)]
struct Entry {
    entry: FleetEntry,
    /// The entry as JSON, made once per change.
    text: Arc<str>,
    /// The view's version when it last changed.
    version: u64,
}

impl FleetEntry {
    /// The fleet's line of one controller (its status, cut down).
    pub fn of(hosted: &Hosted) -> FleetEntry {
        let station = hosted.station();
        let c = &station.controller;
        let (line_program, line) = station.layouts.locate(c.point().line);
        FleetEntry {
            id: hosted.id.clone(),
            name: hosted.name(),
            machine: station.machine.name.clone(),
            kind: super::kind_name(station.machine.kinematics().map(|k| k.kind)),
            dialect: hosted.dialect.name().to_string(),
            mode: super::word(&c.mode()),
            run_state: super::word(&crate::host::station::run_state(c)),
            program: station.program,
            // Lines and alarms in the program they are in, as the status and the controller's
            // stream give them (`docs/api.md`, "Lines of stored programs"), not the service's
            // own numbering of the composed text.
            line,
            line_program,
            alarm: c.alarms().first().map(|a| station.layouts.alarm(a)),
        }
    }
}

/// What a subscriber is sent next.
pub enum Update {
    /// Nothing changed since its version.
    None,
    /// `{"type": "fleet", "controllers": […]}`: the whole fleet.
    Snapshot(String),
    /// `{"type": "fleet_delta", "controllers": [changed or added], "removed": [ids]}`.
    Delta(String),
}

impl FleetView {
    /// Read every controller of `host` if the last reading is older than [`REFRESH`] (after
    /// waiting for a reading under way); changed entries are encoded and get a new version.
    pub async fn refresh(&self, host: &Host) {
        let mut last = self.reading.lock().await;
        if last.is_some_and(|at| at.elapsed() < REFRESH) {
            return;
        }
        // Read the controllers without holding the view: subscribers keep being answered.
        let now: Vec<FleetEntry> = host.list().iter().map(|h| FleetEntry::of(h)).collect();
        *last = Some(Instant::now());
        let mut view = self.view.lock().unwrap_or_else(|e| e.into_inner());
        view.merge(now);
    }

    /// What a subscriber that has seen `seen` (None: nothing yet) is sent, and the version it
    /// has after that. `deltas`: false for a subscriber that asked for whole fleets only.
    pub fn since(&self, seen: Option<u64>, deltas: bool) -> (Update, u64) {
        let view = self.view.lock().unwrap_or_else(|e| e.into_inner());
        let update = match seen {
            Some(v) if v == view.version => Update::None,
            Some(v) if deltas && v >= view.forgotten => Update::Delta(view.delta(v)),
            _ => Update::Snapshot(view.snapshot()),
        };
        (update, view.version)
    }
}

impl View {
    fn merge(&mut self, now: Vec<FleetEntry>) {
        let next = self.version + 1;
        let mut changed = false;
        let mut old: HashMap<String, Entry> = self.entries.drain(..).map(|e| (e.entry.id.clone(), e)).collect();
        let mut entries = Vec::with_capacity(now.len());
        for entry in now {
            match old.remove(&entry.id) {
                Some(kept) if kept.entry == entry => entries.push(kept),
                _ => {
                    changed = true;
                    let text = Arc::from(serde_json::to_string(&entry).unwrap_or_default());
                    entries.push(Entry { entry, text, version: next });
                }
            }
        }
        for id in old.into_keys() {
            changed = true;
            self.removed.push_back((next, id));
        }
        while self.removed.len() > REMOVALS_KEPT {
            if let Some((version, _)) = self.removed.pop_front() {
                self.forgotten = version;
            }
        }
        self.entries = entries;
        if changed {
            self.version = next;
        }
    }

    fn snapshot(&self) -> String {
        let mut out = String::from(r#"{"type":"fleet","controllers":["#);
        join(&mut out, self.entries.iter().map(|e| &*e.text));
        out.push_str("]}");
        out
    }

    /// The entries changed after version `seen` and the ids removed after it.
    fn delta(&self, seen: u64) -> String {
        let mut out = String::from(r#"{"type":"fleet_delta","controllers":["#);
        join(&mut out, self.entries.iter().filter(|e| e.version > seen).map(|e| &*e.text));
        out.push_str(r#"],"removed":["#);
        let ids: Vec<String> = self
            .removed
            .iter()
            .filter(|(v, _)| *v > seen)
            .map(|(_, id)| serde_json::to_string(id).unwrap_or_default())
            .collect();
        join(&mut out, ids.iter().map(String::as_str));
        out.push_str("]}");
        out
    }
}

fn join<'a>(out: &mut String, parts: impl Iterator<Item = &'a str>) {
    for (k, part) in parts.enumerate() {
        if k > 0 {
            out.push(',');
        }
        out.push_str(part);
    }
}
