fn main() {
    std::process::exit(towride::cli::main());
}
