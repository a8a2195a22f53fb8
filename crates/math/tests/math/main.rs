//! The math crate's integration tests, one binary (one link) for all of them: the oracle (glam's
//! camera functions), invariants, depth conventions, the normal matrix, clipping.

mod common;
mod math_clip;
mod math_depth;
mod math_invariants;
mod math_normal;
mod math_oracle;
