//! The service's layers (ARCHITECTURE.md, "server/"): what each may import, read from the
//! sources, so that a shortcut through a layer fails here rather than in review.

use std::path::{Path, PathBuf};

fn sources(dir: &str) -> Vec<(PathBuf, String)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src").join(dir);
    let mut found = Vec::new();
    let mut pending = vec![root];
    while let Some(path) = pending.pop() {
        if path.is_dir() {
            pending.extend(std::fs::read_dir(&path).unwrap().map(|e| e.unwrap().path()));
        } else if path.extension().is_some_and(|e| e == "rs") {
            let text = std::fs::read_to_string(&path).unwrap();
            found.push((path, text));
        }
    }
    assert!(!found.is_empty(), "no sources under {dir}");
    found
}

/// Every `(file, line)` of `files` that holds one of `words`, outside comments.
fn uses(files: &[(PathBuf, String)], words: &[&str]) -> Vec<String> {
    let mut hits = Vec::new();
    for (path, text) in files {
        for line in text.lines().filter(|l| !l.trim_start().starts_with("//")) {
            if words.iter().any(|w| line.contains(w)) {
                hits.push(format!("{}: {}", path.display(), line.trim()));
            }
        }
    }
    hits
}

/// The calls `db::name(` in `files`.
fn db_calls(files: &[(PathBuf, String)]) -> Vec<String> {
    let mut hits = Vec::new();
    for (path, text) in files {
        for line in text.lines().filter(|l| !l.trim_start().starts_with("//")) {
            for (at, _) in line.match_indices("db::") {
                let rest = &line[at + 4..];
                let name: String = rest.chars().take_while(|c| c.is_ascii_lowercase() || *c == '_').collect();
                if !name.is_empty() && rest[name.len()..].starts_with('(') {
                    hits.push(format!("{}: {}", path.display(), line.trim()));
                }
            }
        }
    }
    hits
}

#[test]
fn the_database_module_knows_nothing_above_it() {
    let db = sources("db.rs");
    assert_eq!(uses(&db, &["crate::host", "crate::service", "crate::http", "crate::api"]), Vec::<String>::new());
}

#[test]
fn services_know_no_http() {
    let service = sources("service");
    let http = ["axum", "crate::http", "crate::api", "StatusCode", "ApiError"];
    assert_eq!(uses(&service, &http), Vec::<String>::new());
}

#[test]
fn handlers_reach_the_database_only_through_services() {
    let mut handlers = sources("api");
    handlers.extend(sources("http/extract.rs"));
    handlers.extend(sources("http/router.rs"));
    assert_eq!(db_calls(&handlers), Vec::<String>::new());
    assert_eq!(uses(&handlers, &["sqlx::query"]), Vec::<String>::new());
    // The check finds a call where there is one.
    assert_eq!(db_calls(&[(PathBuf::from("x.rs"), "db::put_program(&db, 1)".into())]).len(), 1);
}
