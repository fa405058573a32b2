// sqlx::migrate! embeds ../migrations at compile time; rebuild when a migration is added.
// The machine library (../machines/*.json) is embedded too: `OUT_DIR/library.rs` lists each
// file as `("name", include_str!(path))`, in name order.
fn main() {
    // The release binary embeds `web/dist` (src/assets.rs): rebuild when the dashboard is rebuilt.
    println!("cargo:rerun-if-changed=../web/dist");
    println!("cargo:rerun-if-changed=../web/dist/index.html");
    println!("cargo:rerun-if-changed=../migrations");
    println!("cargo:rerun-if-changed=../machines");
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../machines");
    let mut files: Vec<std::path::PathBuf> =
        std::fs::read_dir(&dir).map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect()).unwrap_or_default();
    files.retain(|p| p.extension().is_some_and(|e| e == "json"));
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
