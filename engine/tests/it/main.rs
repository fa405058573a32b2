//! The engine's integration tests, one module per subject, in one test binary (one link
//! instead of one per file). Shared helpers are `common`; proptest keeps the failing cases it
//! found under `proptest-regressions/`, one file per module, replayed first on every run.

mod common;

mod ai_contour;
mod alarms;
mod chains;
mod chamfer;
mod controller;
mod corner_rounding;
mod crc16i;
mod cutter;
mod cutting_point;
mod cycles;
mod data;
mod fast_path;
mod frames;
mod haas_core;
mod haas_cycles;
mod haas_five_axis;
mod hpcc;
mod incremental;
mod kinematic_speed;
mod leading_edge;
mod length_vector;
mod library;
mod macro_b;
mod manual;
mod manual_interrupt;
mod modes;
mod motion;
mod no_panic;
mod nurbs;
mod offsets;
mod operation;
mod preview;
mod probing;
mod report;
mod restart;
mod rollover;
mod smoke;
mod smoothing;
mod stop;
mod syntec_calls;
mod syntec_macro;
mod tcp;
mod tcp_random;
mod teach;
mod tool_side;
mod trace_tip;
mod twp;
mod unbuilt;
mod wse;
