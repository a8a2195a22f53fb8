//! The terminal protocol as pure bytes — no I/O, no terminal library: what ratatui-core is to
//! ratatui. Both a local walk and a server's players speak it.
//!
//! - [`frame`]: the character grid ([`Frame`], [`Cell`], [`Color`], [`ColorDepth`]) that the renderer
//!   draws into and the encoder sends;
//! - [`encoder`]: a [`Frame`] in, the fewest bytes out (a diff with what the terminal shows);
//! - [`input`]: the terminal's bytes in, keys, mouse, focus and the terminal's replies out;
//! - [`blocks`]: the block glyphs (halves, quadrants, sextants) as masks, their ink and complements;
//! - [`caps`]: colour depth, block glyphs and BCE from the environment's variables (a function of the
//!   variables it is given), and the questions that ask the terminal itself (truecolor, `REP`);
//! - [`modes`]: the bytes that enter game mode (alternate screen, mouse, focus, kitty keyboard
//!   flags) and put the terminal back.
//!
//! Every escape sequence mazewalk sends is built here; whoever owns a terminal or a channel
//! (the `mazewalk` binary's guard and loop, `mazewalk serve`) only writes them.

#![forbid(unsafe_code)]

pub mod blocks;
pub mod caps;
pub mod encoder;
pub mod frame;
pub mod input;
pub mod modes;

pub use encoder::{EncodeStats, Encoder};
pub use frame::{Cell, Color, ColorDepth, Frame, Region};
