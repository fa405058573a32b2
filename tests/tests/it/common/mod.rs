//! Helpers shared by the end-to-end tests: find the `fivex` binary and run it.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::sync::OnceLock;

pub use fivex_e2e::header::{split_words, tagged_comments};

/// The `fivex` binary under test.
///
/// `FIVEX_BIN` wins when set. Otherwise the binary is `<target dir>/<profile>/fivex`, found
/// from this test executable's own path (`<target dir>/<profile>/deps/<test>-<hash>`).
/// `cargo test --workspace` builds it (the `fivex-server` package has integration tests, so
/// cargo builds its `fivex` binary before running any test). `cargo test -p fivex-e2e` alone
/// does NOT: run `cargo build -p fivex-server --bin fivex` first, or the tests fail with a
/// message saying so.
pub fn fivex_bin() -> &'static Path {
    static BIN: OnceLock<PathBuf> = OnceLock::new();
    BIN.get_or_init(|| {
        if let Some(p) = std::env::var_os("FIVEX_BIN") {
            let p = PathBuf::from(p);
            assert!(p.is_file(), "FIVEX_BIN={} is not a file", p.display());
            return p;
        }
        let exe = std::env::current_exe().expect("current_exe");
        let name = format!("fivex{}", std::env::consts::EXE_SUFFIX);
        for dir in exe.ancestors().skip(1) {
            let candidate = dir.join(&name);
            if candidate.is_file() {
                return candidate;
            }
            if dir.file_name().is_some_and(|n| n == "target") {
                break;
            }
        }
        panic!(
            "the fivex binary was not found next to {} (looked in its ancestors up to the target \
             directory). Build it first: `cargo build -p fivex-server --bin fivex`, or run the \
             whole workspace with `cargo test --workspace`, or set FIVEX_BIN=/path/to/fivex.",
            exe.display()
        )
    })
}

/// Run `fivex ARGS` in directory `cwd` with no standard input.
pub fn fivex_in(cwd: &Path, args: &[&str]) -> Output {
    Command::new(fivex_bin())
        .args(args)
        .current_dir(cwd)
        .stdin(Stdio::null())
        .output()
        .unwrap_or_else(|e| panic!("cannot start {}: {e}", fivex_bin().display()))
}

/// Run `fivex ARGS` in the current directory.
pub fn fivex(args: &[&str]) -> Output {
    fivex_in(Path::new("."), args)
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8(o.stdout.clone()).expect("stdout is UTF-8")
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The fixtures directory (`tests/fixtures`).
pub fn fixtures_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures")
}
