//! A JSON object that names a key twice is ambiguous: `serde_json` keeps the last value without
//! a word, so `{"preset": "mill3", "preset": "head-bc"}` made a head-head machine and a `--tools`
//! file's second entry for a tool replaced the first. Request bodies and the files the CLI reads
//! are checked here first and refused, naming the key and where it stands.

use serde::de::{self, Deserialize, Deserializer, MapAccess, SeqAccess, Visitor};
use std::collections::HashSet;
use std::fmt;

/// The first key an object in `text` holds twice, as `"key" (in "outer" → "inner")`; `None`
/// when there is none or `text` is not JSON (its parse says why).
pub fn duplicate_key(text: &[u8]) -> Option<String> {
    let mut de = serde_json::Deserializer::from_slice(text);
    match Walk::deserialize(&mut de) {
        Err(e) if e.is_data() => Some(e.to_string().split(" at line ").next().unwrap_or_default().to_string()),
        _ => None,
    }
}

/// How a duplicate's message starts (others are the parser's own).
const TWICE: &str = "the key ";

/// A JSON value walked for its objects' keys only.
struct Walk;

impl<'de> Deserialize<'de> for Walk {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(WalkVisitor)
    }
}

struct WalkVisitor;

impl<'de> Visitor<'de> for WalkVisitor {
    type Value = Walk;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("any JSON value")
    }

    fn visit_bool<E>(self, _: bool) -> Result<Walk, E> {
        Ok(Walk)
    }
    fn visit_i64<E>(self, _: i64) -> Result<Walk, E> {
        Ok(Walk)
    }
    fn visit_u64<E>(self, _: u64) -> Result<Walk, E> {
        Ok(Walk)
    }
    fn visit_f64<E>(self, _: f64) -> Result<Walk, E> {
        Ok(Walk)
    }
    fn visit_str<E>(self, _: &str) -> Result<Walk, E> {
        Ok(Walk)
    }
    fn visit_unit<E>(self) -> Result<Walk, E> {
        Ok(Walk)
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Walk, A::Error> {
        while seq.next_element::<Walk>()?.is_some() {}
        Ok(Walk)
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Walk, A::Error> {
        let mut seen = HashSet::new();
        while let Some(key) = map.next_key::<String>()? {
            if !seen.insert(key.clone()) {
                return Err(de::Error::custom(format!("{TWICE}\"{key}\" is given twice")));
            }
            map.next_value::<Walk>().map_err(|e| {
                // Name the enclosing key too, so a tool's or an axis's twice-given field is found;
                // any other error (the text is no JSON) goes on as it is.
                let inner = e.to_string();
                match inner.split(" at line ").next() {
                    Some(twice) if twice.starts_with(TWICE) => de::Error::custom(format!("{twice} (in \"{key}\")")),
                    _ => e,
                }
            })?;
        }
        Ok(Walk)
    }
}

#[cfg(test)]
mod tests {
    use super::duplicate_key;

    #[test]
    fn a_key_given_twice_is_named_with_where_it_stands() {
        assert_eq!(duplicate_key(br#"{"a": 1, "b": 2}"#), None);
        assert_eq!(duplicate_key(br#"{"a": 1, "a": 2}"#).as_deref(), Some("the key \"a\" is given twice"));
        assert_eq!(
            duplicate_key(br#"{"tools": {"1": {"length": 1, "length": 2}}}"#).as_deref(),
            Some("the key \"length\" is given twice (in \"1\") (in \"tools\")")
        );
        assert_eq!(duplicate_key(br#"[{"x": 1}, {"x": 2}]"#), None);
        assert_eq!(
            duplicate_key(br#"{"a": [{"x": 1, "x": 1}]}"#).as_deref(),
            Some("the key \"x\" is given twice (in \"a\")")
        );
        // Not JSON: the parse itself says why.
        assert_eq!(duplicate_key(b"{"), None);
        assert_eq!(duplicate_key(br#"{"a": 1e400}"#), None);
    }
}
