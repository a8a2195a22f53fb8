//! The input decoder's memory against an endless string (red-team pass 11): what it keeps is
//! measured as the process's peak resident memory, so this file holds one test, alone in its process.
#![cfg(target_os = "linux")]

use mazewalk_term::input::{Input, InputDecoder, Key};
use mazewalk_testkit::memory::{peak_kb, reset_peak};

// Red-team pass 11: an OSC string (`ESC ] 11 ; …`, a colour reply that never ends) of `é` after
// `é` was kept whole by the tokenizer, 16 MB for 16 MB sent: the bound on an unfinished sequence
// counted from the last UTF-8 lead byte, so two-byte characters never reached it. A served player
// sending it just under the input rate grew the server by 16 KiB a second until it idled out.
#[test]
fn an_endless_string_of_non_ascii_text_is_dropped_in_bounded_memory() {
    const SENT: usize = 16 << 20;
    let mut d = InputDecoder::new();
    let mut out = Vec::new();
    let chunk = "é".repeat(2048); // 4 KiB, as the walk reads
    let before = reset_peak();
    d.feed(b"\x1b]11;", 0.0, &mut out);
    for _ in 0..SENT / chunk.len() {
        d.feed(chunk.as_bytes(), 0.0, &mut out);
        out.clear(); // the characters past the bound are text: not what is measured
    }
    let grown = peak_kb().saturating_sub(before);
    assert!(grown < 2048, "the decoder grew by {grown} kB for {} kB of one string", SENT >> 10);
    // and the decoder still decodes
    d.feed(b"\x07", 0.0, &mut out);
    out.clear();
    d.feed(b"q", 0.0, &mut out);
    assert_eq!(out, [Input::press(Key::Char('q'))]);
}
