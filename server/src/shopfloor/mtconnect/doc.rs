//! An MTConnect response document as one tree, printed either as the standard's XML or as its
//! JSON form (the reference agent's JSON version 2: an element is an object of its attributes,
//! its text as `value`, and its children; children that are members of a list are grouped by
//! element name into arrays — `"Devices": {"Device": [...]}` — the others are objects).

use std::fmt::Write;

use serde_json::{Map, Value};

/// An attribute's or a text's value: numbers stay numbers in JSON.
#[derive(Debug, Clone, PartialEq)]
pub enum Text {
    Str(String),
    Num(f64),
    /// A three-space sample (`PathPosition`): `"x y z"` in XML, `[x, y, z]` in JSON.
    Vec3([f64; 3]),
}

impl Text {
    fn xml(&self) -> String {
        match self {
            Text::Str(s) => s.clone(),
            Text::Num(v) => number(*v),
            Text::Vec3(v) => v.map(number).join(" "),
        }
    }

    fn json(&self) -> Value {
        match self {
            Text::Str(s) => Value::String(s.clone()),
            Text::Num(v) => json_number(*v),
            Text::Vec3(v) => Value::Array(v.iter().map(|x| json_number(*x)).collect()),
        }
    }
}

impl From<&str> for Text {
    fn from(s: &str) -> Text {
        Text::Str(s.to_string())
    }
}

impl From<String> for Text {
    fn from(s: String) -> Text {
        Text::Str(s)
    }
}

impl From<f64> for Text {
    fn from(v: f64) -> Text {
        Text::Num(v)
    }
}

impl From<u64> for Text {
    fn from(v: u64) -> Text {
        Text::Num(v as f64)
    }
}

/// A number as a document shows it: at most six decimals (a nanometre, a micro-degree: below
/// what a sample means), no trailing zeros.
pub fn number(v: f64) -> String {
    if !v.is_finite() {
        return "UNAVAILABLE".to_string();
    }
    let mut s = format!("{:.6}", v);
    if s.contains('.') {
        while s.ends_with('0') {
            s.pop();
        }
        if s.ends_with('.') {
            s.pop();
        }
    }
    if s == "-0" {
        s = "0".to_string();
    }
    s
}

fn json_number(v: f64) -> Value {
    number(v).parse::<serde_json::Number>().map(Value::Number).unwrap_or_else(|_| Value::String(number(v)))
}

/// One element of a document.
#[derive(Debug, Clone, PartialEq)]
pub struct Element {
    pub name: &'static str,
    pub attrs: Vec<(&'static str, Text)>,
    pub text: Option<Text>,
    pub children: Vec<Element>,
    /// A member of a list in its parent (grouped into an array in JSON).
    pub listed: bool,
}

impl Element {
    /// A single child (an object in JSON): `Header`, `Devices`, `DataItems`, `Samples`, ….
    pub fn one(name: &'static str) -> Element {
        Element { name, attrs: Vec::new(), text: None, children: Vec::new(), listed: false }
    }

    /// A member of a list: `Device`, `DataItem`, `DeviceStream`, an observation, ….
    pub fn item(name: &'static str) -> Element {
        Element { listed: true, ..Element::one(name) }
    }

    pub fn attr(mut self, name: &'static str, value: impl Into<Text>) -> Element {
        self.attrs.push((name, value.into()));
        self
    }

    pub fn attr_opt(self, name: &'static str, value: Option<impl Into<Text>>) -> Element {
        match value {
            Some(v) => self.attr(name, v),
            None => self,
        }
    }

    pub fn text(mut self, text: impl Into<Text>) -> Element {
        self.text = Some(text.into());
        self
    }

    pub fn child(mut self, child: Element) -> Element {
        self.children.push(child);
        self
    }

    pub fn children(mut self, children: impl IntoIterator<Item = Element>) -> Element {
        self.children.extend(children);
        self
    }

    pub fn push(&mut self, child: Element) {
        self.children.push(child);
    }
}

/// The namespaces of a response document of `kind` (`Devices`, `Streams`, `Assets`, `Error`).
fn namespace(kind: &str) -> String {
    format!("urn:mtconnect.org:MTConnect{kind}:{}", super::SCHEMA_VERSION)
}

/// The document as XML, the root element carrying the standard's namespace for `kind`.
pub fn xml(root: &Element, kind: &str) -> String {
    let mut out = String::with_capacity(4096);
    out.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let ns = namespace(kind);
    let _ = write!(
        out,
        "<{} xmlns=\"{ns}\" xmlns:m=\"{ns}\" xmlns:xsi=\"http://www.w3.org/2001/XMLSchema-instance\" \
         xsi:schemaLocation=\"{ns} http://schemas.mtconnect.org/schemas/MTConnect{kind}_{}.xsd\"",
        root.name,
        super::SCHEMA_VERSION
    );
    element_body(&mut out, root, 0);
    out
}

fn element_xml(out: &mut String, e: &Element, depth: usize) {
    indent(out, depth);
    out.push('<');
    out.push_str(e.name);
    element_body(out, e, depth);
}

/// Attributes, content and the end tag of `e`, whose start tag's name is written.
fn element_body(out: &mut String, e: &Element, depth: usize) {
    for (name, value) in &e.attrs {
        let _ = write!(out, " {name}=\"{}\"", escape(&value.xml()));
    }
    match (&e.text, e.children.is_empty()) {
        (None, true) => out.push_str("/>\n"),
        (Some(text), true) => {
            let _ = writeln!(out, ">{}</{}>", escape(&text.xml()), e.name);
        }
        (text, false) => {
            out.push_str(">\n");
            if let Some(text) = text {
                indent(out, depth + 1);
                out.push_str(&escape(&text.xml()));
                out.push('\n');
            }
            for child in &e.children {
                element_xml(out, child, depth + 1);
            }
            indent(out, depth);
            let _ = writeln!(out, "</{}>", e.name);
        }
    }
}

fn indent(out: &mut String, depth: usize) {
    for _ in 0..depth {
        out.push_str("  ");
    }
}

fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            // Characters XML 1.0 cannot carry at all (a control character in an NC comment).
            c if (c as u32) < 0x20 && !matches!(c, '\t' | '\n' | '\r') => out.push('?'),
            c => out.push(c),
        }
    }
    out
}

/// The document as JSON version 2: `{"MTConnectStreams": {"jsonVersion": 2, "schemaVersion":
/// "2.5", …}}`.
pub fn json(root: &Element) -> String {
    let mut body = Map::new();
    body.insert("jsonVersion".into(), Value::from(2));
    body.insert("schemaVersion".into(), Value::from(super::SCHEMA_VERSION));
    fill(&mut body, root);
    let mut doc = Map::new();
    doc.insert(root.name.into(), Value::Object(body));
    serde_json::to_string(&Value::Object(doc)).unwrap_or_default()
}

fn object(e: &Element) -> Value {
    let mut map = Map::new();
    fill(&mut map, e);
    Value::Object(map)
}

fn fill(map: &mut Map<String, Value>, e: &Element) {
    for (name, value) in &e.attrs {
        map.insert((*name).to_string(), value.json());
    }
    if let Some(text) = &e.text {
        map.insert("value".into(), text.json());
    }
    for child in &e.children {
        if child.listed {
            let list = map.entry(child.name).or_insert_with(|| Value::Array(Vec::new()));
            if let Value::Array(items) = list {
                items.push(object(child));
            }
        } else {
            map.insert(child.name.into(), object(child));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_keep_six_decimals_without_trailing_zeros() {
        assert_eq!(number(1.0), "1");
        assert_eq!(number(-0.0000001), "0");
        assert_eq!(number(12.3456789), "12.345679");
        assert_eq!(number(100.5), "100.5");
        assert_eq!(number(f64::NAN), "UNAVAILABLE");
    }

    #[test]
    fn listed_children_group_into_arrays_and_single_ones_stay_objects() {
        let root = Element::one("MTConnectStreams").child(Element::one("Header").attr("instanceId", 7u64)).child(
            Element::one("Streams")
                .child(Element::item("DeviceStream").attr("name", "a"))
                .child(Element::item("DeviceStream").attr("name", "b")),
        );
        let v: Value = serde_json::from_str(&json(&root)).unwrap();
        assert_eq!(v["MTConnectStreams"]["Header"]["instanceId"], 7);
        assert_eq!(v["MTConnectStreams"]["Streams"]["DeviceStream"][1]["name"], "b");
        assert_eq!(v["MTConnectStreams"]["jsonVersion"], 2);
    }

    #[test]
    fn xml_escapes_text_and_attributes() {
        let root = Element::one("MTConnectError").child(Element::item("Error").attr("a", "<\"&").text("x < y"));
        let text = xml(&root, "Error");
        assert!(text.contains("a=\"&lt;&quot;&amp;\""), "{text}");
        assert!(text.contains(">x &lt; y</Error>"), "{text}");
    }
}
