//! The MTConnect agent (tests being written).
