//! One player's walk through a maze, pure: the walk's state and its key handlers ([`state`],
//! [`controls`]), asciicasts of a walk ([`cast`]), the overlays drawn over the 3D view ([`overlay`],
//! and a served maze's player list, [`roster`]), the composed screen ([`screen`]), end-to-end flow
//! control ([`flow`]), views shared by several screens ([`views`]), a walk's stored run for ghosts and
//! replays ([`run`]), the exit clock's text ([`clock`]: a time given, none read) and the [`Session`]
//! that ties them to a terminal's bytes. No I/O, no clock (time comes in as seconds): the `mazewalk`
//! binary runs a session on its own terminal, `mazewalk serve` one per SSH channel.

#![forbid(unsafe_code)]

pub mod cast;
pub mod clock;
pub mod controls;
pub mod flow;
pub mod overlay;
pub mod roster;
pub mod run;
pub mod screen;
pub mod session;
pub mod state;
pub mod views;

pub use controls::Action;
pub use session::{Outcome, Session, SessionOptions};
pub use state::{App, MapMode};
