//! `fivex fleet`: one program on many machines (presets, machine files, the library), all cores
//! at once; stdout is the JSON array of `fivex run` summaries, each with `"machine"` (and
//! `"dialect"`, and with `--report` the run report); progress goes to stderr.

use super::{read_json_text, read_program, read_workpiece, Fail};
use crate::cluster::{self, Job, Outcome, Source};
use crate::fleet::{self, Entry, Event, Options, Tool};
use clap::Args;
use fivex_engine::Dialect;
use std::collections::BTreeMap;
use std::io::Write;
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

#[derive(Args, Debug)]
pub struct FleetArgs {
    program: PathBuf,
    /// A built-in preset (repeat for more machines).
    #[arg(long = "preset")]
    presets: Vec<String>,
    /// A machine file, model or parameter list (repeat for more; a parameter list runs in its
    /// own dialect).
    #[arg(long = "machine")]
    machines: Vec<PathBuf>,
    /// Machines of the library (`machines/`): `--library` alone for all of them, or
    /// `--library NAME,NAME`.
    #[arg(long, num_args = 0.., value_delimiter = ',')]
    library: Option<Vec<String>>,
    /// Dialect of presets and model files.
    #[arg(long, default_value = "fanuc")]
    dialect: Dialect,
    /// Tool offsets file: {"1": {"length": 100.0, "radius": 5.0}, …}; optional per tool
    /// "length_wear", "radius_wear" (mm, within ±99.999; default 0) and "corner_radius" (mm, 0
    /// or more; default 0). Any other field is refused.
    #[arg(long)]
    tools: Option<PathBuf>,
    /// What is clamped on every machine's table, the boxes a G31 probe touches: {"boxes":
    /// [{"min": [x, y, z], "max": [x, y, z]}, …]} in the table frame, mm, as `fivex run
    /// --workpiece` (`docs/conventions.md`). Default: none.
    #[arg(long)]
    workpiece: Option<PathBuf>,
    /// Machines simulated at once (default: one per core).
    #[arg(long, conflicts_with = "nats")]
    jobs: Option<usize>,
    /// Run on a distributed fleet: one job per machine on this NATS server's JetStream work
    /// queue, run by the `fivex serve --nats` nodes connected to it (at least one must run;
    /// docs/fleet.md).
    #[arg(long, env = "FIVEX_NATS", value_name = "URL")]
    nats: Option<String>,
    /// With --nats: give up (exit status 2) when neither a node nor a result was heard from for
    /// this many seconds.
    #[arg(long, default_value_t = 30, value_parser = clap::value_parser!(u64).range(1..=86400))]
    nats_timeout_s: u64,
    /// Add each machine's run report ("report": travel, speeds, singular time, limits,
    /// unwinds, tip deviation).
    #[arg(long)]
    report: bool,
    /// Sampling period of the report, milliseconds.
    #[arg(long, default_value_t = 1.0)]
    report_period_ms: f64,
    /// No progress lines on stderr.
    #[arg(long, short)]
    quiet: bool,
    /// Stop a machine with alarm FX0001 after this many executed blocks.
    #[arg(long, default_value_t = 50_000_000)]
    max_blocks: u64,
    /// Stop a machine with alarm FX0002 after this many simulated seconds.
    #[arg(long, default_value_t = 1.0e6)]
    max_time_s: f64,
}

pub fn run(a: FleetArgs) -> Result<i32, Fail> {
    let text = read_program(&a.program)?;
    let mut entries: Vec<Entry> = Vec::new();
    // Where each machine comes from, for --nats (the nodes build it as this does).
    let mut sources: Vec<Source> = Vec::new();
    for name in &a.presets {
        entries.push(fleet::preset(name, a.dialect).map_err(Fail)?);
        sources.push(Source::Preset(name.clone()));
    }
    for path in &a.machines {
        let file = read_json_text(path)?;
        entries.push(fleet::machine_file(&file, a.dialect).map_err(|e| Fail(format!("{}: {e}", path.display())))?);
        for line in fivex_engine::machine_file::warnings(&path.display().to_string(), &file) {
            eprintln!("{line}");
        }
        sources.push(Source::Document(file));
    }
    match &a.library {
        Some(names) if names.is_empty() => {
            entries.extend(fleet::whole_library(a.dialect).map_err(Fail)?);
            sources.extend(fleet::LIBRARY.iter().map(|(n, _)| Source::Library(n.to_string())));
        }
        Some(names) => {
            for name in names {
                entries.push(fleet::library(name, a.dialect).map_err(Fail)?);
                sources.push(Source::Library(name.clone()));
            }
        }
        None => {}
    }
    if entries.is_empty() {
        return Err(Fail("no machines: give --preset, --machine or --library".into()));
    }
    if !(a.report_period_ms > 0.0 && a.report_period_ms.is_finite()) {
        return Err(Fail("--report-period-ms must be a positive number".into()));
    }
    let tools: Option<BTreeMap<u32, Tool>> = match &a.tools {
        Some(path) => Some(super::read_tools(path)?),
        None => None,
    };
    let workpiece = a.workpiece.as_deref().map(read_workpiece).transpose()?.map(std::sync::Arc::new);
    let opts = Options {
        tools,
        report: a.report,
        report_period_s: a.report_period_ms / 1000.0,
        jobs: a.jobs.unwrap_or_else(fleet::default_jobs).max(1),
        max_blocks: a.max_blocks,
        max_time_s: a.max_time_s,
        workpiece,
        cancel: None,
    };
    let total = entries.len();
    let done = AtomicUsize::new(0);
    let quiet = a.quiet;
    let progress = |e: Event| {
        if quiet {
            return;
        }
        if let Event::Finished { machine, status, cycle_time_s, .. } = e {
            let k = done.fetch_add(1, Ordering::Relaxed) + 1;
            eprintln!("fleet: [{k}/{total}] {machine}: {status}, {cycle_time_s:.3} s");
        }
    };
    let json = match &a.nats {
        None => {
            let results = fleet::run_fleet(&text, &entries, &opts, &progress);
            let completed = |r: &Option<crate::wire::FleetResult>| {
                r.as_ref().is_some_and(|r| r.summary.status == crate::wire::RunStatus::Completed)
            };
            let status = if results.iter().all(completed) { 0 } else { 1 };
            (serde_json::to_string_pretty(&results)?, status)
        }
        Some(url) => {
            let idle = std::time::Duration::from_secs(a.nats_timeout_s);
            let results = remote(url, text, &entries, sources, &opts, idle, &progress)?;
            let status =
                if results.iter().all(|r| r.as_ref().is_some_and(|r| r["status"] == "completed")) { 0 } else { 1 };
            (serde_json::to_string_pretty(&results)?, status)
        }
    };
    let (json, status) = json;
    match writeln!(std::io::stdout().lock(), "{json}") {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(Fail(format!("stdout: {e}"))),
        _ => Ok(status),
    }
}

/// `--nats`: the machines as jobs on the cluster's work queue, the results collected from the
/// run's subject; Ctrl-C cancels the run (its waiting jobs purged, its running ones stopped).
fn remote(
    url: &str,
    program: String,
    entries: &[Entry],
    sources: Vec<Source>,
    opts: &Options,
    idle: std::time::Duration,
    progress: &(dyn Fn(Event) + Sync),
) -> Result<Vec<Option<serde_json::Value>>, Fail> {
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .map_err(|e| Fail(format!("cannot start the async runtime: {e}")))?;
    runtime.block_on(async {
        let nats = cluster::connect(url).await.map_err(Fail)?;
        let run = uuid::Uuid::new_v4().simple().to_string();
        let jobs = Job::all(&run, &program, entries, sources, opts);
        let names: Vec<String> = entries.iter().map(|e| e.name.clone()).collect();
        let (stop, stopped) = tokio::sync::watch::channel(None);
        tokio::spawn(async move {
            if tokio::signal::ctrl_c().await.is_ok() {
                stop.send_replace(Some("cancelled"));
            }
        });
        let (outcome, results) = cluster::run(&nats, jobs, &names, idle, stopped, progress).await;
        match outcome {
            Outcome::Done => Ok(results),
            Outcome::Stopped(why) => Err(Fail(format!("fleet run {run} {why}: its jobs were withdrawn"))),
            Outcome::Failed(e) => Err(Fail(format!("fleet run {run}: {e}"))),
        }
    })
}
