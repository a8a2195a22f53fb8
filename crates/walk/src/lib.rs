//! The walkthrough: pure state and key handlers ([`state`], [`controls`]), the overlays drawn over the
//! 3D view ([`overlay`]), and the event loop that wires them to the terminal ([`run`]).

#![forbid(unsafe_code)]

pub mod controls;
pub mod flow;
pub mod overlay;

pub mod session;
pub mod state;

pub use controls::Action;
pub use session::{Outcome, Session, SessionOptions};
pub use state::{App, MapMode};
