//! The distributed fleet over NATS JetStream (`docs/fleet.md`, "Over NATS"): a fleet run split
//! into one job per machine on a work queue, run by every `fivex serve --nats` node, the results
//! coming back on the run's subject.
//!
//! - Stream [`STREAM`] on `fivex.fleet.jobs.>`, work-queue retention; a job is published on
//!   `fivex.fleet.jobs.{run}.{index}` as a JSON [`Job`].
//! - One durable pull consumer [`CONSUMER`] shared by the nodes, explicit acks, [`ACK_WAIT`]: a
//!   job is acked only after its result is published, so a node that dies mid-job leaves it
//!   unacked and JetStream hands it to another node once the ack wait has passed. A node sends
//!   an in-progress ack every [`HEARTBEAT`] while it runs a job.
//! - Replies ([`Reply`]) on `fivex.fleet.runs.{run}.running` (a job started, and every
//!   [`HEARTBEAT`] while it runs) and `fivex.fleet.runs.{run}.results`; the submitter subscribes
//!   before it publishes and keeps the first result of each machine (a redelivered job's second
//!   result is ignored).
//! - Nodes say they are alive on [`NODES`] every [`HEARTBEAT`]: the submitter gives up when it
//!   has heard neither a node nor a result for its idle time.
//! - Cancel: the submitter purges the run's jobs from the stream (no waiting job runs) and
//!   publishes the run id on [`CANCEL`]: the nodes stop the run's jobs under way before their next
//!   block and skip any of its jobs they still get.

use std::collections::{BTreeMap, HashMap, VecDeque};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use async_nats::jetstream::{self, consumer::pull, consumer::AckPolicy, stream, AckKind};
use bytes::Bytes;
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

fn run_subjects(run: &str) -> String {
    format!("fivex.fleet.runs.{run}.*")
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

/// A connection to NATS with the fleet's stream made sure of.
#[derive(Clone, Debug)]
pub struct Nats {
    client: async_nats::Client,
    js: jetstream::Context,
    stream: jetstream::stream::Stream,
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

/// Connects to `url` and makes sure the fleet stream exists.
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
    Ok(Nats { client, js, stream })
}

/// How a distributed run ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    /// Every machine has its result.
    Done,
    /// Stopped by the caller with this reason (`cancelled`, `interrupted`).
    Stopped(&'static str),
    /// Gave up: the message says why (no node heard from, NATS failing, a job refused).
    Failed(String),
}

/// Publishes `jobs` (one run, in machine order, named `names`) and collects their results,
/// reporting as `fleet::run_fleet` does; stops when `stop` holds a reason (then the run's
/// waiting jobs are purged and its running ones cancelled), or when nothing was heard from a node
/// for `idle`. The results in machine order, `None` for each machine without one.
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
    let outcome = collect(nats, &run, jobs, names, idle, &mut stop, progress, &mut results).await;
    if outcome != Outcome::Done {
        forget(nats, &run).await;
    }
    (outcome, results)
}

#[allow(clippy::too_many_arguments)]
async fn collect(
    nats: &Nats,
    run: &str,
    jobs: Vec<Job>,
    names: &[String],
    idle: Duration,
    stop: &mut watch::Receiver<Option<&'static str>>,
    progress: &(dyn Fn(Event) + Sync),
    results: &mut [Option<Value>],
) -> Outcome {
    let failed = |what: &str, e: &dyn std::fmt::Display| Outcome::Failed(format!("NATS: {what}: {e}"));
    // Subscribed before the jobs go out (the same connection: the server has the subscription
    // before it stores the first job), so no reply is missed.
    let mut replies = match nats.client.subscribe(run_subjects(run)).await {
        Ok(s) => s,
        Err(e) => return failed("cannot subscribe to the run's subjects", &e),
    };
    let mut nodes = match nats.client.subscribe(NODES).await {
        Ok(s) => s,
        Err(e) => return failed("cannot subscribe to the nodes' subject", &e),
    };
    for job in &jobs {
        let payload = match serde_json::to_vec(job) {
            Ok(p) => p,
            Err(e) => return failed("cannot write a job", &e),
        };
        let subject = format!("{JOBS}.{run}.{}", job.index);
        let ack = match nats.js.publish(subject, Bytes::from(payload)).await {
            Ok(ack) => ack,
            Err(e) => return failed("cannot publish a job", &e),
        };
        if let Err(e) = ack.await {
            return failed("a job was not stored", &e);
        }
    }
    let name = |i: usize| names.get(i).cloned().unwrap_or_default();
    let mut started = vec![false; results.len()];
    let mut done = 0;
    let mut deadline = tokio::time::Instant::now() + idle;
    while done < results.len() {
        tokio::select! {
            reply = replies.next() => {
                let Some(message) = reply else { return Outcome::Failed("NATS: the connection closed".into()) };
                deadline = tokio::time::Instant::now() + idle;
                let reply: Reply = match serde_json::from_slice(&message.payload) {
                    Ok(r) => r,
                    Err(e) => {
                        tracing::warn!(subject = %message.subject, error = %e, "fleet reply is not a reply: ignored");
                        continue;
                    }
                };
                let index = reply.index;
                if index >= results.len() || results[index].is_some() {
                    continue; // not of this run, or a redelivered job's second result
                }
                if let Some(e) = reply.error {
                    return Outcome::Failed(format!("machine {index} ({}): a node refused it: {e}", name(index)));
                }
                if let Some(result) = reply.result {
                    let status = match result["status"].as_str() {
                        Some("completed") => "completed",
                        _ => "alarm",
                    };
                    let cycle_time_s = result["cycle_time_s"].as_f64().unwrap_or(0.0);
                    results[index] = Some(result);
                    done += 1;
                    progress(Event::Finished { index, machine: name(index), status, cycle_time_s });
                } else if !started[index] {
                    started[index] = true;
                    progress(Event::Started { index, machine: name(index) });
                }
            }
            Some(_) = nodes.next() => deadline = tokio::time::Instant::now() + idle,
            _ = tokio::time::sleep_until(deadline) => {
                return Outcome::Failed(format!(
                    "no fleet node heard from for {} s: is a `fivex serve --nats` node running on this NATS server?",
                    idle.as_secs()
                ));
            }
            why = stop.wait_for(Option::is_some) => {
                let why = why.ok().and_then(|w| *w).unwrap_or("interrupted");
                return Outcome::Stopped(why);
            }
        }
    }
    Outcome::Done
}

/// A run that will not collect its results: its waiting jobs are purged, its running ones
/// cancelled.
async fn forget(nats: &Nats, run: &str) {
    if let Err(e) = nats.stream.purge().filter(format!("{JOBS}.{run}.>")).await {
        tracing::warn!(%run, error = %e, "fleet run's jobs not purged");
    }
    if let Err(e) = nats.client.publish(CANCEL, Bytes::from(run.to_string())).await {
        tracing::warn!(%run, error = %e, "fleet run's cancel not published");
    }
    let _ = nats.client.flush().await;
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
        let (consumer, client, node) = (consumer.clone(), nats.client.clone(), node.clone());
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
                        Ok(m) => take(&node, &client, m).await,
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
async fn take(node: &Node, client: &async_nats::Client, message: jetstream::Message) {
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
    let reply_to = format!("fivex.fleet.runs.{run}.results");
    let answer = |reply: Reply| {
        let to = reply_to.clone();
        async move {
            match serde_json::to_vec(&reply) {
                Ok(p) => client.publish(to, Bytes::from(p)).await.is_ok() && client.flush().await.is_ok(),
                Err(_) => false,
            }
        }
    };
    if node.is_cancelled(&run) {
        let _ = message.ack().await;
        return;
    }
    let checked = job.tools.as_ref().map_or(Ok(()), fleet::check_tools);
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
        cancel: Some(cancel.clone()),
    };
    let program = job.program;
    let machine = entry.name.clone();
    tracing::info!(%run, index, %machine, "fleet job started");
    let running = format!("fivex.fleet.runs.{run}.running");
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
