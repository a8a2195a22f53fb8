//! The frame encoder checked by a real terminal emulator: its bytes, fed to `vt100`, must reproduce the
//! intended frame cell for cell (glyph, foreground, background), over random sequences of frames.

use mazewalk_testkit as common;

use mazewalk_term::blocks::{HALF, QUAD, sextant_glyph};
use mazewalk_term::caps::RepLevel;
use mazewalk_term::encoder::Encoder;
use mazewalk_term::frame::{Cell, Color, Frame, xterm_rgb};
use proptest::prelude::*;

use mazewalk_testkit::baseline::{full_repaint, lower_bound};
use mazewalk_testkit::oklab_distance;

/// Glyphs the encoder meets: blanks (often, so tails and gaps happen), ASCII, shades, box drawing, block
/// glyphs with complements (halves, quadrants, sextants). All one column wide, as the `Frame` guarantees.
const GLYPHS: &[char] = &[
    ' ', ' ', ' ', 'a', '#', '.', '█', '▓', '░', '─', '│', '┼', '🬀', 'é', '▀', '▄', '▌', '▐', '▘', '▟', '🬻',
    '🬋',
];

/// How a cell looks: a block glyph as the colour of each of its 2×6 sub-cells (so `▀` in A on B and
/// `▄` in B on A look the same), any other glyph as itself, its foreground unless a space, and its
/// background. Written from the renderer's glyph tables, independently of `Cell::same_look`.
#[derive(Debug, PartialEq)]
enum Look {
    Block([Shown; 12]),
    Glyph(char, Option<Color>, Color),
}

/// A colour as a part of a block glyph shows it: the terminal's default foreground and its default
/// background are two different colours (light grey and black, say), though both are `Default`.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Shown {
    Color(Color),
    DefaultForeground,
    DefaultBackground,
}

/// Sub-cells a block glyph covers (bit `column + 2·row` of a 2-column, 6-row grid), from the
/// renderer's tables.
fn coverage(ch: char) -> Option<u16> {
    // Every table entry as (glyph, sample mask, samples across, samples down).
    let half = HALF.iter().enumerate().map(|(m, &g)| (g, m, 1, 2));
    let quad = QUAD.iter().enumerate().map(|(m, &g)| (g, m, 2, 2));
    let sextant = (0..64u8).map(|m| (sextant_glyph(m), usize::from(m), 2, 3));
    let mut found = None;
    for (_, mask, sx, sy) in half.chain(quad).chain(sextant).filter(|entry| entry.0 == ch) {
        let (w, h) = (2 / sx, 6 / sy); // sub-cells per sample
        let covered = (0..sx * sy).filter(|k| mask >> k & 1 == 1).flat_map(|k| {
            let (x, y) = (k % sx, k / sx);
            (x * w..x * w + w).flat_map(move |col| (y * h..y * h + h).map(move |row| 1u16 << (col + 2 * row)))
        });
        let c = covered.sum();
        assert!(found.is_none_or(|f| f == c), "{ch:?} covers the same in every table");
        found = Some(c);
    }
    found
}

fn look(cell: &Cell) -> Look {
    match coverage(cell.ch) {
        Some(c) => Look::Block(std::array::from_fn(|k| match (c >> k & 1 == 1, cell.fg, cell.bg) {
            (true, Color::Default, _) => Shown::DefaultForeground,
            (true, fg, _) => Shown::Color(fg),
            (false, _, Color::Default) => Shown::DefaultBackground,
            (false, _, bg) => Shown::Color(bg),
        })),
        None => Look::Glyph(cell.ch, (cell.ch != ' ').then_some(cell.fg), cell.bg),
    }
}

/// Whether two looks are the same up to `tolerance` steps of 0.01 in OKLab between colours of known
/// RGB: truecolor colours and the palette's entries 16–255 by xterm's RGB for them (the encoder may
/// send an entry for a truecolor colour); others equal. A hair of slack (1e-5) for the encoder's f32
/// arithmetic.
fn looks_close(a: &Look, b: &Look, tolerance: u8) -> bool {
    let close = |a: &Color, b: &Color| match (known_rgb(*a), known_rgb(*b)) {
        (Some(p), Some(q)) if tolerance > 0 => oklab_distance(p, q) <= f64::from(tolerance) * 0.01 + 1e-5,
        _ => a == b,
    };
    match (a, b) {
        (Look::Block(a), Look::Block(b)) => a.iter().zip(b).all(|(a, b)| match (a, b) {
            (Shown::Color(a), Shown::Color(b)) => close(a, b),
            _ => a == b,
        }),
        (Look::Glyph(ch, fg, bg), Look::Glyph(ch2, fg2, bg2)) => {
            ch == ch2
                && close(bg, bg2)
                && fg.zip(*fg2).is_none_or(|(a, b)| close(&a, &b))
                && fg.is_some() == fg2.is_some()
        }
        _ => false,
    }
}

/// The RGB a colour shows on every xterm-like terminal: a truecolor colour's own, a palette entry
/// 16–255's xterm RGB; `None` for the defaults and the 16 ANSI colours (the theme's).
fn known_rgb(color: Color) -> Option<[u8; 3]> {
    match color {
        Color::Rgb(r, g, b) => Some([r, g, b]),
        Color::Indexed(n @ 16..) => Some(xterm_rgb(n)),
        _ => None,
    }
}

/// Asserts the emulated screen shows `frame`: every cell looks as intended (see [`Look`]).
fn assert_screen_shows(parser: &vt100::Parser, frame: &Frame, context: impl Fn() -> String) {
    assert_screen_shows_within(parser, frame, 0, context);
}

/// [`assert_screen_shows`] up to the encoder's colour `tolerance`.
fn assert_screen_shows_within(
    parser: &vt100::Parser,
    frame: &Frame,
    tolerance: u8,
    context: impl Fn() -> String,
) {
    let shown = screen_frame(parser);
    for y in 0..frame.height() {
        for x in 0..frame.width() {
            let (want, got) = (frame.get(x, y).unwrap(), shown.get(x, y).unwrap());
            if !looks_close(&look(got), &look(want), tolerance) {
                panic!(
                    "cell ({x}, {y}) {}\nwant {want:?}\ngot  {got:?}\nwant lines {:?}\ngot screen\n{}",
                    context(),
                    frame.lines(),
                    parser.screen().contents()
                );
            }
        }
    }
}

/// What the emulated screen shows, as a frame.
fn screen_frame(parser: &vt100::Parser) -> Frame {
    let screen = parser.screen();
    let (rows, cols) = screen.size();
    let mut frame = Frame::new(cols.get().into(), rows.get().into());
    for y in 0..rows.get() {
        for x in 0..cols.get() {
            let got = screen.cell(y, x).unwrap();
            let ch = got.contents().chars().next().unwrap_or(' '); // erased cells are empty
            frame.set(
                x.into(),
                y.into(),
                Cell { ch, fg: from_vt(got.fgcolor()), bg: from_vt(got.bgcolor()) },
            );
        }
    }
    frame
}

fn from_vt(color: vt100::Color) -> Color {
    match color {
        vt100::Color::Default => Color::Default,
        vt100::Color::Idx(n) => Color::Indexed(n),
        vt100::Color::Rgb(r, g, b) => Color::Rgb(r, g, b),
    }
}

/// `Cell::inverse` and `Cell::same_look` agree with how the glyphs look, for every block glyph of every
/// charset and for other glyphs.
#[test]
fn inverse_cells_look_the_same_and_nothing_else_does() {
    let (a, b, c) = (Color::Rgb(200, 10, 10), Color::Indexed(33), Color::Default);
    let mut glyphs: Vec<char> = HALF.iter().chain(&QUAD).copied().chain((0..64).map(sextant_glyph)).collect();
    glyphs.extend(['a', '░', '▓', '─', 'é']);
    let mut inverses = 0;
    for &g in &glyphs {
        let cell = Cell { ch: g, fg: a, bg: b };
        if let Some(inverse) = cell.inverse() {
            inverses += 1;
            assert_eq!(look(&inverse), look(&cell), "{cell:?} vs its inverse {inverse:?}");
            assert!(cell.same_look(&inverse) && inverse.same_look(&cell));
        } else {
            assert!(coverage(g).is_none(), "block glyph {g:?} has no inverse");
        }
        // same_look is exactly "looks the same", and looks_within "looks the same up to the tolerance",
        // against every cell of these glyphs and colours (`near` is 1 step from `a`, `nearer` 2).
        let (near, nearer) = (Color::Rgb(201, 10, 9), Color::Rgb(200, 12, 10));
        for &h in &glyphs {
            for (fg, bg) in
                [(a, b), (b, a), (a, c), (c, b), (a, a), (near, b), (b, nearer), (a, near), (near, near)]
            {
                let other = Cell { ch: h, fg, bg };
                assert_eq!(cell.same_look(&other), look(&cell) == look(&other), "{cell:?} vs {other:?}");
                for tolerance in 0..=2 {
                    assert_eq!(
                        cell.looks_within(&other, tolerance),
                        looks_close(&look(&cell), &look(&other), tolerance),
                        "{cell:?} vs {other:?} within {tolerance}"
                    );
                }
            }
        }
    }
    assert_eq!(inverses, HALF.len() + QUAD.len() + 64, "every block glyph of every table has one");
}

/// An emulated terminal of `width × height` cells, no scrollback.
fn terminal(width: usize, height: usize) -> vt100::Parser {
    vt100::Parser::new(nonzero(height), nonzero(width), 0)
}

/// `first`, then `second`, sent by `encoder` to a new terminal of their size: the terminal, and the
/// bytes and stats of `second`.
fn shown_after(
    encoder: &mut Encoder,
    first: &Frame,
    second: &Frame,
) -> (vt100::Parser, Vec<u8>, mazewalk_term::EncodeStats) {
    let mut parser = terminal(first.width(), first.height());
    let mut out = Vec::new();
    encoder.encode(first, &mut out);
    parser.process(&out);
    out.clear();
    let stats = encoder.encode(second, &mut out);
    parser.process(&out);
    (parser, out, stats)
}

/// Resizes the emulated terminal to the frame's size, as the real one would have been.
fn resize(parser: &mut vt100::Parser, width: usize, height: usize) {
    if parser.screen().size() != (nonzero(height), nonzero(width)) {
        parser.set_size(nonzero(height), nonzero(width));
    }
}

fn nonzero(n: usize) -> std::num::NonZeroU16 {
    std::num::NonZeroU16::new(u16::try_from(n).unwrap()).expect("frames in these tests are never empty")
}

fn arb_color() -> impl Strategy<Value = Color> {
    prop_oneof![
        2 => Just(Color::Default),
        2 => (0u8..16).prop_map(Color::Indexed),
        1 => any::<u8>().prop_map(Color::Indexed),
        2 => (any::<u8>(), any::<u8>(), any::<u8>()).prop_map(|(r, g, b)| Color::Rgb(r, g, b)),
    ]
}

/// A small palette per sequence, so that colours repeat (runs, unchanged gaps, equal backgrounds).
fn arb_palette() -> impl Strategy<Value = Vec<Color>> {
    prop::collection::vec(arb_color(), 1..5)
}

fn arb_cell(palette: Vec<Color>) -> impl Strategy<Value = Cell> + Clone {
    let n = palette.len();
    (prop::sample::select(GLYPHS), 0..n, 0..n).prop_map(move |(ch, fg, bg)| Cell {
        ch,
        fg: palette[fg],
        bg: palette[bg],
    })
}

fn arb_size() -> impl Strategy<Value = (usize, usize)> {
    prop_oneof![3 => (1usize..=12, 1usize..=6), 1 => (1usize..=40, 1usize..=12)]
}

/// A frame of random cells from `palette`.
fn arb_frame(palette: Vec<Color>) -> impl Strategy<Value = Frame> {
    arb_size().prop_flat_map(move |(w, h)| {
        prop::collection::vec(arb_cell(palette.clone()), w * h).prop_map(move |cells| {
            let mut frame = Frame::new(w, h);
            frame.cells_mut().copy_from_slice(&cells);
            frame
        })
    })
}

/// One step from a frame to the next.
#[derive(Clone, Debug)]
enum Step {
    /// A few cells change (positions taken modulo the size).
    Cells(Vec<(usize, usize, Cell)>),
    /// A rectangle is filled with one cell.
    Rect { x: usize, y: usize, w: usize, h: usize, cell: Cell },
    /// Row `y` from column `x` becomes blanks with background `bg`.
    BlankTail { x: usize, y: usize, bg: Color },
    /// Nothing changes.
    Same,
    /// A new frame of another size (the emulated terminal is resized too).
    Resize(Frame),
    /// Someone scribbled on the terminal (resume from Ctrl-Z): the encoder is told to invalidate.
    Invalidate,
}

fn arb_step(palette: Vec<Color>) -> impl Strategy<Value = Step> {
    let cell = arb_cell(palette.clone());
    let color = prop::sample::select(palette.clone());
    prop_oneof![
        4 => prop::collection::vec((0usize..64, 0usize..16, cell.clone()), 1..8).prop_map(Step::Cells),
        2 => (0usize..40, 0usize..12, 1usize..40, 1usize..12, cell)
            .prop_map(|(x, y, w, h, cell)| Step::Rect { x, y, w, h, cell }),
        2 => (0usize..40, 0usize..12, color).prop_map(|(x, y, bg)| Step::BlankTail { x, y, bg }),
        1 => Just(Step::Same),
        1 => arb_frame(palette).prop_map(Step::Resize),
        1 => Just(Step::Invalidate),
    ]
}

/// A first frame and the steps that follow it, all from one palette.
fn arb_frame_sequence() -> impl Strategy<Value = (Frame, Vec<Step>)> {
    arb_palette().prop_flat_map(|palette| {
        (arb_frame(palette.clone()), prop::collection::vec(arb_step(palette), 1..12))
    })
}

/// Applies a step; returns whether the encoder must be invalidated.
fn apply(frame: &mut Frame, step: &Step) -> bool {
    let (w, h) = (frame.width(), frame.height());
    match step {
        Step::Cells(cells) => cells.iter().for_each(|&(x, y, cell)| frame.set(x % w, y % h, cell)),
        Step::Rect { x, y, w: rw, h: rh, cell } => {
            for yy in y % h..(y % h + rh).min(h) {
                for xx in x % w..(x % w + rw).min(w) {
                    frame.set(xx, yy, *cell);
                }
            }
        }
        Step::BlankTail { x, y, bg } => {
            for xx in x % w..w {
                frame.set(xx, y % h, Cell { ch: ' ', fg: Color::Default, bg: *bg });
            }
        }
        Step::Same => {}
        Step::Resize(next) => frame.clone_from(next),
        Step::Invalidate => return true,
    }
    false
}

fn same_look(a: &Frame, b: &Frame) -> bool {
    a.width() == b.width()
        && a.height() == b.height()
        && a.cells().iter().zip(b.cells()).all(|(a, b)| a.same_look(b))
}

/// An encoder set up as a property draws it: erasures with or without BCE, a colour tolerance, a REP
/// level and block glyphs or not.
fn configured(bce: bool, tolerance: u8, rep: RepLevel, blocks: bool) -> Encoder {
    let mut encoder = Encoder::new();
    encoder.set_bce(bce);
    encoder.set_tolerance(tolerance);
    encoder.set_rep(rep);
    encoder.set_blocks(blocks);
    encoder
}

proptest! {
    #![proptest_config(common::config())]

    #[test]
    fn the_emulated_screen_always_shows_the_last_frame(
        (first, steps) in arb_frame_sequence(),
        bce in any::<bool>(),
        tolerance in prop_oneof![3 => Just(0u8), 1 => 1u8..4],
        rep in prop_oneof![Just(RepLevel::None), Just(RepLevel::Ascii), Just(RepLevel::Any)],
        blocks in any::<bool>(),
    ) {
        let mut encoder = configured(bce, tolerance, rep, blocks);
        let mut parser = terminal(first.width(), first.height());
        // The terminal starts with junk on it and odd colours set.
        parser.process(b"\x1b[1;1Hjunk\x1b[31;42mmore junk\x1b[7;3H");
        let mut frame = first.clone();
        let mut prev: Option<Frame> = None;
        let mut out = Vec::new();
        for (i, step) in std::iter::once(&Step::Same).chain(&steps).enumerate() {
            let invalidate = apply(&mut frame, step);
            if invalidate {
                encoder.invalidate();
                parser.process(b"\x1b[H\x1b[2;33;44mscribble\x1b[4;4Hhere");
            }
            resize(&mut parser, frame.width(), frame.height());
            let resized = prev.as_ref().is_none_or(|p| (p.width(), p.height()) != (frame.width(), frame.height()));
            let full_paint = invalidate || resized;
            // The screen as shown (within the tolerance of `prev`), unless the encoder starts afresh.
            let shown = (!full_paint).then(|| screen_frame(&parser));
            let bound = lower_bound(shown.as_ref(), &frame, tolerance);
            out.clear();
            let stats = encoder.encode(&frame, &mut out);
            prop_assert_eq!(stats.full_paint, full_paint);
            prop_assert_eq!(stats.bytes, out.len());
            // (REP sends a run of glyphs in fewer bytes than the glyphs: the bound is of glyphs)
            prop_assert!(rep != RepLevel::None || bound <= out.len(), "lower bound {} > {} bytes", bound, out.len());
            prop_assert!(std::str::from_utf8(&out).is_ok());
            let unchanged = !invalidate && prev.as_ref().is_some_and(|p| same_look(p, &frame));
            if unchanged {
                prop_assert!(out.is_empty(), "unchanged frame sent {:?}", String::from_utf8_lossy(&out));
                prop_assert_eq!(stats.cells_changed, 0);
            }
            parser.process(&out);
            assert_screen_shows_within(&parser, &frame, tolerance, || format!("after step {i} {step:?}\nbytes {:?}", String::from_utf8_lossy(&out)));
            prev = Some(frame.clone());
        }
    }
}

/// A maze-like truecolor scene: ceiling and floor gradients, a wall band with shaded glyphs, a HUD line.
fn scene(width: usize, height: usize, shift: usize) -> Frame {
    let mut frame = Frame::new(width, height);
    for y in 0..height {
        for x in 0..width {
            let t = (y * 255 / height.max(1)) as u8;
            let wall = (x + shift) % 40 < 24 && y > height / 4 && y < height * 3 / 4;
            let cell = if wall {
                let shade = (((x + shift) % 40) * 6) as u8;
                Cell {
                    ch: ['█', '▓', '▒', '░'][(x + shift) % 4],
                    fg: Color::Rgb(200 - shade, 180 - shade, 120),
                    bg: Color::Rgb(40, 30, 20),
                }
            } else if y < height / 2 {
                Cell { ch: ' ', fg: Color::Default, bg: Color::Rgb(10, 10, 30 + t / 4) }
            } else {
                Cell { ch: '.', fg: Color::Rgb(90, 90, 90), bg: Color::Rgb(t / 3, t / 3, t / 3) }
            };
            frame.set(x, y, cell);
        }
    }
    frame.put_str(0, height - 1, "pos 12.5,3.0  fps 60", Color::Indexed(15), Color::Default);
    frame
}

#[test]
fn an_unchanged_frame_costs_nothing_and_one_cell_a_handful_of_bytes() {
    let mut encoder = Encoder::new();
    let mut out = Vec::new();
    let mut frame = scene(160, 48, 0);
    encoder.encode(&frame, &mut out);
    out.clear();
    assert_eq!(encoder.encode(&frame, &mut out).bytes, 0);
    assert!(out.is_empty());
    frame.set(100, 30, Cell { ch: 'x', fg: Color::Rgb(255, 0, 0), bg: Color::Rgb(1, 2, 3) });
    let stats = encoder.encode(&frame, &mut out);
    assert_eq!(stats.cells_changed, 1);
    // 16 bytes of sync markers, ~8 of cursor move, ~30 for two truecolor SGRs, 1 glyph.
    assert!(out.len() < 64, "{} bytes: {:?}", out.len(), String::from_utf8_lossy(&out));
    // The same in the default colours: move + glyph inside the sync markers.
    frame.set(100, 30, Cell::plain('y'));
    let mut encoder = Encoder::new();
    encoder.encode(&Frame::new(160, 48), &mut out);
    out.clear();
    let mut plain = Frame::new(160, 48);
    plain.set(100, 30, Cell::plain('y'));
    encoder.encode(&plain, &mut out);
    assert_eq!(out, b"\x1b[?2026h\x1b[31;101Hy\x1b[?2026l");
    assert!(out.len() < 40);
}

#[test]
fn the_last_row_never_gets_a_line_feed() {
    // Changes on the last two rows, in column 0: "\r\n" would be cheapest if it were allowed to scroll.
    let mut encoder = Encoder::new();
    let mut out = Vec::new();
    let mut frame = Frame::new(5, 2);
    encoder.encode(&frame, &mut out);
    let mut parser = terminal(5, 2);
    parser.process(&out);
    for step in 0..6 {
        frame.set(0, step % 2, Cell::plain(char::from(b'a' + step as u8)));
        frame.set(4, 1, Cell::plain('z'));
        out.clear();
        encoder.encode(&frame, &mut out);
        parser.process(&out);
        assert_screen_shows(&parser, &frame, || format!("step {step}"));
    }
}

#[test]
fn report_bytes_for_typical_scenarios() {
    let (w, h) = (160, 48);
    let mut out = Vec::new();
    let first = scene(w, h, 0);
    let mut naive = Vec::new();
    full_repaint(&first, &mut naive);
    let mut encoder = Encoder::new();
    let full = encoder.encode(&first, &mut out).bytes;
    let mut parser = terminal(w, h);
    parser.process(&out);
    assert_screen_shows(&parser, &first, || "full paint".into());
    out.clear();
    let turned = scene(w, h, 1);
    let turn_bound = lower_bound(Some(&first), &turned, 0);
    let turn = encoder.encode(&turned, &mut out).bytes;
    parser.process(&out);
    assert_screen_shows(&parser, &turned, || "turn".into());
    out.clear();
    let none = encoder.encode(&turned, &mut out).bytes;
    let mut hud = turned.clone();
    hud.put_str(18, h - 1, "59", Color::Indexed(15), Color::Default);
    out.clear();
    let hud_bytes = encoder.encode(&hud, &mut out).bytes;
    let mut one = hud.clone();
    one.set(100, 30, Cell { ch: 'x', fg: Color::Rgb(255, 0, 0), bg: Color::Rgb(1, 2, 3) });
    out.clear();
    let one_cell = encoder.encode(&one, &mut out).bytes;
    let one_cell_text = String::from_utf8_lossy(&out).replace('\x1b', "ESC");
    eprintln!(
        "160x48 truecolor scene: full paint {full} B (naive every-cell SGR {} B); \
         everything shifts one column {turn} B (glyph lower bound {turn_bound} B); \
         HUD digits change {hud_bytes} B; one truecolor cell {one_cell} B ({one_cell_text}); no change {none} B",
        naive.len()
    );
    assert!(full < naive.len() / 2);
    assert_eq!(none, 0);
}

/// With a tolerance, colours that creep by one 8-bit step a frame are resent whenever the screen would
/// lag by more than the tolerance (an OKLab distance), never later; nothing is sent while they stay
/// within it; other glyphs and indexed colours are always exact.
#[test]
fn a_tolerance_lets_small_changes_wait_but_never_drift() {
    let (width, height) = (12, 4);
    let colors = |t: u8, x: usize| {
        let v = 100 + t + x as u8; // every cell one step brighter per frame
        ([v, v / 2, 40], [30, v, v / 3])
    };
    let frame_at = |t: u8| {
        let mut frame = Frame::new(width, height);
        for y in 0..height {
            for x in 0..width {
                let ch = ['▀', ' ', '▄', '🬻'][y];
                let ([r, g, b], [r2, g2, b2]) = colors(t, x);
                frame.set(x, y, Cell { ch, fg: Color::Rgb(r, g, b), bg: Color::Rgb(r2, g2, b2) });
            }
        }
        frame.set(0, 0, Cell { ch: 'x', fg: Color::Indexed(100 + t), bg: Color::Default });
        frame
    };
    // Whether every colour of frame `t` is within the tolerance of frame 0's, by the oracle: whether
    // the first paint may stand.
    let all_within = |t: u8, tolerance: u8| {
        (0..width).all(|x| {
            let ((f0, b0), (f, b)) = (colors(0, x), colors(t, x));
            let limit = f64::from(tolerance) * 0.01;
            oklab_distance(f0, f) <= limit - 1e-5 && oklab_distance(b0, b) <= limit - 1e-5
        })
    };
    let none_within = |t: u8, tolerance: u8| {
        (0..width).all(|x| {
            let ((f0, b0), (f, b)) = (colors(0, x), colors(t, x));
            let limit = f64::from(tolerance) * 0.01;
            oklab_distance(f0, f) > limit + 1e-5 && oklab_distance(b0, b) > limit + 1e-5
        })
    };
    for tolerance in [0u8, 1, 2] {
        let mut encoder = Encoder::new();
        encoder.set_tolerance(tolerance);
        let mut parser = terminal(width, height);
        let mut out = Vec::new();
        let (mut waited, mut resent) = (0, false);
        for t in 0..40u8 {
            let frame = frame_at(t);
            out.clear();
            let stats = encoder.encode(&frame, &mut out);
            parser.process(&out);
            // Never further off than the tolerance, however long the creep goes on.
            assert_screen_shows_within(&parser, &frame, tolerance, || {
                format!("tolerance {tolerance}, frame {t}")
            });
            // After the first paint the screen lags by t steps: while every cell is within the tolerance
            // only the indexed cell is sent (it changes every frame and is always exact); if the first
            // frame that is not has every cell beyond it, every cell is sent. (Later, cells lag by
            // different amounts, as some are resent and the pen's colours are reused within the
            // tolerance: the check above is what holds.)
            if t == 0 || resent {
                continue;
            }
            if all_within(t, tolerance) {
                assert_eq!(stats.cells_changed, 1, "tolerance {tolerance}, frame {t}");
                waited += 1;
                continue;
            }
            if none_within(t, tolerance) {
                assert_eq!(stats.cells_changed, width * height, "tolerance {tolerance}, frame {t}");
            }
            assert!(stats.cells_changed > 1, "tolerance {tolerance}, frame {t}: the lag outgrew it");
            resent = true;
        }
        assert!(resent, "tolerance {tolerance}: the creep outgrew it");
        assert!(tolerance == 0 || waited > 0, "tolerance {tolerance}: some frames waited");
    }
}

/// Issue #42: a half block whose two halves are within the tolerance of one colour (a wall's gentle
/// vertical gradient) goes as a blank in one colour: a single colour code and a one-byte glyph where
/// the exact encoding needs two codes and a three-byte glyph; the screen stays within the tolerance.
/// (Glyphs and colours together, the 60 cells' second frame: 1,401 bytes exact, 463 at the default
/// tolerance, at `de48035`; 2,363 and 449 at `adc70af`.)
#[test]
fn a_half_block_of_two_near_colours_goes_as_a_blank() {
    let (width, height) = (30, 2);
    let wall = |shift: u8| {
        let mut frame = Frame::new(width, height);
        for y in 0..height {
            for x in 0..width {
                let v = 90 + shift + (12 * x / 5) as u8; // a new colour every cell or so along the row
                frame.set(
                    x,
                    y,
                    Cell { ch: '▀', fg: Color::Rgb(v, v + 20, 140), bg: Color::Rgb(v + 1, v + 21, 141) },
                );
            }
        }
        frame
    };
    let mut sizes = Vec::new();
    for tolerance in [0u8, 2] {
        let mut encoder = Encoder::new();
        encoder.set_tolerance(tolerance);
        let frame = wall(60); // every cell far from what is shown
        let (parser, out, _) = shown_after(&mut encoder, &wall(0), &frame);
        assert_screen_shows_within(&parser, &frame, tolerance, || format!("tolerance {tolerance}"));
        let text = String::from_utf8_lossy(&out).into_owned();
        sizes.push((out.len(), text.matches('▀').count() + text.matches('▄').count()));
    }
    assert_eq!(sizes[0].1, width * height, "exact: every cell a half block ({sizes:?})");
    // (A half block stays where the pen's two colours already fit it: three bytes, no colour code.)
    assert!(sizes[1].1 <= width * height / 10, "within 0.02: blanks ({sizes:?})");
    assert!(sizes[1].0 * 2 < sizes[0].0, "less than half the bytes ({sizes:?})");
}

/// With a tolerance, a changed cell whose colour is within it of the colour the terminal is already
/// set to is sent in that colour: along a gradient of one step per cell, about every other cell needs
/// no colour code. The screen stays within the tolerance of the frame.
#[test]
fn a_tolerance_reuses_the_current_colour_along_gradients() {
    let (width, height) = (40, 3);
    let gradient = |shift: u8| {
        let mut frame = Frame::new(width, height);
        for y in 0..height {
            for x in 0..width {
                // (No colour met twice: rows apart by more than a row's width of steps.)
                let v = 60 + shift + x as u8 + 40 * y as u8;
                frame.set(x, y, Cell { ch: '▀', fg: Color::Rgb(v, v, 90), bg: Color::Rgb(20, v, v) });
            }
        }
        frame
    };
    let sgr_count = |bytes: &[u8]| String::from_utf8_lossy(bytes).matches('m').count();
    let mut sgrs = Vec::new();
    for tolerance in [0u8, 1] {
        let mut encoder = Encoder::new();
        encoder.set_tolerance(tolerance);
        let frame = gradient(50); // every cell changes by far more than the tolerance
        let (parser, out, stats) = shown_after(&mut encoder, &gradient(0), &frame); // first paint, exact
        assert_eq!(stats.cells_changed, width * height);
        assert_screen_shows_within(&parser, &frame, tolerance, || format!("tolerance {tolerance}"));
        sgrs.push(sgr_count(&out));
    }
    let cells = width * height;
    // (but the one cell of the colours the first paint left the pen in, which goes first)
    assert!(sgrs[0] >= cells - 1, "exact: a colour code per cell ({sgrs:?})");
    assert!(sgrs[1] <= cells / 2 + height, "±1: about one per two cells ({sgrs:?})");
}

/// Frames of ASCII only (`set_blocks(false)`): a blank is never sent as a full block in the pen's
/// ink, however many bytes that would save (with blocks, the same frames do send one), and the
/// screen shows the frames.
#[test]
fn without_blocks_a_blank_never_goes_as_a_full_block() {
    let (ink, paper) = (Color::Rgb(200, 180, 90), Color::Rgb(20, 30, 40));
    let (w, h) = (12, 6);
    // The pen's ink ends as `ink`; then columns of blanks in `ink` go where it is cheapest.
    let mut first = Frame::filled(w, h, Cell { ch: '#', fg: ink, bg: paper });
    first.set(0, 0, Cell { ch: 'x', fg: paper, bg: ink });
    let mut second = first.clone();
    for y in 0..h {
        // Blanks of the picture (ink = paper): a space in text always goes as a space.
        second.set(5, y, Cell { ch: ' ', fg: ink, bg: ink });
        second.set(9, y, Cell { ch: ' ', fg: ink, bg: ink });
    }
    let mut sent_blocks = Vec::new();
    for blocks in [true, false] {
        let mut encoder = Encoder::new();
        encoder.set_blocks(blocks);
        let (parser, out, _) = shown_after(&mut encoder, &first, &second);
        assert_screen_shows(&parser, &second, || format!("blocks {blocks}"));
        sent_blocks.push(String::from_utf8_lossy(&out).contains('█'));
    }
    assert_eq!(sent_blocks, [true, false], "full blocks sent with blocks on / off");
}

/// The REP questions: on a terminal that repeats any glyph (vt100, as xterm) the cursor ends two
/// cells into row 2 (a space repeated) and three into row 3 (`▀` repeated twice), which
/// [`rep_answer`] reads as yes to both; one cell in is no (REP ignored: everywhere without REP,
/// after `▀` in tmux); a `▀` drawn two cells wide leaves column 3 without REP, also no; row 1 is not
/// an answer. The probe's cells are in rows 2 and 3 only, in the terminal's current colours.
#[test]
fn the_rep_probe_asks_after_a_space_then_after_a_block() {
    use mazewalk_term::caps::{REP_PROBE, RepReport, rep_answer};
    let mut parser = terminal(20, 5);
    parser.process(b"\x1b[31mjunk\x1b[4;7H");
    let second = REP_PROBE.windows(4).position(|w| w == b"\x1b[6n").expect("a first report") + 4;
    parser.process(&REP_PROBE[..second]);
    let (row, col) = parser.screen().cursor_position();
    assert_eq!((row, col), (1, 2));
    assert_eq!(rep_answer(row + 1, col + 1), Some(RepReport::Space(true)));
    assert_eq!(rep_answer(row + 1, col), Some(RepReport::Space(false)));
    parser.process(&REP_PROBE[second..]);
    assert!(REP_PROBE.ends_with(b"\x1b[6n"), "two reports, the last at the end");
    let (row, col) = parser.screen().cursor_position();
    assert_eq!((row, col), (2, 3));
    assert_eq!(rep_answer(row + 1, col + 1), Some(RepReport::Block(true)));
    assert_eq!(rep_answer(3, 2), Some(RepReport::Block(false)), "tmux: `▀` written, REP ignored");
    assert_eq!(rep_answer(3, 3), Some(RepReport::Block(false)), "`▀` two cells wide, REP ignored");
    assert_eq!(rep_answer(3, 7), Some(RepReport::Block(false)), "`▀` two cells wide, repeated");
    assert_eq!(rep_answer(1, 3), None, "Alt-F3 in xterm's encoding");
    assert_eq!(rep_answer(1, 4), None);
    assert_eq!(rep_answer(2, 40), None);
    assert_eq!(rep_answer(4, 4), None);
    let text = parser.screen().contents();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.get(1).map(|l| l.trim_end()), Some(""), "row 2: a space and its repeat");
    assert_eq!(lines.get(2).map(|l| l.trim_end()), Some("▀▀▀"), "row 3: `▀` and two repeats");
}

/// With REP on, a run of changed cells of one look goes as its first glyph and `CSI n b`, the screen
/// shows the same, and the fixed walk costs fewer bytes; a run too short to gain, and cells whose
/// colours differ, go as before.
#[test]
fn rep_sends_runs_of_one_look_in_fewer_bytes() {
    let (w, h) = (40, 3);
    let (ink, paper) = (Color::Rgb(200, 180, 90), Color::Rgb(20, 30, 40));
    let first = Frame::filled(w, h, Cell { ch: ' ', fg: Color::Default, bg: paper });
    let mut second = first.clone();
    for x in 5..25 {
        second.set(x, 1, Cell { ch: '#', fg: ink, bg: paper });
    }
    second.set(30, 1, Cell { ch: '#', fg: ink, bg: paper });
    second.set(31, 1, Cell { ch: '#', fg: ink, bg: paper }); // two: one byte of REP is not shorter
    second.set(33, 2, Cell { ch: '#', fg: paper, bg: ink }); // colours the other way: another look
    for x in 0..w {
        second.set(x, 0, Cell { ch: '▀', fg: ink, bg: paper }); // a block glyph: never repeated
    }
    let levels = [RepLevel::None, RepLevel::Ascii, RepLevel::Any];
    let mut sent = Vec::new();
    for rep in levels {
        let mut encoder = Encoder::new();
        encoder.set_rep(rep);
        let (parser, out, _) = shown_after(&mut encoder, &first, &second);
        assert_screen_shows(&parser, &second, || format!("rep {rep:?}: {:?}", String::from_utf8_lossy(&out)));
        sent.push(out);
    }
    let text = String::from_utf8_lossy(&sent[1]);
    assert!(text.contains("#\x1b[19b"), "the run of 20 as one glyph and REP: {text:?}");
    assert!(text.contains("##"), "a run of two goes as glyphs: {text:?}");
    assert!(text.contains(&"▀".repeat(40)), "block glyphs are written out (tmux): {text:?}");
    assert_eq!(text.matches("b").count(), 1, "one REP: {text:?}");
    assert!(!String::from_utf8_lossy(&sent[0]).contains('b'), "no REP when off");
    assert_eq!(sent[0].len() - sent[1].len(), 19 - 5, "REP saves the 19 glyphs it repeats less its 5 bytes");
    // Where the terminal repeats any glyph: the row of 40 `▀` as one and REP too.
    let any = String::from_utf8_lossy(&sent[2]);
    assert!(any.contains("▀\x1b[39b"), "the row of blocks as one glyph and REP: {any:?}");
    assert!(!any.contains("▀▀"), "no block written twice: {any:?}");
    assert!(any.contains("#\x1b[19b") && any.contains("##"), "ASCII runs as before: {any:?}");
    assert_eq!(
        sent[1].len() - sent[2].len(),
        39 * 3 - 5,
        "REP saves the 39 blocks it repeats less its 5 bytes"
    );
    // The fixed walk of `a_fixed_walk_encodes_to_the_same_bytes`, with REP: fewer bytes, the same screens.
    let (w, h) = (160, 48);
    let mut totals = [0; 3];
    for (k, rep) in levels.into_iter().enumerate() {
        let mut encoder = Encoder::new();
        encoder.set_tolerance(mazewalk_term::encoder::DEFAULT_TOLERANCE);
        encoder.set_rep(rep);
        let mut parser = terminal(w, h);
        let mut out = Vec::new();
        for shift in 0..24 {
            let frame = scene(w, h, shift);
            let start = out.len();
            encoder.encode(&frame, &mut out);
            parser.process(&out[start..]);
            assert_screen_shows_within(&parser, &frame, mazewalk_term::encoder::DEFAULT_TOLERANCE, || {
                format!("rep {rep:?}, shift {shift}")
            });
        }
        totals[k] = out.len();
    }
    assert!(
        totals[2] <= totals[1] && totals[1] < totals[0],
        "REP after any glyph / ASCII / none: {totals:?} bytes"
    );
}

/// The encoder's bytes for a fixed walk through [`scene`] (full paint, then turning one column a frame
/// with the background flickering by a step or two and the HUD changing, then standing still), exact
/// and at the walkthrough's tolerance (an OKLab distance of 0.02 since issue #42), pinned: a
/// refactoring must not change a byte. A deliberate change to the encoding updates the numbers (and BENCHMARKS.md).
#[test]
fn a_fixed_walk_encodes_to_the_same_bytes() {
    let (w, h) = (160, 48);
    let mut totals = Vec::new();
    for (bce, tolerance) in [(true, 0), (true, mazewalk_term::encoder::DEFAULT_TOLERANCE), (false, 0)] {
        let mut encoder = Encoder::new();
        encoder.set_bce(bce);
        encoder.set_tolerance(tolerance);
        let mut out = Vec::new();
        let mut parser = terminal(w, h);
        for shift in (0..24).chain([23, 23]) {
            let mut frame = scene(w, h, shift);
            for cell in frame.cells_mut() {
                if let Color::Rgb(r, g, b) = cell.bg {
                    cell.bg = Color::Rgb(r, g, b.saturating_add((shift % 3) as u8)); // a flicker of one step
                }
            }
            frame.put_str(18, h - 1, &format!("{:02}", 60 - shift % 3), Color::Indexed(15), Color::Default);
            let start = out.len();
            encoder.encode(&frame, &mut out);
            parser.process(&out[start..]);
            assert_screen_shows_within(&parser, &frame, tolerance, || format!("shift {shift}"));
        }
        totals.push(out.len());
    }
    assert_eq!(totals, [432_895, 328_922, 483_058]);
}

/// A space between words (a blank whose ink is not its paper, as `Frame::put_str` writes text) goes as
/// a space, whatever the pen: text reads back as written (copy and paste, screen readers, a test
/// reading the screen), not as a full block in the pen's ink that looks the same. The walk's HUD once
/// began `█heading` where the view's last cell left the pen's ink in the HUD's paper (`cee9c4f`).
/// A blank in one colour (ink = paper, as the renderer draws them) may still go as a full block.
#[test]
fn a_space_in_text_goes_as_a_space_whatever_the_pen() {
    let (w, h) = (24, 3);
    let (view, hud, text) = (Color::Indexed(239), Color::Indexed(236), Color::Indexed(252));
    for blocks in [true, false] {
        for bce in [true, false] {
            let first = Frame::filled(w, h, Cell { ch: ' ', fg: view, bg: view });
            let mut second = first.clone();
            // The view's last row ends in the HUD's paper as ink: the pen's ink when the HUD starts.
            for x in 0..w {
                second.set(x, 1, Cell { ch: '▀', fg: hud, bg: view });
            }
            second.set(0, 2, Cell { ch: ' ', fg: text, bg: hud }); // as overlay.rs pads the HUD
            second.put_str(1, 2, "heading 0° E", text, hud);
            second.set(13, 2, Cell { ch: ' ', fg: text, bg: hud });
            second.put_str(14, 2, "? help", text, hud);
            // One-colour blanks right after the pen's ink is theirs: these may go as full blocks. (In
            // a colour the pen the HUD leaves does not have: blanks in its paper would go first, as
            // spaces, before the pen changes.)
            let ink = Color::Indexed(101);
            let mut third = second.clone();
            for x in 0..3 {
                third.set(x, 0, Cell { ch: 'x', fg: ink, bg: view });
                third.set(x + 3, 0, Cell { ch: ' ', fg: ink, bg: ink });
            }
            let mut encoder = Encoder::new();
            encoder.set_blocks(blocks);
            encoder.set_bce(bce);
            let mut parser = terminal(w, h);
            let mut sent = Vec::new();
            for (k, frame) in [&first, &second, &third].into_iter().enumerate() {
                let mut out = Vec::new();
                encoder.encode(frame, &mut out);
                parser.process(&out);
                let context = || format!("blocks {blocks}, bce {bce}: {:?}", String::from_utf8_lossy(&out));
                assert_screen_shows(&parser, frame, context);
                let row = parser.screen().contents_between(2, 0, 2, w as u16);
                if k > 0 {
                    assert_eq!(row.trim_end(), " heading 0° E ? help", "{}", context());
                }
                sent.push(out);
            }
            let blocks_sent = String::from_utf8_lossy(&sent[2]).contains('█');
            assert_eq!(blocks_sent, blocks, "a one-colour blank as a full block, blocks {blocks}");
        }
    }
}

/// The glyphs in `bytes` outside escape sequences (not controls): each is a cell written.
fn glyphs_written(bytes: &[u8]) -> usize {
    let text = String::from_utf8_lossy(bytes);
    let mut in_escape = false;
    text.chars()
        .filter(|&c| {
            if in_escape {
                in_escape = !(('@'..='~').contains(&c) && c != '[');
                return false;
            }
            in_escape = c == '\x1b';
            !in_escape && !c.is_control()
        })
        .count()
}

/// Issue #42: two walls' edges slanting across the rows, one look each (half blocks of two palette
/// entries), so that row by row the looks alternate: row by row the pen would change at every cell
/// (two colour codes a row). The encoder writes the cells of the pen's colours elsewhere before it
/// changes the pen, edge by edge: a few colour codes for the frame, every changed cell written once
/// (the edges stand far enough apart that no unchanged cell is rewritten on the way), and the screen
/// the frame, in 256 colours and in truecolor, with and without REP.
#[test]
fn cells_of_the_pens_colours_elsewhere_go_before_the_pen_changes() {
    let (width, height) = (100, 12);
    let ground = Cell { ch: ' ', fg: Color::Indexed(236), bg: Color::Indexed(236) };
    for (a, b, c, d) in [
        (Color::Indexed(101), Color::Indexed(180), Color::Indexed(66), Color::Indexed(144)),
        (
            Color::Rgb(120, 90, 40),
            Color::Rgb(200, 180, 120),
            Color::Rgb(40, 90, 120),
            Color::Rgb(150, 180, 200),
        ),
    ] {
        for rep in [RepLevel::None, RepLevel::Any] {
            let mut frame = Frame::new(width, height);
            frame.cells_mut().fill(ground);
            let mut encoder = Encoder::new();
            encoder.set_rep(rep);
            let mut parser = terminal(width, height);
            let mut out = Vec::new();
            encoder.encode(&frame, &mut out);
            parser.process(&out);
            for y in 0..height {
                frame.set(16 + 2 * y, y, Cell { ch: '▀', fg: a, bg: b });
                frame.set(90 - 2 * y, y, Cell { ch: '▄', fg: c, bg: d });
            }
            out.clear();
            let stats = encoder.encode(&frame, &mut out);
            parser.process(&out);
            assert_screen_shows(&parser, &frame, || format!("{a:?} {rep:?}"));
            assert_eq!(stats.cells_changed, 2 * height);
            assert_eq!(glyphs_written(&out), 2 * height, "{:?}", String::from_utf8_lossy(&out));
            let sgrs = String::from_utf8_lossy(&out).matches('m').count();
            assert!(sgrs <= 3, "{sgrs} colour codes for two looks: {:?}", String::from_utf8_lossy(&out));
        }
    }
}

/// The colours the SGR sequences in `bytes` set, as ink and paper alike: `38;2;r;g;b`,
/// `38;5;n`, `3x`/`9x` (ANSI 0–15), the defaults, in the order sent.
fn colours_set(bytes: &[u8]) -> Vec<Color> {
    let text = String::from_utf8_lossy(bytes);
    let mut colours = Vec::new();
    for sequence in text.split("\x1b[").skip(1) {
        let Some(end) = sequence.find(|c: char| ('@'..='~').contains(&c)) else { continue };
        if !sequence[end..].starts_with('m') {
            continue;
        }
        let params: Vec<u8> =
            sequence[..end].split(';').map(|p| if p.is_empty() { 0 } else { p.parse().unwrap() }).collect();
        let mut i = 0;
        while i < params.len() {
            let p = params[i];
            match p {
                38 | 48 if params[i + 1] == 5 => {
                    colours.push(Color::Indexed(params[i + 2]));
                    i += 2;
                }
                38 | 48 => {
                    colours.push(Color::Rgb(params[i + 2], params[i + 3], params[i + 4]));
                    i += 4;
                }
                39 | 49 => colours.push(Color::Default),
                30..=37 | 40..=47 => colours.push(Color::Indexed(p % 10)),
                90..=97 | 100..=107 => colours.push(Color::Indexed(p % 10 + 8)),
                _ => {} // 0: the reset
            }
            i += 1;
        }
    }
    colours
}

/// A truecolor palette near the short codes (issue #42): greys about the cube's 95 and the ramp,
/// channels just over 100 and 10, the cube's levels, and any colour.
fn arb_truecolor_palette() -> impl Strategy<Value = Vec<Color>> {
    let near = |v: u8| (v.saturating_sub(4)..=v.saturating_add(4)).boxed();
    let channel = prop_oneof![near(95), near(100), near(10), near(135), near(215), any::<u8>().boxed()];
    let colour = prop_oneof![
        1 => Just(Color::Default),
        6 => (channel.clone(), channel.clone(), channel).prop_map(|(r, g, b)| Color::Rgb(r, g, b)),
        2 => (0u8..255).prop_map(|v| Color::Rgb(v, v, v.saturating_add(1))),
    ];
    prop::collection::vec(colour, 1..5)
}

proptest! {
    #![proptest_config(common::config())]

    /// Issue #42: of a truecolor frame, every colour the encoder sets is within the tolerance of a
    /// colour the frame shows or one the screen showed before it (a cell rewritten as it is on the
    /// way to another), never one of the 16 ANSI colours (the theme's: unknown RGB); and the screen
    /// shows the frame within the tolerance, over random frames and steps, every BCE, REP level
    /// and blocks setting.
    #[test]
    fn every_colour_sent_is_within_the_tolerance_and_never_a_theme_colour(
        (first, steps) in arb_truecolor_palette().prop_flat_map(|palette| {
            (arb_frame(palette.clone()), prop::collection::vec(arb_step(palette), 1..12))
        }),
        bce in any::<bool>(),
        tolerance in 0u8..5,
        rep in prop_oneof![Just(RepLevel::None), Just(RepLevel::Ascii), Just(RepLevel::Any)],
        blocks in any::<bool>(),
    ) {
        let mut encoder = configured(bce, tolerance, rep, blocks);
        let mut parser = terminal(first.width(), first.height());
        let mut frame = first.clone();
        let mut out = Vec::new();
        let close = |a: Color, b: Color| match (known_rgb(a), known_rgb(b)) {
            (Some(p), Some(q)) => oklab_distance(p, q) <= f64::from(tolerance) * 0.01 + 1e-5,
            _ => a == b,
        };
        for (i, step) in std::iter::once(&Step::Same).chain(&steps).enumerate() {
            if apply(&mut frame, step) {
                encoder.invalidate();
            }
            resize(&mut parser, frame.width(), frame.height());
            let before = screen_frame(&parser);
            out.clear();
            encoder.encode(&frame, &mut out);
            parser.process(&out);
            let shown: Vec<Color> = frame.cells().iter().chain(before.cells()).flat_map(|c| [c.fg, c.bg]).collect();
            for colour in colours_set(&out) {
                prop_assert!(!matches!(colour, Color::Indexed(0..=15)), "a theme colour {:?} sent", colour);
                prop_assert!(
                    shown.iter().any(|&s| close(colour, s)),
                    "{:?} sent, near no colour of the frame or the screen (step {})", colour, i
                );
            }
            assert_screen_shows_within(&parser, &frame, tolerance, || format!("after step {i} {step:?}"));
        }
    }
}

/// Issue #42: where a truecolor frame's colours have a shorter code within the tolerance (a grey
/// of 100 near the ramp's 98 grey, `38;5;241`; a colour whose channel of 101 may go as 99), the
/// encoder sends that code, in fewer bytes than the colours' own, and the screen shows the frame
/// within the tolerance; at tolerance 0 the colours' own. (Without the shorter codes the two
/// tolerances send the same bytes here.)
#[test]
fn a_colour_with_a_shorter_code_within_the_tolerance_goes_in_it() {
    let (width, height) = (40, 4);
    let (grey, ochre) = (Color::Rgb(100, 100, 100), Color::Rgb(160, 101, 20));
    let mut sent = Vec::new();
    for tolerance in [0, 2] {
        let mut encoder = Encoder::new();
        encoder.set_tolerance(tolerance);
        let mut parser = terminal(width, height);
        let mut frame = Frame::new(width, height);
        let mut out = Vec::new();
        encoder.encode(&frame, &mut out);
        parser.process(&out);
        for y in 0..height {
            frame.set(3 + 7 * y, y, Cell { ch: '▀', fg: grey, bg: Color::Default });
            frame.set(30 - 5 * y, y, Cell { ch: 'x', fg: ochre, bg: grey });
        }
        out.clear();
        encoder.encode(&frame, &mut out);
        parser.process(&out);
        assert_screen_shows_within(&parser, &frame, tolerance, || format!("tolerance {tolerance}"));
        sent.push((String::from_utf8_lossy(&out).into_owned(), colours_set(&out)));
    }
    let [(exact, exact_colours), (near, near_colours)] = &sent[..] else { unreachable!() };
    assert!(exact_colours.contains(&grey) && exact_colours.contains(&ochre), "{exact:?}");
    assert!(near_colours.contains(&Color::Indexed(241)) && !near_colours.contains(&grey), "{near:?}");
    assert!(
        near_colours.iter().any(|c| matches!(c, Color::Rgb(_, 99, _))) && !near_colours.contains(&ochre),
        "{near:?}"
    );
    assert!(near.len() < exact.len(), "{} bytes within the tolerance, {} exact", near.len(), exact.len());
}

/// The rows where two frames of one size differ, as one range (empty at `0` where none does).
fn changed_rows(before: &Frame, after: &Frame) -> std::ops::Range<usize> {
    let differ = |y: usize| before.row(y) != after.row(y);
    let height = after.height();
    match ((0..height).find(|&y| differ(y)), (0..height).rev().find(|&y| differ(y))) {
        (Some(first), Some(last)) => first..last + 1,
        _ => 0..0,
    }
}

proptest! {
    #![proptest_config(common::config())]

    /// Issue #42 (a clock tick costs what it changes): [`Encoder::encode_rows`] told the rows that
    /// changed, and [`Encoder::encode_cells`] the cells (either told a few more either side, across
    /// rows too, or none where none changed), send the bytes, and return the statistics, of
    /// [`Encoder::encode`] of the whole frame, frame after frame: random frames and steps (resizes and
    /// invalidations included, where they paint the whole frame), palettes of any colours and of near
    /// truecolor ones (cells left and drawn within the tolerance), the tolerance changing between
    /// frames as the walk's does (a slow link's, the settle's exact frame), every BCE, REP level and
    /// blocks setting. The rows or cells scanned only in part keep what the encoder knew of their
    /// other cells (whether the screen is off them within the tolerance).
    #[test]
    fn encoding_only_the_changed_rows_or_cells_sends_the_bytes_of_the_whole_frame(
        (first, steps) in prop_oneof![arb_palette(), arb_truecolor_palette()].prop_flat_map(|palette| {
            let steps = (
                arb_step(palette.clone()),
                (0usize..12, 0usize..12, any::<bool>()),
                prop_oneof![0u8..4, Just(2u8)],
            );
            (arb_frame(palette), prop::collection::vec(steps, 1..16))
        }),
        bce in any::<bool>(),
        rep in prop_oneof![Just(RepLevel::None), Just(RepLevel::Ascii), Just(RepLevel::Any)],
        blocks in any::<bool>(),
    ) {
        let (mut told, mut whole) = (configured(bce, 2, rep, blocks), configured(bce, 2, rep, blocks));
        let mut frame = first;
        let (mut out, mut expected) = (Vec::new(), Vec::new());
        told.encode(&frame, &mut out);
        whole.encode(&frame, &mut expected);
        for (i, (step, (before_n, after_n, by_rows), tolerance)) in steps.iter().enumerate() {
            let before = frame.clone();
            if apply(&mut frame, step) {
                told.invalidate();
                whole.invalidate();
            }
            let same_size = (before.width(), before.height()) == (frame.width(), frame.height());
            // (a resize: a full paint, whatever it is told)
            let widened = |changed: &dyn Fn() -> std::ops::Range<usize>, (n, above, below): (usize, usize, usize)| {
                let changed = if same_size { changed() } else { 0..0 };
                if changed.is_empty() { 0..0 } else { changed.start.saturating_sub(above)..(changed.end + below).min(n) }
            };
            for encoder in [&mut told, &mut whole] {
                encoder.set_tolerance(*tolerance);
            }
            out.clear();
            expected.clear();
            let (stats, range) = if *by_rows {
                let rows = widened(&|| changed_rows(&before, &frame), (frame.height(), before_n % 3, after_n % 3));
                (told.encode_rows(&frame, rows.clone(), &mut out), rows)
            } else {
                let cells = widened(&|| changed_cells(&before, &frame), (frame.cells().len(), *before_n, *after_n));
                (told.encode_cells(&frame, cells.clone(), &mut out), cells)
            };
            let expected_stats = whole.encode(&frame, &mut expected);
            let told_of = if *by_rows { "rows" } else { "cells" };
            prop_assert_eq!(stats, expected_stats, "step {} ({:?}), {} {:?}", i, step, told_of, range);
            prop_assert_eq!(&out, &expected, "step {} ({:?}), {} {:?}", i, step, told_of, range);
        }
    }
}

/// The cells (indices into [`Frame::cells`]) from the first where `after` differs from `before` to
/// the last (none where none does).
fn changed_cells(before: &Frame, after: &Frame) -> std::ops::Range<usize> {
    let (old, new) = (before.cells(), after.cells());
    let differ = |k: &usize| old[*k] != new[*k];
    match ((0..new.len()).find(differ), (0..new.len()).rev().find(differ)) {
        (Some(first), Some(last)) => first..last + 1,
        _ => 0..0,
    }
}

/// [`Encoder::encode_cells`]'s contract is checked in debug builds: a cell changed in a row it was
/// told of, but outside the cells, is a caller's bug.
#[cfg(debug_assertions)]
#[test]
#[should_panic(expected = "changed outside the rows or cells")]
fn encoding_cells_of_a_frame_changed_elsewhere_in_their_row_is_caught() {
    let mut encoder = Encoder::new();
    let mut frame = Frame::new(10, 4);
    encoder.encode(&frame, &mut Vec::new());
    frame.set(2, 3, Cell::plain('x'));
    frame.set(7, 3, Cell::plain('y'));
    encoder.encode_cells(&frame, 32..33, &mut Vec::new());
}

/// [`Encoder::encode_rows`]'s contract is checked in debug builds: a frame changed outside the rows
/// it is told of is a caller's bug, not a frame sent wrong.
#[cfg(debug_assertions)]
#[test]
#[should_panic(expected = "changed outside the rows")]
fn encoding_rows_of_a_frame_changed_elsewhere_is_caught() {
    let mut encoder = Encoder::new();
    let mut frame = Frame::new(10, 4);
    encoder.encode(&frame, &mut Vec::new());
    frame.set(2, 1, Cell::plain('x'));
    frame.set(2, 3, Cell::plain('y'));
    encoder.encode_rows(&frame, 3..4, &mut Vec::new());
}
