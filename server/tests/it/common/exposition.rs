//! Reading `/metrics` in tests: a small strict parser of the Prometheus text exposition format
//! 0.0.4, and an independent one, Python's `prometheus_client.parser` (Debian's
//! `python3-prometheus-client`, which `scripts/test.sh` installs; without it the check fails).

use std::collections::{BTreeMap, HashSet};
use std::io::Write;
use std::process::{Command, Stdio};

/// One sample: its name and labels.
pub type Key = (String, BTreeMap<String, String>);

/// A scrape, read: every sample's value, and every family's type.
#[derive(Debug, Default)]
pub struct Exposition {
    pub samples: BTreeMap<Key, f64>,
    pub types: BTreeMap<String, String>,
}

impl Exposition {
    /// The value of the sample `name` with exactly `labels`; panics when there is none.
    pub fn value(&self, name: &str, labels: &[(&str, &str)]) -> f64 {
        let key = (name.to_string(), labels.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect());
        *self.samples.get(&key).unwrap_or_else(|| panic!("no sample {name} {labels:?} in {:#?}", self.samples.keys()))
    }

    /// The sum of the samples named `name`, whatever their labels.
    pub fn sum(&self, name: &str) -> f64 {
        self.samples.iter().filter(|((n, _), _)| n == name).map(|(_, v)| v).sum()
    }
}

fn is_name(name: &str) -> bool {
    let mut chars = name.chars();
    chars.next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_' || c == ':')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_' || c == ':')
}

fn is_label_name(name: &str) -> bool {
    is_name(name) && !name.contains(':')
}

/// A value as the format writes it (Go's `ParseFloat`, and `+Inf`, `-Inf`, `NaN`).
fn value(text: &str) -> Result<f64, String> {
    match text {
        "+Inf" => Ok(f64::INFINITY),
        "-Inf" => Ok(f64::NEG_INFINITY),
        "NaN" => Ok(f64::NAN),
        _ if text.chars().all(|c| c.is_ascii_digit() || "+-.eE".contains(c)) => {
            text.parse().map_err(|e| format!("value {text:?}: {e}"))
        }
        _ => Err(format!("value {text:?}")),
    }
}

/// `{a="1",b="x\"y"}` after the name: the labels and the rest of the line.
fn labels(text: &str) -> Result<(BTreeMap<String, String>, &str), String> {
    let mut labels = BTreeMap::new();
    let Some(mut rest) = text.strip_prefix('{') else { return Ok((labels, text)) };
    loop {
        if let Some(after) = rest.strip_prefix('}') {
            return Ok((labels, after));
        }
        let eq = rest.find('=').ok_or_else(|| format!("label without '=': {rest:?}"))?;
        let name = &rest[..eq];
        if !is_label_name(name) {
            return Err(format!("label name {name:?}"));
        }
        let mut chars = rest[eq + 1..].strip_prefix('"').ok_or("label value not quoted")?.char_indices();
        let mut value = String::new();
        let end = loop {
            match chars.next() {
                Some((_, '\\')) => match chars.next() {
                    Some((_, '\\')) => value.push('\\'),
                    Some((_, '"')) => value.push('"'),
                    Some((_, 'n')) => value.push('\n'),
                    other => return Err(format!("escape {other:?} in a label value")),
                },
                Some((i, '"')) => break i,
                Some((_, '\n')) | None => return Err("label value not closed".into()),
                Some((_, c)) => value.push(c),
            }
        };
        if labels.insert(name.to_string(), value).is_some() {
            return Err(format!("label {name} twice"));
        }
        rest = &rest[eq + 1..][1 + end + 1..];
        rest = rest.strip_prefix(',').unwrap_or(rest);
    }
}

/// The family a sample belongs to, given the families typed so far.
fn family_of<'a>(name: &'a str, types: &BTreeMap<String, String>) -> Option<&'a str> {
    if types.contains_key(name) {
        return Some(name);
    }
    for suffix in ["_bucket", "_sum", "_count"] {
        if let Some(base) = name.strip_suffix(suffix) {
            match types.get(base).map(String::as_str) {
                Some("histogram") => return Some(base),
                Some("summary") if suffix != "_bucket" => return Some(base),
                _ => {}
            }
        }
    }
    None
}

/// Reads `text` strictly: every line is `# HELP name text`, `# TYPE name type` or a sample
/// `name{labels} value` (at most one `# HELP` and one `# TYPE` per name, the type before the
/// samples, every sample of a family typed and in one group, no sample twice); a histogram's
/// buckets are cumulative and end with `+Inf` equal to its `_count`.
pub fn parse_strict(text: &str) -> Result<Exposition, String> {
    let mut out = Exposition::default();
    let mut helped = HashSet::new();
    let mut done: HashSet<String> = HashSet::new();
    let mut current: Option<String> = None;
    if !text.ends_with('\n') {
        return Err("the text does not end with a newline".into());
    }
    for (number, line) in text.lines().enumerate() {
        let fail = |why: String| format!("line {}: {why}: {line:?}", number + 1);
        if let Some(comment) = line.strip_prefix("# ") {
            let mut parts = comment.splitn(3, ' ');
            let (kind, name, rest) = (parts.next(), parts.next().unwrap_or(""), parts.next());
            if !is_name(name) {
                return Err(fail(format!("metric name {name:?}")));
            }
            match kind {
                Some("HELP") => {
                    if !helped.insert(name.to_string()) {
                        return Err(fail("a second HELP".into()));
                    }
                }
                Some("TYPE") => {
                    let kind = rest.ok_or_else(|| fail("no type".into()))?;
                    if !["counter", "gauge", "histogram", "summary", "untyped"].contains(&kind) {
                        return Err(fail(format!("type {kind:?}")));
                    }
                    if out.types.insert(name.to_string(), kind.to_string()).is_some() {
                        return Err(fail("a second TYPE".into()));
                    }
                    if out.samples.keys().any(|(n, _)| family_of(n, &out.types) == Some(name)) {
                        return Err(fail("TYPE after its samples".into()));
                    }
                }
                _ => return Err(fail("a comment that is neither HELP nor TYPE".into())),
            }
            continue;
        }
        let end = line.find(['{', ' ']).ok_or_else(|| fail("no value".into()))?;
        let name = &line[..end];
        if !is_name(name) {
            return Err(fail(format!("metric name {name:?}")));
        }
        let (labels, rest) = labels(&line[end..]).map_err(fail)?;
        let rest = rest.strip_prefix(' ').ok_or_else(|| fail("no space before the value".into()))?;
        let mut fields = rest.split(' ');
        let v = value(fields.next().unwrap_or("")).map_err(fail)?;
        if let Some(timestamp) = fields.next() {
            timestamp.parse::<i64>().map_err(|e| fail(format!("timestamp: {e}")))?;
        }
        if fields.next().is_some() {
            return Err(fail("more than a value and a timestamp".into()));
        }
        let family = family_of(name, &out.types).ok_or_else(|| fail(format!("{name} has no TYPE")))?.to_string();
        if current.as_deref() != Some(family.as_str()) {
            if let Some(previous) = current.replace(family.clone()) {
                done.insert(previous);
            }
            if done.contains(&family) {
                return Err(fail(format!("the samples of {family} are not in one group")));
            }
        }
        if out.samples.insert((name.to_string(), labels), v).is_some() {
            return Err(fail("the same sample twice".into()));
        }
    }
    check_histograms(&out)?;
    Ok(out)
}

fn check_histograms(out: &Exposition) -> Result<(), String> {
    for (name, _) in out.types.iter().filter(|(_, t)| *t == "histogram") {
        // Per label set (without `le`): the buckets in order of their bound.
        let mut series: BTreeMap<BTreeMap<String, String>, Vec<(f64, f64)>> = BTreeMap::new();
        for ((n, labels), v) in &out.samples {
            if *n == format!("{name}_bucket") {
                let le = labels.get("le").ok_or_else(|| format!("{n} without le"))?;
                let mut rest = labels.clone();
                rest.remove("le");
                series.entry(rest).or_default().push((value(le)?, *v));
            }
        }
        for (labels, mut buckets) in series {
            buckets.sort_by(|a, b| a.0.total_cmp(&b.0));
            if !buckets.windows(2).all(|w| w[0].1 <= w[1].1) {
                return Err(format!("{name} {labels:?}: buckets not cumulative: {buckets:?}"));
            }
            let last = buckets.last().copied().unwrap_or((0.0, 0.0));
            let count = out.samples.get(&(format!("{name}_count"), labels.clone()));
            if last.0 != f64::INFINITY || count != Some(&last.1) {
                return Err(format!("{name} {labels:?}: the +Inf bucket {last:?} is not the count {count:?}"));
            }
            if !out.samples.contains_key(&(format!("{name}_sum"), labels.clone())) {
                return Err(format!("{name} {labels:?}: no _sum"));
            }
        }
    }
    Ok(())
}

/// What Python's `prometheus_client.parser.text_string_to_metric_families` reads in `text`:
/// every sample as `(name, labels) = value`; fails if the parser refuses the text, if a sample
/// falls outside a typed family (the parser makes it an untyped family of its own), or if
/// python3 or its `prometheus_client` module is missing.
pub fn parse_with_python(text: &str) -> Exposition {
    const SCRIPT: &str = r#"
import json, sys
from prometheus_client.parser import text_string_to_metric_families
families = []
for family in text_string_to_metric_families(sys.stdin.read()):
    if family.type in ("untyped", "unknown"):
        sys.exit("untyped family (a sample without its TYPE): %s" % family.name)
    families.append({"name": family.name, "type": family.type,
                     "samples": [[s.name, s.labels, repr(float(s.value))] for s in family.samples]})
print(json.dumps(families))
"#;
    // Debian's python3-prometheus-client is for the system's interpreter (a python3 earlier on
    // PATH may not have it).
    let python = if std::path::Path::new("/usr/bin/python3").exists() { "/usr/bin/python3" } else { "python3" };
    let mut child = Command::new(python)
        .args(["-c", SCRIPT])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("python3 (with prometheus_client: apt install python3-prometheus-client; scripts/test.sh does)");
    child.stdin.take().expect("stdin").write_all(text.as_bytes()).expect("write to python3");
    let output = child.wait_with_output().expect("python3 ran");
    assert!(
        output.status.success(),
        "Python's prometheus_client parser failed (is python3-prometheus-client installed? scripts/test.sh \
         installs it): {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let families: serde_json::Value = serde_json::from_slice(&output.stdout).expect("JSON from the script");
    let mut out = Exposition::default();
    for family in families.as_array().expect("an array") {
        let name = family["name"].as_str().expect("a name");
        out.types.insert(name.to_string(), family["type"].as_str().expect("a type").to_string());
        for sample in family["samples"].as_array().expect("samples") {
            let labels = sample[1]
                .as_object()
                .expect("labels")
                .iter()
                .map(|(k, v)| (k.clone(), v.as_str().expect("a label value").to_string()))
                .collect();
            let v: f64 = sample[2].as_str().expect("a value").parse().expect("a number");
            let key = (sample[0].as_str().expect("a sample name").to_string(), labels);
            assert!(out.samples.insert(key.clone(), v).is_none(), "{key:?} twice");
        }
    }
    out
}

/// Both parsers read `text` and agree on every sample and every family's type (Python's parser
/// names a counter's family without `_total`).
pub fn parse_both(text: &str) -> Exposition {
    let strict = parse_strict(text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    let python = parse_with_python(text);
    let same = |a: &f64, b: &f64| a == b || (a.is_nan() && b.is_nan());
    assert_eq!(strict.samples.len(), python.samples.len(), "samples:\n{:#?}\n{:#?}", strict.samples, python.samples);
    for (key, v) in &strict.samples {
        let p = python.samples.get(key).unwrap_or_else(|| panic!("Python's parser has no {key:?}"));
        assert!(same(v, p), "{key:?}: {v} against Python's {p}");
    }
    for (name, kind) in &strict.types {
        let python_name = if kind == "counter" { name.strip_suffix("_total").unwrap_or(name) } else { name };
        assert_eq!(python.types.get(python_name), Some(kind), "{name}");
    }
    strict
}

#[test]
fn the_strict_parser_refuses_what_the_format_does_not_allow() {
    let good = "# HELP a_total A.\n# TYPE a_total counter\na_total{x=\"1\"} 3\na_total{x=\"q\\\"\\n\"} 4\n\
                # TYPE h histogram\nh_bucket{le=\"1\"} 1\nh_bucket{le=\"+Inf\"} 2\nh_sum 3.5\nh_count 2\n";
    let read = parse_strict(good).unwrap();
    assert_eq!(read.value("a_total", &[("x", "q\"\n")]), 4.0);
    assert_eq!(read.value("h_count", &[]), 2.0);
    for bad in [
        "a 1\n",                                                   // no TYPE
        "# TYPE a gauge\na 1",                                     // no final newline
        "# TYPE a gauge\na{x=1} 1\n",                              // label value not quoted
        "# TYPE a gauge\na one\n",                                 // not a number
        "# TYPE a gauge\n# TYPE a gauge\na 1\n",                   // TYPE twice
        "# TYPE a gauge\na 1\na 2\n",                              // the same sample twice
        "# TYPE a gauge\n# TYPE b gauge\na 1\nb 1\na{x=\"\"} 1\n", // not one group
        "# TYPE a gauge\n# EOF\na 1\n",                            // another comment
        "# TYPE h histogram\nh_bucket{le=\"1\"} 2\nh_bucket{le=\"+Inf\"} 1\nh_sum 1\nh_count 1\n",
        "# TYPE a gauge\na  1\n",
    ] {
        assert!(parse_strict(bad).is_err(), "{bad:?} taken");
    }
}

#[test]
fn python_reads_what_the_strict_parser_reads() {
    let text = "# HELP a_total A.\n# TYPE a_total counter\na_total{x=\"1\"} 3\n\
                # TYPE h histogram\nh_bucket{le=\"1\"} 1\nh_bucket{le=\"+Inf\"} 2\nh_sum 3.5\nh_count 2\n";
    assert_eq!(parse_both(text).value("h_sum", &[]), 3.5);
}

#[test]
#[should_panic(expected = "untyped family")]
fn python_refuses_a_sample_outside_its_typed_family() {
    // OpenMetrics' counter (what the `prometheus-client` crate writes): TYPE without `_total`.
    parse_with_python("# TYPE a counter\na_total 1\n");
}
