//! Controllers as the service keeps them: bringing the stored ones back at start-up.

use std::collections::HashMap;
use std::sync::Arc;

use crate::db;
use crate::host::{Host, Hosted, Spec};

/// Every stored controller hosted again in reset state (one this version refuses is logged and
/// left in the database), after marking the fleet runs the last process left under way as
/// interrupted.
pub async fn restore(db: &db::Db, host: &Host) -> Result<(), sqlx::Error> {
    let settings = db::controller_settings(db).await?;
    db::interrupt_fleet_runs(db).await?;
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
        station.unmodelled =
            crate::api::parameters::unmodelled(dialect, &station.machine.clone(), &station.extra_parameters);
    }
    // Syntec Pr3014 = 2: the tilted working plane survives the restart.
    if let Some(json) = db::kept_plane(db, &row_id).await? {
        match serde_json::from_str(&json) {
            Ok(plane) => hosted.station().load_kept_plane(&plane),
            Err(e) => tracing::warn!(id = %row_id, error = %e, "stored tilted plane is not a plane"),
        }
    }
    Ok(Some(hosted))
}
