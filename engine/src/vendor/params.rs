//! A vendor parameter list as numbers and values, with the reading helpers both vendors use.

use crate::machine::ConfigError;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// One parameter's value: a number, or one number per axis (FANUC's axis-type parameters;
/// Syntec numbers its per-axis parameters consecutively, so all its values are single).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema), schema(as = ParameterValue))]
#[serde(untagged)]
pub enum Value {
    One(f64),
    PerAxis(Vec<f64>),
}

/// Whole numbers are written without a fraction (`3001: 1`, as on the control's screen).
#[derive(Serialize)]
#[serde(untagged)]
enum Number {
    Whole(i64),
    Real(f64),
}

fn number(x: f64) -> Number {
    if x.fract() == 0.0 && x.abs() < 9e15 {
        Number::Whole(x as i64)
    } else {
        Number::Real(x)
    }
}

impl Serialize for Value {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Value::One(x) => number(*x).serialize(s),
            Value::PerAxis(v) => s.collect_seq(v.iter().map(|x| number(*x))),
        }
    }
}

/// [`Value`] by the name the schema gives it (a type named `Value` would be taken for any JSON).
#[cfg(feature = "schema")]
type ParameterValue = Value;

/// A parameter list in the vendor's numbering (`{"19680": 2, "1020": [88, 89, 90, 66, 67]}`).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
// (JSON object keys are strings: the numbers as text.)
#[cfg_attr(
    feature = "schema",
    derive(utoipa::ToSchema),
    schema(value_type = std::collections::HashMap<String, ParameterValue>)
)]
#[serde(transparent)]
pub struct Params(pub BTreeMap<u32, Value>);

impl Params {
    pub fn set(&mut self, number: u32, value: f64) {
        self.0.insert(number, Value::One(value));
    }

    /// Set bits of a bit parameter that several settings share (FANUC No.19746 holds LOD, LOZ
    /// and CRS), keeping the bits already set.
    pub fn set_bits(&mut self, number: u32, bits: u32) {
        let old = match self.0.get(&number) {
            Some(Value::One(x)) => *x as u32,
            _ => 0,
        };
        self.set(number, (old | bits) as f64);
    }

    pub fn set_axes(&mut self, number: u32, values: Vec<f64>) {
        self.0.insert(number, Value::PerAxis(values));
    }

    /// A single value; a missing parameter is 0, as on a control whose parameters were cleared.
    pub fn get(&self, number: u32) -> Result<f64, ConfigError> {
        match self.0.get(&number) {
            None => Ok(0.0),
            Some(Value::One(x)) if x.is_finite() => Ok(*x),
            Some(_) => Err(ConfigError::invalid(format!("parameter {number} needs one finite number"))),
        }
    }

    /// Three consecutive single values as a vector.
    pub fn get3(&self, first: u32) -> Result<[f64; 3], ConfigError> {
        Ok([self.get(first)?, self.get(first + 1)?, self.get(first + 2)?])
    }

    /// A whole number in `lo..=hi`.
    pub fn code(&self, number: u32, lo: i64, hi: i64) -> Result<i64, ConfigError> {
        whole(number, self.get(number)?, lo, hi)
    }

    /// Bit `bit` of a bit parameter (stored as its byte value).
    pub fn bit(&self, number: u32, bit: u32) -> Result<bool, ConfigError> {
        Ok(self.code(number, 0, 255)? >> bit & 1 == 1)
    }

    /// A per-axis parameter's values for `axes` axes; missing: all 0.
    pub fn axes(&self, number: u32, axes: usize) -> Result<Vec<f64>, ConfigError> {
        match self.0.get(&number) {
            None => Ok(vec![0.0; axes]),
            Some(Value::PerAxis(v)) if v.len() == axes && v.iter().all(|x| x.is_finite()) => Ok(v.clone()),
            Some(_) => {
                Err(ConfigError::invalid(format!("parameter {number} needs {axes} finite numbers, one per axis")))
            }
        }
    }
}

/// `x` as a whole number in `lo..=hi`, or an error naming the parameter.
pub fn whole(number: u32, x: f64, lo: i64, hi: i64) -> Result<i64, ConfigError> {
    if x.fract() == 0.0 && x >= lo as f64 && x <= hi as f64 {
        Ok(x as i64)
    } else {
        Err(ConfigError::invalid(format!("parameter {number} = {x} is not a whole number in {lo}..{hi}")))
    }
}

/// A machine described by its vendor parameter list: the other form of `--machine FILE.json`.
/// A key it does not have is refused, not dropped (a model field such as `motion` written
/// beside `parameters` changed nothing, without a word).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct ParamFile {
    pub name: String,
    pub dialect: crate::Dialect,
    pub parameters: Params,
}
