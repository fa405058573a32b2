//! Fleet runs (`docs/fleet.md`): one program on many machines, queued for one of
//! `--fleet-jobs` places, then on a blocking thread so the service keeps answering; stored in
//! the database from queued to over; their progress in a `watch` per run; stopped by a cancel
//! or the service's end. With `--nats` a run is sent to the cluster's work queue instead and its
//! results collected (`crate::cluster`), each recorded as it comes; on a cluster with a shared
//! database a run whose collector is gone is taken over by another node (`super::fleet_rescue`).

use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use serde::Serialize;
use tokio::sync::{watch, Semaphore};
use utoipa::ToSchema;

use super::ServiceError;
use crate::cluster::{self, Heard, Job, Outcome, Source};
use crate::db::{self, FleetRunRow};
use crate::fleet::{self, Entry, Event, Options};
use crate::fleet_lease::Leases;
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
    /// Held while this node claims runs of other nodes (`super::fleet_rescue`, a cancel of a
    /// run collected elsewhere), so it never takes one run over twice.
    claims: Arc<tokio::sync::Mutex<()>>,
}

/// The cluster a node with `--nats` sends its runs to and takes jobs from.
#[derive(Clone, Debug)]
pub struct Remote {
    pub nats: cluster::Nats,
    /// This node's share of the work (stopped with the service).
    pub node: cluster::Node,
    /// A run gives up when no node nor result was heard from for this long.
    pub idle: Duration,
    /// On a cluster with a shared database (`crate::placement`): who collects each run, so a
    /// run outlives its node (`super::fleet_rescue`). `None` (a SQLite node): a run lives and
    /// dies with the node it was submitted to.
    pub leases: Option<Leases>,
}

/// Why a run over NATS stops here without ending: this node stops cleanly and hands it over to
/// the cluster (its collector key deleted).
pub const HANDED_OVER: &str = "handed over";
/// Why a run over NATS stops here without ending: another node claimed it (this node was cut
/// off from NATS long enough to leave the cluster).
pub const TAKEN: &str = "taken over by another node";

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

/// A run added by [`Runs::adopt`]: where its progress and stop reason go.
pub(super) struct Adopted {
    pub(super) tx: watch::Sender<Progress>,
    pub(super) stopped: Arc<watch::Sender<Option<&'static str>>>,
    pub(super) cancel: Arc<AtomicBool>,
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
            claims: Default::default(),
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

    /// Whether run `id` is queued or under way here.
    pub(super) fn has(&self, id: &str) -> bool {
        self.lock().0.contains_key(id)
    }

    /// The runs queued or under way here.
    pub(super) fn ids(&self) -> Vec<String> {
        self.lock().0.keys().cloned().collect()
    }

    /// Whether the service stops (no run is added).
    pub(super) fn stopping(&self) -> bool {
        self.lock().1
    }

    /// The cluster runs go to, with `--nats`.
    pub(super) fn remote(&self) -> Option<&Remote> {
        self.remote.as_ref()
    }

    /// Held while claiming runs of other nodes.
    pub(super) fn claims(&self) -> &tokio::sync::Mutex<()> {
        &self.claims
    }

    /// Adds run `id`, taken over from another node, with its progress: its progress sender
    /// and stop reason, the engine's cancel flag; `None` once the service stops.
    pub(super) fn adopt(&self, id: &str, progress: Progress) -> Option<Adopted> {
        let (tx, rx) = watch::channel(progress);
        let cancel = Arc::new(AtomicBool::new(false));
        let stopped = Arc::new(watch::channel(None).0);
        let run = Run { progress: rx, cancel: cancel.clone(), stopped: stopped.clone() };
        self.put(id, run).then_some(Adopted { tx, stopped, cancel })
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
    pub(super) fn stop(&self, id: &str, why: &'static str) -> Option<watch::Receiver<Progress>> {
        let run = self.get(id)?;
        run.stopped.send_if_modified(|s| s.is_none() && s.replace(why).is_none());
        run.cancel.store(true, Ordering::Relaxed);
        Some(run.progress)
    }

    /// Stop every run, recorded as `interrupted`, and take no new one (the service shuts down).
    /// On a cluster with a shared database the runs over NATS are handed over instead: they go
    /// on, collected by another node (or by this one once it is back).
    pub fn interrupt_all(&self) {
        let ids: Vec<String> = {
            let mut runs = self.lock();
            runs.1 = true;
            runs.0.keys().cloned().collect()
        };
        let mut why = "interrupted";
        if let Some(remote) = &self.remote {
            remote.node.stop();
            if remote.leases.is_some() {
                why = HANDED_OVER;
            }
        }
        for id in ids {
            self.stop(&id, why);
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
    if let Some(w) = &options.workpiece {
        w.check().map_err(|e| ServiceError::invalid(format!("workpiece: {e}")))?;
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
    let names: Vec<String> = entries.iter().map(|e| e.name.clone()).collect();
    let progress = progress_of(&id, "queued", &names, &vec![None; names.len()]);
    let (tx, rx) = watch::channel(progress);
    let cancel = Arc::new(AtomicBool::new(false));
    let stopped = Arc::new(watch::channel(None).0);
    if !runs.put(&id, Run { progress: rx, cancel: cancel.clone(), stopped: stopped.clone() }) {
        return Err(ServiceError::Unavailable("the service is stopping: no new fleet runs".into()));
    }
    // Collected here: recorded before the run is stored, so a stored run under way without a
    // collector has none (`crate::fleet_lease`).
    let leases = runs.remote.as_ref().and_then(|r| r.leases.clone());
    if let Some(leases) = &leases {
        if let Err(e) = leases.take_new(&id).await {
            runs.remove(&id);
            return Err(ServiceError::Unavailable(e));
        }
    }
    if let Err(e) = db::insert_fleet_run(db, &row).await {
        runs.remove(&id);
        if let Some(leases) = &leases {
            leases.end(&id).await;
        }
        return Err(e.into());
    }
    let opts = Options { cancel: Some(cancel), ..options };
    let run = Execution { db: db.clone(), runs: runs.clone(), id, program, entries, sources, opts, tx, stopped };
    let end = tokio::spawn(execute(run));
    Ok(Started { row, end })
}

/// A fleet run started: what it runs and where its progress and outcome go.
pub(super) struct Execution {
    pub(super) db: db::Db,
    pub(super) runs: Runs,
    pub(super) id: String,
    pub(super) program: String,
    pub(super) entries: Vec<Entry>,
    pub(super) sources: Vec<Source>,
    pub(super) opts: Options,
    pub(super) tx: watch::Sender<Progress>,
    pub(super) stopped: Arc<watch::Sender<Option<&'static str>>>,
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
        let events = Arc::new(tx.clone());
        results = tokio::task::spawn_blocking(move || {
            let results = fleet::run_fleet(&program, &entries, &opts, &|e| on_event(&events, e));
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
    match db::finish_fleet_run(db, id, status, &now_rfc3339(), completed, alarms, &json).await {
        Ok(true) => {}
        Ok(false) => tracing::warn!(%id, status, "fleet run was over already (ended by another node): kept as it was"),
        Err(e) => tracing::error!(%id, error = %e, "fleet run not stored"),
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
/// from the results stream ([`collect_remote`]); no place (`--fleet-jobs`) is taken: the nodes'
/// jobs are the limit.
async fn execute_remote(run: Execution, remote: Remote) -> Ended {
    let total = run.entries.len();
    let stopped_first = *run.stopped.borrow();
    match stopped_first {
        // Handed over before any job went out: the node taking it publishes them all.
        Some(HANDED_OVER) => {}
        Some(why) => return finish(&run.db, &run.runs, &run.id, &run.tx, why, vec![None; total], None).await,
        None => {
            if let Err(e) = db::start_fleet_run(&run.db, &run.id).await {
                tracing::error!(id = %run.id, error = %e, "fleet run start not stored");
            }
            run.tx.send_modify(|p| p.status = "running");
        }
    }
    let jobs = match stopped_first {
        Some(_) => Vec::new(),
        None => Job::all(&run.id, &run.program, &run.entries, run.sources.clone(), &run.opts),
    };
    collect_remote(run, remote, jobs, vec![None; total]).await
}

/// Publishes `jobs` of run `run` and collects the results the run does not have in `results`
/// (those computed before come first: `cluster::Collection`), recording each in the database as
/// it comes (any node reads the progress; a node taking the run over records only what is
/// missing), until the run is over: then stores it, withdraws its jobs if it did not complete,
/// and purges its results and its collector key. A run handed over or taken by another node
/// stops here without ending.
pub(super) async fn collect_remote(
    run: Execution,
    remote: Remote,
    jobs: Vec<Job>,
    mut results: Vec<Option<Value>>,
) -> Ended {
    let Execution { db, runs, id, entries, tx, stopped, .. } = run;
    let names: Vec<String> = entries.iter().map(|e| e.name.clone()).collect();
    let have = results.iter().map(Option::is_some).collect();
    let mut stop = stopped.subscribe();
    let outcome = match cluster::Collection::open(&remote.nats, &id, names.clone(), have, remote.idle).await {
        Err(e) => Outcome::Failed(e),
        Ok(mut collection) => {
            let outcome = match cluster::publish(&remote.nats, &jobs).await {
                Err(e) => Outcome::Failed(e),
                Ok(()) => loop {
                    match collection.next(&mut stop).await {
                        Ok(Heard::Started(index)) => tx.send_modify(|p| {
                            if p.machines[index].state == "queued" {
                                p.machines[index].state = "running";
                            }
                        }),
                        Ok(Heard::Result(index, result)) => {
                            record(&db, &id, index, &result).await;
                            on_event(&tx, cluster::finished(index, names[index].clone(), &result));
                            results[index] = Some(result);
                        }
                        Err(outcome) => break outcome,
                    }
                },
            };
            collection.close(&remote.nats).await;
            outcome
        }
    };
    let (status, error) = match outcome {
        Outcome::Stopped(why @ (HANDED_OVER | TAKEN)) => {
            runs.remove(&id);
            if why == HANDED_OVER {
                if let Some(leases) = &remote.leases {
                    leases.release(&id).await;
                }
            }
            tracing::info!(%id, why, "fleet run no longer collected here: it goes on in the cluster");
            let error =
                format!("this node stops: the run goes on on another node of the cluster (GET /fleet/runs/{id})");
            return Ended {
                status: "running",
                results,
                error: Some(if why == TAKEN { why.to_string() } else { error }),
            };
        }
        Outcome::Done => ("done", None),
        Outcome::Stopped(why) => (why, None),
        Outcome::Failed(e) => ("interrupted", Some(e)),
    };
    if status != "done" {
        cluster::withdraw(&remote.nats, &id).await;
    }
    let ended = finish(&db, &runs, &id, &tx, status, results, error).await;
    cluster::clean(&remote.nats, &id).await;
    if let Some(leases) = &remote.leases {
        leases.end(&id).await;
    }
    ended
}

/// The progress of run `id` with `status`, whose machines are `names` and results so far
/// `results` (a machine without one is `queued`).
pub(super) fn progress_of(id: &str, status: &'static str, names: &[String], results: &[Option<Value>]) -> Progress {
    Progress {
        kind: "progress",
        id: id.to_string(),
        status,
        total: names.len(),
        done: results.iter().flatten().count(),
        finished: false,
        machines: names
            .iter()
            .zip(results)
            .map(|(name, result)| MachineProgress {
                machine: name.clone(),
                state: match result {
                    None => "queued",
                    Some(r) if r["status"] == "completed" => "completed",
                    Some(_) => "alarm",
                },
                cycle_time_s: result.as_ref().and_then(|r| r["cycle_time_s"].as_f64()),
            })
            .collect(),
    }
}

/// A run's progress on event `e`.
pub(super) fn on_event(tx: &watch::Sender<Progress>, e: Event) {
    tx.send_modify(|p| match e {
        Event::Started { index, .. } => p.machines[index].state = "running",
        Event::Finished { index, status, cycle_time_s, .. } => {
            p.machines[index].state = status;
            p.machines[index].cycle_time_s = Some(cycle_time_s);
            p.done += 1;
        }
        Event::Cancelled { index, .. } => p.machines[index].state = "cancelled",
    })
}

/// Records machine `index`'s result of run `id` (a failure is logged: the run's end stores
/// every result again).
async fn record(db: &db::Db, id: &str, index: usize, result: &Value) {
    let completed = result["status"] == "completed";
    if let Err(e) = db::record_fleet_result(db, id, index, &result.to_string(), completed).await {
        tracing::warn!(%id, index, error = %e, "fleet result not recorded yet");
    }
}

/// The results recorded so far of run `id` under way, in machine order (`None` for a machine
/// without one), for `total` machines.
pub async fn recorded(db: &db::Db, id: &str, total: usize) -> Result<Vec<Option<Value>>, sqlx::Error> {
    let mut results = vec![None; total];
    for (index, json) in db::fleet_run_results(db, id).await? {
        if let (Some(slot), Ok(value)) = (results.get_mut(index), serde_json::from_str(&json)) {
            *slot = Some(value);
        }
    }
    Ok(results)
}

/// The runs a stopped process left queued or under way become `interrupted`, with the results
/// they had recorded (a single node at start: no other process collects them).
pub async fn interrupt_unfinished(db: &db::Db) -> Result<(), sqlx::Error> {
    for id in db::unfinished_fleet_runs(db).await? {
        let Some(row) = db::fleet_run(db, &id).await? else { continue };
        let results = recorded(db, &id, row.machines as usize).await?;
        let completed = results.iter().flatten().filter(|r| r["status"] == "completed").count() as u32;
        let alarms = results.iter().flatten().count() as u32 - completed;
        let json = serde_json::to_string(&results).unwrap_or_else(|_| "[]".into());
        db::finish_fleet_run(db, &id, "interrupted", &now_rfc3339(), completed, alarms, &json).await?;
        tracing::warn!(%id, completed, alarms, "fleet run left under way by the last process: interrupted");
    }
    Ok(())
}

/// Ends run `id`, under way and not collected here, with `status`: its jobs withdrawn, the
/// results recorded kept (`null` for the others), its results and collector key purged. The
/// caller holds its collector key.
pub(super) async fn end_elsewhere(
    db: &db::Db,
    remote: &Remote,
    row: &FleetRunRow,
    status: &'static str,
    error: Option<String>,
) {
    let id = &row.id;
    cluster::withdraw(&remote.nats, id).await;
    let results = recorded(db, id, row.machines as usize).await.unwrap_or_else(|_| vec![None; row.machines as usize]);
    let completed = results.iter().flatten().filter(|r| r["status"] == "completed").count() as u32;
    let alarms = results.iter().flatten().count() as u32 - completed;
    let json = serde_json::to_string(&results).unwrap_or_else(|_| "[]".into());
    match db::finish_fleet_run(db, id, status, &now_rfc3339(), completed, alarms, &json).await {
        Ok(true) => tracing::info!(%id, status, error = error.as_deref().unwrap_or(""), "fleet run over"),
        Ok(false) => tracing::info!(%id, "fleet run was over already"),
        Err(e) => tracing::error!(%id, error = %e, "fleet run not stored"),
    }
    cluster::clean(&remote.nats, id).await;
    if let Some(leases) = &remote.leases {
        leases.end(id).await;
    }
}

/// Stops a queued or running run and waits (10 s at most) until it is stored as over: the run as
/// stored then (`cancelled`, or `done` if it ended first); a run already over is a conflict. A
/// run of a cluster collected by another node (or by none: its node died) is claimed and ended
/// here; its former collector stops at its next beat.
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
    if stopping.is_some() {
        return Ok(row);
    }
    let under_way = matches!(row.status.as_str(), "queued" | "running");
    match runs.remote.as_ref().filter(|r| r.leases.is_some()) {
        Some(remote) if under_way => cancel_elsewhere(db, runs, remote, row).await,
        _ => Err(ServiceError::Conflict(format!("fleet run {id} is already over ({})", row.status))),
    }
}

/// [`cancel`] of a run not collected here: its collector key taken (revision-checked), then
/// the run ended `cancelled` with the results recorded.
async fn cancel_elsewhere(
    db: &db::Db,
    runs: &Runs,
    remote: &Remote,
    row: FleetRunRow,
) -> Result<FleetRunRow, ServiceError> {
    let Some(leases) = &remote.leases else { return Err(ServiceError::Conflict("not a cluster".into())) };
    let id = row.id.clone();
    let _claiming = runs.claims().lock().await;
    for _ in 0..3 {
        let holder = leases.holder(&id).await.map_err(ServiceError::Unavailable)?;
        if leases.claim(&id, holder.revision).await {
            tracing::info!(%id, from = ?holder.node, "fleet run collected elsewhere: cancelled here");
            end_elsewhere(db, remote, &row, "cancelled", None).await;
            return get(db, &id).await;
        }
    }
    Err(ServiceError::Unavailable(format!("fleet run {id}: its collector changed while it was being cancelled; retry")))
}

/// The stored runs, newest first, at most `limit` (0–10000).
pub async fn list(db: &db::Db, limit: u32) -> Result<Vec<FleetRunRow>, ServiceError> {
    Ok(db::fleet_runs(db, limit.min(10_000)).await?)
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
