//! The terminal layer: the only place that knows about crossterm and escape sequences.
//!
//! - [`encoder`]: a [`Frame`](crate::frame::Frame) in, the fewest bytes out (pure);
//! - [`guard`]: raw mode, alternate screen and the rest, always restored (drop, panic, signals, Ctrl-Z);
//! - [`caps`]: colour depth from the environment (pure);
//! - [`input`]: crossterm events mapped to mazewalk's own [`Input`](input::Input).

pub mod encoder;
pub mod guard;
