//! The fivex service and command line.
pub mod cli;
pub mod db;
pub mod serve;
