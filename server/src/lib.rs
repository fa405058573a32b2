//! The fivex service and command line.
pub mod api;
pub mod assets;
pub mod cli;
pub mod db;
pub mod fleet;
pub mod host;
pub mod listen;
pub mod machine_file;
pub mod serve;
pub mod tools;
