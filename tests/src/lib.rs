//! End-to-end tests live in `tests/tests/`. This library holds what both fixture harnesses
//! share: the grammar of a fixture's header comments (`tests/README.md`), used by the e2e
//! fixtures (`tests/tests/it/fixtures.rs`) and the engine's data harness
//! (`engine/tests/it/data`).

pub mod header {
    /// The texts of every `(TAG: …)` comment in `text`, in order.
    pub fn tagged_comments<'a>(text: &'a str, tag: &str) -> Vec<&'a str> {
        let open = format!("({tag}:");
        let mut out = Vec::new();
        for line in text.lines() {
            let mut rest = line;
            while let Some(i) = rest.find(&open) {
                let body = &rest[i + open.len()..];
                let end = body.find(')').unwrap_or(body.len());
                out.push(body[..end].trim());
                rest = &body[end..];
            }
        }
        out
    }

    /// Split a line of options on whitespace, keeping `"double quoted"` parts together.
    pub fn split_words(s: &str) -> Vec<String> {
        let mut out = Vec::new();
        let mut cur = String::new();
        let mut quoted = false;
        let mut any = false;
        for ch in s.chars() {
            match ch {
                '"' => {
                    quoted = !quoted;
                    any = true;
                }
                c if c.is_whitespace() && !quoted => {
                    if any {
                        out.push(std::mem::take(&mut cur));
                        any = false;
                    }
                }
                c => {
                    cur.push(c);
                    any = true;
                }
            }
        }
        if any {
            out.push(cur);
        }
        out
    }
}
