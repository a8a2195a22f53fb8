//! Issue #35: a message from Redis is untrusted input. Feeds arbitrary bytes to the shared world's
//! decoder (`mazewalk_serve::shared::codec::decode`) with the built-in maze's bounds, the maze tag
//! taken from the input's own header so that the fuzzer reaches the bodies, and to a view of the
//! other servers (`Others::hear`). Asserts: no panic and no hang; a message that decodes has every
//! position inside the maze's extents and every cell in the maze, encodes back, and decodes again
//! to the same message; the view never holds more players than the messages brought.

#![no_main]

use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use mazewalk_serve::shared::codec::{self, Body, Bounds, MAX_PLAYERS, ServerId};
use mazewalk_serve::shared::view::Others;

/// The built-in maze's bounds (parsed once: the maze is not what is fuzzed here).
fn bounds() -> Bounds {
    static BOUNDS: OnceLock<Bounds> = OnceLock::new();
    *BOUNDS.get_or_init(|| Bounds::of(&mazewalk_maze::builtin().expect("built-in maze")))
}

fuzz_target!(|bytes: &[u8]| {
    let bounds = bounds();
    let tag = bytes.get(4..12).map_or(0, |b| u64::from_le_bytes(b.try_into().expect("8 bytes")));
    let mut view = Others::new(ServerId(u64::MAX), tag, bounds);
    // The input cut after each 0xff byte: several messages into one view.
    for (i, part) in bytes.split_inclusive(|&b| b == 0xff).enumerate() {
        let _ = view.hear(part, i as f64);
        assert!(view.len() <= MAX_PLAYERS * (i + 1));
    }
    let Ok(message) = codec::decode(bytes, tag, &bounds) else { return };
    let positions: Vec<_> = match &message.body {
        Body::Full { players, .. } => players.iter().map(|p| p.at).collect(),
        Body::Delta { joined, moved, .. } => {
            joined.iter().map(|p| p.at).chain(moved.iter().map(|m| m.at)).collect()
        }
        Body::Bye => Vec::new(),
    };
    for at in positions {
        assert!(at.cell < bounds.cells, "{at:?}");
        assert!(at.position.is_finite() && (0.0..360.0).contains(&at.heading_deg), "{at:?}");
    }
    let mut again = Vec::new();
    codec::encode(&message, &mut again);
    assert_eq!(again.len(), bytes.len(), "one encoding per message");
    assert_eq!(codec::decode(&again, tag, &bounds).as_ref(), Ok(&message), "a round trip");
});
