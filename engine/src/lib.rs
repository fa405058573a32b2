//! The pure engine of fivex.
//!
//! No IO, no threads, no wall clock: every input arrives as a value, time advances only when the
//! caller says so, and the same inputs give the same outputs bit for bit. See `ARCHITECTURE.md`.

pub mod alarm;
pub mod angle;
pub mod blend;
pub mod canon;
pub mod check;
pub mod chords;
pub mod controller;
pub mod cutting_point;
pub mod dialect;
pub mod geom;
mod golden;
pub mod interp;
pub mod kin;
pub mod lang;
pub mod machine;
pub mod machine_file;
pub mod motion;
pub mod notice;
pub mod nurbs;
pub mod pocket;
pub mod preview;
pub mod report;
pub mod run;
pub mod smoothing;
pub mod stage;
pub mod teach;
pub mod tip;
pub mod twp;
pub mod vendor;
pub mod workpiece;
pub mod wse;

pub use alarm::{Alarm, AlarmId};
pub use dialect::Dialect;
