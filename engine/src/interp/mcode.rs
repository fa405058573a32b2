//! The M codes the interpreter acts on, by name (an M code is held as its number: `M98` is 98).
//! Any other M code is passed on as `CanonKind::Aux`.

/// Program stop.
pub const M00: u32 = 0;
/// Optional stop.
pub const M01: u32 = 1;
/// Program end.
pub const M02: u32 = 2;
/// Spindle CW.
pub const M03: u32 = 3;
/// Spindle CCW.
pub const M04: u32 = 4;
/// Spindle stop.
pub const M05: u32 = 5;
/// Tool change.
pub const M06: u32 = 6;
/// Mist coolant.
pub const M07: u32 = 7;
/// Flood coolant.
pub const M08: u32 = 8;
/// Coolant off.
pub const M09: u32 = 9;
/// Spindle orientation (the shifting boring cycles G76/G87 give it).
pub const M19: u32 = 19;
/// Program end and rewind.
pub const M30: u32 = 30;
/// Haas: alarm if the last skip move (G31) touched / did not touch (`interp::skip`).
pub const M78: u32 = 78;
pub const M79: u32 = 79;
/// Haas: local subprogram call (`M97 P<n> L<count>`: the block N<n> of the same program). In
/// the FANUC and Syntec dialects an ordinary M code.
pub const M97: u32 = 97;
/// Subprogram call.
pub const M98: u32 = 98;
/// Return from a subprogram (in the main program: start it again).
pub const M99: u32 = 99;
/// Subprogram call (FANUC: from an external device; fivex calls it as M98).
pub const M198: u32 = 198;

/// The subprogram calls.
pub const SUBPROGRAM_CALLS: [u32; 2] = [M98, M198];

/// A subprogram call or the return from one (its P and L are the call's).
pub fn call_or_return(m: u32) -> bool {
    SUBPROGRAM_CALLS.contains(&m) || m == M99
}
