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
//! send, what the others have, who keeps a label), both pure; [`redis`] the keys, connections and
//! commands; [`task`] the world task that drives them ([`SharedWorld::join`]) for a [`Host`];
//! [`records`] the best times in Redis behind the records' `Store`.

pub mod codec;
pub mod records;
pub mod redis;
pub mod task;
pub mod view;

pub use codec::{Bounds, ServerId};
pub use redis::WorldError;
pub use task::{Host, LocalFinish, SharedWorld, Stats, WorldConfig};
pub use view::Caps;
