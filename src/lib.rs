//! The `mazewalk` binary's own library: what only the binary does, kept testable beside it — the
//! command line ([`cli`], clap), the local walk's terminal guard ([`guard`]: raw mode, the alternate
//! screen and the rest, always restored) and its event loop ([`run`]: stdin and stdout around a
//! [`Session`](mazewalk_walk::Session)), which `--record` writes down as an asciicast ([`cast`]).
//! Everything else is the crates' under `crates/`.

#![forbid(unsafe_code)]

pub mod cast;
pub mod cli;
pub mod commands;
#[cfg(unix)]
pub mod guard;
#[cfg(unix)]
pub mod run;
