//! The shop-floor interfaces driven by independent clients: the MTConnect agent's documents
//! validated by lxml against the standard's schemas (`mtconnect`), the OPC UA server browsed,
//! read, subscribed to and called by Python's asyncua (`opcua`). The Python is
//! scripts/python-venv.sh's (`$FIVEX_TEST_PYTHON`, else target/venv/bin/python): without it
//! these tests fail, they are not skipped.

mod mtconnect;
mod opcua;

use std::path::PathBuf;
use std::process::Command;

/// The Python with asyncua and lxml.
pub fn python() -> PathBuf {
    if let Some(p) = std::env::var_os("FIVEX_TEST_PYTHON") {
        return PathBuf::from(p);
    }
    let venv = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/venv/bin/python");
    assert!(venv.exists(), "{} missing: run scripts/python-venv.sh (or set FIVEX_TEST_PYTHON)", venv.display());
    venv
}

/// Runs `script` (Python source) with `args`; its stdout if it exits 0, else a panic with both
/// outputs.
pub fn run_python(script: &str, args: &[&str]) -> String {
    let out = Command::new(python()).arg("-c").arg(script).args(args).output().expect("run python");
    let (stdout, stderr) = (String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "python failed ({}):\nstdout:\n{stdout}\nstderr:\n{stderr}", out.status);
    stdout.into_owned()
}

/// The address a log line `… {marker}ADDR` announced, waiting up to 30 s for it.
pub fn announced(log: impl Fn() -> String, marker: &str) -> String {
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(30);
    loop {
        let text = log();
        if let Some(at) = text.find(marker) {
            let rest = &text[at + marker.len()..];
            return rest.split_whitespace().next().unwrap_or_default().trim_end_matches('/').to_string();
        }
        assert!(std::time::Instant::now() < deadline, "never announced {marker:?}; log: {text}");
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
}
