//! The `fivex` command line (see `docs/contracts.md`): `run`, `interp`, `check`, `kin`, `machine`
//! and `serve`.
//!
//! Exit status: 0 completed, 1 ended in an alarm (or diagnostics for `check`), 2 usage or IO.

mod fleet;
pub(crate) mod json;
mod kin;
mod limits;
mod machine;

use clap::{Args, Parser, Subcommand};
use fivex_engine::canon::Canon;
use fivex_engine::interp::{Config, Interpreter, Step};
use fivex_engine::lang::parse_file;
use fivex_engine::machine::MachineConfig;
use fivex_engine::run::{run, RunOptions};
use fivex_engine::stage::Pipeline;
use fivex_engine::Dialect;
use std::collections::BTreeMap;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

#[derive(Parser, Debug)]
#[command(
    name = "fivex",
    version,
    about = "Virtual 5-axis CNC controllers (FANUC 30i-A5, Syntec and Haas NGC dialects)"
)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run a program on a virtual machine and print a JSON summary.
    Run(RunArgs),
    /// Interpret a program and print its canonical commands, one JSON object per line.
    Interp(InterpArgs),
    /// Check a program from its text (with --preset/--machine also run on that machine, nothing
    /// moving); one line per diagnostic.
    Check(CheckArgs),
    /// Run a program on many machines at once; a JSON array of run summaries (docs/fleet.md).
    Fleet(fleet::FleetArgs),
    /// Kinematics of a machine: `kin fk` and `kin ik`.
    #[command(subcommand)]
    Kin(kin::KinCommand),
    /// Print a machine as a model file or as a FANUC / Syntec / Haas parameter list.
    Machine(machine::MachineShowArgs),
    /// Start the HTTP service.
    Serve(ServeArgs),
}

#[derive(Args, Debug)]
struct MachineArgs {
    /// Built-in machine preset (mill3, head-bc, table-ac, table-bc, mixed-bc).
    #[arg(long, conflicts_with = "machine")]
    preset: Option<String>,
    /// Machine configuration file (JSON, see docs/machine-config.md).
    #[arg(long)]
    machine: Option<PathBuf>,
}

#[derive(Args, Debug)]
struct InterpreterArgs {
    #[command(flatten)]
    machine: MachineArgs,
    /// Dialect: fanuc, syntec or haas [default: a parameter list's own dialect, else fanuc].
    #[arg(long)]
    dialect: Option<Dialect>,
    /// Tool offsets file: {"1": {"length": 100.0, "radius": 5.0}, …}; optional per tool
    /// "length_wear", "radius_wear" (mm, within ±99.999; default 0) and "corner_radius" (mm, 0
    /// or more; default 0). Any other field is refused.
    #[arg(long)]
    tools: Option<PathBuf>,
    /// What is clamped on the table, the boxes a G31 probe touches: {"boxes": [{"min": [x, y,
    /// z], "max": [x, y, z]}, …]} in the table frame, mm (`docs/conventions.md`). Default: none.
    #[arg(long)]
    workpiece: Option<PathBuf>,
    /// Turn the block delete switch on (skip blocks starting with '/').
    #[arg(long)]
    block_delete: bool,
    /// Turn the optional stop switch on (M01 stops).
    #[arg(long)]
    optional_stop: bool,
    /// Stop with alarm FX0001 after this many executed blocks (endless loops, recursion).
    #[arg(long, default_value_t = 50_000_000)]
    max_blocks: u64,
}

#[derive(Args, Debug)]
struct RunArgs {
    program: PathBuf,
    #[command(flatten)]
    interp: InterpreterArgs,
    /// Write one JSON object per interpolation period to this file.
    #[arg(long)]
    trace: Option<PathBuf>,
    /// Interpolation period in milliseconds.
    #[arg(long, default_value_t = 1.0)]
    period_ms: f64,
    /// Stop with alarm FX0002 after this many simulated seconds.
    #[arg(long, default_value_t = 1.0e6)]
    max_time_s: f64,
    /// Retained variables (#500–#999, #500000–#999999, #3002, #3901, #3902): read from this JSON file if it exists ({"#500": 1.5, …})
    /// and written back after the run, like a control's battery-backed memory.
    #[arg(long)]
    variables: Option<PathBuf>,
}

#[derive(Args, Debug)]
struct InterpArgs {
    program: PathBuf,
    #[command(flatten)]
    interp: InterpreterArgs,
    /// The commands after the path stages (cutter compensation C: the tool centre path, with
    /// the `--tools` radii) instead of as the program states them.
    #[arg(long)]
    stages: bool,
}

#[derive(Args, Debug)]
struct CheckArgs {
    program: PathBuf,
    /// Dialect: fanuc, syntec or haas [default: a parameter list's own dialect, else fanuc].
    #[arg(long)]
    dialect: Option<Dialect>,
    /// With a machine (`--preset` or `--machine`), the program is also run through the
    /// interpreter and the path stages on it (nothing moves): what only that machine refuses,
    /// and cutter compensation's alarms, are reported too. Without one, a program that turns
    /// cutter compensation on (G41/G42) is run so on the default machine (mill3) and only the
    /// compensation's alarms are reported.
    #[command(flatten)]
    machine: MachineArgs,
    /// Tool offsets file for the run (as for `run`); default: 1–99 with length 100, radius 5.
    #[arg(long)]
    tools: Option<PathBuf>,
}

/// Blocks a machine check runs before it gives up (FX0001): a program that runs longer is
/// reported as a runaway.
const CHECK_MAX_BLOCKS: u64 = 5_000_000;

#[derive(Args, Debug)]
struct ServeArgs {
    /// SQLite database file (created and migrated on start), or a PostgreSQL URL
    /// (`postgres://user:password@host/database`: its tables created and migrated on start).
    #[arg(long, env = "FIVEX_DB", default_value = "fivex.db")]
    db: PathBuf,
    /// Address to listen on.
    #[arg(long, env = "FIVEX_ADDR", default_value = "127.0.0.1:8080")]
    addr: String,
    /// Require `Authorization: Bearer TOKEN` on the API (websockets may pass `?token=TOKEN`).
    #[arg(long, env = "FIVEX_TOKEN", hide_env_values = true)]
    token: Option<String>,
    /// Worker threads that run the controllers (default: one per core).
    #[arg(long, env = "FIVEX_WORKERS")]
    workers: Option<usize>,
    /// Let web pages from this origin (`scheme://host[:port]`) drive the service besides the
    /// service's own; repeatable (`FIVEX_ALLOW_ORIGIN`: comma-separated).
    #[arg(long = "allow-origin", value_name = "ORIGIN", env = "FIVEX_ALLOW_ORIGIN", value_delimiter = ',')]
    allow_origin: Vec<crate::origin::Origin>,
    #[command(flatten)]
    limits: limits::LimitArgs,
    /// Distributed fleet runs: take fleet jobs from this NATS server's JetStream work queue,
    /// and send this service's fleet runs there (`nats://HOST:PORT`; docs/fleet.md).
    #[arg(long, env = "FIVEX_NATS", value_name = "URL")]
    nats: Option<String>,
    /// With --nats: fleet jobs (machines) this node runs at once (default: one per core).
    #[arg(long, env = "FIVEX_NATS_JOBS", value_parser = clap::value_parser!(u32).range(1..=1024))]
    nats_jobs: Option<u32>,
    /// With --nats: a fleet run gives up (`interrupted`) when neither a node nor a result was
    /// heard from for this many seconds.
    #[arg(long, env = "FIVEX_NATS_TIMEOUT_S", default_value_t = 30, value_parser = clap::value_parser!(u64).range(1..=86400))]
    nats_timeout_s: u64,
    /// With --nats and a PostgreSQL --db: this node's name in the cluster of controller hosts
    /// (docs/cluster.md; 1 to 64 of A-Z a-z 0-9 _ -). Default: the host's name.
    #[arg(long, env = "FIVEX_NODE", value_name = "NAME", requires = "nats")]
    node: Option<String>,
    /// Serve an MTConnect agent for the controllers on this address (`HOST:PORT`, e.g.
    /// `0.0.0.0:5000`; docs/shopfloor.md). Read-only, without the token.
    #[arg(long, env = "FIVEX_MTCONNECT", value_name = "ADDR")]
    mtconnect: Option<String>,
    /// Observations the MTConnect agent keeps for `/sample` (its buffer size).
    #[arg(long, env = "FIVEX_MTCONNECT_BUFFER", default_value_t = crate::shopfloor::mtconnect::DEFAULT_BUFFER as u32, value_parser = clap::value_parser!(u32).range(16..=16_777_216))]
    mtconnect_buffer: u32,
    /// Serve OPC UA (Machine Tools companion specification) on this address (`HOST:PORT`, e.g.
    /// `0.0.0.0:4840`; docs/shopfloor.md).
    #[arg(long, env = "FIVEX_OPCUA", value_name = "ADDR")]
    opcua: Option<String>,
    /// How often the shop-floor interfaces read every controller, milliseconds.
    #[arg(long, env = "FIVEX_SHOPFLOOR_PERIOD_MS", default_value_t = 100, value_parser = clap::value_parser!(u64).range(10..=10_000))]
    shopfloor_period_ms: u64,
}

/// A usage or IO error: exit status 2.
struct Fail(String);

impl<E: std::fmt::Display> From<E> for Fail {
    fn from(e: E) -> Self {
        Fail(e.to_string())
    }
}

/// Parse the process arguments and run; returns the exit status.
pub fn main() -> i32 {
    let cli = Cli::parse();
    match dispatch(cli) {
        Ok(code) => code,
        Err(Fail(message)) => {
            eprintln!("fivex: {message}");
            2
        }
    }
}

fn dispatch(cli: Cli) -> Result<i32, Fail> {
    match cli.command {
        Command::Run(a) => cmd_run(a),
        Command::Interp(a) => cmd_interp(a),
        Command::Kin(c) => kin::run(c),
        Command::Machine(a) => machine::run(a),
        Command::Check(a) => cmd_check(a),
        Command::Fleet(a) => fleet::run(a),
        Command::Serve(a) => {
            let options = crate::serve::ServeOptions {
                db: a.db,
                addr: a.addr,
                token: a.token,
                workers: a.workers,
                allow_origins: a.allow_origin,
                limits: a.limits.limits(),
                fleet_jobs: a.limits.fleet_jobs as usize,
                nats: a.nats,
                nats_jobs: a.nats_jobs.map(|n| n as usize),
                nats_idle: std::time::Duration::from_secs(a.nats_timeout_s),
                node: a.node,
                shopfloor: crate::shopfloor::Options {
                    mtconnect: a.mtconnect,
                    mtconnect_buffer: a.mtconnect_buffer as usize,
                    opcua: a.opcua,
                    period: std::time::Duration::from_millis(a.shopfloor_period_ms),
                },
            };
            crate::serve::run_with(options).map_err(Fail)?;
            Ok(0)
        }
    }
}

fn read_program(path: &Path) -> Result<String, Fail> {
    let bytes = std::fs::read(path).map_err(|e| Fail(format!("{}: {e}", path.display())))?;
    // NC files are ASCII; anything else is kept (and alarms where it matters) rather than refused.
    let text = String::from_utf8(bytes).unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into_owned());
    // A byte order mark (an editor's, not the program's) is dropped as the API drops it.
    Ok(match text.strip_prefix('\u{FEFF}') {
        Some(rest) => rest.to_string(),
        None => text,
    })
}

/// The machine and the dialect it runs in: `given` (`--dialect`) when there is one, else a
/// parameter list's own dialect, else FANUC — as `POST /controllers` and `fivex fleet` choose
/// (a Syntec list read as a FANUC program would misread its programs without a word).
fn load_machine(args: &MachineArgs, given: Option<Dialect>) -> Result<(MachineConfig, Dialect), Fail> {
    if let Some(path) = &args.machine {
        let text = read_json_text(path)?;
        let machine = fivex_engine::machine_file::parse(&text).map_err(|e| Fail(format!("{}: {e}", path.display())))?;
        // Never dropped silently: what the file sets that fivex does not carry out.
        for line in fivex_engine::machine_file::warnings(&path.display().to_string(), &text) {
            eprintln!("{line}");
        }
        let dialect = given.or_else(|| fivex_engine::machine_file::dialect_of(&text)).unwrap_or(Dialect::Fanuc);
        return Ok((machine, dialect));
    }
    let name = args.preset.as_deref().unwrap_or("mill3");
    let machine = MachineConfig::preset(name)
        .ok_or_else(|| Fail(format!("unknown preset '{name}' (presets: {})", MachineConfig::PRESETS.join(", "))))?;
    Ok((machine, given.unwrap_or(Dialect::Fanuc)))
}

/// Build the interpreter for a program file with the CLI's settings.
fn interpreter(text: &str, args: &InterpreterArgs) -> Result<Interpreter, Fail> {
    let cfg = config(args)?;
    equip(Interpreter::new(parse_file(text), cfg), args.tools.as_deref())
}

fn config(args: &InterpreterArgs) -> Result<Config, Fail> {
    let (machine, dialect) = load_machine(&args.machine, args.dialect)?;
    let mut cfg = Config::new(machine, dialect);
    cfg.block_delete = args.block_delete;
    cfg.optional_stop = args.optional_stop;
    cfg.max_blocks = args.max_blocks;
    if let Some(path) = &args.workpiece {
        cfg.workpiece = read_workpiece(path)?.into();
    }
    Ok(cfg)
}

/// A JSON file's text; one that gives a key twice is refused naming it (`json_keys`: the last
/// would win without a word).
fn read_json_text(path: &Path) -> Result<String, Fail> {
    let text = std::fs::read_to_string(path).map_err(|e| Fail(format!("{}: {e}", path.display())))?;
    match crate::json_keys::duplicate_key(text.as_bytes()) {
        Some(twice) => Err(Fail(format!("{}: ambiguous: {twice}", path.display()))),
        None => Ok(text),
    }
}

/// A JSON file read as a `T` ([`read_json_text`]); what does not fit is a usage error naming
/// the file and the reason.
fn read_json<T: serde::de::DeserializeOwned>(path: &Path) -> Result<T, Fail> {
    serde_json::from_str(&read_json_text(path)?).map_err(|e| Fail(format!("{}: {e}", path.display())))
}

/// A `--workpiece` file (`fivex run`, `fivex fleet`): read, parsed and checked
/// (`Workpiece::check`); a file that is none is a usage error naming the file and the reason.
fn read_workpiece(path: &Path) -> Result<fivex_engine::workpiece::Workpiece, Fail> {
    let workpiece: fivex_engine::workpiece::Workpiece = read_json(path)?;
    workpiece.check().map_err(|e| Fail(format!("{}: {e}", path.display())))?;
    Ok(workpiece)
}

/// Load the tool offsets (`--tools`, or the default 1–99: length 100, radius 5), read and
/// checked as `fivex fleet` reads them (`read_tools`).
fn equip(mut interp: Interpreter, tools: Option<&Path>) -> Result<Interpreter, Fail> {
    let tools: Option<BTreeMap<u32, crate::fleet::Tool>> = match tools {
        Some(path) => Some(read_tools(path)?),
        None => None,
    };
    crate::fleet::equip(&mut interp, tools.as_ref()).map_err(Fail)?;
    Ok(interp)
}

/// A `--tools` file (`fivex run`/`interp`/`check`/`fleet`): read and parsed (`read_json`: a
/// number given twice, or an unknown field, is refused) and checked (`fleet::check_tools`); a
/// file that is none is a usage error naming the file and the reason.
fn read_tools(path: &Path) -> Result<BTreeMap<u32, crate::fleet::Tool>, Fail> {
    let tools = read_json(path)?;
    crate::fleet::check_tools(&tools).map_err(|e| Fail(format!("{}: {e}", path.display())))?;
    Ok(tools)
}

fn cmd_run(a: RunArgs) -> Result<i32, Fail> {
    let text = read_program(&a.program)?;
    let mut interp = interpreter(&text, &a.interp)?;
    if !(a.period_ms > 0.0 && a.period_ms.is_finite()) {
        return Err(Fail("--period-ms must be a positive number".into()));
    }
    let opts = RunOptions {
        period_s: if a.trace.is_some() { a.period_ms / 1000.0 } else { 0.0 },
        max_time_s: a.max_time_s,
        ..RunOptions::default()
    };
    if let Some(path) = &a.variables {
        if path.exists() {
            let values = load_retained(path)?;
            interp
                .state
                .load_retained(&values)
                .map_err(|_| Fail(format!("{}: not retained variables", path.display())))?;
        }
    }
    let axes: Vec<char> = interp.config().machine.axes.iter().map(|x| x.name).collect();
    let mut trace = match &a.trace {
        Some(path) => {
            Some(BufWriter::new(std::fs::File::create(path).map_err(|e| Fail(format!("{}: {e}", path.display())))?))
        }
        None => None,
    };
    let mut trace_error = None;
    let mut line = Vec::with_capacity(256);
    let result = run(&mut interp, &opts, |s| {
        if let (Some(w), None) = (trace.as_mut(), &trace_error) {
            line.clear();
            json::write_sample(&mut line, s, &axes);
            if let Err(e) = w.write_all(&line) {
                trace_error = Some(e);
            }
        }
    });
    if let Some(mut w) = trace {
        w.flush()?;
    }
    if let Some(e) = trace_error {
        return Err(Fail(format!("trace: {e}")));
    }
    if let Some(path) = &a.variables {
        let retained: BTreeMap<String, f64> =
            interp.state.retained_variables().into_iter().map(|(n, x)| (format!("#{n}"), x)).collect();
        std::fs::write(path, serde_json::to_string_pretty(&retained)?)
            .map_err(|e| Fail(format!("{}: {e}", path.display())))?;
    }
    let summary = crate::wire::RunSummary::of(&result, &axes);
    let status = if result.completed() { 0 } else { 1 };
    // A reader that went away (`| head`) is not an error of ours.
    match writeln!(std::io::stdout().lock(), "{}", serde_json::to_string_pretty(&summary)?) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(Fail(format!("stdout: {e}"))),
        _ => Ok(status),
    }
}

/// `{"#500": 1.5, …}` → the retained variable array (keys that are not retained are refused).
fn load_retained(path: &Path) -> Result<Vec<(u32, Option<f64>)>, Fail> {
    let map: BTreeMap<String, Option<f64>> = read_json(path)?;
    let mut values = Vec::with_capacity(map.len());
    for (key, value) in map {
        let n: u32 = key.strip_prefix('#').and_then(|k| k.parse().ok()).unwrap_or(0);
        if !fivex_engine::interp::State::is_retained(n) {
            return Err(Fail(format!(
                "{}: '{key}' is not a retained variable (#500–#999, #500000–#999999, #3002, #3901, #3902, FANUC #4006)",
                path.display()
            )));
        }
        values.push((n, value));
    }
    Ok(values)
}

fn cmd_interp(a: InterpArgs) -> Result<i32, Fail> {
    let text = read_program(&a.program)?;
    let mut interp = equip(Interpreter::new_incremental(config(&a.interp)?), a.interp.tools.as_deref())?;
    let axes: Vec<char> = interp.config().machine.axes.iter().map(|x| x.name).collect();
    // Three stages side by side: a parser thread hands the file over in parts (the first one
    // small, so interpretation starts at once), the interpreter runs on this thread, and a
    // writer thread formats the JSON.
    let (part_tx, part_rx) = std::sync::mpsc::sync_channel(2);
    let parser = std::thread::spawn(move || {
        let mut first_line = 1u32;
        let mut rest = text.as_str();
        // Parts end at a line end near these sizes: small first, so interpretation starts at once.
        // A Syntec `%@MACRO` line refuses the whole file before anything of it runs: such a
        // file comes as one part, so the interpreter sees the line before it starts.
        let mut part_bytes = if fivex_engine::lang::has_macro_format_line(&text) { usize::MAX } else { 32 * 1024 };
        while !rest.is_empty() {
            let end = rest.get(part_bytes..).and_then(|t| t.find('\n')).map_or(rest.len(), |i| part_bytes + i + 1);
            let (chunk, tail) = rest.split_at(end);
            let part = fivex_engine::lang::parse_part(chunk, first_line, first_line > 1);
            first_line += part.lines;
            if part_tx.send(part).is_err() {
                return;
            }
            rest = tail;
            part_bytes = part_bytes.max(512 * 1024);
        }
    });
    // Interpretation and JSON formatting run side by side: the interpreter hands batches of
    // canonical commands to a writer thread (bounded, so memory stays flat on long programs).
    const BATCH: usize = 4096;
    let (tx, rx) = std::sync::mpsc::sync_channel::<Vec<Canon>>(4);
    let (recycle_tx, recycle_rx) = std::sync::mpsc::channel::<Vec<Canon>>();
    let writer = std::thread::spawn(move || -> std::io::Result<()> {
        let stdout = std::io::stdout();
        let mut out = stdout.lock();
        let mut text = Vec::with_capacity(BATCH * 400);
        let mut json = json::CanonWriter::new(axes);
        for mut batch in rx {
            text.clear();
            for c in &batch {
                json.write(&mut text, c);
            }
            out.write_all(&text)?;
            batch.clear();
            let _ = recycle_tx.send(batch);
        }
        out.flush()
    });
    // The interpreter appends straight into the batch that goes to the writer; with the path
    // stages, into a step's own buffer that the stages turn into what they release.
    let mut batch = Vec::with_capacity(BATCH + 64);
    let mut stages = a.stages.then(|| (Pipeline::for_config(interp.config()), Vec::new()));
    let result = loop {
        let step = match &mut stages {
            None => interp.step(&mut batch),
            Some((pipeline, step_out)) => {
                let step = interp.step(step_out);
                let end = !matches!(step, Ok(Step::Continue | Step::NeedInput));
                let alarm = pipeline.process(step_out, end);
                batch.append(step_out);
                if let Some(alarm) = alarm {
                    break Err(alarm);
                }
                step
            }
        };
        match step {
            Ok(Step::Continue) => {}
            Ok(Step::NeedInput) => match part_rx.recv() {
                Ok(part) => interp.push_part(part),
                Err(_) => interp.finish(),
            },
            Ok(Step::Ended) => break Ok(()),
            Err(alarm) => break Err(alarm),
        }
        if batch.len() >= BATCH {
            let next = recycle_rx.try_recv().unwrap_or_else(|_| Vec::with_capacity(BATCH + 64));
            if tx.send(std::mem::replace(&mut batch, next)).is_err() {
                // The writer stopped (stdout closed): its error is reported below.
                batch.clear();
                break Ok(());
            }
        }
    };
    if !batch.is_empty() {
        let _ = tx.send(batch);
    }
    drop(tx);
    drop(part_rx);
    parser.join().map_err(|_| Fail("the parser thread failed".into()))?;
    let written = writer.join().map_err(|_| Fail("the output thread failed".into()))?;
    written.map_err(|e| Fail(format!("stdout: {e}")))?;
    // The process ends here: leave the programs' memory to the OS instead of freeing it block
    // by block.
    std::mem::forget(interp);
    match result {
        Ok(()) => Ok(0),
        Err(alarm) => {
            eprintln!("{}:{}: {} {}", a.program.display(), alarm.line, alarm.code, alarm.message);
            Ok(1)
        }
    }
}

fn cmd_check(a: CheckArgs) -> Result<i32, Fail> {
    let text = read_program(&a.program)?;
    let (machine, dialect) = load_machine(&a.machine, a.dialect)?;
    // (line, column, code, the text after the position)
    let mut lines: Vec<(u32, u32, String, String)> = fivex_engine::check::check(parse_file(&text), dialect)
        .into_iter()
        .map(|d| {
            let (code, message) = dialect.describe(&d.id);
            let text = format!("{code} {message}: {}", d.detail);
            (d.line, d.col, code, text)
        })
        .collect();
    let on_machine = a.machine.preset.is_some() || a.machine.machine.is_some();
    let file = parse_file(&text);
    // Without a machine the program is run on the default one for what hardly depends on
    // the machine: the alarms of cutter compensation, those of the program's own form or
    // geometry (`AlarmId::is_the_programs`: a radius off its arc, a nesting too deep …) and the
    // notices (a unit switched mid-program, FX1005 …); its other alarms are the stand-in's,
    // not the text's.
    let name = machine.name.clone();
    let mut cfg = Config::new(machine, dialect);
    cfg.max_blocks = CHECK_MAX_BLOCKS;
    let interp = equip(Interpreter::new(file, cfg), a.tools.as_deref())?;
    let mut notices = Vec::new();
    let (stop, unheld_call) = machine_alarm(interp, on_machine, &mut notices);
    // A run that never ended is reported on any machine: the blocks it did not reach were
    // not checked, and a program that may loop without end is no clean one.
    let budget = |s: &fivex_engine::check::RunStop| {
        matches!(s.id, Some(fivex_engine::alarm::AlarmId::BlockBudgetExceeded { .. }))
    };
    let of_the_program = |s: &fivex_engine::check::RunStop| s.id.as_ref().is_some_and(|id| id.is_the_programs());
    let reported = |s: &fivex_engine::check::RunStop| on_machine || s.compensating || budget(s) || of_the_program(s);
    let in_text = |s: &fivex_engine::check::RunStop| {
        lines.iter().any(|(line, _, code, _)| *line == s.alarm.line && *code == s.alarm.code)
    };
    if let Some(s) = stop.as_ref().filter(|s| !reported(s) && !in_text(s)) {
        // Not a diagnostic (the default machine's alarm is not the text's), but the blocks
        // after it were checked from the text only: a clean check must not hide that.
        eprintln!(
            "{}:{}: the run on {name} (the default machine) stopped here ({} {}): the blocks after \
             it are checked from the text only; give --preset or --machine to run the program on \
             its machine",
            a.program.display(),
            s.alarm.line,
            s.alarm.code,
            s.alarm.message
        );
    }
    let stop = stop.filter(reported);
    if let Some(line) = unheld_call.filter(|_| on_machine) {
        // Not a diagnostic (the control may hold the program), but the check is partial.
        eprintln!(
            "{}:{line}: the run on {name} ends at this call of a program the file does not hold: \
             the blocks after it are checked from the text only",
            a.program.display()
        );
    }
    // Where the text names the same alarm on that line it says it already; another alarm
    // there (the run stops on the line for a reason the text does not show) is shown too.
    if let Some(stop) = stop {
        let alarm = &stop.alarm;
        if !in_text(&stop) {
            let on = if on_machine { name } else { format!("{name} (the default machine)") };
            let detail = if budget(&stop) {
                format!(
                    "the run on {on} stopped after {CHECK_MAX_BLOCKS} blocks without reaching the end: \
                     the program may loop without end (a WHILE or GOTO that never leaves, M99 in the \
                     main program), and the blocks it did not reach are checked from the text only; \
                     a program meant to run longer can be run with `fivex run --max-blocks N`"
                )
            } else {
                format!("when run on {on}")
            };
            lines.push((alarm.line, 1, alarm.code.clone(), format!("{} {}: {detail}", alarm.code, alarm.message)));
        }
    }
    lines.extend(notices.into_iter().map(|n| (n.line, 1, n.code.clone(), format!("{} {}", n.code, n.message))));
    lines.sort_by_key(|&(line, col, ..)| (line, col));
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    for (line, col, _, text) in &lines {
        match writeln!(out, "{}:{line}:{col}: {text}", a.program.display()) {
            Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => break,
            other => other?,
        }
    }
    Ok(if lines.is_empty() { 0 } else { 1 })
}

/// How a program stops when the interpreter and the path stages run it on a machine (nothing
/// moves), if it does; the strokes are checked on the machine the caller named (`strokes`), not
/// on the default one. A call of a program the file does not hold is not an alarm here (a check
/// sees one file, the control has them all; a missing sequence number or a call without P
/// share FANUC's PS0078 but are errors of the file itself): the run ends there, and its line
/// is returned instead, as the lines after it were not run.
fn machine_alarm(
    mut interp: Interpreter,
    strokes: bool,
    notices: &mut Vec<fivex_engine::notice::Notice>,
) -> (Option<fivex_engine::check::RunStop>, Option<u32>) {
    match fivex_engine::check::run_noting(&mut interp, strokes, notices) {
        Some(s) if s.id == Some(fivex_engine::alarm::AlarmId::ProgramNotFound) => (None, Some(s.alarm.line)),
        stop => (stop, None),
    }
}
