//! What the benchmarks (`benches/*.rs`) and the measuring tools (`benches/examples/*.rs`) share: the
//! benchmark mazes and viewpoints ([`common`]), a stream's bytes by kind ([`stream`]). The tests' harnesses they also use are in
//! mazewalk-testkit.

pub mod common;
pub mod stream;
