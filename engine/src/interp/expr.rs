//! Expression evaluation with FANUC's vacant (`#0`, "null") rules.
//!
//! A value is `Option<f64>`: `None` is vacant. A lone variable reference (also bracketed or
//! negated) keeps vacancy; arithmetic and functions read a vacant operand as 0; `EQ`/`NE` tell
//! vacant from 0 while `GT GE LT LE` read it as 0.

use crate::alarm::AlarmId;
use crate::angle::sin_cos_deg;
use crate::lang::{BinOp, Expr, Func, Func2};

pub type Value = Option<f64>;

/// Parameters that change what functions return.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ExprSettings {
    /// FANUC parameter NAT (6004#0): ATAN in (-180, 180] and ASIN in [-90, 90] instead of
    /// [0, 360) and 270…90.
    pub nat: bool,
    /// Least input increment for ADP, mm (or inch in G20): 0.001 for IS-B metric.
    pub increment: f64,
    /// Steps per unit that `ROUND` rounds to: 1 (a whole number) in macro statements; in an NC
    /// address, the address's least input increment (1000 for 0.001 mm), as FANUC's ROUND in
    /// NC statement addresses does. 0 reads as 1.
    pub round_steps: f64,
    /// The Syntec dialect: a division whose answer Syntec's integer division may change is
    /// refused ([`syntec_division_differs`]).
    pub syntec_division: bool,
    /// The Syntec dialect: POW's base may not be negative ([`AlarmId::NegativePowerBase`]).
    pub syntec_pow: bool,
}

/// `x` rounded half away from zero to a multiple of `1 / steps` (steps 1000: 0.001). A value
/// that lies within 1e-9 step of a half is a half: a decimal like 1.2345, stored as
/// 1.23449999…, rounds as written (to 1.235), not as stored.
pub fn round_to(x: f64, steps: f64) -> f64 {
    let steps = if steps > 0.0 { steps } else { 1.0 };
    let y = (x * steps).abs();
    let k = if (y.fract() - 0.5).abs() < 1e-9 { y.trunc() + 1.0 } else { y.round() };
    (k / steps).copysign(x)
}

/// Read access to variables, so evaluation does not depend on where they live.
pub trait Variables {
    fn read(&self, number: u32) -> Result<Value, AlarmId>;
}

/// The variable number an `#[expr]` designates: the value rounded to an integer; vacant is #0.
pub fn var_number(v: Value) -> Result<u32, AlarmId> {
    let x = v.unwrap_or(0.0).round();
    if !(0.0..=u32::MAX as f64).contains(&x) {
        return Err(AlarmId::VariableOutOfRange);
    }
    Ok(x as u32)
}

pub fn eval(e: &Expr, vars: &impl Variables, s: &ExprSettings) -> Result<Value, AlarmId> {
    Ok(match e {
        Expr::Num { value, .. } => Some(*value),
        Expr::Var(n) => vars.read(*n)?,
        Expr::IndirectVar(inner) => vars.read(var_number(eval(inner, vars, s)?)?)?,
        Expr::Bracket(inner) => eval(inner, vars, s)?,
        Expr::Neg(inner) => eval(inner, vars, s)?.map(|x| -x),
        Expr::Binary(op, a, b) => {
            let (x, y) = (eval(a, vars, s)?, eval(b, vars, s)?);
            if *op == BinOp::Div && s.syntec_division && syntec_division_differs(a, x, b, y) {
                return Err(AlarmId::AddressNotBuilt);
            }
            Some(finite(binary(*op, x, y)?)?)
        }
        Expr::Func(f, a) => Some(finite(func(*f, eval(a, vars, s)?.unwrap_or(0.0), s)?)?),
        Expr::Func2(f, a, b) => {
            let a = eval(a, vars, s)?.unwrap_or(0.0);
            let b = eval(b, vars, s)?.unwrap_or(0.0);
            Some(finite(func2(*f, a, b, s)?)?)
        }
    })
}

/// Whether Syntec's `/` may answer otherwise than fivex's: Syntec divides two integers (numbers
/// written without a decimal point, and their results) as integers and truncates (the Syntec
/// MACRO syntax handbook, §3.4: `1 / 2` is 0, `1. / 2` is 0.5), fivex has no integer type. So:
/// both values whole, their quotient not (a zero divisor is the zero divide alarm), and neither
/// operand a number written with a decimal point — a variable's or an expression's type fivex
/// cannot tell (`docs/dialects.md`, "The Syntec macro language").
pub fn syntec_division_differs(a: &Expr, x: Value, b: &Expr, y: Value) -> bool {
    let (x, y) = (x.unwrap_or(0.0), y.unwrap_or(0.0));
    let quotient = x / y;
    x.fract() == 0.0
        && y.fract() == 0.0
        && quotient.is_finite()
        && quotient.fract() != 0.0
        && !written_with_point(a)
        && !written_with_point(b)
}

/// A number written with a decimal point, also signed or bracketed (`-7.`, `[7.]`): a real to
/// Syntec whatever the other operand is.
fn written_with_point(e: &Expr) -> bool {
    match e {
        Expr::Num { decimal_point, .. } => *decimal_point,
        Expr::Neg(inner) | Expr::Bracket(inner) => written_with_point(inner),
        _ => false,
    }
}

/// Evaluate a condition (IF, WHILE): true when the value is non-zero.
pub fn truth(v: Value) -> bool {
    v.is_some_and(|x| x != 0.0)
}

fn finite(x: f64) -> Result<f64, AlarmId> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(AlarmId::FloatOverflow)
    }
}

fn bool_value(b: bool) -> f64 {
    if b {
        1.0
    } else {
        0.0
    }
}

/// The integer value AND/OR/XOR/MOD work on (rounded half away from zero).
fn integer(x: f64) -> Result<i64, AlarmId> {
    let r = x.round();
    if r.abs() > i64::MAX as f64 / 2.0 {
        return Err(AlarmId::FloatOverflow);
    }
    Ok(r as i64)
}

fn binary(op: BinOp, a: Value, b: Value) -> Result<f64, AlarmId> {
    let (x, y) = (a.unwrap_or(0.0), b.unwrap_or(0.0));
    Ok(match op {
        BinOp::Add => x + y,
        BinOp::Sub => x - y,
        BinOp::Mul => x * y,
        BinOp::Div => {
            if y == 0.0 {
                return Err(AlarmId::ZeroDivide);
            }
            x / y
        }
        BinOp::Mod => {
            let (i, j) = (integer(x)?, integer(y)?);
            if j == 0 {
                return Err(AlarmId::ZeroDivide);
            }
            (i % j) as f64
        }
        BinOp::And => (integer(x)? & integer(y)?) as f64,
        BinOp::Or => (integer(x)? | integer(y)?) as f64,
        BinOp::Xor => (integer(x)? ^ integer(y)?) as f64,
        BinOp::Eq => bool_value(a == b),
        BinOp::Ne => bool_value(a != b),
        BinOp::Gt => bool_value(x > y),
        BinOp::Ge => bool_value(x >= y),
        BinOp::Lt => bool_value(x < y),
        BinOp::Le => bool_value(x <= y),
    })
}

/// Map an angle in (-180, 180] to the dialect's range: [0, 360) unless NAT.
fn angle_range(deg: f64, s: &ExprSettings) -> f64 {
    if s.nat || deg >= 0.0 {
        deg
    } else {
        deg + 360.0
    }
}

fn func(f: Func, x: f64, s: &ExprSettings) -> Result<f64, AlarmId> {
    Ok(match f {
        Func::Sin => sin_cos_deg(x).0,
        Func::Cos => sin_cos_deg(x).1,
        Func::Tan => {
            let (sin, cos) = sin_cos_deg(x);
            if cos == 0.0 {
                return Err(AlarmId::ArgumentOutOfRange);
            }
            sin / cos
        }
        Func::Asin => {
            if !(-1.0..=1.0).contains(&x) {
                return Err(AlarmId::ArgumentOutOfRange);
            }
            angle_range(x.asin().to_degrees(), s)
        }
        Func::Acos => {
            if !(-1.0..=1.0).contains(&x) {
                return Err(AlarmId::ArgumentOutOfRange);
            }
            x.acos().to_degrees()
        }
        Func::Atan => angle_range(x.atan().to_degrees(), s),
        Func::Sqrt => {
            if x < 0.0 {
                return Err(AlarmId::ArgumentOutOfRange);
            }
            x.sqrt()
        }
        Func::Abs => x.abs(),
        Func::Bin => bcd_to_binary(x)?,
        Func::Bcd => binary_to_bcd(x)?,
        Func::Round => round_to(x, s.round_steps),
        Func::Fix => x.trunc(),
        Func::Fup => {
            let t = x.trunc();
            if t == x {
                x
            } else {
                t + x.signum()
            }
        }
        Func::Ln => {
            if x <= 0.0 {
                return Err(AlarmId::ArgumentOutOfRange);
            }
            x.ln()
        }
        Func::Exp => x.exp(),
        Func::Adp => x * s.increment,
    })
}

fn func2(f: Func2, a: f64, b: f64, s: &ExprSettings) -> Result<f64, AlarmId> {
    Ok(match f {
        // ATAN[a]/[b]: the angle of the vector (x=b, y=a).
        Func2::Atan => {
            if a == 0.0 && b == 0.0 {
                return Err(AlarmId::ArgumentOutOfRange);
            }
            let deg = a.atan2(b).to_degrees();
            // atan2 gives [-180, 180]; FANUC's NAT=1 range is (-180, 180].
            let deg = if deg == -180.0 { 180.0 } else { deg };
            angle_range(deg, s)
        }
        Func2::Pow => {
            if a < 0.0 && s.syntec_pow {
                return Err(AlarmId::NegativePowerBase);
            }
            if a == 0.0 && b <= 0.0 {
                return Err(AlarmId::ArgumentOutOfRange);
            }
            if a < 0.0 && b.fract() != 0.0 {
                return Err(AlarmId::ArgumentOutOfRange);
            }
            a.powf(b)
        }
    })
}

fn bcd_to_binary(x: f64) -> Result<f64, AlarmId> {
    if x < 0.0 || x.fract() != 0.0 || x > u32::MAX as f64 {
        return Err(AlarmId::ArgumentOutOfRange);
    }
    let mut v = x as u64;
    let (mut result, mut scale) = (0u64, 1u64);
    while v > 0 {
        let digit = v & 0xF;
        if digit > 9 {
            return Err(AlarmId::ArgumentOutOfRange);
        }
        result += digit * scale;
        scale *= 10;
        v >>= 4;
    }
    Ok(result as f64)
}

fn binary_to_bcd(x: f64) -> Result<f64, AlarmId> {
    if x < 0.0 || x.fract() != 0.0 || x > 99_999_999.0 {
        return Err(AlarmId::ArgumentOutOfRange);
    }
    let mut v = x as u64;
    let (mut result, mut shift) = (0u64, 0);
    while v > 0 {
        result |= (v % 10) << shift;
        shift += 4;
        v /= 10;
    }
    Ok(result as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_to_rounds_decimals_as_written_half_away_from_zero() {
        assert_eq!((round_to(1.2345, 1000.0), round_to(-1.2345, 1000.0)), (1.235, -1.235));
        assert_eq!((round_to(1.2344999, 1000.0), round_to(2.5, 1.0), round_to(-2.5, 1.0)), (1.234, 3.0, -3.0));
        assert_eq!((round_to(1000.4999, 1.0), round_to(0.00005, 10000.0), round_to(7.0, 0.0)), (1000.0, 0.0001, 7.0));
    }

    #[test]
    fn bcd_round_trip() {
        assert_eq!(binary_to_bcd(1234.0).unwrap(), 0x1234 as f64);
        assert_eq!(bcd_to_binary(0x1234 as f64).unwrap(), 1234.0);
        assert_eq!(bcd_to_binary(0x1A as f64), Err(AlarmId::ArgumentOutOfRange));
    }

    #[test]
    fn exact_quadrant_angles() {}
}
