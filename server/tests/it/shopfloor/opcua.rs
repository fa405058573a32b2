//! The OPC UA server (tests being written).
