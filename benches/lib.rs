//! What the benchmarks (`benches/*.rs`) and the measuring tools (`benches/examples/*.rs`) share: the
//! benchmark mazes and viewpoints ([`common`]). The tests' harnesses they also use are in
//! mazewalk-testkit.

pub mod common;
