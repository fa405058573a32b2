fn main() {
    std::process::exit(fivex_server::cli::main());
}
