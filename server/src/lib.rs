//! The fivex service and command line.
pub mod cli;
pub mod db;
pub mod machine_file;
pub mod serve;
