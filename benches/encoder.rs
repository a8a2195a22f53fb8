//! Bytes and time per frame over a scripted walk at 160×48 (half blocks), in truecolor and in 256
//! colours: mazewalk's encoder beside ratatui's crossterm backend drawing the same frames into a byte
//! counter, beside a naive full repaint, and beside the lower bound (the changed cells' glyphs alone).
//!
//! The walk (60 frames a second, the walkthrough's own cap; keys held through the app's own handlers,
//! as a terminal with key releases would send them): forward, a full 360° turn, strafe right, look up,
//! down and back level, then stand still. It starts at the open-area view of the 100×100 maze with loops
//! (see `common`). Frames are the renderer's alone (no HUD or map overlay).
//!
//! Bytes do not depend on timing: they are computed once, checked (both byte streams, fed to the `vt100`
//! terminal emulator, must show every frame exactly), printed, and written to
//! `target/criterion/encoder-bytes.md` and `encoder-frames-*.tsv`. Criterion then times each encoder over
//! the whole walk (`encode-walk/<depth>/<encoder>`, ours exact and with the walkthrough's tolerance (OKLab 0.02) as
//! `mazewalk_tolerant`; divide by the frame count for a frame).
//!
//! ```sh
//! nice cargo bench -p mazewalk-bench --bench encoder -- --warm-up-time 1 --measurement-time 3 --sample-size 10
//! ```

use mazewalk_bench::common;
use mazewalk_bench::stream::Kinds;

use std::cell::Cell as StdCell;
use std::fmt::Write as _;
use std::hint::black_box;
use std::io;
use std::rc::Rc;

use criterion::{Criterion, Throughput};
use mazewalk_render::{Charset, Renderer, Target};
use mazewalk_term::encoder::{DEFAULT_TOLERANCE, Encoder};
use mazewalk_term::frame::{Cell, Color, ColorDepth, Frame, Region};
use mazewalk_testkit::baseline::{full_repaint, lower_bound};
use mazewalk_testkit::screen;
use mazewalk_walk::App;
use ratatui::backend::CrosstermBackend;
use ratatui::layout::Rect;
use ratatui::style::Color as RColor;
use ratatui::{Terminal, TerminalOptions, Viewport};

const COLS: usize = 160;
const ROWS: usize = 48;
/// The maze the walk happens in (cells across).
const MAZE_SIDE: u32 = 100;

/// One frame of the walk.
struct Step {
    phase: &'static str,
    /// The camera moved since the previous frame.
    moved: bool,
    frame: Frame,
}

/// Plays the script through [`App`] and renders every frame at `depth`.
fn walk(depth: ColorDepth) -> Vec<Step> {
    let mut app = common::walk_app(MAZE_SIDE, Charset::Half, depth);
    let mut renderer = Renderer::new();
    let mut steps = Vec::new();
    let mut render = |app: &App, phase, moved| {
        let mut frame = Frame::new(COLS, ROWS);
        renderer
            .render(
                app.maze(),
                &app.camera,
                &[],
                &app.options,
                Target::Frame(&mut frame, Region { col: 0, row: 0, cols: COLS, rows: ROWS }),
            )
            .expect("camera");
        steps.push(Step { phase, moved, frame });
    };
    common::play_walk(&mut app, &common::walk_script(), &mut render);
    steps
}

/// A `Write` that only counts.
#[derive(Clone, Default)]
struct Counter(Rc<StdCell<usize>>, Option<Rc<std::cell::RefCell<Vec<u8>>>>);

impl io::Write for Counter {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.0.set(self.0.get() + buf.len());
        if let Some(copy) = &self.1 {
            copy.borrow_mut().extend_from_slice(buf);
        }
        Ok(buf.len())
    }
    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

fn ratatui_color(color: Color) -> RColor {
    match color {
        Color::Default => RColor::Reset,
        Color::Indexed(n) => RColor::Indexed(n),
        Color::Rgb(r, g, b) => RColor::Rgb(r, g, b),
    }
}

/// ratatui drawing our frames: each frame copied into its buffer (as a widget would), then
/// `Terminal::draw`, which diffs against the previous buffer and writes through the crossterm backend.
struct Ratatui {
    terminal: Terminal<CrosstermBackend<Counter>>,
    count: Rc<StdCell<usize>>,
    /// Copy cells as they are (blanks keep fg = bg) instead of giving blanks the default foreground.
    literal: bool,
}

impl Ratatui {
    fn new(copy: Option<Rc<std::cell::RefCell<Vec<u8>>>>, literal: bool) -> Ratatui {
        let count = Rc::new(StdCell::new(0));
        let backend = CrosstermBackend::new(Counter(count.clone(), copy));
        // A fixed viewport: no terminal size query (there is no terminal).
        let viewport = Viewport::Fixed(Rect::new(0, 0, COLS as u16, ROWS as u16));
        let terminal =
            Terminal::with_options(backend, TerminalOptions { viewport }).expect("ratatui terminal");
        Ratatui { terminal, count, literal }
    }

    /// Draws `frame`; returns the bytes written.
    fn draw(&mut self, frame: &Frame) -> usize {
        let before = self.count.get();
        let literal = self.literal;
        self.terminal
            .draw(|f| {
                for (cell, ours) in f.buffer_mut().content.iter_mut().zip(frame.cells()) {
                    // A blank shows no ink: unless `literal`, leave its foreground at the default,
                    // ratatui's cheapest (`39` instead of `38;2;r;g;b`; our frames give blanks fg = bg).
                    let fg = if ours.ch == ' ' && !literal { RColor::Reset } else { ratatui_color(ours.fg) };
                    cell.set_char(ours.ch).set_fg(fg).set_bg(ratatui_color(ours.bg));
                }
            })
            .expect("counting writer");
        self.count.get() - before
    }
}

/// Bytes of one frame by each method.
#[derive(Clone, Copy, Default)]
struct Bytes {
    ours: usize,
    /// Ours with the walkthrough's colour tolerance ([`DEFAULT_TOLERANCE`]).
    ours_tolerant: usize,
    ratatui: usize,
    ratatui_literal: usize,
    naive: usize,
    lower: usize,
    cells_changed: usize,
    ours_kinds: Kinds,
    ratatui_kinds: Kinds,
}

/// Panics unless the emulated screen shows `frame`: every cell looks the same up to `tolerance` 8-bit
/// steps per truecolor channel ([`Cell::looks_within`]: glyph and colours, or the inverse block glyph in
/// swapped colours; tested against the glyphs' coverage in `tests/term_encoder.rs`).
fn check_screen(who: &str, parser: &vt100::Parser, frame: &Frame, k: usize, tolerance: u8) {
    let screen = parser.screen();
    for y in 0..frame.height() {
        for x in 0..frame.width() {
            let want = frame.get(x, y).expect("in the frame");
            let got = screen.cell(y as u16, x as u16).expect("in the screen");
            let ch = got.contents().chars().next().unwrap_or(' ');
            let got = Cell { ch, fg: screen::color(got.fgcolor()), bg: screen::color(got.bgcolor()) };
            assert!(
                want.looks_within(&got, tolerance),
                "{who}: frame {k}, cell ({x}, {y}): want {want:?}, got {got:?}"
            );
        }
    }
}

/// Every frame's bytes by each method; both diffing streams are checked on an emulated terminal.
fn measure_bytes(steps: &[Step]) -> Vec<Bytes> {
    let size = |n: usize| std::num::NonZeroU16::new(n as u16).expect("non-empty");
    let terminal = || vt100::Parser::new(size(ROWS), size(COLS), 0);
    let (mut ours_vt, mut tolerant_vt, mut ratatui_vt) = (terminal(), terminal(), terminal());
    let mut encoder = Encoder::new();
    let mut tolerant = Encoder::new();
    tolerant.set_tolerance(DEFAULT_TOLERANCE);
    let mut tolerant_out = Vec::new();
    let copy = Rc::new(std::cell::RefCell::new(Vec::new()));
    let mut ratatui = Ratatui::new(Some(copy.clone()), false);
    let mut ratatui_literal = Ratatui::new(None, true);
    let (mut out, mut naive) = (Vec::new(), Vec::new());
    let mut all = Vec::new();
    for (k, step) in steps.iter().enumerate() {
        // The exact encoder's screen shows the previous frame.
        let lower = lower_bound(k.checked_sub(1).map(|p| &steps[p].frame), &step.frame, 0);
        out.clear();
        let stats = encoder.encode(&step.frame, &mut out);
        tolerant_out.clear();
        tolerant.encode(&step.frame, &mut tolerant_out);
        tolerant_vt.process(&tolerant_out);
        naive.clear();
        full_repaint(&step.frame, &mut naive);
        let ratatui_bytes = ratatui.draw(&step.frame);
        let ratatui_literal_bytes = ratatui_literal.draw(&step.frame);
        ours_vt.process(&out);
        ratatui_vt.process(&copy.borrow());
        let ratatui_kinds = Kinds::of(&copy.borrow());
        copy.borrow_mut().clear();
        check_screen("mazewalk", &ours_vt, &step.frame, k, 0);
        check_screen("mazewalk, tolerant", &tolerant_vt, &step.frame, k, DEFAULT_TOLERANCE);
        check_screen("ratatui", &ratatui_vt, &step.frame, k, 0);
        all.push(Bytes {
            ours: stats.bytes,
            ours_tolerant: tolerant_out.len(),
            ratatui: ratatui_bytes,
            ratatui_literal: ratatui_literal_bytes,
            naive: naive.len(),
            lower,
            cells_changed: stats.cells_changed,
            ours_kinds: Kinds::of(&out),
            ratatui_kinds,
        });
    }
    all
}

fn median(mut v: Vec<usize>) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_unstable();
    let n = v.len();
    if n % 2 == 1 { v[n / 2] as f64 } else { (v[n / 2 - 1] + v[n / 2]) as f64 / 2.0 }
}

fn mean(v: &[usize]) -> f64 {
    if v.is_empty() { 0.0 } else { v.iter().sum::<usize>() as f64 / v.len() as f64 }
}

/// The bytes tables for one colour depth (markdown), and a per-frame TSV.
fn report(depth: ColorDepth, steps: &[Step], bytes: &[Bytes]) -> (String, String) {
    let mut md = String::new();
    let mut tsv = String::from("frame\tphase\tmoved\tcells_changed\tmazewalk\tratatui\tnaive\tlower_bound\n");
    for (k, (s, b)) in steps.iter().zip(bytes).enumerate() {
        let _ = writeln!(
            tsv,
            "{k}\t{}\t{}\t{}\t{}\t{}\t{}\t{}",
            s.phase, s.moved, b.cells_changed, b.ours, b.ratatui, b.naive, b.lower
        );
    }
    let rows = |pick: &dyn Fn(&Step) -> bool| -> Vec<Bytes> {
        steps.iter().zip(bytes).skip(1).filter(|(s, _)| pick(s)).map(|(_, b)| *b).collect()
    };
    let line = |md: &mut String, name: &str, rows: &[Bytes]| {
        let col = |f: fn(&Bytes) -> usize| rows.iter().map(f).collect::<Vec<_>>();
        let (ours, rat, lit) = (col(|b| b.ours), col(|b| b.ratatui), col(|b| b.ratatui_literal));
        let tolerant = col(|b| b.ours_tolerant);
        let (naive, lower) = (col(|b| b.naive), col(|b| b.lower));
        let ratio = |a: f64, b: f64| if b > 0.0 { format!("{:.0} %", 100.0 * a / b) } else { "–".into() };
        let _ = writeln!(
            md,
            "| {name} | {} | {:.0} / {:.0} | {:.0} / {:.0} | {:.0} / {:.0} | {:.0} | {:.0} | {:.0} / {:.0} \
             | **{}** / {} | **{}** / {} | {} |",
            rows.len(),
            median(ours.clone()),
            mean(&ours),
            median(tolerant.clone()),
            mean(&tolerant),
            median(rat.clone()),
            mean(&rat),
            mean(&lit),
            median(naive.clone()),
            median(lower.clone()),
            mean(&lower),
            ratio(mean(&ours), mean(&rat)),
            ratio(median(ours.clone()), median(rat.clone())),
            ratio(mean(&tolerant), mean(&rat)),
            ratio(median(tolerant.clone()), median(rat.clone())),
            ratio(mean(&ours), mean(&naive)),
        );
    };
    let _ = writeln!(md, "#### {depth:?}, {COLS}×{ROWS} half blocks\n");
    let _ = writeln!(
        md,
        "| frames | n | mazewalk exact, median / mean | mazewalk at tolerance {DEFAULT_TOLERANCE} (default), median / mean \
         | ratatui median / mean | ratatui, literal cells, mean | full repaint median \
         | lower bound median / mean | exact ÷ ratatui, means / medians | tolerant ÷ ratatui, means / medians \
         | exact ÷ full repaint (means) |"
    );
    let _ = writeln!(md, "|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|");
    line(&mut md, "**walking** (camera moved)", &rows(&|s| s.moved));
    line(&mut md, "idle (camera still)", &rows(&|s| !s.moved));
    let mut phases: Vec<&str> = Vec::new();
    for s in steps.iter().skip(1) {
        if !phases.contains(&s.phase) {
            phases.push(s.phase);
        }
    }
    for phase in phases {
        line(&mut md, &format!("· {phase}"), &rows(&|s| s.phase == phase));
    }
    let _ = writeln!(md, "\nWhere the walking frames' bytes go (share of all their bytes):\n");
    let _ =
        writeln!(md, "| stream | colours (SGR) | cursor moves | erase | sync / cursor markers | glyphs |");
    let _ = writeln!(md, "|---|--:|--:|--:|--:|--:|");
    for (name, pick) in
        [("mazewalk", (|b: &Bytes| b.ours_kinds) as fn(&Bytes) -> Kinds), ("ratatui", |b| b.ratatui_kinds)]
    {
        let mut k = Kinds::default();
        steps.iter().zip(bytes).skip(1).filter(|(s, _)| s.moved).for_each(|(_, b)| k.merge(pick(b)));
        let pct = |n: usize| format!("{:.0} %", 100.0 * n as f64 / k.total().max(1) as f64);
        let _ = writeln!(
            md,
            "| {name} | {} | {} | {} | {} | {} |",
            pct(k.sgr),
            pct(k.moves),
            pct(k.erase),
            pct(k.markers),
            pct(k.glyphs)
        );
    }
    let first = bytes[0];
    let _ = writeln!(
        md,
        "\nFirst frame (full paint): mazewalk {} B, ratatui {} B (no clear: ratatui assumes a blank \
         screen), full repaint {} B, lower bound {} B.\n",
        first.ours, first.ratatui, first.naive, first.lower
    );
    (md, tsv)
}

fn depth_name(depth: ColorDepth) -> &'static str {
    match depth {
        ColorDepth::TrueColor => "truecolor",
        ColorDepth::Ansi256 => "256",
        ColorDepth::Ansi16 => "16",
        ColorDepth::None => "none",
    }
}

fn main() {
    let mut c = Criterion::default().configure_from_args();
    let dir = std::path::Path::new(&std::env::var("CARGO_TARGET_DIR").unwrap_or_else(|_| "target".into()))
        .join("criterion");
    let _ = std::fs::create_dir_all(&dir);
    let mut md = String::new();
    for depth in [ColorDepth::TrueColor, ColorDepth::Ansi256] {
        let steps = walk(depth);
        let bytes = measure_bytes(&steps);
        let (table, tsv) = report(depth, &steps, &bytes);
        eprintln!("{table}");
        md.push_str(&table);
        let _ = std::fs::write(dir.join(format!("encoder-frames-{}.tsv", depth_name(depth))), tsv);

        let frames: Vec<&Frame> = steps.iter().map(|s| &s.frame).collect();
        let mut group = c.benchmark_group(format!("encode-walk/{}", depth_name(depth)));
        group.throughput(Throughput::Elements(frames.len() as u64));
        let mut out = Vec::with_capacity(1 << 20);
        for (name, tolerance) in [("mazewalk", 0), ("mazewalk_tolerant", DEFAULT_TOLERANCE)] {
            group.bench_function(name, |b| {
                b.iter(|| {
                    let mut encoder = Encoder::new();
                    encoder.set_tolerance(tolerance);
                    let mut total = 0;
                    for frame in &frames {
                        out.clear();
                        total += encoder.encode(black_box(frame), &mut out).bytes;
                    }
                    total
                });
            });
        }
        group.bench_function("ratatui", |b| {
            b.iter(|| {
                let mut ratatui = Ratatui::new(None, false);
                frames.iter().map(|frame| ratatui.draw(black_box(frame))).sum::<usize>()
            });
        });
        group.bench_function("full_repaint", |b| {
            b.iter(|| {
                let mut total = 0;
                for frame in &frames {
                    out.clear();
                    full_repaint(black_box(frame), &mut out);
                    total += out.len();
                }
                total
            });
        });
        group.finish();
        let _ = writeln!(md, "Walk: {} frames.\n", frames.len());
    }
    let _ = std::fs::write(dir.join("encoder-bytes.md"), md);
    c.final_summary();
}
