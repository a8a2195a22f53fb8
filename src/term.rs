//! The terminal layer: the only place that knows about crossterm and escape sequences.
//!
//! - [`encoder`]: a [`Frame`](crate::frame::Frame) in, the fewest bytes out (pure);
//! - [`guard`]: raw mode, alternate screen and the rest, always restored (drop, panic, signals, hang-up,
//!   Ctrl-Z and SIGTSTP);
//! - [`caps`]: colour depth and BCE from the environment (pure);
//! - [`input`]: crossterm events mapped to mazewalk's own [`Input`](input::Input).
//!
//! How an event loop uses them:
//!
//! ```no_run
//! use std::time::Duration;
//! use mazewalk::frame::Frame;
//! use mazewalk::term::{Encoder, GuardOptions, Input, InputReader, Key, TerminalGuard, caps, guard};
//!
//! let env = |k: &str| std::env::var(k).ok();
//! let _depth = caps::detect_color_depth(env); // unless --color says otherwise
//! let mut terminal = TerminalGuard::enter(GuardOptions::default())?;
//! let mut encoder = Encoder::new();
//! encoder.set_bce(caps::detect_bce(env));
//! let mut input = InputReader::new();
//! let (cols, rows) = guard::size()?;
//! let mut frame = Frame::new(cols.into(), rows.into());
//! let mut bytes = Vec::new();
//! loop {
//!     while let Some(event) = input.next_input(Duration::ZERO)? {
//!         match event {
//!             Input::Key { key: Key::Char('q'), .. } => return Ok(()), // the guard restores on drop
//!             Input::Key { key: Key::Char('z'), modifiers, .. } if modifiers.ctrl => {
//!                 terminal.suspend()?; // Ctrl-Z; back after `fg`
//!             }
//!             Input::Resize { cols, rows } => frame.resize(cols.into(), rows.into()),
//!             _ => {} // hand the rest to the (pure) app state
//!         }
//!     }
//!     if terminal.take_resumed() {
//!         // Back from Ctrl-Z or SIGTSTP: the screen was cleared, the size may differ.
//!         encoder.invalidate();
//!         let (cols, rows) = guard::size()?;
//!         frame.resize(cols.into(), rows.into());
//!     }
//!     // render into `frame` here
//!     bytes.clear();
//!     let _stats = encoder.encode(&frame, &mut bytes); // HUD: stats.bytes, stats.cells_changed
//!     terminal.write_frame(&bytes)?;
//!     # break;
//! }
//! # Ok::<(), std::io::Error>(())
//! ```

pub mod caps;
pub mod encoder;
pub mod guard;
pub mod input;

pub use encoder::{EncodeStats, Encoder};
pub use guard::{Enabled, GuardOptions, TerminalGuard};
pub use input::{Input, InputReader, Key, KeyAction, Modifiers, MouseButton};
