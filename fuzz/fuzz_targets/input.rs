//! Feeds arbitrary bytes to the input decoder, in chunks cut where the input says, with pauses.
//! Asserts: no panic and no hang; after a pause long enough for any unfinished sequence or paste to
//! be given up, a well-formed key comes out exactly (nothing earlier can swallow it).

#![no_main]

use libfuzzer_sys::fuzz_target;
use mazewalk_term::input::{ESC_TIMEOUT, Input, InputDecoder, Key, PASTE_IDLE};

fuzz_target!(|bytes: &[u8]| {
    let mut decoder = InputDecoder::new();
    let mut out = Vec::new();
    let mut t = 0.0;
    // The first byte of each chunk is its length; a zero length is a pause.
    let mut rest = bytes;
    while let Some((&len, tail)) = rest.split_first() {
        let len = usize::from(len).min(tail.len());
        let (chunk, tail) = tail.split_at(len);
        if len == 0 {
            t += ESC_TIMEOUT;
            decoder.expire(t, &mut out);
        } else {
            decoder.feed(chunk, t, &mut out);
        }
        rest = tail;
    }
    t += PASTE_IDLE.max(ESC_TIMEOUT);
    decoder.expire(t, &mut out);
    out.clear();
    decoder.feed(b"q\x1b[D", t, &mut out);
    assert_eq!(out, [Input::press(Key::Char('q')), Input::press(Key::Left)]);
});
