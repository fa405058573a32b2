// sqlx::migrate! embeds ../migrations at compile time; rebuild when a migration is added.
// The machine library (../machines/*.json) is embedded too: `OUT_DIR/library.rs` lists each
// file as `("name", include_str!(path))`, in name order.
fn main() {
    // The release binary embeds `web/dist` (src/assets.rs): rebuild when the dashboard is rebuilt.
    // Cargo takes a watched path that does not exist as changed on every build, so without a
    // built dashboard (a fresh clone or worktree) watch `web/` itself: its newest file changes
    // when `npm run build` creates `dist`, and nothing else recompiles the server meanwhile.
    // The manifest directory of this build, read when the script runs: `env!` would freeze the
    // one the script was compiled in (a target directory copied between worktrees then read
    // a machines folder that no longer exists and embedded an empty library without a word).
    let manifest = std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR");
    let manifest = std::path::Path::new(&manifest);
    if manifest.join("../web/dist").is_dir() {
        println!("cargo:rerun-if-changed=../web/dist");
        println!("cargo:rerun-if-changed=../web/dist/index.html");
    } else {
        println!("cargo:rerun-if-changed=../web");
    }
    println!("cargo:rerun-if-changed=../migrations");
    println!("cargo:rerun-if-changed=../machines");
    let dir = manifest.join("../machines");
    let entries = std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("the machine library {}: {e}", dir.display()));
    let mut files: Vec<std::path::PathBuf> = entries.map(|e| e.expect("a machine library entry").path()).collect();
    files.retain(|p| p.extension().is_some_and(|e| e == "json"));
    assert!(!files.is_empty(), "the machine library {} holds no machine file", dir.display());
    files.sort();
    let mut out = String::from("[\n");
    for path in &files {
        println!("cargo:rerun-if-changed={}", path.display());
        let name = path.file_stem().unwrap().to_string_lossy();
        let path = path.canonicalize().unwrap();
        out.push_str(&format!("    ({name:?}, include_str!({:?})),\n", path.display().to_string()));
    }
    out.push(']');
    let target = std::path::Path::new(&std::env::var("OUT_DIR").unwrap()).join("library.rs");
    std::fs::write(target, out).unwrap();
}
