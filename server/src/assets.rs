//! The browser dashboard's files (`web/dist`, built by `npm run build` in `web/`).
//!
//! A release build embeds whatever `web/dist` holds when it is compiled; a debug build reads the
//! folder at run time, so a rebuilt dashboard shows on reload without recompiling — also when
//! the folder did not exist yet when the binary was compiled. Neither needs npm: without a built
//! dashboard, `/` serves a small fallback page that lists the controllers and says how to build
//! the real one.

use axum::http::{header, HeaderValue, StatusCode, Uri};
use axum::response::{Html, IntoResponse, Response};
use rust_embed::EmbeddedFile;

/// The fallback page served at `/` when the dashboard is not built.
pub const FALLBACK_HTML: &str = include_str!("fallback.html");

#[cfg(not(debug_assertions))]
#[derive(rust_embed::Embed)]
#[folder = "../web/dist/"]
#[allow_missing = true]
struct Dashboard;

/// A file of the built dashboard, by its path in `web/dist`.
#[cfg(not(debug_assertions))]
fn file(path: &str) -> Option<EmbeddedFile> {
    Dashboard::get(path)
}

/// A file of the built dashboard, read from `web/dist` now. Not rust-embed's own debug mode: it
/// compares a file's canonical path with the folder's path as canonicalized when the binary was
/// compiled, and when `web/dist` did not exist then, that is `server/../web/dist` as written,
/// which no file's path starts with — a debug binary compiled before `npm run build` served the
/// fallback page, and 404 for every file, until it was compiled again.
#[cfg(debug_assertions)]
fn file(path: &str) -> Option<EmbeddedFile> {
    let dist = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../web/dist");
    within(&dist, path).and_then(|f| rust_embed::utils::read_file_from_fs(&f).ok())
}

/// `path` in `dist`, when it is a file there (not outside it by `..` or a link).
#[cfg(debug_assertions)]
fn within(dist: &std::path::Path, path: &str) -> Option<std::path::PathBuf> {
    let dist = dist.canonicalize().ok()?;
    let file = dist.join(path).canonicalize().ok()?;
    (file.starts_with(&dist) && file.is_file()).then_some(file)
}

/// Whether the built dashboard is available.
pub fn dashboard_built() -> bool {
    file("index.html").is_some()
}

/// `GET /`: the dashboard's page, or the fallback.
pub async fn index() -> Response {
    match file("index.html") {
        Some(file) => with_type(file.data.into_owned(), "text/html; charset=utf-8", "no-cache"),
        None => Html(FALLBACK_HTML).into_response(),
    }
}

/// `GET /assets/{file}`: the dashboard's scripts and styles. Their names carry a content hash,
/// so they may be cached for good.
pub async fn asset(uri: Uri) -> Response {
    let path = uri.path().trim_start_matches('/');
    match file(path) {
        Some(file) => {
            let mime = file.metadata.mimetype().to_string();
            with_type(file.data.into_owned(), &mime, "public, max-age=31536000, immutable")
        }
        None => crate::http::ApiError::NotFound(format!("no file {path}")).into_response(),
    }
}

fn with_type(body: Vec<u8>, mime: &str, cache: &'static str) -> Response {
    let mut response = (StatusCode::OK, body).into_response();
    let headers = response.headers_mut();
    if let Ok(value) = HeaderValue::from_str(mime) {
        headers.insert(header::CONTENT_TYPE, value);
    }
    headers.insert(header::CACHE_CONTROL, HeaderValue::from_static(cache));
    response
}

#[cfg(all(test, debug_assertions))]
mod tests {
    use super::within;

    /// A debug build reads the folder as it is when asked, whatever it was at compile time: a
    /// folder made after the start is read, and nothing outside it.
    #[test]
    fn a_debug_build_reads_a_folder_made_after_it_started() {
        let root = std::env::temp_dir().join(format!("fivex-assets-{}", std::process::id()));
        let dist = root.join("web/dist");
        let _ = std::fs::remove_dir_all(&root);
        assert_eq!(within(&dist, "index.html"), None, "no folder yet");
        std::fs::create_dir_all(dist.join("assets")).unwrap();
        std::fs::write(dist.join("index.html"), "<title>fivex</title>").unwrap();
        std::fs::write(dist.join("assets/a.js"), "1").unwrap();
        std::fs::write(root.join("secret.txt"), "no").unwrap();
        let index = within(&dist, "index.html").expect("read once it is there");
        assert_eq!(std::fs::read_to_string(index).unwrap(), "<title>fivex</title>");
        assert!(within(&dist, "assets/a.js").is_some());
        assert_eq!(within(&dist, "../../secret.txt"), None, "not outside the folder");
        assert_eq!(within(&dist, "assets"), None, "a folder is no file");
        let _ = std::fs::remove_dir_all(&root);
    }
}
