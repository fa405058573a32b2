//! What is clamped on a controller's table (`fivex_engine::workpiece`): the boxes a G31 probe
//! touches. Kept in the database beside the controller (migration 0009), so it survives a
//! restart of the service and, with the controller, a parameter change. A change is told to the
//! controller's stream subscribers (`{"type": "workpiece", "boxes": […]}`).

use std::sync::Arc;

use fivex_engine::controller::Refusal;
use fivex_engine::workpiece::Workpiece;

use super::ServiceError;
use crate::db;
use crate::host::{Hosted, Message};

/// Why a workpiece change is refused while the axes move (the engine's `Refusal::Busy`).
const BUSY: &str = "the workpiece changes only at a block boundary: not while the axes move or a move is planned";

/// The workpiece as the controller has it.
pub fn of(hosted: &Hosted) -> Arc<Workpiece> {
    hosted.station().controller.workpiece().clone()
}

/// `workpiece` as stored: checked (`Workpiece::check`), as JSON.
pub fn checked_json(workpiece: &Workpiece) -> Result<String, ServiceError> {
    workpiece.check().map_err(ServiceError::invalid)?;
    serde_json::to_string(workpiece).map_err(|e| ServiceError::invalid(e.to_string()))
}

/// Puts `workpiece` on the controller's table: checked (else 422), only at a block boundary
/// (else 409, as machine lock), stored first so that a refusal of the database changes nothing.
pub async fn set(db: &db::Db, hosted: &Hosted, workpiece: Workpiece) -> Result<Arc<Workpiece>, ServiceError> {
    let json = checked_json(&workpiece)?;
    // One change of the controller's settings at a time: two at once could be stored in either
    // order, and the put-back below overwrite the other's.
    let _editing = hosted.editing().await;
    let old = {
        let station = hosted.station();
        if !station.controller.at_block_boundary() {
            return Err(ServiceError::Conflict(BUSY.into()));
        }
        station.controller.workpiece().clone()
    };
    if !db::save_workpiece(db, &hosted.id, &json).await? {
        return Err(ServiceError::NotFound(format!("no controller {}", hosted.id)));
    }
    let workpiece = Arc::new(workpiece);
    let refused = {
        let mut station = hosted.station();
        let refused = station.controller.set_workpiece(workpiece.clone());
        if refused.is_ok() {
            // Told while the station is locked, so that two changes reach every subscriber in
            // the order the controller took them.
            hosted.publish(vec![Message::workpiece(&workpiece)]);
        }
        refused
    };
    match refused {
        Ok(()) => Ok(workpiece),
        Err(refusal) => {
            // The axes began to move between the check and now: the stored one goes back.
            let old = serde_json::to_string(&*old).unwrap_or_else(|_| r#"{"boxes":[]}"#.into());
            db::save_workpiece(db, &hosted.id, &old).await?;
            Err(match refusal {
                Refusal::Busy => ServiceError::Conflict(BUSY.into()),
                other => ServiceError::invalid(format!("the controller refused the workpiece: {other:?}")),
            })
        }
    }
}

/// The workpiece stored for controller `id` (none: nothing on the table). A stored value this
/// version cannot read or refuses is logged and left out, as a refused machine is.
pub async fn stored(db: &db::Db, id: &str) -> Result<Option<Workpiece>, sqlx::Error> {
    let Some(json) = db::workpiece(db, id).await? else { return Ok(None) };
    let read = serde_json::from_str::<Workpiece>(&json).map_err(|e| e.to_string());
    match read.and_then(|w| w.check().map(|()| w)) {
        Ok(w) => Ok(Some(w)),
        Err(e) => {
            tracing::warn!(%id, error = %e, "stored workpiece not used: it is not a workpiece");
            Ok(None)
        }
    }
}
