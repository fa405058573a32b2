//! The fivex service and command line.
pub mod api;
pub mod assets;
pub mod auth;
pub mod cli;
pub mod content_type;
pub mod db;
pub mod fleet;
pub mod host;
pub mod http;
pub mod json_errors;
pub mod listen;
pub mod openapi_doc;
pub mod origin;
pub mod serve;
pub mod service;
pub mod tools;
pub mod wire;
