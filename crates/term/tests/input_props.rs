//! The byte-stream input decoder against anything a terminal, a network or a fuzzer can send.

use mazewalk_testkit as common;

use mazewalk_term::input::{
    ESC_TIMEOUT, Input, InputDecoder, Key, KeyPhase, Modifiers, PASTE_IDLE, Protocol, encode,
};
use proptest::prelude::*;

/// Every key mazewalk binds, plus the ones its host handles (Ctrl-C, Ctrl-Z).
fn arb_key() -> impl Strategy<Value = (Key, Modifiers)> {
    let ctrl = Modifiers { ctrl: true, ..Modifiers::NONE };
    let shift = Modifiers { shift: true, ..Modifiers::NONE };
    prop_oneof![
        prop::sample::select(b"wasdqWASDQ[]+-=_pmcrh?xyz019 ".to_vec()).prop_map(move |b| {
            let c = char::from(b);
            if c.is_ascii_uppercase() {
                (Key::Char(c.to_ascii_lowercase()), shift)
            } else {
                (Key::Char(c), Modifiers::NONE)
            }
        }),
        prop::sample::select(vec![Key::Up, Key::Down, Key::Left, Key::Right, Key::Enter, Key::Esc, Key::Tab])
            .prop_map(|k| (k, Modifiers::NONE)),
        prop::sample::select(vec!['c', 'z']).prop_map(move |c| (Key::Char(c), ctrl)),
    ]
}

fn arb_phase() -> impl Strategy<Value = KeyPhase> {
    prop::sample::select(vec![KeyPhase::Press, KeyPhase::Repeat, KeyPhase::Release])
}

/// Garbage with a bias toward the bytes that start and shape sequences.
fn arb_garbage() -> impl Strategy<Value = Vec<u8>> {
    prop::collection::vec(
        prop_oneof![
            3 => any::<u8>(),
            2 => prop::sample::select(b"\x1b[]O;:<?~Mu0123456789\x07\x9b\x90".to_vec()),
        ],
        0..64,
    )
}

/// Decodes `chunks` one after the other at time `t`, then lets the stream pause.
fn decode_paused(decoder: &mut InputDecoder, chunks: &[&[u8]], t: f64) -> Vec<Input> {
    let mut out = Vec::new();
    for chunk in chunks {
        decoder.feed(chunk, t, &mut out);
    }
    decoder.expire(t + ESC_TIMEOUT.max(PASTE_IDLE), &mut out);
    out
}

proptest! {
    #![proptest_config(common::config())]

    /// No byte sequence panics, and once the stream has paused, a well-formed key that follows comes
    /// out exactly, whatever came before it (an unfinished sequence, a paste marker, an X10 mouse
    /// report, invalid UTF-8).
    #[test]
    fn garbage_never_loses_a_later_key(garbage in arb_garbage(), (key, modifiers) in arb_key(), kitty in any::<bool>()) {
        let protocol = if kitty { Protocol::Kitty } else { Protocol::Legacy };
        let input = Input::Key { key, phase: KeyPhase::Press, modifiers };
        let bytes = encode(&input, protocol).expect("every key mazewalk uses has an encoding");
        let mut decoder = InputDecoder::new();
        decode_paused(&mut decoder, &[&garbage], 0.0);
        prop_assert_eq!(decode_paused(&mut decoder, &[&bytes], 10.0), vec![input]);
    }

    /// Encode → decode is the identity for every key mazewalk uses, with every phase the protocol
    /// can express, split into chunks at any two points.
    #[test]
    fn keys_round_trip_split_anywhere(
        script in prop::collection::vec((arb_key(), arb_phase()), 1..12),
        kitty in any::<bool>(),
        cuts in (any::<prop::sample::Index>(), any::<prop::sample::Index>()),
    ) {
        let protocol = if kitty { Protocol::Kitty } else { Protocol::Legacy };
        let inputs: Vec<Input> = script
            .into_iter()
            .map(|((key, modifiers), phase)| Input::Key { key, phase, modifiers })
            // Legacy terminals report presses only; a lone Esc then needs a pause, so none mid-script.
            .filter(|i| kitty || matches!(i, Input::Key { phase: KeyPhase::Press, key, .. } if *key != Key::Esc))
            .collect();
        let bytes: Vec<u8> = inputs.iter().flat_map(|i| encode(i, protocol).unwrap()).collect();
        let (mut a, mut b) = (cuts.0.index(bytes.len() + 1), cuts.1.index(bytes.len() + 1));
        if a > b { std::mem::swap(&mut a, &mut b); }
        let mut decoder = InputDecoder::new();
        let decoded = decode_paused(&mut decoder, &[&bytes[..a], &bytes[a..b], &bytes[b..]], 0.0);
        prop_assert_eq!(decoded, inputs);
    }

    /// Mouse reports round-trip too (drags as deltas from the press).
    #[test]
    fn mouse_reports_round_trip(col in 0u16..500, row in 0u16..200) {
        use mazewalk_term::input::MouseButton::Left;
        let down = Input::MouseDown { button: Left, col, row };
        let bytes = encode(&down, Protocol::Legacy).unwrap();
        let mut decoder = InputDecoder::new();
        prop_assert_eq!(decode_paused(&mut decoder, &[&bytes], 0.0), vec![down]);
    }
}
