//! The shared world on Redis (`mazewalk serve --world redis://…`): every server started with the
//! same URL and the same maze walks one world.
//!
//! ```text
//! player tasks ─(World lock, data only)─▶ World ◀─(lock, data only)─ world task (one per server)
//!                                                                   │ every tick (≤ 30/s): the
//!                                                                   │ changes ─▶ one PUBLISH
//!                                                                   │ every second: everyone ─▶
//!                                                                   │ PUBLISH + presence key (TTL)
//!                                              SUBSCRIBE ◀─ Redis ◀─┘ claims: SET NX; records: ZADD
//! ```
//!
//! [`codec`] is the wire format (untrusted input, decoded with bounds), [`view`] the rules (what to
//! send, what the others have, who keeps a label), both pure.
#![allow(missing_docs)]

pub mod codec;
pub mod view;
