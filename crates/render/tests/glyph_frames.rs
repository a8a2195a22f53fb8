//! Samples → frames, tested as text: ascii ramp, half blocks, quadrant and sextant mappings and best fit,
//! light ramps in 256 and 16 colours, and odd sizes.

use glam::Vec3;
use mazewalk_render::glyph::{self, block_glyph};
use mazewalk_render::options::ASCII_RAMP;
use mazewalk_render::palette::{Palette, ramp_entry, xterm_rgb};
use mazewalk_render::shade::srgb_to_linear;
use mazewalk_render::{Charset, RenderOptions, SampleBuffer, to_frame};
use mazewalk_term::blocks::{QUAD, sextant_glyph};
use mazewalk_term::frame::{Cell, Color, ColorDepth, Frame};

const RED: Vec3 = Vec3::new(1.0, 0.0, 0.0);
const BLUE: Vec3 = Vec3::new(0.0, 0.0, 1.0);

/// A buffer from rows of sample colours.
fn samples(rows: &[&[Vec3]]) -> SampleBuffer {
    let mut buffer = SampleBuffer::new(rows.first().map_or(0, |r| r.len()), rows.len());
    for (y, row) in rows.iter().enumerate() {
        for (x, &c) in row.iter().enumerate() {
            buffer.put(x, y, c, 0.5, 0);
        }
    }
    buffer
}

/// Frames start filled with a sentinel so untouched cells would show; the frame is as many cells as
/// the samples fill.
fn render(buffer: &SampleBuffer, charset: Charset, depth: ColorDepth) -> Frame {
    let (sx, sy) = charset.samples_per_cell();
    let mut frame = Frame::filled(buffer.width() / sx, buffer.height() / sy, Cell::plain('?'));
    let region = frame.region();
    to_frame(
        buffer,
        &RenderOptions { charset, color_depth: depth, ..RenderOptions::default() },
        &mut frame,
        region,
    );
    frame
}

fn grey(srgb: f32) -> Vec3 {
    Vec3::splat(srgb_to_linear(srgb))
}

#[test]
fn ascii_maps_lightness_to_the_ramp_without_colour() {
    // Lightness from RAMP_BOTTOM to RAMP_TOP spans the whole ramp, one step per glyph.
    let (bottom, top) = (glyph::RAMP_BOTTOM, glyph::RAMP_TOP);
    let ramp: Vec<Vec3> = (0..10).map(|k| grey(bottom + (top - bottom) * k as f32 / 9.0)).collect();
    let frame = render(&samples(&[&ramp]), Charset::Ascii, ColorDepth::None);
    assert_eq!(frame.lines(), [" .:-=+*#%@"]);
    // Darker than the bottom is blank, lighter than the top the densest.
    let ends = render(&samples(&[&[grey(0.02), grey(0.95)]]), Charset::Ascii, ColorDepth::None);
    assert_eq!(ends.lines(), [" @"]);
    assert!(frame.cells().iter().all(|c| c.fg == Color::Default && c.bg == Color::Default));
    assert_eq!(ASCII_RAMP.iter().collect::<String>(), frame.lines()[0]);
}

#[test]
fn ascii_in_colour_inks_the_glyph_and_leaves_the_background() {
    let frame = render(&samples(&[&[RED, Vec3::ZERO]]), Charset::Ascii, ColorDepth::TrueColor);
    // Red's lightness is 0.2126 linear → sRGB 0.5, stretched: (0.5 - 0.05) / 0.55 ≈ 0.82 → step 7 of 9.
    assert_eq!(frame.lines(), ["# "]);
    assert_eq!(frame.cells()[0].fg, Color::Rgb(255, 0, 0));
    assert_eq!(frame.cells()[0].bg, Color::Default);
    assert_eq!(frame.cells()[1], Cell::BLANK);
}

#[test]
fn half_blocks_ink_the_top_sample_and_blank_equal_pairs() {
    let g = grey(128.0 / 255.0);
    let frame = render(&samples(&[&[RED, g, BLUE], &[BLUE, g, BLUE]]), Charset::Half, ColorDepth::TrueColor);
    assert_eq!(frame.lines(), ["▀  "]);
    assert_eq!(frame.cells()[0], Cell { ch: '▀', fg: Color::Rgb(255, 0, 0), bg: Color::Rgb(0, 0, 255) });
    assert_eq!(
        frame.cells()[1],
        Cell { ch: ' ', fg: Color::Rgb(128, 128, 128), bg: Color::Rgb(128, 128, 128) }
    );
    assert_eq!(frame.cells()[2].bg, Color::Rgb(0, 0, 255));
}

#[test]
fn half_blocks_quantize_to_256_colours() {
    let frame =
        render(&samples(&[&[RED, grey(0.5)], &[BLUE, grey(0.5)]]), Charset::Half, ColorDepth::Ansi256);
    assert_eq!(frame.cells()[0], Cell { ch: '▀', fg: Color::Indexed(196), bg: Color::Indexed(21) });
    assert_eq!(frame.cells()[1].bg, Color::Indexed(244)); // sRGB 128 grey: the ramp, not the cube
}

#[test]
fn colourless_block_modes_shade_by_lightness() {
    let row: Vec<Vec3> = [0.0, 0.0, 0.5, 0.5, 1.0, 1.0].into_iter().map(grey).collect();
    let frame = render(&samples(&[&row, &row]), Charset::Quad, ColorDepth::None);
    // sRGB 0.5 stretched over the walls' range: (0.5 - 0.05) / 0.55 ≈ 0.82 → step 3 of 4.
    assert_eq!(frame.lines(), [" ▓█"]);
    assert!(frame.cells().iter().all(|c| c.fg == Color::Default && c.bg == Color::Default));
}

/// Which cells of a glyph are lit, from its Unicode name: bit `x + sx·y` as in the renderer.
fn lit_from_name(name: &str, charset: Charset) -> u8 {
    let (left, right, all) =
        if charset == Charset::Sextant { (0b01_0101, 0b10_1010, 63) } else { (0b0101, 0b1010, 15) };
    match name {
        "SPACE" => 0,
        "FULL BLOCK" => all,
        "LEFT HALF BLOCK" => left,
        "RIGHT HALF BLOCK" => right,
        "UPPER HALF BLOCK" => 0b0011,
        "LOWER HALF BLOCK" => 0b1100,
        _ if name.starts_with("BLOCK SEXTANT-") => {
            name["BLOCK SEXTANT-".len()..].bytes().map(|d| 1u8 << (d - b'1')).fold(0, |a, b| a | b)
        }
        _ => name["QUADRANT ".len()..]
            .split(" AND ")
            .map(|q| match q {
                "UPPER LEFT" => 1u8,
                "UPPER RIGHT" => 2,
                "LOWER LEFT" => 4,
                "LOWER RIGHT" => 8,
                _ => panic!("unexpected quadrant {q}"),
            })
            .fold(0, |a, b| a | b),
    }
}

/// Unicode names of the quadrant glyphs (UnicodeData.txt, U+2580–U+259F).
const QUAD_NAMES: [(char, &str); 16] = [
    (' ', "SPACE"),
    ('▀', "UPPER HALF BLOCK"),
    ('▄', "LOWER HALF BLOCK"),
    ('█', "FULL BLOCK"),
    ('▌', "LEFT HALF BLOCK"),
    ('▐', "RIGHT HALF BLOCK"),
    ('▖', "QUADRANT LOWER LEFT"),
    ('▗', "QUADRANT LOWER RIGHT"),
    ('▘', "QUADRANT UPPER LEFT"),
    ('▙', "QUADRANT UPPER LEFT AND LOWER LEFT AND LOWER RIGHT"),
    ('▚', "QUADRANT UPPER LEFT AND LOWER RIGHT"),
    ('▛', "QUADRANT UPPER LEFT AND UPPER RIGHT AND LOWER LEFT"),
    ('▜', "QUADRANT UPPER LEFT AND UPPER RIGHT AND LOWER RIGHT"),
    ('▝', "QUADRANT UPPER RIGHT"),
    ('▞', "QUADRANT UPPER RIGHT AND LOWER LEFT"),
    ('▟', "QUADRANT UPPER RIGHT AND LOWER LEFT AND LOWER RIGHT"),
];

/// The sextants U+1FB00–U+1FB3B in codepoint order with the digits of their names `BLOCK SEXTANT-…`.
const SEXTANT_NAMES: [&str; 60] = [
    "1", "2", "12", "3", "13", "23", "123", "4", "14", "24", "124", "34", "134", "234", "1234", "5", "15",
    "25", "125", "35", "235", "1235", "45", "145", "245", "1245", "345", "1345", "2345", "12345", "6", "16",
    "26", "126", "36", "136", "236", "1236", "46", "146", "1246", "346", "1346", "2346", "12346", "56",
    "156", "256", "1256", "356", "1356", "2356", "12356", "456", "1456", "2456", "12456", "3456", "13456",
    "23456",
];

fn name_of(ch: char, charset: Charset) -> String {
    if let Some(&(_, name)) = QUAD_NAMES.iter().find(|(c, _)| *c == ch) {
        return name.to_owned();
    }
    let index =
        (ch as u32).checked_sub(0x1FB00).filter(|&i| i < 60).unwrap_or_else(|| panic!("{ch:?} ({charset})"));
    format!("BLOCK SEXTANT-{}", SEXTANT_NAMES[index as usize])
}

#[test]
fn every_quadrant_and_sextant_pattern_maps_to_the_glyph_lighting_it() {
    for mask in 0..16u8 {
        let ch = block_glyph(Charset::Quad, mask);
        assert_eq!(ch, QUAD[usize::from(mask)]);
        assert_eq!(lit_from_name(&name_of(ch, Charset::Quad), Charset::Quad), mask, "quad {mask:04b} → {ch}");
    }
    let mut seen = std::collections::HashSet::new();
    for mask in 0..64u8 {
        let ch = sextant_glyph(mask);
        assert!(seen.insert(ch), "{ch} twice");
        assert_eq!(
            lit_from_name(&name_of(ch, Charset::Sextant), Charset::Sextant),
            mask,
            "sextant {mask:06b} → {ch}"
        );
    }
}

/// End to end: each two-colour pattern of a cell comes back as a glyph whose ink and background show
/// exactly the samples' colours (with ink and background possibly swapped).
#[test]
fn best_fit_reproduces_every_two_colour_pattern() {
    for charset in [Charset::Half, Charset::Quad, Charset::Sextant] {
        let (sx, sy) = charset.samples_per_cell();
        let n = sx * sy;
        for mask in 0..1u8 << n {
            let mut buffer = SampleBuffer::new(sx, sy);
            for k in 0..n {
                buffer.put(k % sx, k / sx, if mask >> k & 1 == 1 { RED } else { BLUE }, 0.5, 0);
            }
            let frame = render(&buffer, charset, ColorDepth::TrueColor);
            let cell = frame.cells()[0];
            let name = if charset == Charset::Half {
                ["SPACE", "UPPER HALF BLOCK"][usize::from(cell.ch == '▀')].to_owned()
            } else {
                name_of(cell.ch, charset)
            };
            let lit = if charset == Charset::Half {
                u8::from(cell.ch == '▀')
            } else {
                lit_from_name(&name, charset)
            };
            for k in 0..n {
                let shown = if lit >> k & 1 == 1 { cell.fg } else { cell.bg };
                let want = if mask >> k & 1 == 1 { Color::Rgb(255, 0, 0) } else { Color::Rgb(0, 0, 255) };
                assert_eq!(shown, want, "{charset} mask {mask:b} sample {k}: {cell:?}");
            }
        }
    }
}

#[test]
fn best_fit_groups_similar_samples_and_flat_cells_are_blank() {
    // Two reds and four blues, slightly noisy: the split follows colour, the means are the two groups.
    let (r1, r2) = (Vec3::new(0.9, 0.05, 0.0), Vec3::new(1.0, 0.0, 0.05));
    let (b1, b2) = (Vec3::new(0.0, 0.05, 0.9), Vec3::new(0.05, 0.0, 1.0));
    let frame = render(&samples(&[&[r1, b1], &[b2, r2], &[b1, b2]]), Charset::Sextant, ColorDepth::Ansi256);
    // In 256 colours each sample takes its light ramp's entry and the cell shows them: across an edge
    // (red beside blue) each side in its most frequent entry, the earlier sample's on a tie.
    let cell = frame.cells()[0];
    assert_eq!(cell.ch, sextant_glyph(0b00_1001));
    let entry = |c: Vec3| Color::Indexed(ramp_entry(c, Palette::Xterm256));
    assert_eq!((cell.fg, cell.bg), (entry(r1), entry(b1)));
    let rgb = |c: Color| match c {
        Color::Indexed(i) => xterm_rgb(i),
        other => panic!("{other:?}"),
    };
    assert!(rgb(cell.fg)[0] > 200 && rgb(cell.fg)[2] == 0, "red: {cell:?}");
    assert!(rgb(cell.bg)[2] > 200 && rgb(cell.bg)[0] == 0, "blue: {cell:?}");
    // Within one surface the samples' entries are its own ramp's: reds only.
    let (r1, r2) = (Vec3::new(0.9, 0.05, 0.0), Vec3::new(0.95, 0.03, 0.02));
    let frame = render(&samples(&[&[r1, r2], &[r2, r1], &[r1, r2]]), Charset::Sextant, ColorDepth::Ansi256);
    let cell = frame.cells()[0];
    assert!([cell.fg, cell.bg].iter().all(|&c| rgb(c)[0] == 255 && rgb(c)[2] == 0), "reds only: {cell:?}");
    // Differences below one sRGB step look equal: one colour, blank glyph, stable from frame to frame.
    let g = grey(0.5);
    let frame = render(&samples(&[&[g, g + 1e-5], &[g, g]]), Charset::Quad, ColorDepth::TrueColor);
    assert_eq!(frame.lines(), [" "]);
}

#[test]
fn odd_sizes_never_panic_and_fill_every_whole_cell() {
    for charset in [Charset::Ascii, Charset::Half, Charset::Quad, Charset::Sextant] {
        for depth in [ColorDepth::None, ColorDepth::Ansi16, ColorDepth::Ansi256, ColorDepth::TrueColor] {
            for (w, h) in [(0, 0), (1, 1), (0, 5), (5, 0), (3, 7)] {
                let mut buffer = SampleBuffer::new(w, h);
                buffer.clear(Vec3::splat(0.2));
                let frame = render(&buffer, charset, depth);
                let (sx, sy) = charset.samples_per_cell();
                assert_eq!((frame.width(), frame.height()), (w / sx, h / sy), "{charset} {w}×{h}");
                assert!(frame.cells().iter().all(|c| c.ch != '?'));
            }
        }
    }
}
