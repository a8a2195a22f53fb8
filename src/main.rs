//! The `mazewalk` binary: command-line wiring only; everything else lives in the library.

fn main() {
    println!("mazewalk: work in progress");
}
