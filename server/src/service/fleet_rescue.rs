//! Fleet runs that outlive the node collecting them (issue 23; docs/fleet.md "Over NATS",
//! docs/cluster.md). On a cluster with a shared database, every beat each node
//!
//! - stops collecting the runs another node has claimed (this node was cut off from NATS long
//!   enough to leave the cluster): they are not ended here;
//! - looks for the runs under way in the database whose collector is gone
//!   (`crate::fleet_lease`: killed, stopped cleanly, or this node before a restart), claims
//!   each (exactly one node wins) and takes it over ([`adopt`]): the results recorded stay, those
//!   computed meanwhile are read from the results stream, the jobs lost (neither on the queue
//!   nor answered: the submitter died while it published them) are published again, and the
//!   run ends on this node like one submitted here.
//!
//! A stored run is taken over from its request: the machines are built again from it as the
//! submitting node built them (`cluster::Source::requested`).

use std::collections::BTreeMap;

use serde::Deserialize;
use serde_json::Value;

use super::fleet_runs::{self, Execution, Remote, Runs, TAKEN};
use crate::cluster::{self, Job, Source};
use crate::db::{self, FleetRunRow};
use crate::fleet::{Entry, Options, Tool};
use crate::fleet_lease::Leases;

/// Starts the beat on this node's fleet runs (a node of a cluster with `--nats`).
pub fn start(db: db::Db, runs: Runs) {
    let Some(remote) = runs.remote().cloned() else { return };
    let Some(leases) = remote.leases.clone() else { return };
    tokio::spawn(async move {
        sweep(&db, &leases).await;
        let mut beat = tokio::time::interval(crate::fleet_lease::BEAT);
        beat.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
        loop {
            beat.tick().await;
            if runs.stopping() {
                break;
            }
            if let Err(e) = once(&db, &runs, &remote, &leases).await {
                tracing::warn!(error = %e, "fleet runs of the cluster not looked after");
            }
        }
    });
}

/// The collector keys of runs that are over (a node died between storing a run's end and
/// purging its key) leave the bucket.
async fn sweep(db: &db::Db, leases: &Leases) {
    let Ok(keys) = leases.runs().await else { return };
    for run in keys {
        if let Ok(Some(row)) = db::fleet_run(db, &run).await {
            if matches!(row.status.as_str(), "queued" | "running") {
                continue;
            }
        }
        leases.end(&run).await;
    }
}

/// One beat (see the module's description).
async fn once(db: &db::Db, runs: &Runs, remote: &Remote, leases: &Leases) -> Result<(), String> {
    let _claiming = runs.claims().lock().await;
    for id in runs.ids() {
        if let Some(node) = leases.holder(&id).await?.node {
            if node != leases.node() {
                tracing::warn!(%id, %node, "fleet run claimed by another node: no longer collected here");
                runs.stop(&id, TAKEN);
            }
        }
    }
    let under_way = db::unfinished_fleet_runs(db).await.map_err(|e| format!("cannot list the fleet runs: {e}"))?;
    for id in under_way {
        if runs.has(&id) || runs.stopping() {
            continue;
        }
        let holder = leases.holder(&id).await?;
        if !leases.free(&holder) || !leases.claim(&id, holder.revision).await {
            continue;
        }
        if let Err(e) = adopt(db, runs, remote, &id, holder.node.as_deref()).await {
            // Another node, or this one at its next beat, tries again.
            tracing::warn!(%id, error = %e, "fleet run not taken over");
            leases.release(&id).await;
        }
    }
    Ok(())
}

/// Takes over run `id`, claimed by this node from `from`: collected here from where it is.
async fn adopt(db: &db::Db, runs: &Runs, remote: &Remote, id: &str, from: Option<&str>) -> Result<(), String> {
    let Some(leases) = &remote.leases else { return Ok(()) };
    let row = db::fleet_run(db, id).await.map_err(|e| format!("cannot read the run: {e}"))?;
    let Some(row) = row.filter(|r| matches!(r.status.as_str(), "queued" | "running")) else {
        // Ended meanwhile (its collector stored it before it purged its key).
        leases.end(id).await;
        return Ok(());
    };
    let (entries, sources, opts) = match rebuild(&row) {
        Ok(plan) => plan,
        Err(e) => {
            let why = format!("node {} cannot take it over: {e}", leases.node());
            fleet_runs::end_elsewhere(db, remote, &row, "interrupted", Some(why)).await;
            return Ok(());
        }
    };
    let total = entries.len();
    let results = fleet_runs::recorded(db, id, total).await.map_err(|e| format!("cannot read its results: {e}"))?;
    let missing: Vec<usize> = (0..total).filter(|&i| results[i].is_none()).collect();
    let lost = cluster::lost_jobs(&remote.nats, id, &missing).await?;
    let jobs: Vec<Job> = Job::all(id, &row.program, &entries, sources, &opts)
        .into_iter()
        .filter(|job| lost.contains(&job.index))
        .collect();
    let names: Vec<String> = entries.iter().map(|e| e.name.clone()).collect();
    if row.status == "queued" {
        db::start_fleet_run(db, id).await.map_err(|e| format!("cannot store its start: {e}"))?;
    }
    let progress = fleet_runs::progress_of(id, "running", &names, &results);
    let Some(adopted) = runs.adopt(id, progress) else { return Err("the service stops".into()) };
    tracing::info!(
        %id,
        from = from.unwrap_or("none"),
        recorded = total - missing.len(),
        republished = jobs.len(),
        "fleet run taken over: collected here"
    );
    let run = Execution {
        db: db.clone(),
        runs: runs.clone(),
        id: id.to_string(),
        program: row.program,
        entries,
        sources: Vec::new(),
        opts: Options { cancel: Some(adopted.cancel), ..opts },
        tx: adopted.tx,
        stopped: adopted.stopped,
    };
    tokio::spawn(fleet_runs::collect_remote(run, remote.clone(), jobs, results));
    Ok(())
}

/// What `POST /fleet/runs` stored of a request, as far as a run over NATS uses it (a run over
/// NATS names no existing controller).
#[derive(Deserialize)]
struct Asked {
    #[serde(default)]
    presets: Vec<String>,
    #[serde(default)]
    machines: Vec<Value>,
    #[serde(default)]
    library: Vec<String>,
    #[serde(default)]
    controllers: Vec<String>,
    dialect: Option<String>,
    tools: Option<BTreeMap<u32, Tool>>,
    workpiece: Option<fivex_engine::workpiece::Workpiece>,
    #[serde(default)]
    report: bool,
}

/// The machines of a stored run, where each comes from, and its options, built again from its
/// request as the submitting node built them.
fn rebuild(row: &FleetRunRow) -> Result<(Vec<Entry>, Vec<Source>, Options), String> {
    let asked: Asked =
        serde_json::from_str(&row.request_json).map_err(|e| format!("its request does not read: {e}"))?;
    if !asked.controllers.is_empty() {
        return Err("it names existing controllers".into());
    }
    let dialect = match &asked.dialect {
        Some(d) => d.parse()?,
        None => fivex_engine::Dialect::Fanuc,
    };
    let sources = Source::requested(&asked.presets, &asked.machines, &asked.library);
    let entries = sources.iter().map(|s| s.entry(dialect)).collect::<Result<Vec<_>, _>>()?;
    if entries.len() != row.machines as usize {
        return Err(format!("its request names {} machines, the run {}", entries.len(), row.machines));
    }
    // Checked when it was posted; checked again, as the tools are by the nodes.
    if let Some(w) = &asked.workpiece {
        w.check().map_err(|e| format!("its workpiece: {e}"))?;
    }
    let workpiece = asked.workpiece.map(std::sync::Arc::new);
    Ok((entries, sources, Options { tools: asked.tools, report: asked.report, workpiece, ..Options::default() }))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(request: Value, machines: u32) -> FleetRunRow {
        FleetRunRow {
            id: "r".into(),
            created_at: String::new(),
            finished_at: None,
            status: "running".into(),
            machines,
            completed: 0,
            alarms: 0,
            program: "M30\n".into(),
            request_json: request.to_string(),
            results_json: None,
        }
    }

    #[test]
    fn a_stored_request_gives_the_machines_back_in_order() {
        let document = serde_json::from_str::<Value>(crate::fleet::LIBRARY[0].1).unwrap();
        let request = serde_json::json!({"program": "M30\n", "presets": ["mill3", "head-bc"], "machines": [document],
            "library": ["trunnion-ac-120"], "dialect": "syntec", "tools": {"3": {"length": 50.0, "radius": 2.0}}, "report": true});
        let (entries, sources, opts) = rebuild(&row(request, 4)).unwrap();
        let names: Vec<&str> = entries.iter().map(|e| e.name.as_str()).collect();
        assert_eq!(names[..2], ["mill3", "head-bc"]);
        assert_eq!(names[3], "trunnion-ac-120");
        assert_eq!(sources[0], Source::Preset("mill3".into()));
        assert_eq!(sources[3], Source::Library("trunnion-ac-120".into()));
        assert!(opts.report);
        assert_eq!(opts.tools.unwrap()[&3].length, 50.0);
        assert!(opts.workpiece.is_none(), "none asked for: nothing on the tables");
        // The run's workpiece comes back with it, checked again.
        let block = serde_json::json!({"boxes": [{"min": [12.0, 8.0, -20.0], "max": [62.0, 48.0, -3.0]}]});
        let (_, _, opts) =
            rebuild(&row(serde_json::json!({"program": "M30\n", "presets": ["mill3"], "workpiece": block}), 1))
                .unwrap();
        assert_eq!(serde_json::to_value(&*opts.workpiece.unwrap()).unwrap(), block);
        let flat = serde_json::json!({"boxes": [{"min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0]}]});
        let refused =
            rebuild(&row(serde_json::json!({"program": "M30\n", "presets": ["mill3"], "workpiece": flat}), 1));
        assert!(refused.unwrap_err().contains("its workpiece: box 0"));
        // The whole library, in name order.
        let (entries, _, _) = rebuild(&row(
            serde_json::json!({"program": "M30\n", "library": ["*"]}),
            crate::fleet::LIBRARY.len() as u32,
        ))
        .unwrap();
        assert_eq!(entries.len(), crate::fleet::LIBRARY.len());
        // What cannot be taken over says why.
        let refused = rebuild(&row(serde_json::json!({"program": "M30\n", "controllers": ["c1"]}), 1));
        assert!(refused.unwrap_err().contains("controllers"));
        let refused = rebuild(&row(serde_json::json!({"program": "M30\n", "presets": ["nope"]}), 1));
        assert!(refused.is_err());
        assert!(rebuild(&row(serde_json::json!({"program": "M30\n", "presets": ["mill3"]}), 2)).is_err());
    }
}
