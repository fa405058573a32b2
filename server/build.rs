// The release binary embeds `web/dist` (see src/assets.rs): rebuild when the dashboard is rebuilt.
fn main() {
    println!("cargo:rerun-if-changed=../web/dist");
    println!("cargo:rerun-if-changed=../web/dist/index.html");
}
