//! The `prehensile` executable: everything is in the library's `cli` module.

fn main() {
    prehensile::cli::main();
}
