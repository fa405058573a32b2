//! A controller's alarm and run history, as the database keeps it.

use super::ServiceError;
use crate::db::{self, AlarmRow, RunRow};
use crate::host::Hosted;

/// The latest `limit` alarms raised, newest first.
pub async fn alarms(db: &db::Db, hosted: &Hosted, limit: u32) -> Result<Vec<AlarmRow>, ServiceError> {
    Ok(db::alarm_history(db, &hosted.id, limit).await?)
}

/// The latest `limit` finished runs, newest first.
pub async fn runs(db: &db::Db, hosted: &Hosted, limit: u32) -> Result<Vec<RunRow>, ServiceError> {
    Ok(db::run_history(db, &hosted.id, limit).await?)
}
