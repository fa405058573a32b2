//! Controllers as the service keeps them: created, changed, cloned and removed in the database
//! and the host together, and brought back at start-up.

use std::collections::HashMap;
use std::sync::Arc;

use fivex_engine::machine::MachineConfig;
use fivex_engine::Dialect;

use super::{parameters, workpiece, ServiceError};
use crate::db::{self, ControllerRow};
use crate::host::{now_rfc3339, Host, Hosted, Spec, MAX_SPEED};

/// What a new controller is made of, as a client gives it.
#[derive(Debug, Clone)]
pub struct NewController {
    pub name: String,
    /// A preset's name, or else
    pub preset: Option<String>,
    /// a machine document (a model or a vendor parameter list).
    pub machine: Option<serde_json::Value>,
    /// `fanuc` when none (or the parameter list's own).
    pub dialect: Option<String>,
    pub speed: Option<f64>,
    /// What is clamped on its table (none: nothing).
    pub workpiece: Option<fivex_engine::workpiece::Workpiece>,
}

/// A display name: trimmed, 1 to 200 characters, none a control character (NUL, a line end, a
/// tab, ESC, DEL, C1: a name is one line to show, and PostgreSQL's text cannot hold a NUL —
/// refused on both databases alike).
pub fn check_name(name: &str) -> Result<String, ServiceError> {
    let name = name.trim();
    if name.is_empty() || name.chars().count() > 200 {
        return Err(ServiceError::invalid("name must have 1 to 200 characters"));
    }
    if let Some(c) = name.chars().find(|c| c.is_control()) {
        return Err(ServiceError::invalid(format!(
            "name must not hold control characters (U+{:04X} at character {})",
            c as u32,
            name.chars().position(|d| d == c).unwrap_or(0) + 1
        )));
    }
    Ok(name.to_string())
}

fn check_speed(speed: f64) -> Result<f64, ServiceError> {
    if !(speed.is_finite() && speed > 0.0 && speed <= MAX_SPEED) {
        return Err(ServiceError::invalid(format!("speed must be above 0 and at most {MAX_SPEED}")));
    }
    Ok(speed)
}

fn machine_of(request: &NewController) -> Result<MachineConfig, ServiceError> {
    match (&request.preset, &request.machine) {
        (Some(preset), None) => MachineConfig::preset(preset).ok_or_else(|| {
            ServiceError::invalid(format!("unknown preset '{preset}' ({})", MachineConfig::PRESETS.join(", ")))
        }),
        (None, Some(machine)) => fivex_engine::machine_file::parse(&machine.to_string()).map_err(ServiceError::invalid),
        _ => Err(ServiceError::invalid("give exactly one of preset and machine")),
    }
}

/// A controller in reset state (AUTO, idle), kept in the database and hosted.
pub async fn create(db: &db::Db, host: &Host, request: NewController) -> Result<Arc<Hosted>, ServiceError> {
    let name = check_name(&request.name)?;
    let machine = machine_of(&request)?;
    // A parameter list gives its own dialect unless the request names one.
    let given: Option<fivex_engine::vendor::ParamFile> = request
        .machine
        .as_ref()
        .filter(|m| m.get("parameters").is_some())
        .and_then(|m| serde_json::from_value(m.clone()).ok());
    let dialect: Dialect = match (&request.dialect, &given) {
        (Some(d), _) => d.parse().map_err(ServiceError::invalid)?,
        (None, Some(file)) => file.dialect,
        (None, None) => Dialect::Fanuc,
    };
    let extra = match &given {
        Some(file) if file.dialect == dialect => parameters::extras(dialect, &machine, &file.parameters),
        _ => Default::default(),
    };
    // The list the controller will show must read back as it does after a change
    // (`parameters::change`), whatever the machine came from; without a list in its dialect
    // there is nothing to show.
    if let Ok(shown) = parameters::list(dialect, &machine, &extra) {
        parameters::shown_back(dialect, &machine.name, &shown.parameters)?;
    }
    let speed = check_speed(request.speed.unwrap_or(1.0))?;
    let workpiece_json = request.workpiece.as_ref().map(workpiece::checked_json).transpose()?;
    let row = ControllerRow {
        id: uuid::Uuid::new_v4().simple().to_string(),
        name: name.clone(),
        dialect: dialect.name().to_string(),
        machine_json: serde_json::to_string(&machine).map_err(|e| ServiceError::invalid(e.to_string()))?,
        created_at: now_rfc3339(),
    };
    let extra_json = serde_json::to_string(&extra).unwrap_or_else(|_| "{}".into());
    db::insert_controller_with(db, &row, speed, &extra_json, workpiece_json.as_deref()).await?;
    let machine_name = machine.name.clone();
    let hosted = Arc::new(Hosted::new(Spec {
        id: row.id.clone(),
        name,
        dialect,
        machine,
        created_at: row.created_at.clone(),
        speed,
    }));
    {
        let mut station = hosted.station();
        // Everything the request's document sets that fivex does not carry out (its unknown
        // fields too, which the stored model no longer holds).
        station.unmodelled = match &request.machine {
            Some(doc) => fivex_engine::machine_file::unmodelled(&doc.to_string()),
            None => parameters::unmodelled(dialect, &station.machine, &extra),
        };
        station.extra_parameters = extra;
        if let Some(w) = request.workpiece {
            // A new controller is at rest, and the boxes were checked above.
            let _ = station.controller.set_workpiece(w.into());
        }
    }
    host.add(hosted.clone());
    tracing::info!(id = %row.id, name = %row.name, machine = %machine_name, "controller created");
    Ok(hosted)
}

/// Renames `hosted` or changes its speed factor (`None`: as it is). The row stored holds both,
/// so changes take their turn (`Hosted::editing`, held across the write): a rename and a speed
/// change at once both stay.
pub async fn update(db: &db::Db, hosted: &Hosted, name: Option<&str>, speed: Option<f64>) -> Result<(), ServiceError> {
    let name = name.map(check_name).transpose()?;
    let speed = speed.map(check_speed).transpose()?;
    let _editing = hosted.editing().await;
    let name = name.unwrap_or_else(|| hosted.name());
    let speed = speed.unwrap_or_else(|| hosted.speed());
    db::update_controller(db, &hosted.id, &name, speed).await?;
    hosted.rename(name);
    hosted.set_speed(speed);
    Ok(())
}

/// Removes a controller with everything stored of it; its streams close.
/// Whether controller `id` is still stored: one that left this node's host and is stored moved
/// to another node of a cluster (deleted, it is not). A failed read counts as stored: "moved,
/// reconnect" is the answer a client can act on either way.
pub async fn still_stored(db: &db::Db, id: &str) -> bool {
    !matches!(db::controller(db, id).await, Ok(None))
}

pub async fn remove(db: &db::Db, host: &Host, hosted: &Hosted) -> Result<(), ServiceError> {
    db::delete_controller(db, &hosted.id).await?;
    host.remove(&hosted.id);
    tracing::info!(id = %hosted.id, "controller removed");
    Ok(())
}

/// A new controller named `name` with what `source` stores (machine, dialect, speed,
/// parameters, the workpiece, programs, retained variables, offsets; not its history), in
/// reset state.
pub async fn clone(db: &db::Db, host: &Host, source: &Hosted, name: &str) -> Result<Arc<Hosted>, ServiceError> {
    let name = check_name(name)?;
    let id = uuid::Uuid::new_v4().simple().to_string();
    if !db::clone_controller(db, &source.id, &id, &name, &now_rfc3339()).await? {
        return Err(ServiceError::NotFound(format!("no controller {}", source.id)));
    }
    let row = db::controller(db, &id).await?.ok_or_else(|| ServiceError::NotFound(format!("no controller {id}")))?;
    let settings = db::controller_settings(db).await?;
    let Some(hosted) = load(db, row, &settings).await? else {
        db::delete_controller(db, &id).await?;
        return Err(ServiceError::invalid("the source controller's machine cannot be loaded"));
    };
    let hosted = Arc::new(hosted);
    host.add(hosted.clone());
    tracing::info!(%id, from = %source.id, "controller cloned");
    Ok(hosted)
}

/// Every stored controller hosted again in reset state (one this version refuses is logged and
/// left in the database), after marking the fleet runs the last process left under way as
/// interrupted.
pub async fn restore(db: &db::Db, host: &Host) -> Result<(), sqlx::Error> {
    let settings = db::controller_settings(db).await?;
    super::fleet_runs::interrupt_unfinished(db).await?;
    for row in db::list_controllers(db).await? {
        if let Some(hosted) = load(db, row, &settings).await? {
            host.add(Arc::new(hosted));
        }
    }
    tracing::info!(controllers = host.len(), "controllers restored");
    Ok(())
}

/// A stored controller as the host runs it, in reset state with what it keeps (`None`, logged,
/// when this version refuses its machine or dialect).
pub async fn load(
    db: &db::Db,
    row: db::ControllerRow,
    settings: &HashMap<String, (f64, String)>,
) -> Result<Option<Hosted>, sqlx::Error> {
    let machine = match fivex_engine::machine_file::parse(&row.machine_json) {
        Ok(m) => m,
        Err(e) => {
            tracing::warn!(id = %row.id, error = %e, "stored controller not hosted: its machine is refused");
            return Ok(None);
        }
    };
    let Ok(dialect) = row.dialect.parse() else {
        tracing::warn!(id = %row.id, dialect = %row.dialect, "stored controller not hosted: unknown dialect");
        return Ok(None);
    };
    let retained = db::retained_variables(db, &row.id).await?;
    let row_id = row.id.clone();
    let hosted = Hosted::new(Spec {
        speed: settings.get(&row.id).map_or(1.0, |s| s.0),
        id: row.id,
        name: row.name,
        dialect,
        machine,
        created_at: row.created_at,
    });
    let (tools, work) = (db::tool_offsets(db, &row_id).await?, db::work_offsets(db, &row_id).await?);
    {
        let mut station = hosted.station();
        station.load_retained(&retained);
        station.load_offsets(&tools, &work);
        let extra = settings.get(&row_id).map_or("{}", |s| s.1.as_str());
        station.extra_parameters = serde_json::from_str(extra).unwrap_or_else(|e| {
            tracing::warn!(id = %row_id, error = %e, "stored extra parameters are not a parameter list");
            Default::default()
        });
        station.unmodelled = parameters::unmodelled(dialect, &station.machine.clone(), &station.extra_parameters);
    }
    // What is clamped on the table stays there through a restart.
    if let Some(w) = workpiece::stored(db, &row_id).await? {
        // A controller just made is at rest, and `stored` checked the boxes.
        let _ = hosted.station().controller.set_workpiece(w.into());
    }
    let times = db::operation_times(db, &row_id).await?;
    hosted.station().load_times(times);
    // Syntec Pr3014 = 2: the tilted working plane survives the restart.
    if let Some(json) = db::kept_plane(db, &row_id).await? {
        match serde_json::from_str(&json) {
            Ok(plane) => hosted.station().load_kept_plane(&plane),
            Err(e) => tracing::warn!(id = %row_id, error = %e, "stored tilted plane is not a plane"),
        }
    }
    Ok(Some(hosted))
}
