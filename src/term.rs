//! The terminal layer: the only place that knows about crossterm and writes escape sequences.
//!
//! - [`encoder`]: a [`Frame`](crate::frame::Frame) in, the fewest bytes out (pure);
//! - [`guard`]: raw mode, alternate screen and the rest, always restored (drop, panic, signals, Ctrl-Z
//!   and SIGTSTP);
//! - [`caps`]: colour depth and BCE from the environment (pure).
//!
//! Input is not here: the terminal's bytes are decoded by the pure [`crate::input`] module, so that
//! a local terminal and an SSH channel share one decoder.
//!
//! How an event loop uses them: see [`crate::app::run`], which sleeps in `poll(2)` on stdin and on
//! [`TerminalGuard::wakeups`], feeds what it reads to a [`Session`](crate::app::Session) and writes
//! each frame with [`TerminalGuard::write_frame`].

pub mod caps;
pub mod encoder;
pub mod guard;

pub use encoder::{EncodeStats, Encoder};
pub use guard::{Enabled, GuardOptions, TerminalGuard};
