//! What an operator sets on a controller that the database keeps: macro variables (the
//! retained ones), tool offsets and work offsets. Each is stored first, then set in the
//! controller, so a refusal of the database changes nothing.

use fivex_engine::controller::RunState;
use serde_json::{Map, Value};

use super::ServiceError;
use crate::db::{self, ToolRow};
use crate::host::station::tool_row;
use crate::host::stream::Message;
use crate::host::Hosted;

/// Sets macro variable `number` (`None`: vacant) or input signal #1000–#1035 (`None`: 0), and
/// tells the controller's subscribers.
pub async fn set_variable(db: &db::Db, hosted: &Hosted, number: u32, value: Option<f64>) -> Result<(), ServiceError> {
    let signal = (1000..=1035).contains(&number);
    if !signal && !matches!(number, 100..=199 | 500..=999 | 100_000..=199_999 | 500_000..=999_999) {
        return Err(ServiceError::invalid(format!(
            "#{number} is not writable here (#100–#199, #500–#999, #100000–#199999, #500000–#999999, \
             input signals #1000–#1035)"
        )));
    }
    if value.is_some_and(|v| !v.is_finite()) {
        return Err(ServiceError::invalid("the value must be a finite number or null"));
    }
    if fivex_engine::interp::State::is_retained(number) {
        db::save_variables(db, &hosted.id, &[(number, value)]).await?;
    }
    {
        let mut station = hosted.station();
        let state = &mut station.controller.interpreter_mut().state;
        let set = if signal {
            state.signals.set_input(number, value.unwrap_or(0.0))
        } else {
            state.set_common_variable(number, value)
        };
        set.map_err(|_| ServiceError::invalid(format!("#{number}: not a value it can take")))?;
        station.variable_saved(number, value);
    }
    hosted.publish(vec![Message::variables(&[(number, value)])]);
    Ok(())
}

/// An offset value: finite and below 1e6 in size.
fn finite(v: f64, what: &str) -> Result<f64, ServiceError> {
    if v.is_finite() && v.abs() < 1.0e6 {
        Ok(v)
    } else {
        Err(ServiceError::invalid(format!("{what} must be a finite number below 1e6 in size")))
    }
}

/// A corner radius: an offset value (`finite`) that is not negative.
fn corner_radius(v: f64) -> Result<f64, ServiceError> {
    if v.is_finite() && (0.0..1.0e6).contains(&v) {
        Ok(v)
    } else {
        Err(ServiceError::invalid("corner_radius must be a finite number from 0 to below 1e6"))
    }
}

/// Tool offset `number` (1–999) as it is now.
pub fn tool_offset(hosted: &Hosted, number: u32) -> Result<ToolRow, ServiceError> {
    hosted
        .station()
        .controller
        .interpreter()
        .state
        .offsets
        .tool(number)
        .filter(|_| number >= 1)
        .map(|t| tool_row(number, t))
        .ok_or_else(|| ServiceError::invalid(format!("tool offset number {number} is outside 1–999")))
}

/// A change of a tool offset: the values given, the others as they are.
#[derive(Debug, Clone, Copy, Default)]
pub struct ToolChange {
    pub length: Option<f64>,
    pub length_wear: Option<f64>,
    pub radius: Option<f64>,
    pub radius_wear: Option<f64>,
    pub corner_radius: Option<f64>,
}

/// Changes tool offset `number`; the offset after the change.
pub async fn set_tool_offset(
    db: &db::Db,
    hosted: &Hosted,
    number: u32,
    change: ToolChange,
) -> Result<ToolRow, ServiceError> {
    let current = tool_offset(hosted, number)?;
    let row = ToolRow {
        number,
        length: finite(change.length.unwrap_or(current.length), "length")?,
        length_wear: finite(change.length_wear.unwrap_or(current.length_wear), "length_wear")?,
        radius: finite(change.radius.unwrap_or(current.radius), "radius")?,
        radius_wear: finite(change.radius_wear.unwrap_or(current.radius_wear), "radius_wear")?,
        corner_radius: corner_radius(change.corner_radius.unwrap_or(current.corner_radius))?,
    };
    db::save_tool_offsets(db, &hosted.id, &[row]).await?;
    let mut station = hosted.station();
    if let Some(t) = station.controller.interpreter_mut().state.offsets.tool_mut(number) {
        (t.h_geometry, t.h_wear, t.d_geometry, t.d_wear, t.corner_radius) =
            (row.length, row.length_wear, row.radius, row.radius_wear, row.corner_radius);
    }
    station.offsets_saved();
    Ok(row)
}

/// Changes the axes `axes` names (letter: number) of work offset `slot`, only while nothing
/// runs; the offset after the change, per axis letter.
pub async fn set_work_offset(
    db: &db::Db,
    hosted: &Hosted,
    slot: usize,
    axes: &Map<String, Value>,
) -> Result<Map<String, Value>, ServiceError> {
    let (machine, mut values) = {
        let station = hosted.station();
        let values = station.controller.interpreter().state.offsets.work(slot)[..station.machine.axes.len()].to_vec();
        (station.machine.clone(), values)
    };
    for (letter, value) in axes {
        let index = machine
            .axes
            .iter()
            .position(|a| a.name.to_string().eq_ignore_ascii_case(letter))
            .ok_or_else(|| ServiceError::invalid(format!("the machine has no axis {letter}")))?;
        let v = value.as_f64().ok_or_else(|| ServiceError::invalid(format!("{letter} must be a number")))?;
        values[index] = finite(v, letter)?;
    }
    if hosted.station().controller.run_state() != RunState::Idle {
        return Err(ServiceError::Conflict("work offsets change only while nothing runs".into()));
    }
    db::save_work_offsets(db, &hosted.id, &[(slot, values.clone())]).await?;
    let mut station = hosted.station();
    let work = station.controller.interpreter_mut().state.offsets.work_mut(slot);
    work[..values.len()].copy_from_slice(&values);
    let shown = crate::host::stream::axes(&machine, work);
    station.offsets_saved();
    station.controller.offsets_changed();
    Ok(shown)
}
