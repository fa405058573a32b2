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
    /// The Syntec dialect: values are typed as Syntec types them and `/` divides as Syntec's
    /// does ([`eval_typed`], [`syntec_divide`]).
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

/// Syntec's type of a value (the Syntec MACRO syntax handbook, §2.5, §3.4, §3.9): a Long (an
/// integer: a number written without a decimal point, an argument so written, the result of
/// two Longs, `ROUND`), a Double (a number written with a point, an argument so written, the
/// result of an operation with a Double, `ABS`, `SQRT`, any value with a fraction), or not known
/// to fivex (a function the handbook gives no type for, FANUC's functions, a vacant variable,
/// a variable fivex does not track, a comparison). Only the Syntec dialect uses it: FANUC and
/// Haas divide as reals (`docs/dialects.md`, "The Syntec macro language").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Ty {
    #[default]
    Unknown,
    Long,
    Double,
}

impl Ty {
    /// The type of `v` as `self` says, but a value with a fraction is a Double whatever was
    /// said (a Long cannot hold it), and vacant is not known.
    fn of(self, v: Value) -> Ty {
        match v {
            None => Ty::Unknown,
            Some(x) if x.fract() != 0.0 => Ty::Double,
            Some(_) => self,
        }
    }
}

/// Read access to variables, so evaluation does not depend on where they live.
pub trait Variables {
    fn read(&self, number: u32) -> Result<Value, AlarmId>;

    /// The Syntec type of what variable `number` holds, where it is tracked (`Ty`).
    fn ty(&self, _number: u32) -> Ty {
        Ty::Unknown
    }
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
    eval_typed(e, vars, s).map(|(v, _)| v)
}

/// [`eval`] and, in the Syntec dialect, the value's Syntec type ([`Ty`]; not known elsewhere).
pub fn eval_typed(e: &Expr, vars: &impl Variables, s: &ExprSettings) -> Result<(Value, Ty), AlarmId> {
    let read = |n: u32| -> Result<(Value, Ty), AlarmId> {
        let v = vars.read(n)?;
        Ok((v, if s.syntec_division { vars.ty(n).of(v) } else { Ty::Unknown }))
    };
    Ok(match e {
        Expr::Num { value, decimal_point } => (Some(*value), if *decimal_point { Ty::Double } else { Ty::Long }),
        Expr::Var(n) => read(*n)?,
        Expr::IndirectVar(inner) => read(var_number(eval(inner, vars, s)?)?)?,
        Expr::Bracket(inner) => eval_typed(inner, vars, s)?,
        Expr::Neg(inner) => {
            let (v, t) = eval_typed(inner, vars, s)?;
            (v.map(|x| -x), t)
        }
        Expr::Binary(op, a, b) => {
            let (a, b) = (eval_typed(a, vars, s)?, eval_typed(b, vars, s)?);
            if s.syntec_division {
                syntec_binary(*op, a, b)?
            } else {
                (Some(finite(binary(*op, a.0, b.0)?)?), Ty::Unknown)
            }
        }
        Expr::Func(f, a) => {
            let v = finite(func(*f, eval(a, vars, s)?.unwrap_or(0.0), s)?)?;
            let t = match f {
                // The handbook's return types (§9.2): ABS and SQRT a Double, ROUND a Long (in a
                // macro statement, where it rounds to a whole number).
                Func::Abs | Func::Sqrt => Ty::Double,
                Func::Round if s.round_steps <= 1.0 => Ty::Long,
                _ => Ty::Unknown,
            };
            (Some(v), t.of(Some(v)))
        }
        Expr::Func2(f, a, b) => {
            let a = eval(a, vars, s)?.unwrap_or(0.0);
            let b = eval(b, vars, s)?.unwrap_or(0.0);
            let v = finite(func2(*f, a, b, s)?)?;
            (Some(v), Ty::Unknown.of(Some(v)))
        }
    })
}

/// A binary operation as Syntec types it (the handbook, §3.9: Long with Long is a Long, with a
/// Double a Double), with Syntec's division ([`syntec_divide`]).
fn syntec_binary(op: BinOp, (x, tx): (Value, Ty), (y, ty): (Value, Ty)) -> Result<(Value, Ty), AlarmId> {
    let (tx, ty) = (tx.of(x), ty.of(y));
    if op == BinOp::Div {
        return syntec_divide((x.unwrap_or(0.0), tx), (y.unwrap_or(0.0), ty)).map(|(q, t)| (Some(q), t));
    }
    // A vacant operand adds nothing (it counts as 0): the sum has the other's type, so an
    // argument left out does not hide a Long (`#2 + #5` with #2 = 10 is 10, a Long).
    let (tx, ty) = match (x, y, op) {
        (None, Some(_), BinOp::Add | BinOp::Sub) => (ty, ty),
        (Some(_), None, BinOp::Add | BinOp::Sub) => (tx, tx),
        _ => (tx, ty),
    };
    let v = finite(binary(op, x, y)?)?;
    let t = match op {
        BinOp::Add | BinOp::Sub | BinOp::Mul if tx == Ty::Double || ty == Ty::Double => Ty::Double,
        BinOp::Add | BinOp::Sub | BinOp::Mul | BinOp::Mod if tx == Ty::Long && ty == Ty::Long => Ty::Long,
        _ => Ty::Unknown,
    };
    Ok((Some(v), t.of(Some(v))))
}

/// Syntec's `/` (the handbook, §3.4, §3.9): with a Double operand a real division; of two Longs
/// a Long, the quotient truncated (`7 / 2` is 3, `1 / 2` is 0, `(1/2) * 1.0` is 0.0). What the
/// handbook leaves open is refused (`AddressNotBuilt`) rather than guessed: a Long quotient
/// below zero that is not whole (the direction of its rounding is "to be confirmed", §3.4), and
/// a quotient that is not whole of operands whose type fivex does not know. A zero divisor is
/// the zero divide alarm.
pub fn syntec_divide((x, tx): (f64, Ty), (y, ty): (f64, Ty)) -> Result<(f64, Ty), AlarmId> {
    if y == 0.0 {
        return Err(AlarmId::ZeroDivide);
    }
    let q = finite(x / y)?;
    let (tx, ty) = (tx.of(Some(x)), ty.of(Some(y)));
    if tx == Ty::Double || ty == Ty::Double {
        return Ok((q, Ty::Double));
    }
    let long = tx == Ty::Long && ty == Ty::Long;
    if q.fract() == 0.0 {
        return Ok((q, if long { Ty::Long } else { Ty::Unknown }));
    }
    if long && q > 0.0 {
        // Whole operands below 2^53: the rounded quotient truncates as the exact one does.
        return Ok((q.trunc(), Ty::Long));
    }
    Err(AlarmId::AddressNotBuilt)
}

/// A number written with a decimal point, also signed or bracketed (`-7.`, `[7.]`): a Double
/// to Syntec.
pub fn written_with_point(e: &Expr) -> bool {
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
