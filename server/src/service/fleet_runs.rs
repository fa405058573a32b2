//! Fleet runs (`docs/fleet.md`): one program on many machines, queued for one of
//! `--fleet-jobs` places, then on a blocking thread so the service keeps answering; stored in
//! the database from queued to over; their progress in a `watch` per run; stopped by a cancel
//! or the service's end.

use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use serde::Serialize;
use tokio::sync::{watch, Semaphore};
use utoipa::ToSchema;

use super::ServiceError;
use crate::cluster::{self, Source};
use crate::db::{self, FleetRunRow};
use crate::fleet::{self, Entry, Event, Options};
use crate::host::now_rfc3339;
use serde_json::Value;

/// The most machines one fleet run may have.
pub const MAX_MACHINES: usize = 200;

/// The fleet runs queued or under way, by id (a run leaves when it is stored as over), and the
/// places to run in (`--fleet-jobs`).
#[derive(Clone, Debug)]
pub struct Runs {
    /// The runs, and whether the service stops (then no run is added: every one added before
    /// was interrupted).
    runs: Arc<Mutex<(HashMap<String, Run>, bool)>>,
    slots: Arc<Semaphore>,
    /// `--fleet-jobs`: the places.
    jobs: usize,
    /// The runs over since the service started, by [`FINISHED`] status.
    finished: Arc<[AtomicU64; 3]>,
    /// `--nats`: runs go to the cluster's work queue (`crate::cluster`), not to the places.
    remote: Option<Remote>,
}

/// The cluster a node with `--nats` sends its runs to and takes jobs from.
#[derive(Clone, Debug)]
pub struct Remote {
    pub nats: cluster::Nats,
    /// This node's share of the work (stopped with the service).
    pub node: cluster::Node,
    /// A run gives up when no node nor result was heard from for this long.
    pub idle: Duration,
}

/// How a run ends: the statuses of a run that is over.
pub const FINISHED: [&str; 3] = ["done", "cancelled", "interrupted"];

/// The fleet runs now, for `/metrics`.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Census {
    /// Runs waiting for a place.
    pub queued: usize,
    /// Runs under way (as their progress says).
    pub running: usize,
    /// `--fleet-jobs`.
    pub jobs: usize,
    /// Places taken now (a run holds one from the moment it leaves the queue until its
    /// machines are over).
    pub jobs_running: usize,
    /// Runs over since the service started, by status ([`FINISHED`]'s order).
    pub finished: [u64; 3],
}

/// One run queued or under way: its progress and how to stop it.
#[derive(Clone, Debug)]
struct Run {
    progress: watch::Receiver<Progress>,
    /// Read by the engine before every block (`fleet::Options::cancel`).
    cancel: Arc<AtomicBool>,
    /// Why it was stopped (`cancelled`, `interrupted`), for the task that waits in the queue.
    stopped: Arc<watch::Sender<Option<&'static str>>>,
}

impl Default for Runs {
    fn default() -> Self {
        Runs::new(1)
    }
}

impl Runs {
    /// At most `jobs` runs at once (at least 1).
    pub fn new(jobs: usize) -> Self {
        let jobs = jobs.max(1);
        Runs {
            runs: Default::default(),
            slots: Arc::new(Semaphore::new(jobs)),
            jobs,
            finished: Default::default(),
            remote: None,
        }
    }

    /// Runs sent to a cluster (`--nats`): each machine a job on the work queue.
    pub fn with_remote(mut self, remote: Remote) -> Self {
        self.remote = Some(remote);
        self
    }

    /// How many runs are queued and running, the places, and the runs over by status.
    pub fn census(&self) -> Census {
        let (mut queued, mut running) = (0, 0);
        for run in self.lock().0.values() {
            match run.progress.borrow().status {
                "queued" => queued += 1,
                _ => running += 1,
            }
        }
        Census {
            queued,
            running,
            jobs: self.jobs,
            jobs_running: self.jobs.saturating_sub(self.slots.available_permits()),
            finished: std::array::from_fn(|i| self.finished[i].load(Ordering::Relaxed)),
        }
    }

    /// A run ended with `status` (one of [`FINISHED`]).
    fn finished(&self, status: &str) {
        if let Some(i) = FINISHED.iter().position(|s| *s == status) {
            self.finished[i].fetch_add(1, Ordering::Relaxed);
        }
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, (HashMap<String, Run>, bool)> {
        self.runs.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn get(&self, id: &str) -> Option<Run> {
        self.lock().0.get(id).cloned()
    }

    /// Adds a run; `false` once the service stops.
    fn put(&self, id: &str, run: Run) -> bool {
        let mut runs = self.lock();
        if runs.1 {
            return false;
        }
        runs.0.insert(id.to_string(), run);
        true
    }

    fn remove(&self, id: &str) {
        self.lock().0.remove(id);
    }

    /// Stop a run (the first reason given is kept); `None` if it is not queued or running.
    fn stop(&self, id: &str, why: &'static str) -> Option<watch::Receiver<Progress>> {
        let run = self.get(id)?;
        run.stopped.send_if_modified(|s| s.is_none() && s.replace(why).is_none());
        run.cancel.store(true, Ordering::Relaxed);
        Some(run.progress)
    }

    /// Stop every run, recorded as `interrupted`, and take no new one (the service shuts down).
    pub fn interrupt_all(&self) {
        let ids: Vec<String> = {
            let mut runs = self.lock();
            runs.1 = true;
            runs.0.keys().cloned().collect()
        };
        if let Some(remote) = &self.remote {
            remote.node.stop();
        }
        for id in ids {
            self.stop(&id, "interrupted");
        }
    }

    /// Resolves when no run is queued or under way (each has been stored as over).
    pub async fn all_ended(&self) {
        while !self.lock().0.is_empty() {
            tokio::time::sleep(Duration::from_millis(20)).await;
        }
    }
}

/// One machine's state in a progress message.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct MachineProgress {
    pub machine: String,
    /// `queued`, `running`, `completed`, `alarm` or `cancelled` (the run was stopped before
    /// it finished).
    #[schema(value_type = crate::wire::words::MachineState)]
    pub state: &'static str,
    /// Simulated seconds, once done.
    pub cycle_time_s: Option<f64>,
}

/// `{"type": "progress", …}`: where a fleet run is.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct Progress {
    /// Always `"progress"`.
    #[serde(rename = "type")]
    #[schema(value_type = crate::wire::words::ProgressType, inline)]
    pub kind: &'static str,
    pub id: String,
    /// The run's status: `queued`, `running`, `done`, `cancelled` or `interrupted`.
    #[schema(value_type = crate::wire::words::FleetRunStatus)]
    pub status: &'static str,
    pub total: usize,
    /// Machines done.
    pub done: usize,
    /// The run is over (the last message before the socket closes).
    pub finished: bool,
    pub machines: Vec<MachineProgress>,
}

/// A run to start: the program, its machines in order, how to run them, and the request as
/// stored.
pub struct Plan {
    pub program: String,
    pub entries: Vec<Entry>,
    /// Where each entry comes from, for a run over NATS (`crate::cluster`); shorter than
    /// `entries` when a machine cannot be sent (an existing controller's).
    pub sources: Vec<Source>,
    pub options: Options,
    pub request_json: String,
}

/// A run started: as stored (queued), and its end.
pub struct Started {
    pub row: FleetRunRow,
    pub end: tokio::task::JoinHandle<Ended>,
}

/// How a run ended.
#[derive(Debug, Clone)]
pub struct Ended {
    /// `done`, `cancelled` or `interrupted`.
    pub status: &'static str,
    /// The fleet array (`null` for each machine that did not finish).
    pub results: Vec<Option<Value>>,
    /// Why a run over NATS gave up (stored `interrupted`).
    pub error: Option<String>,
}

/// Queues a run of `plan` (at least one machine, at most [`MAX_MACHINES`]), stored as
/// `queued`; it runs once a place is free.
pub async fn start(db: &db::Db, runs: &Runs, plan: Plan) -> Result<Started, ServiceError> {
    let Plan { program, entries, sources, options, request_json } = plan;
    if entries.is_empty() {
        return Err(ServiceError::invalid("no machines: give presets, machines, library or controllers"));
    }
    if entries.len() > MAX_MACHINES {
        return Err(ServiceError::invalid(format!("{} machines: at most {MAX_MACHINES} in one run", entries.len())));
    }
    if let Some(tools) = &options.tools {
        fleet::check_tools(tools).map_err(ServiceError::invalid)?;
    }
    if runs.remote.is_some() && sources.len() != entries.len() {
        return Err(ServiceError::invalid(
            "existing controllers cannot run on a distributed fleet (this node runs with --nats): \
             give their machines as presets, machines or library",
        ));
    }
    let row = FleetRunRow {
        id: uuid::Uuid::new_v4().simple().to_string(),
        created_at: now_rfc3339(),
        finished_at: None,
        status: "queued".into(),
        machines: entries.len() as u32,
        completed: 0,
        alarms: 0,
        program: program.clone(),
        request_json,
        results_json: None,
    };
    let id = row.id.clone();
    let progress = Progress {
        kind: "progress",
        id: id.clone(),
        status: "queued",
        total: entries.len(),
        done: 0,
        finished: false,
        machines: entries
            .iter()
            .map(|e| MachineProgress { machine: e.name.clone(), state: "queued", cycle_time_s: None })
            .collect(),
    };
    let (tx, rx) = watch::channel(progress);
    let cancel = Arc::new(AtomicBool::new(false));
    let stopped = Arc::new(watch::channel(None).0);
    if !runs.put(&id, Run { progress: rx, cancel: cancel.clone(), stopped: stopped.clone() }) {
        return Err(ServiceError::Unavailable("the service is stopping: no new fleet runs".into()));
    }
    if let Err(e) = db::insert_fleet_run(db, &row).await {
        runs.remove(&id);
        return Err(e.into());
    }
    let opts = Options { cancel: Some(cancel), ..options };
    let run = Execution { db: db.clone(), runs: runs.clone(), id, program, entries, sources, opts, tx, stopped };
    let end = tokio::spawn(execute(run));
    Ok(Started { row, end })
}

/// A fleet run started: what it runs and where its progress and outcome go.
struct Execution {
    db: db::Db,
    runs: Runs,
    id: String,
    program: String,
    entries: Vec<Entry>,
    sources: Vec<Source>,
    opts: Options,
    tx: watch::Sender<Progress>,
    stopped: Arc<watch::Sender<Option<&'static str>>>,
}

/// A fleet run from the queue to its record: waits for a place (`--fleet-jobs`) unless it is
/// stopped first, runs on a blocking thread, stores the outcome and answers it (`done`,
/// `cancelled` or `interrupted`, and the fleet array with `null` for each machine that did not
/// finish).
async fn execute(run: Execution) -> Ended {
    if let Some(remote) = run.runs.remote.clone() {
        return execute_remote(run, remote).await;
    }
    let Execution { db, runs, id, program, entries, sources: _, opts, tx, stopped } = run;
    let total = entries.len();
    let mut why = stopped.subscribe();
    let slot = tokio::select! {
        slot = runs.slots.clone().acquire_owned() => slot.ok(),
        _ = why.wait_for(Option::is_some) => None,
    };
    let mut results: Vec<Option<Value>> = vec![None; total];
    if slot.is_some() && stopped.borrow().is_none() {
        if let Err(e) = db::start_fleet_run(&db, &id).await {
            tracing::error!(%id, error = %e, "fleet run start not stored");
        }
        tx.send_modify(|p| p.status = "running");
        let tx = Arc::new(tx.clone());
        let events = tx.clone();
        results = tokio::task::spawn_blocking(move || {
            let on_event = |e: Event| {
                events.send_modify(|p| match e {
                    Event::Started { index, .. } => p.machines[index].state = "running",
                    Event::Finished { index, status, cycle_time_s, .. } => {
                        p.machines[index].state = status;
                        p.machines[index].cycle_time_s = Some(cycle_time_s);
                        p.done += 1;
                    }
                    Event::Cancelled { index, .. } => p.machines[index].state = "cancelled",
                })
            };
            let results = fleet::run_fleet(&program, &entries, &opts, &on_event);
            // As the fleet array is written: the same JSON (`serde_json`'s numbers keep their bits).
            results.iter().map(|r| r.as_ref().and_then(|r| serde_json::to_value(r).ok())).collect()
        })
        .await
        .unwrap_or_else(|_| vec![None; total]);
    }
    drop(slot);
    // A stop that came after every machine finished changes nothing.
    let status = match *stopped.borrow() {
        Some(why) if results.iter().any(Option::is_none) => why,
        _ => "done",
    };
    finish(&db, &runs, &id, &tx, status, results, None).await
}

/// Stores a run's outcome and tells its followers.
async fn finish(
    db: &db::Db,
    runs: &Runs,
    id: &str,
    tx: &watch::Sender<Progress>,
    status: &'static str,
    results: Vec<Option<Value>>,
    error: Option<String>,
) -> Ended {
    let total = results.len();
    let completed = results.iter().flatten().filter(|r| r["status"] == "completed").count() as u32;
    let alarms = results.iter().flatten().count() as u32 - completed;
    let json = serde_json::to_string(&results).unwrap_or_else(|_| "[]".into());
    if let Err(e) = db::finish_fleet_run(db, id, status, &now_rfc3339(), completed, alarms, &json).await {
        tracing::error!(%id, error = %e, "fleet run not stored");
    }
    tx.send_modify(|p| {
        p.status = status;
        p.finished = true;
        for m in p.machines.iter_mut().filter(|m| matches!(m.state, "queued" | "running")) {
            m.state = "cancelled";
        }
    });
    runs.remove(id);
    runs.finished(status);
    match &error {
        Some(error) => tracing::warn!(%id, machines = total, completed, alarms, status, %error, "fleet run over"),
        None => tracing::info!(%id, machines = total, completed, alarms, status, "fleet run over"),
    }
    Ended { status, results, error }
}

/// A run over NATS: one job per machine on the cluster's work queue, the results collected
/// from the run's subject (`crate::cluster::run`); no place (`--fleet-jobs`) is taken: the
/// nodes' jobs are the limit.
async fn execute_remote(run: Execution, remote: Remote) -> Ended {
    let Execution { db, runs, id, program, entries, sources, opts, tx, stopped } = run;
    let total = entries.len();
    if stopped.borrow().is_some() {
        let why = (*stopped.borrow()).unwrap_or("interrupted");
        return finish(&db, &runs, &id, &tx, why, vec![None; total], None).await;
    }
    if let Err(e) = db::start_fleet_run(&db, &id).await {
        tracing::error!(%id, error = %e, "fleet run start not stored");
    }
    tx.send_modify(|p| p.status = "running");
    let jobs = cluster::Job::all(&id, &program, &entries, sources, &opts);
    let names: Vec<String> = entries.iter().map(|e| e.name.clone()).collect();
    let on_event = |e: Event| {
        tx.send_modify(|p| match e {
            Event::Started { index, .. } => p.machines[index].state = "running",
            Event::Finished { index, status, cycle_time_s, .. } => {
                p.machines[index].state = status;
                p.machines[index].cycle_time_s = Some(cycle_time_s);
                p.done += 1;
            }
            Event::Cancelled { index, .. } => p.machines[index].state = "cancelled",
        })
    };
    let (outcome, results) =
        cluster::run(&remote.nats, jobs, &names, remote.idle, stopped.subscribe(), &on_event).await;
    let (status, error) = match outcome {
        cluster::Outcome::Done => ("done", None),
        cluster::Outcome::Stopped(why) => (why, None),
        cluster::Outcome::Failed(e) => ("interrupted", Some(e)),
    };
    finish(&db, &runs, &id, &tx, status, results, error).await
}

/// Stops a queued or running run and waits (10 s at most) until it is stored as over: the run as
/// stored then (`cancelled`, or `done` if it ended first); a run already over is a conflict.
pub async fn cancel(db: &db::Db, runs: &Runs, id: &str) -> Result<FleetRunRow, ServiceError> {
    let stopping = runs.stop(id, "cancelled");
    if let Some(mut progress) = stopping.clone() {
        // The engine stops within a block; storing the outcome takes a moment more.
        let over = progress.wait_for(|p| p.finished);
        if tokio::time::timeout(Duration::from_secs(10), over).await.is_err() {
            tracing::warn!(%id, "fleet run not stopped 10 s after its cancel");
        }
    }
    let row = get(db, id).await?;
    if stopping.is_none() {
        return Err(ServiceError::Conflict(format!("fleet run {id} is already over ({})", row.status)));
    }
    Ok(row)
}

/// The stored runs, newest first, at most `limit` (1–10000).
pub async fn list(db: &db::Db, limit: u32) -> Result<Vec<FleetRunRow>, ServiceError> {
    Ok(db::fleet_runs(db, limit.clamp(1, 10_000)).await?)
}

/// Run `id` as stored.
pub async fn get(db: &db::Db, id: &str) -> Result<FleetRunRow, ServiceError> {
    db::fleet_run(db, id).await?.ok_or_else(|| ServiceError::NotFound(format!("no fleet run {id}")))
}

/// Where a run is: its progress while queued or under way, else the run as stored.
pub async fn follow(
    db: &db::Db,
    runs: &Runs,
    id: &str,
) -> Result<Result<watch::Receiver<Progress>, FleetRunRow>, ServiceError> {
    match runs.get(id) {
        Some(run) => Ok(Ok(run.progress)),
        None => get(db, id).await.map(Err),
    }
}
