//! No library: the benchmarks are `benches/*.rs`, the measuring tools `benches/examples/*.rs`.
