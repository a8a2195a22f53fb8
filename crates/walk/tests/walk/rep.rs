//! Issue #42: runs of one look go as REP (`CSI n b`) to a terminal that has it. The session asks
//! before its first frame ([`REP_PROBE`]), after a space and after `▀`; a terminal that repeats any
//! glyph (vt100, as xterm) answers that the cursor moved two cells, then three, and the frames send
//! runs of any glyph as REP from then on; one that repeats only ASCII (tmux: its second answer one
//! cell) gets REP after ASCII glyphs only, never after a block; one without it (one cell each), or
//! an answer that is not one to the probe (row 1: how xterm sends Alt-F3), leaves it off. Either way
//! the terminal shows every frame exactly.

use mazewalk_maze as maze;
use mazewalk_render::quality::shown;
use mazewalk_render::{Charset, RenderOptions};
use mazewalk_term::caps::REP_PROBE;
use mazewalk_term::frame::{ColorDepth, Frame};
use mazewalk_testkit::screen::screen_frame;
use mazewalk_walk::{App, Session, SessionOptions};

const COLS: u16 = 120;
const ROWS: u16 = 40;

/// How the terminal answers the cursor position queries.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Answer {
    /// Where the cursor is: vt100 repeats any glyph.
    Truly,
    /// As tmux: the space repeated (where vt100's cursor is), the block not (column 2).
    AsciiOnly,
    /// As a terminal without REP would: one cell written for each question (column 2).
    WithoutRep,
    /// Row 1 and the column vt100 says (not an answer to the probe).
    RowOne,
}

impl Answer {
    /// The report for vt100's cursor at 1-based (`row`, `col`).
    fn report(self, row: u16, col: u16) -> (u16, u16) {
        match self {
            Answer::Truly => (row, col),
            Answer::AsciiOnly if row == 3 => (row, 2),
            Answer::AsciiOnly => (row, col),
            Answer::WithoutRep => (row, 2),
            Answer::RowOne => (1, col),
        }
    }
}

/// What a walk sent: bytes, REPs, and REPs right after a glyph that is not ASCII.
#[derive(Clone, Copy, Debug, Default)]
struct Sent {
    bytes: usize,
    reps: usize,
    block_reps: usize,
}

/// A session of the built-in maze in half blocks of `depth`, `COLS × ROWS`, that sends every frame
/// exactly (no flow control, tolerance 0); `bce`: whether the terminal erases in the pen's colour.
fn exact_session(depth: ColorDepth, bce: bool) -> Session {
    let options = RenderOptions { charset: Charset::Half, color_depth: depth, ..RenderOptions::default() };
    let app = App::new(maze::builtin().expect("built-in maze"), options, 0.0).expect("a start cell");
    Session::new(
        app,
        COLS,
        ROWS,
        SessionOptions { flow_control: false, color_tolerance: 0, bce, sample_rate: None },
    )
}

/// Walks forward for two seconds in `depth`, exactly (tolerance 0), the terminal answering the
/// probe as `answer`; checks the screen after every frame; returns what was sent.
fn walk(depth: ColorDepth, answer: Answer) -> Sent {
    let mut session = exact_session(depth, SessionOptions::default().bce);
    let nz = |n: u16| std::num::NonZeroU16::new(n).expect("not zero");
    let mut parser = vt100::Parser::new(nz(ROWS), nz(COLS), 0);
    let mut sent = Sent::default();
    let mut out = Vec::new();
    for i in 0..60 {
        let now = f64::from(i) / 30.0;
        session.feed(b"w", now);
        out.clear();
        if !session.frame(now, &mut out) {
            continue;
        }
        if i == 0 {
            assert!(out.starts_with(REP_PROBE), "the probe goes before the first frame");
        }
        let mut rest = &out[..];
        while let Some(at) = rest.windows(4).position(|w| w == b"\x1b[6n") {
            parser.process(&rest[..at + 4]);
            let (row, col) = parser.screen().cursor_position();
            let (row, col) = answer.report(row + 1, col + 1);
            session.feed(format!("\x1b[{row};{col}R").as_bytes(), now);
            rest = &rest[at + 4..];
        }
        parser.process(rest);
        assert!(
            shown(&screen_frame(&parser), Charset::Half) == shown(session.screen(), Charset::Half),
            "{depth} {answer:?}: frame {i} not shown exactly"
        );
        sent.bytes += out.len();
        let (reps, block_reps) = reps_in(if i == 0 { &out[REP_PROBE.len()..] } else { &out[..] });
        sent.reps += reps;
        sent.block_reps += block_reps;
    }
    sent
}

/// The REPs in a frame's bytes (past the probe's own), and how many of them repeat a block glyph:
/// REP is ESC [ digits b (nothing else the encoder sends ends in `b`), and the glyph it repeats is
/// what comes just before it (a UTF-8 sequence ends in a byte ≥ 0x80).
fn reps_in(frame: &[u8]) -> (usize, usize) {
    let is_rep =
        |s: &[u8]| s.first() == Some(&b'[') && s[1..].iter().find(|b| !b.is_ascii_digit()) == Some(&b'b');
    let (mut reps, mut block_reps) = (0, 0);
    for (at, _) in frame.iter().enumerate().filter(|&(at, &b)| b == 0x1b && is_rep(&frame[at + 1..])) {
        assert!(at > 0, "REP first in a frame");
        reps += 1;
        block_reps += usize::from(frame[at - 1] >= 0x80);
    }
    (reps, block_reps)
}

#[test]
fn runs_go_as_rep_only_to_a_terminal_that_said_it_has_it() {
    for depth in [ColorDepth::TrueColor, ColorDepth::Ansi256] {
        let any = walk(depth, Answer::Truly);
        let ascii = walk(depth, Answer::AsciiOnly);
        let without = walk(depth, Answer::WithoutRep);
        let row_one = walk(depth, Answer::RowOne);
        eprintln!(
            "{depth}: {} bytes with REP after any glyph ({} REPs, {} after a block), {} after ASCII only ({} REPs), {} without",
            any.bytes, any.reps, any.block_reps, ascii.bytes, ascii.reps, without.bytes
        );
        assert!(any.block_reps > 0, "{depth}: REP never used after a block: {any:?}");
        assert!(ascii.reps > 0, "{depth}: REP never used after ASCII: {ascii:?}");
        assert_eq!(ascii.block_reps, 0, "{depth}: REP after a block to a terminal that repeats only ASCII");
        assert!(any.bytes < ascii.bytes, "{depth}: block REP did not save bytes: {any:?} vs {ascii:?}");
        assert!(ascii.bytes < without.bytes, "{depth}: REP did not save bytes: {ascii:?} vs {without:?}");
        assert_eq!(
            (without.reps, row_one.reps),
            (0, 0),
            "{depth}: REP to a terminal that did not say it has it"
        );
        assert_eq!(without.bytes, row_one.bytes, "{depth}: an answer of row 1 is no answer");
    }
}

/// A real tmux server, on its own socket in a directory of its own, killed (and the directory
/// removed) when dropped, however the test ends.
struct Tmux {
    dir: std::path::PathBuf,
}

impl Tmux {
    /// tmux with one 120×40 pane (no status line) running `command`.
    fn start(command: &str) -> Tmux {
        let dir = std::env::temp_dir().join(format!("mazewalk-rep-tmux-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("a temporary directory");
        let tmux = Tmux { dir };
        std::fs::write(tmux.dir.join("tmux.conf"), "set -g status off\n").expect("tmux.conf");
        let (cols, rows) = (COLS.to_string(), ROWS.to_string());
        let out = tmux.run(&["new-session", "-d", "-s", "rep", "-x", &cols, "-y", &rows, command]);
        assert!(out.status.success(), "tmux new-session: {}", String::from_utf8_lossy(&out.stderr));
        tmux
    }

    fn run(&self, args: &[&str]) -> std::process::Output {
        std::process::Command::new("tmux")
            .arg("-f")
            .arg(self.dir.join("tmux.conf"))
            .arg("-S")
            .arg(self.dir.join("socket"))
            .args(args)
            .env_remove("TMUX") // (its own server, whether or not the test runs inside a tmux)
            .stdin(std::process::Stdio::null())
            .output()
            .expect("tmux runs")
    }

    /// The pane's screen as a frame: `capture-pane -e` (each cell's glyph and colours, except the
    /// background of erased cells: the session below erases only default-background blanks).
    fn screen(&self) -> Frame {
        let out = self.run(&["capture-pane", "-p", "-e", "-N", "-t", "rep"]);
        assert!(out.status.success(), "tmux capture-pane: {}", String::from_utf8_lossy(&out.stderr));
        let nz = |n: u16| std::num::NonZeroU16::new(n).expect("not zero");
        let mut parser = vt100::Parser::new(nz(ROWS), nz(COLS), 0);
        let text = String::from_utf8_lossy(&out.stdout);
        parser.process(text.trim_end_matches('\n').replace('\n', "\r\n").as_bytes());
        screen_frame(&parser)
    }
}

impl Drop for Tmux {
    fn drop(&mut self) {
        let _ = self.run(&["kill-server"]);
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// The cursor position reports (`CSI row ; col R`) in `bytes`, in order.
fn reports(bytes: &[u8]) -> Vec<(u16, u16)> {
    let text = String::from_utf8_lossy(bytes);
    text.split("\x1b[")
        .skip(1)
        .filter_map(|s| {
            let (body, _) = s.split_once('R')?;
            let (row, col) = body.split_once(';')?;
            Some((row.parse().ok()?, col.parse().ok()?))
        })
        .collect()
}

/// Issue #42, against a real tmux (3.3a here), which repeats only an ASCII last character: it
/// answers the probe's space question yes and its block question no, so the walk sends REP after
/// ASCII glyphs and never after a block, and tmux's screen is the frame after every tenth frame of
/// a walk (its glyphs, and its colours: the session without BCE, so `capture-pane` shows every
/// cell's background). At `5268d1c`, REP after `▀` left tmux's cursor short and the HUD's clock
/// written over its first letters.
#[test]
fn tmux_gets_rep_after_ascii_only_and_shows_every_frame() {
    use std::io::{Read, Write};
    use std::sync::mpsc;
    use std::time::Duration;
    mazewalk_testkit::require_tool("tmux", "tmux");
    mazewalk_testkit::require_tool("mkfifo", "coreutils");
    // The pane: raw mode, what the test writes to `to-pane` shown, what tmux answers sent back to
    // the test through `from-pane`.
    let dir = std::env::temp_dir().join(format!("mazewalk-rep-fifos-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let (to_pane, from_pane) = (dir.join("to-pane"), dir.join("from-pane"));
    for fifo in [&to_pane, &from_pane] {
        let made = std::process::Command::new("mkfifo").arg(fifo).status().expect("mkfifo runs");
        assert!(made.success());
    }
    let command =
        format!("stty raw -echo; cat '{}' & exec cat > '{}'", to_pane.display(), from_pane.display());
    let tmux = Tmux::start(&command);
    let size = tmux.run(&["display", "-p", "-t", "rep", "#{pane_width}x#{pane_height}"]);
    assert_eq!(String::from_utf8_lossy(&size.stdout).trim(), format!("{COLS}x{ROWS}"));
    // Opening a FIFO waits for its other end: in threads, so a pane that never opens them fails
    // the test rather than hanging it.
    let (opened, open) = mpsc::channel();
    let (paths, dir_for_thread) = ((to_pane.clone(), from_pane.clone()), dir.clone());
    std::thread::spawn(move || {
        let writer = std::fs::OpenOptions::new().write(true).open(&paths.0);
        let reader = std::fs::File::open(&paths.1);
        let _ = opened.send((writer, reader));
        drop(dir_for_thread);
    });
    let (writer, reader) = open.recv_timeout(Duration::from_secs(10)).expect("the pane opened its FIFOs");
    let (mut writer, mut reader) = (writer.expect("to-pane"), reader.expect("from-pane"));
    let (answered, answers) = mpsc::channel::<Vec<u8>>();
    std::thread::spawn(move || {
        let mut buf = [0; 256];
        while let Ok(n @ 1..) = reader.read(&mut buf) {
            if answered.send(buf[..n].to_vec()).is_err() {
                break;
            }
        }
    });
    // Reads what tmux answers until it holds `n` reports (10 s at most).
    let wait_reports = |n: usize| {
        let mut got = Vec::new();
        let deadline = std::time::Instant::now() + Duration::from_secs(10);
        while reports(&got).len() < n {
            let left = deadline.saturating_duration_since(std::time::Instant::now());
            match answers.recv_timeout(left) {
                Ok(bytes) => got.extend(bytes),
                Err(_) => panic!("tmux answered {} of {n} reports: {:?}", reports(&got).len(), got),
            }
        }
        got
    };

    for depth in [ColorDepth::TrueColor, ColorDepth::Ansi256] {
        let mut session = exact_session(depth, false);
        let (mut reps, mut block_reps) = (0, 0);
        let mut out = Vec::new();
        for i in 0..60 {
            let now = f64::from(i) / 30.0;
            session.feed(b"w", now);
            out.clear();
            if !session.frame(now, &mut out) {
                continue;
            }
            writer.write_all(&out).expect("to the pane");
            if i == 0 {
                assert!(out.starts_with(REP_PROBE));
                let got = wait_reports(2);
                assert_eq!(reports(&got), [(2, 3), (3, 2)], "{depth}: tmux repeats a space, not `▀`");
                session.feed(&got, now);
            }
            let (r, b) = reps_in(if i == 0 { &out[REP_PROBE.len()..] } else { &out[..] });
            (reps, block_reps) = (reps + r, block_reps + b);
            if i % 10 == 9 {
                // A report of our own: when it comes, tmux has drawn everything before it.
                writer.write_all(b"\x1b[6n").expect("to the pane");
                wait_reports(1);
                let screen = tmux.screen();
                // Text where the frame has text (the HUD, the map's letters); blocks and blanks may
                // go in another form of the same look, which `shown` compares.
                for (k, (a, b)) in screen.cells().iter().zip(session.screen().cells()).enumerate() {
                    if a.ch.is_ascii_graphic() || b.ch.is_ascii_graphic() {
                        let (x, y) = (k % usize::from(COLS), k / usize::from(COLS));
                        assert_eq!(
                            a.ch,
                            b.ch,
                            "{depth}: frame {i}, ({x}, {y}): tmux shows {:?}",
                            screen.lines()[y]
                        );
                    }
                }
                assert!(
                    shown(&screen, Charset::Half) == shown(session.screen(), Charset::Half),
                    "{depth}: frame {i}: tmux's colours are not the frame's"
                );
            }
        }
        eprintln!("{depth}: {reps} REPs to tmux, {block_reps} after a block");
        assert!(reps > 0, "{depth}: REP after ASCII never used");
        assert_eq!(block_reps, 0, "{depth}: REP after a block sent to tmux");
        // The next walk starts with a full paint, as a new session does.
    }
    drop(writer);
    let _ = std::fs::remove_dir_all(&dir);
}
