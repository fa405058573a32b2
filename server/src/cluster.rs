//! The distributed fleet over NATS JetStream (`docs/fleet.md`, "Over NATS"): a fleet run split
//! into one job per machine on a work queue, run by every `fivex serve --nats` node, the results
//! kept on a stream of their own until the run is over.
//!
//! - Stream [`STREAM`] on `fivex.fleet.jobs.>`, work-queue retention; a job is published on
//!   `fivex.fleet.jobs.{run}.{index}` as a JSON [`Job`].
//! - One durable pull consumer [`CONSUMER`] shared by the nodes, explicit acks, [`ACK_WAIT`]: a
//!   job is acked only after its result is stored, so a node that dies mid-job leaves it
//!   unacked and JetStream hands it to another node once the ack wait has passed. A node sends
//!   an in-progress ack every [`HEARTBEAT`] while it runs a job.
//! - Results ([`Reply`]) on the stream [`RESULTS_STREAM`], `fivex.fleet.results.{run}.{index}`
//!   (one message per subject): they outlive the node collecting them, so another node can
//!   take a run over and read them from the start ([`Collection`]: an ordered consumer of the
//!   run's results, which keeps the first of each machine). A job under way says so on the core
//!   subject `fivex.fleet.runs.{run}.running` when it starts and every [`HEARTBEAT`].
//! - Nodes say they are alive on [`NODES`] every [`HEARTBEAT`]: a collection gives up when it
//!   has heard neither a node nor a result for its idle time.
//! - Cancel: the collector purges the run's jobs from the stream (no waiting job runs) and
//!   publishes the run id on [`CANCEL`]: the nodes stop the run's jobs under way before their next
//!   block and skip any of its jobs they still get; the run's collector, wherever it is, stops.
//! - A run over has its results purged ([`clean`]).

use std::collections::{BTreeMap, HashMap, VecDeque};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use async_nats::jetstream::consumer::{pull, push, AckPolicy, DeliverPolicy};
use async_nats::jetstream::stream::LastRawMessageErrorKind;
use async_nats::jetstream::{self, kv, stream, AckKind};
use bytes::Bytes;
use fivex_engine::workpiece::Workpiece;
use fivex_engine::Dialect;
use futures_util::StreamExt;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use tokio::sync::watch;

use crate::fleet::{self, Entry, Event, Options, Tool};

/// The work-queue stream of fleet jobs.
pub const STREAM: &str = "FIVEX_FLEET";
/// The prefix of the job subjects (`fivex.fleet.jobs.{run}.{index}`).
pub const JOBS: &str = "fivex.fleet.jobs";
/// The durable pull consumer every node takes jobs from.
pub const CONSUMER: &str = "fivex-fleet-nodes";
/// How long JetStream waits for a job's ack before it hands the job to another node.
pub const ACK_WAIT: Duration = Duration::from_secs(10);
/// How often a node running a job tells JetStream (in-progress ack) and the submitter.
pub const HEARTBEAT: Duration = Duration::from_secs(2);
/// Core subject on which a run's id is published when it is cancelled.
pub const CANCEL: &str = "fivex.fleet.cancel";
/// Core subject on which every node says it is alive.
pub const NODES: &str = "fivex.fleet.nodes";
/// Default: give up a run when neither a result nor a node was heard for this long.
pub const IDLE_TIMEOUT: Duration = Duration::from_secs(30);
/// The stream of the results (`fivex.fleet.results.{run}.{index}`).
pub const RESULTS_STREAM: &str = "FIVEX_FLEET_RESULTS";
/// The prefix of the result subjects.
pub const RESULTS: &str = "fivex.fleet.results";
/// How long a result stays on [`RESULTS_STREAM`] at most: a run over purges its own at once;
/// this bounds what runs nobody ended leave (a `fivex fleet --nats` killed).
pub const RESULTS_MAX_AGE: Duration = Duration::from_secs(24 * 3600);

fn result_subject(run: &str, index: usize) -> String {
    format!("{RESULTS}.{run}.{index}")
}

fn job_subject(run: &str, index: usize) -> String {
    format!("{JOBS}.{run}.{index}")
}

fn running_subject(run: &str) -> String {
    format!("fivex.fleet.runs.{run}.running")
}

/// Where a job's machine comes from: the node builds it as the submitter did (`fleet::preset`,
/// `fleet::library`, `fleet::machine_file`), so it is the same machine bit for bit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", content = "value", rename_all = "lowercase")]
pub enum Source {
    Preset(String),
    Library(String),
    /// A machine document or file, as text.
    Document(String),
}

impl Source {
    /// The machines of a fleet request that can be sent, in the request's order (`POST
    /// /fleet/runs`, and a node taking a stored run over): presets, machine documents (as JSON
    /// text), library machines (`"*"`: the whole library, in name order).
    pub fn requested(presets: &[String], machines: &[Value], library: &[String]) -> Vec<Source> {
        let mut sources: Vec<Source> = presets.iter().cloned().map(Source::Preset).collect();
        sources.extend(machines.iter().map(|m| Source::Document(m.to_string())));
        for name in library {
            if name == "*" {
                sources.extend(fleet::LIBRARY.iter().map(|(n, _)| Source::Library(n.to_string())));
            } else {
                sources.push(Source::Library(name.clone()));
            }
        }
        sources
    }

    /// The machine, as `fivex fleet` and `POST /fleet/runs` build it.
    pub fn entry(&self, dialect: Dialect) -> Result<Entry, String> {
        match self {
            Source::Preset(name) => fleet::preset(name, dialect),
            Source::Library(name) => fleet::library(name, dialect),
            Source::Document(text) => fleet::machine_file(text, dialect),
        }
    }
}

/// One machine of a run: everything a node needs to run it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Job {
    pub run: String,
    /// The machine's place in the run.
    pub index: usize,
    pub program: String,
    pub machine: Source,
    /// Of presets, models and library models (a parameter list runs in its own).
    pub dialect: Dialect,
    pub tools: Option<BTreeMap<u32, Tool>>,
    /// What is clamped on the machine's table (the run's `workpiece`); absent: nothing, and
    /// then not written, so a job without one reads as before.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub workpiece: Option<Workpiece>,
    pub report: bool,
    pub report_period_s: f64,
    pub max_blocks: u64,
    pub max_time_s: f64,
}

impl Job {
    /// The jobs of run `run`: one per machine of `entries`, with its `sources` (how a node
    /// builds it) and the run's options.
    pub fn all(run: &str, program: &str, entries: &[Entry], sources: Vec<Source>, opts: &Options) -> Vec<Job> {
        entries
            .iter()
            .zip(sources)
            .enumerate()
            .map(|(index, (entry, machine))| Job {
                run: run.to_owned(),
                index,
                program: program.to_owned(),
                machine,
                dialect: entry.dialect,
                tools: opts.tools.clone(),
                workpiece: opts.workpiece.as_deref().cloned(),
                report: opts.report,
                report_period_s: opts.report_period_s,
                max_blocks: opts.max_blocks,
                max_time_s: opts.max_time_s,
            })
            .collect()
    }
}

/// What a node sends back on the run's subjects.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Reply {
    pub index: usize,
    /// The machine's result (the `fivex fleet` array's element) once done.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub result: Option<Value>,
    /// The job could not be run (a machine or tool table the node refuses).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
}

/// A connection to NATS with the fleet's streams made sure of.
#[derive(Clone, Debug)]
pub struct Nats {
    client: async_nats::Client,
    js: jetstream::Context,
    /// The jobs ([`STREAM`]).
    stream: jetstream::stream::Stream,
    /// The results ([`RESULTS_STREAM`]).
    results: jetstream::stream::Stream,
}

impl Nats {
    /// The core NATS connection.
    pub fn client(&self) -> &async_nats::Client {
        &self.client
    }

    /// The JetStream context over it.
    pub fn jetstream(&self) -> &jetstream::Context {
        &self.js
    }
}

/// Connects to `url` and makes sure the fleet's streams exist.
pub async fn connect(url: &str) -> Result<Nats, String> {
    let client = async_nats::connect(url).await.map_err(|e| format!("cannot connect to NATS at {url}: {e}"))?;
    let js = jetstream::new(client.clone());
    let config = stream::Config {
        name: STREAM.into(),
        subjects: vec![format!("{JOBS}.>")],
        retention: stream::RetentionPolicy::WorkQueue,
        storage: stream::StorageType::File,
        // A job nobody takes within a day is dropped.
        max_age: Duration::from_secs(24 * 3600),
        ..Default::default()
    };
    let stream = js.get_or_create_stream(config).await.map_err(|e| {
        format!("NATS at {url}: cannot create the stream {STREAM} (is JetStream on, `nats-server -js`?): {e}")
    })?;
    let config = stream::Config {
        name: RESULTS_STREAM.into(),
        subjects: vec![format!("{RESULTS}.>")],
        retention: stream::RetentionPolicy::Limits,
        storage: stream::StorageType::File,
        // One result per machine: a redelivered job's result replaces its first (the same, bit
        // for bit), so a run holds at most one message per machine.
        max_messages_per_subject: 1,
        discard: stream::DiscardPolicy::Old,
        max_age: RESULTS_MAX_AGE,
        ..Default::default()
    };
    let results = js
        .get_or_create_stream(config)
        .await
        .map_err(|e| format!("NATS at {url}: cannot create the stream {RESULTS_STREAM}: {e}"))?;
    Ok(Nats { client, js, stream, results })
}

/// The JetStream key-value bucket `name` (entries living `max_age`, zero: for ever), made sure
/// of: its stream made here as `create_key_value` would (that call reads the account first,
/// which fails on nats-server 2.9, Debian's): one value per key, deletes as markers.
pub async fn key_value(js: &jetstream::Context, name: &str, max_age: Duration) -> Result<kv::Store, String> {
    let config = stream::Config {
        name: format!("KV_{name}"),
        subjects: vec![format!("$KV.{name}.>")],
        max_messages_per_subject: 1,
        max_age,
        max_message_size: -1,
        max_bytes: -1,
        allow_rollup: true,
        deny_delete: true,
        allow_direct: true,
        num_replicas: 1,
        discard: stream::DiscardPolicy::New,
        ..Default::default()
    };
    js.get_or_create_stream(config).await.map_err(|e| format!("NATS: cannot create the bucket {name}: {e}"))?;
    js.get_key_value(name).await.map_err(|e| format!("NATS: cannot open the bucket {name}: {e}"))
}

/// How a distributed run ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    /// Every machine has its result.
    Done,
    /// Stopped by the caller with this reason (`cancelled`, `interrupted`), or `cancelled` from
    /// any node ([`CANCEL`]).
    Stopped(&'static str),
    /// Gave up: the message says why (no node heard from, NATS failing, a job refused).
    Failed(String),
}

/// What a [`Collection`] hears about a machine.
#[derive(Debug, Clone, PartialEq)]
pub enum Heard {
    /// Its job started on a node (said once).
    Started(usize),
    /// Its result (the first one).
    Result(usize, Value),
}

/// The progress event of machine `index` named `machine` whose result is `result`.
pub fn finished(index: usize, machine: String, result: &Value) -> Event {
    let status = match result["status"].as_str() {
        Some("completed") => "completed",
        _ => "alarm",
    };
    Event::Finished { index, machine, status, cycle_time_s: result["cycle_time_s"].as_f64().unwrap_or(0.0) }
}

/// Publishes `jobs` (one run's, in machine order) and collects their results, reporting as
/// `fleet::run_fleet` does; stops when `stop` holds a reason (then the run's waiting jobs are
/// purged and its running ones cancelled), or when nothing was heard from a node for `idle`.
/// The run's results are purged from the stream at the end. The results in machine order,
/// `None` for each machine without one.
pub async fn run(
    nats: &Nats,
    jobs: Vec<Job>,
    names: &[String],
    idle: Duration,
    mut stop: watch::Receiver<Option<&'static str>>,
    progress: &(dyn Fn(Event) + Sync),
) -> (Outcome, Vec<Option<Value>>) {
    let total = jobs.len();
    let mut results: Vec<Option<Value>> = vec![None; total];
    let Some(run) = jobs.first().map(|j| j.run.clone()) else { return (Outcome::Done, results) };
    let name = |i: usize| names.get(i).cloned().unwrap_or_default();
    let outcome = match Collection::open(nats, &run, names.to_vec(), vec![false; total], idle).await {
        Err(e) => Outcome::Failed(e),
        Ok(mut collection) => {
            let outcome = match publish(nats, &jobs).await {
                Err(e) => Outcome::Failed(e),
                Ok(()) => loop {
                    match collection.next(&mut stop).await {
                        Ok(Heard::Started(index)) => progress(Event::Started { index, machine: name(index) }),
                        Ok(Heard::Result(index, result)) => {
                            progress(finished(index, name(index), &result));
                            results[index] = Some(result);
                        }
                        Err(outcome) => break outcome,
                    }
                },
            };
            collection.close(nats).await;
            outcome
        }
    };
    if outcome != Outcome::Done {
        withdraw(nats, &run).await;
    }
    clean(nats, &run).await;
    (outcome, results)
}

/// Publishes `jobs` (one run's) on the work queue, each stored before the next goes.
pub async fn publish(nats: &Nats, jobs: &[Job]) -> Result<(), String> {
    for job in jobs {
        let payload = serde_json::to_vec(job).map_err(|e| format!("NATS: cannot write a job: {e}"))?;
        let ack = nats
            .js
            .publish(job_subject(&job.run, job.index), Bytes::from(payload))
            .await
            .map_err(|e| format!("NATS: cannot publish a job: {e}"))?;
        ack.await.map_err(|e| format!("NATS: a job was not stored: {e}"))?;
    }
    Ok(())
}

/// Of the machines `indices` of run `run`, those with neither a job on the queue (waiting, or
/// under way on a node) nor a stored result: their jobs were lost (the submitting node died
/// before it had published them all) and must be published again.
pub async fn lost_jobs(nats: &Nats, run: &str, indices: &[usize]) -> Result<Vec<usize>, String> {
    // The queue first: a job gone from it was acked, which a node does only once its result is
    // stored, so the result looked for afterwards is there.
    let mut gone = Vec::new();
    for &index in indices {
        if !has_message(&nats.stream, &job_subject(run, index)).await? {
            gone.push(index);
        }
    }
    let mut lost = Vec::new();
    for index in gone {
        if !has_message(&nats.results, &result_subject(run, index)).await? {
            lost.push(index);
        }
    }
    Ok(lost)
}

async fn has_message(stream: &jetstream::stream::Stream, subject: &str) -> Result<bool, String> {
    match stream.get_last_raw_message_by_subject(subject).await {
        Ok(_) => Ok(true),
        Err(e) if e.kind() == LastRawMessageErrorKind::NoMessageFound => Ok(false),
        Err(e) => Err(format!("NATS: cannot read {subject}: {e}")),
    }
}

/// The results of one run as they come, read from the start of the results stream (so what was
/// computed before the collection opened, the case of a run taken over, comes first): the first
/// result of each machine not known already, the jobs starting, the run's cancel from any node,
/// and the nodes' being alive.
pub struct Collection {
    run: String,
    names: Vec<String>,
    /// Whether each machine's result is known (heard, or known before).
    have: Vec<bool>,
    started: Vec<bool>,
    /// Machines without a result.
    left: usize,
    results: push::Ordered,
    /// The consumer's name: deleted when the collection closes.
    consumer: String,
    beats: async_nats::Subscriber,
    nodes: async_nats::Subscriber,
    cancels: async_nats::Subscriber,
    idle: Duration,
    deadline: tokio::time::Instant,
}

impl Collection {
    /// Opens the collection of run `run`, whose machines are `names`; `have[i]`: machine `i`'s
    /// result is known already (it is not heard again).
    pub async fn open(
        nats: &Nats,
        run: &str,
        names: Vec<String>,
        have: Vec<bool>,
        idle: Duration,
    ) -> Result<Collection, String> {
        let subscribe = |subject: String| async move {
            nats.client
                .subscribe(subject.clone())
                .await
                .map_err(|e| format!("NATS: cannot subscribe to {subject}: {e}"))
        };
        let beats = subscribe(running_subject(run)).await?;
        let nodes = subscribe(NODES.into()).await?;
        let cancels = subscribe(CANCEL.into()).await?;
        let config = push::OrderedConfig {
            deliver_subject: nats.client.new_inbox(),
            filter_subject: format!("{RESULTS}.{run}.>"),
            deliver_policy: DeliverPolicy::All,
            ..Default::default()
        };
        let consumer = nats
            .results
            .create_consumer(config)
            .await
            .map_err(|e| format!("NATS: cannot read the results of run {run}: {e}"))?;
        let name = consumer.cached_info().name.clone();
        let results =
            consumer.messages().await.map_err(|e| format!("NATS: cannot read the results of run {run}: {e}"))?;
        Ok(Collection {
            run: run.to_owned(),
            names,
            left: have.iter().filter(|h| !**h).count(),
            started: vec![false; have.len()],
            have,
            results,
            consumer: name,
            beats,
            nodes,
            cancels,
            idle,
            deadline: tokio::time::Instant::now() + idle,
        })
    }

    /// The next thing heard; `Err` once the collection is over: every result in
    /// ([`Outcome::Done`]), `stop` holding a reason, the run cancelled from any node, a job
    /// refused by a node, nothing heard from a node for the idle time.
    pub async fn next(&mut self, stop: &mut watch::Receiver<Option<&'static str>>) -> Result<Heard, Outcome> {
        loop {
            if self.left == 0 {
                return Err(Outcome::Done);
            }
            tokio::select! {
                message = self.results.next() => {
                    let message = match message {
                        Some(Ok(m)) => m,
                        Some(Err(e)) => {
                            // The ordered consumer makes itself again from where it was.
                            tracing::warn!(run = %self.run, error = %e, "fleet results: reading again");
                            continue;
                        }
                        None => return Err(Outcome::Failed("NATS: the results' consumer ended".into())),
                    };
                    self.deadline = tokio::time::Instant::now() + self.idle;
                    let reply: Reply = match serde_json::from_slice(&message.payload) {
                        Ok(r) => r,
                        Err(e) => {
                            tracing::warn!(subject = %message.subject, error = %e, "fleet reply is not a reply: ignored");
                            continue;
                        }
                    };
                    let index = reply.index;
                    if index >= self.have.len() || self.have[index] {
                        continue; // not of this run, or known already
                    }
                    if let Some(e) = reply.error {
                        let name = self.names.get(index).map_or("", String::as_str);
                        return Err(Outcome::Failed(format!("machine {index} ({name}): a node refused it: {e}")));
                    }
                    if let Some(result) = reply.result {
                        self.have[index] = true;
                        self.left -= 1;
                        return Ok(Heard::Result(index, result));
                    }
                }
                beat = self.beats.next() => {
                    let Some(message) = beat else { return Err(Outcome::Failed("NATS: the connection closed".into())) };
                    self.deadline = tokio::time::Instant::now() + self.idle;
                    let Ok(Reply { index, .. }) = serde_json::from_slice(&message.payload) else { continue };
                    if index < self.have.len() && !self.have[index] && !self.started[index] {
                        self.started[index] = true;
                        return Ok(Heard::Started(index));
                    }
                }
                Some(_) = self.nodes.next() => self.deadline = tokio::time::Instant::now() + self.idle,
                Some(cancel) = self.cancels.next() => {
                    if cancel.payload.as_ref() == self.run.as_bytes() {
                        return Err(Outcome::Stopped("cancelled"));
                    }
                }
                _ = tokio::time::sleep_until(self.deadline) => {
                    return Err(Outcome::Failed(format!(
                        "no fleet node heard from for {} s: is a `fivex serve --nats` node running on this NATS server?",
                        self.idle.as_secs()
                    )));
                }
                why = stop.wait_for(Option::is_some) => {
                    let why = why.ok().and_then(|w| *w).unwrap_or("interrupted");
                    return Err(Outcome::Stopped(why));
                }
            }
        }
    }

    /// Ends the collection and deletes its consumer (the server would, 30 s after its reader
    /// left).
    pub async fn close(self, nats: &Nats) {
        let Collection { results, consumer, run, .. } = self;
        drop(results);
        if let Err(e) = nats.results.delete_consumer(&consumer).await {
            tracing::debug!(%run, error = %e, "fleet results' consumer not deleted");
        }
    }
}

/// A run that will not collect its results: its waiting jobs are purged, its running ones
/// cancelled.
pub async fn withdraw(nats: &Nats, run: &str) {
    if let Err(e) = nats.stream.purge().filter(format!("{JOBS}.{run}.>")).await {
        tracing::warn!(%run, error = %e, "fleet run's jobs not purged");
    }
    if let Err(e) = nats.client.publish(CANCEL, Bytes::from(run.to_string())).await {
        tracing::warn!(%run, error = %e, "fleet run's cancel not published");
    }
    let _ = nats.client.flush().await;
}

/// A run over: its results leave the stream.
pub async fn clean(nats: &Nats, run: &str) {
    if let Err(e) = nats.results.purge().filter(format!("{RESULTS}.{run}.>")).await {
        tracing::warn!(%run, error = %e, "fleet run's results not purged");
    }
}

/// A node's share of the work: takes jobs, at most `jobs` at once.
#[derive(Clone, Debug)]
pub struct Node {
    inner: Arc<NodeInner>,
}

#[derive(Debug, Default)]
struct NodeInner {
    /// The cancel flag of each run with a job under way here.
    running: Mutex<HashMap<String, (Arc<AtomicBool>, usize)>>,
    /// The runs cancelled lately (their jobs still to come are skipped).
    cancelled: Mutex<VecDeque<String>>,
    /// The service stops: no job is taken, the ones under way are given back.
    stopping: AtomicBool,
}

/// How many cancelled runs a node remembers.
const REMEMBERED: usize = 1024;

impl Node {
    /// The node stops: takes no more jobs and gives those under way back to the queue (another
    /// node runs them).
    pub fn stop(&self) {
        self.inner.stopping.store(true, Ordering::Relaxed);
        for (flag, _) in lock(&self.inner.running).values() {
            flag.store(true, Ordering::Relaxed);
        }
    }

    fn stopping(&self) -> bool {
        self.inner.stopping.load(Ordering::Relaxed)
    }

    fn cancel(&self, run: &str) {
        let mut cancelled = lock(&self.inner.cancelled);
        cancelled.push_back(run.to_string());
        if cancelled.len() > REMEMBERED {
            cancelled.pop_front();
        }
        drop(cancelled);
        if let Some((flag, _)) = lock(&self.inner.running).get(run) {
            flag.store(true, Ordering::Relaxed);
        }
    }

    fn is_cancelled(&self, run: &str) -> bool {
        lock(&self.inner.cancelled).iter().any(|r| r == run)
    }

    /// The cancel flag for a job of `run` starting here.
    fn enter(&self, run: &str) -> Arc<AtomicBool> {
        let mut running = lock(&self.inner.running);
        let entry = running.entry(run.to_string()).or_insert_with(|| (Arc::new(AtomicBool::new(false)), 0));
        entry.1 += 1;
        let flag = entry.0.clone();
        drop(running);
        // After the entry is in: a cancel that comes meanwhile sees it, or is seen here.
        if self.stopping() || self.is_cancelled(run) {
            flag.store(true, Ordering::Relaxed);
        }
        flag
    }

    fn leave(&self, run: &str) {
        let mut running = lock(&self.inner.running);
        if let Some(entry) = running.get_mut(run) {
            entry.1 -= 1;
            if entry.1 == 0 {
                running.remove(run);
            }
        }
    }
}

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// Starts taking jobs from the queue, at most `jobs` at once (at least 1), on the current
/// runtime; the answer stops it.
pub async fn start_node(nats: &Nats, jobs: usize) -> Result<Node, String> {
    let config = pull::Config {
        durable_name: Some(CONSUMER.into()),
        ack_policy: AckPolicy::Explicit,
        ack_wait: ACK_WAIT,
        ..Default::default()
    };
    let consumer = nats
        .stream
        .get_or_create_consumer(CONSUMER, config)
        .await
        .map_err(|e| format!("NATS: cannot create the consumer {CONSUMER}: {e}"))?;
    let mut cancels =
        nats.client.subscribe(CANCEL).await.map_err(|e| format!("NATS: cannot subscribe to {CANCEL}: {e}"))?;
    let node = Node { inner: Arc::default() };
    let n = node.clone();
    tokio::spawn(async move {
        while let Some(m) = cancels.next().await {
            if let Ok(run) = std::str::from_utf8(&m.payload) {
                tracing::info!(%run, "fleet run cancelled: its jobs here stop");
                n.cancel(run);
            }
        }
    });
    let (client, n) = (nats.client.clone(), node.clone());
    tokio::spawn(async move {
        while !n.stopping() {
            let _ = client.publish(NODES, Bytes::new()).await;
            tokio::time::sleep(HEARTBEAT).await;
        }
    });
    for _ in 0..jobs.max(1) {
        let (consumer, nats, node) = (consumer.clone(), nats.clone(), node.clone());
        tokio::spawn(async move {
            while !node.stopping() {
                let batch = consumer.batch().max_messages(1).expires(HEARTBEAT).messages().await;
                let mut batch = match batch {
                    Ok(b) => b,
                    Err(e) => {
                        tracing::warn!(error = %e, "fleet jobs: cannot pull");
                        tokio::time::sleep(HEARTBEAT).await;
                        continue;
                    }
                };
                while let Some(message) = batch.next().await {
                    match message {
                        Ok(m) => take(&node, &nats, m).await,
                        Err(e) => tracing::debug!(error = %e, "fleet jobs: pull ended"),
                    }
                }
            }
        });
    }
    tracing::info!(jobs = jobs.max(1), "fleet node: taking jobs from NATS");
    Ok(node)
}

/// Runs one job and answers it.
async fn take(node: &Node, nats: &Nats, message: jetstream::Message) {
    let client = &nats.client;
    let job: Job = match serde_json::from_slice(&message.payload) {
        Ok(job) => job,
        Err(e) => {
            // Never redelivered: it will not parse next time either.
            tracing::warn!(subject = %message.subject, error = %e, "fleet job is not a job: terminated");
            let _ = message.ack_with(AckKind::Term).await;
            return;
        }
    };
    let (run, index) = (job.run.clone(), job.index);
    let reply_to = result_subject(&run, index);
    // Stored on the results stream (its ack awaited) before the job is acked.
    let answer = |reply: Reply| {
        let to = reply_to.clone();
        async move {
            let Ok(payload) = serde_json::to_vec(&reply) else { return false };
            match nats.js.publish(to, Bytes::from(payload)).await {
                Ok(ack) => ack.await.is_ok(),
                Err(_) => false,
            }
        }
    };
    if node.is_cancelled(&run) {
        let _ = message.ack().await;
        return;
    }
    let checked = job
        .tools
        .as_ref()
        .map_or(Ok(()), fleet::check_tools)
        .and_then(|()| job.workpiece.as_ref().map_or(Ok(()), |w| w.check().map_err(|e| format!("workpiece: {e}"))));
    let entry = match checked.and_then(|()| job.machine.entry(job.dialect)) {
        Ok(entry) => entry,
        Err(e) => {
            tracing::warn!(%run, index, error = %e, "fleet job refused");
            if answer(Reply { index, result: None, error: Some(e) }).await {
                let _ = message.ack_with(AckKind::Term).await;
            }
            return;
        }
    };
    let cancel = node.enter(&run);
    let opts = Options {
        tools: job.tools,
        report: job.report,
        report_period_s: job.report_period_s,
        jobs: 1,
        max_blocks: job.max_blocks,
        max_time_s: job.max_time_s,
        workpiece: job.workpiece.map(Arc::new),
        cancel: Some(cancel.clone()),
    };
    let program = job.program;
    let machine = entry.name.clone();
    tracing::info!(%run, index, %machine, "fleet job started");
    let running = running_subject(&run);
    let beat = Bytes::from(format!("{{\"index\":{index}}}"));
    let _ = client.publish(running.clone(), beat.clone()).await;
    let mut task = tokio::task::spawn_blocking(move || fleet::run_one(&program, &entry, &opts));
    let mut tick = tokio::time::interval(HEARTBEAT);
    tick.tick().await;
    let result = loop {
        tokio::select! {
            r = &mut task => break r,
            _ = tick.tick() => {
                let _ = message.ack_with(AckKind::Progress).await;
                let _ = client.publish(running.clone(), beat.clone()).await;
            }
        }
    };
    node.leave(&run);
    if cancel.load(Ordering::Relaxed) {
        if node.stopping() {
            // Given back: another node runs it at once.
            let _ = message.ack_with(AckKind::Nak(None)).await;
            tracing::info!(%run, index, %machine, "fleet job given back: the node stops");
        } else {
            let _ = message.ack().await;
            tracing::info!(%run, index, %machine, "fleet job cancelled");
        }
        return;
    }
    let reply = match result.map(|r| serde_json::to_value(&r)) {
        Ok(Ok(value)) => Reply { index, result: Some(value), error: None },
        Ok(Err(e)) => Reply { index, result: None, error: Some(format!("result not written: {e}")) },
        Err(e) => Reply { index, result: None, error: Some(format!("the run failed: {e}")) },
    };
    // Acked only once the result is out: a node that dies before leaves the job to another.
    if answer(reply).await {
        let _ = message.ack().await;
        tracing::info!(%run, index, %machine, "fleet job done");
    } else {
        tracing::warn!(%run, index, %machine, "fleet job's result not published: left for redelivery");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A job carries the run's workpiece to the node, and a run without one writes no
    /// `workpiece` (its jobs read as before it existed).
    #[test]
    fn a_job_carries_the_workpiece_only_when_the_run_has_one() {
        let entries = vec![fleet::preset("mill3", Dialect::Fanuc).unwrap()];
        let sources = vec![Source::Preset("mill3".into())];
        let bare = Job::all("r", "M30\n", &entries, sources.clone(), &Options::default());
        let text = serde_json::to_value(&bare[0]).unwrap();
        assert!(text.get("workpiece").is_none(), "{text}");
        assert_eq!(serde_json::from_value::<Job>(text).unwrap(), bare[0]);

        let block: Workpiece =
            serde_json::from_str(r#"{"boxes": [{"min": [12, 8, -20], "max": [62, 48, -3]}]}"#).unwrap();
        let opts = Options { workpiece: Some(Arc::new(block.clone())), ..Options::default() };
        let jobs = Job::all("r", "M30\n", &entries, sources, &opts);
        let read: Job = serde_json::from_slice(&serde_json::to_vec(&jobs[0]).unwrap()).unwrap();
        assert_eq!(read.workpiece, Some(block));
    }
}
