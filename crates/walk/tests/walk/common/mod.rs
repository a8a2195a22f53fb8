//! Shared by the walk crate's tests: the slow-link harness.

#![allow(dead_code)]

pub use mazewalk_testkit::link;
