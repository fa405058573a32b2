//! A controller's machine as its dialect's parameter list, and changing one parameter, which
//! puts a new machine under the controller as a power cycle would.

use fivex_engine::controller::RunState;
use fivex_engine::machine::MachineConfig;
use fivex_engine::vendor::{self, unmodelled::Unmodelled, Params, Value};
use fivex_engine::Dialect;

use super::ServiceError;
use crate::db;
use crate::host::station::run_state;
use crate::host::Hosted;

/// The dialect's list of a machine and what of it fivex does not carry out.
#[derive(Debug, Clone)]
pub struct ParameterSet {
    pub parameters: Params,
    pub unmodelled: Vec<Unmodelled>,
}

/// The dialect's list: the model's canonical parameters and, for the numbers the model does not
/// write, the extra ones kept as given.
pub fn list(dialect: Dialect, machine: &MachineConfig, extra: &Params) -> Result<ParameterSet, ServiceError> {
    let mut parameters = vendor::params_of(dialect, machine).map_err(|e| {
        ServiceError::Conflict(format!(
            "this machine has no {} parameter form: {}",
            dialect.name(),
            e.describe(dialect)
        ))
    })?;
    for (number, value) in &extra.0 {
        parameters.0.entry(*number).or_insert_with(|| value.clone());
    }
    let unmodelled = vendor::unmodelled::of_params(dialect, &parameters);
    Ok(ParameterSet { parameters, unmodelled })
}

/// What of the controller's machine (its model and the extra parameters kept beside it) fivex
/// does not carry out: of the dialect's list when the machine has one, else of the model.
pub fn unmodelled(dialect: Dialect, machine: &MachineConfig, extra: &Params) -> Vec<Unmodelled> {
    match list(dialect, machine, extra) {
        Ok(l) => vendor::unmodelled::of_params(dialect, &l.parameters),
        Err(_) => vendor::unmodelled::of_model(machine),
    }
}

/// What of `given` the model of `machine` does not write back: a control keeps every parameter it
/// is given, so these are stored beside the machine and shown with it.
pub fn extras(dialect: Dialect, machine: &MachineConfig, given: &Params) -> Params {
    let canonical = vendor::params_of(dialect, machine).unwrap_or_default();
    Params(given.0.iter().filter(|(n, _)| !canonical.0.contains_key(n)).map(|(n, v)| (*n, v.clone())).collect())
}

/// Whether every number of `value` is finite (JSON has no other numbers).
fn finite(value: &Value) -> bool {
    match value {
        Value::One(x) => x.is_finite(),
        Value::PerAxis(v) => v.iter().all(|x| x.is_finite()),
    }
}

/// The list a change leaves is the one the service shows and starts every later change from:
/// it must be finite numbers only (a non-finite one is written `null`, against the schema) that
/// describe a machine again (else every later change is refused). A value that only its
/// canonical form makes unusable is refused here instead: FANUC's list rounds to 1e-9, so a
/// stroke beyond about 1.8e299 comes back infinite.
pub(super) fn shown_back(dialect: Dialect, name: &str, shown: &Params) -> Result<(), ServiceError> {
    if let Some((number, _)) = shown.0.iter().find(|(_, v)| !finite(v)) {
        return Err(ServiceError::invalid(format!(
            "parameter {number} would read back as no number: the value is too large to keep"
        )));
    }
    vendor::machine_from(dialect, name, shown).map(|_| ()).map_err(|e| {
        ServiceError::invalid(format!(
            "the value cannot be kept: the list it leaves is refused ({})",
            e.describe(dialect)
        ))
    })
}

/// The controller's list now.
pub fn of(hosted: &Hosted) -> Result<ParameterSet, ServiceError> {
    let station = hosted.station();
    list(hosted.dialect, &station.machine, &station.extra_parameters)
}

/// Sets parameter `number` to `value`: the new set must describe a machine that works (else the
/// vendor's alarm), and nothing may run; the controller restarts on it in reset state and the
/// machine is stored. The whole list after the change.
pub async fn set(db: &db::Db, hosted: &Hosted, number: u32, value: Value) -> Result<ParameterSet, ServiceError> {
    if !finite(&value) {
        return Err(ServiceError::invalid("parameter values must be finite numbers"));
    }
    // One change of this controller's settings at a time: a second one read before this one took
    // effect would undo it, and the two database writes could land in either order.
    let _editing = hosted.editing().await;
    let (current, extra) = {
        let station = hosted.station();
        (station.machine.clone(), station.extra_parameters.clone())
    };
    let mut parameters = list(hosted.dialect, &current, &extra)?.parameters;
    parameters.0.insert(number, value);
    let machine = vendor::machine_from(hosted.dialect, &current.name, &parameters)
        .map_err(|e| ServiceError::invalid(e.describe(hosted.dialect)))?;
    let busy = || ServiceError::Conflict("parameters change only while nothing runs".into());
    if run_state(&hosted.station().controller) != RunState::Idle {
        return Err(busy());
    }
    let stored = |machine: &MachineConfig, extra: &Params| {
        let json = serde_json::to_string(machine).map_err(|e| ServiceError::invalid(e.to_string()))?;
        Ok::<_, ServiceError>((json, serde_json::to_string(extra).unwrap_or_else(|_| "{}".into())))
    };
    let after = extras(hosted.dialect, &machine, &parameters);
    let answer = list(hosted.dialect, &machine, &after)?;
    shown_back(hosted.dialect, &current.name, &answer.parameters)?;
    let (json, extra_json) = stored(&machine, &after)?;
    db::update_machine(db, &hosted.id, &json, &extra_json).await?;
    // Checked again where the change takes effect: a cycle start while the machine was being
    // stored runs on the machine it started on (restarting the controller under it, as fivex
    // did, ended the program unasked), and the stored machine goes back.
    let applied = {
        let mut station = hosted.station();
        let idle = run_state(&station.controller) == RunState::Idle;
        if idle {
            station.replace_machine(machine, hosted.dialect);
            station.unmodelled = answer.unmodelled.clone();
            station.extra_parameters = after;
        }
        idle
    };
    if !applied {
        let (json, extra_json) = stored(&current, &extra)?;
        db::update_machine(db, &hosted.id, &json, &extra_json).await?;
        return Err(busy());
    }
    tracing::info!(id = %hosted.id, number, "parameter changed; controller restarted on the new machine");
    Ok(answer)
}
