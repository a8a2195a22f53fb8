//! Two Sessions side by side, fed scripted byte streams, their frames read back through the vt100
//! emulator: each walks on its own (issue #11: no globals, nothing shared between players).

use mazewalk_maze as maze;
use mazewalk_render::RenderOptions;
use mazewalk_walk::{App, Session, SessionOptions};

const COLS: u16 = 100;
const ROWS: u16 = 30;

fn session() -> Session {
    let app = App::new(maze::builtin().unwrap(), RenderOptions::default(), 0.0).unwrap();
    Session::new(app, COLS, ROWS, SessionOptions::default())
}

fn nz(n: u16) -> std::num::NonZeroU16 {
    std::num::NonZeroU16::new(n).unwrap()
}

/// A player: a session and the terminal it draws on.
struct Player {
    session: Session,
    terminal: vt100::Parser,
    bytes: Vec<u8>,
}

impl Player {
    fn new() -> Player {
        Player { session: session(), terminal: vt100::Parser::new(nz(ROWS), nz(COLS), 0), bytes: Vec::new() }
    }

    /// Feeds `input` at `now`, then draws whatever frame is due and shows it on the terminal.
    fn step(&mut self, input: &[u8], now: f64) {
        self.session.feed(input, now);
        self.bytes.clear();
        self.session.frame(now, &mut self.bytes);
        self.terminal.process(&self.bytes);
    }

    /// The screen's rows but the HUD (whose frame time and byte count depend on the machine).
    fn view(&self) -> Vec<String> {
        let rows: Vec<String> = self.terminal.screen().rows(0, COLS).collect();
        rows[..rows.len() - 1].to_vec()
    }

    fn hud(&self) -> String {
        self.terminal.screen().rows(0, COLS).last().unwrap()
    }
}

/// The HUD's position and heading fields: ` (x, y) z+0.0  heading 60° …`.
fn position_and_heading(hud: &str) -> (String, String) {
    let position = hud[hud.find('(').unwrap()..=hud.find(')').unwrap()].to_string();
    let heading = hud.split("heading ").nth(1).unwrap().split('°').next().unwrap().to_string();
    (position, heading)
}

/// Player A walks forward (`w`), B turns left (`←`), in the same ticks, interleaved.
fn script(t: usize) -> (&'static [u8], &'static [u8]) {
    if t < 20 { (b"w", b"\x1b[D") } else { (b"", b"") }
}

#[test]
fn two_sessions_walk_independently_and_each_screen_is_its_own() {
    let (mut a, mut b) = (Player::new(), Player::new());
    a.step(b"", 0.0);
    b.step(b"", 0.0);
    let start = position_and_heading(&a.hud());
    assert_eq!(start, position_and_heading(&b.hud()), "both start at the maze's viewer");
    for t in 0..60 {
        let now = 0.02 * t as f64;
        let (ka, kb) = script(t);
        a.step(ka, now);
        b.step(kb, now);
    }
    let (pos_a, heading_a) = position_and_heading(&a.hud());
    let (pos_b, heading_b) = position_and_heading(&b.hud());
    assert_ne!(pos_a, start.0, "A walked");
    assert_eq!(heading_a, start.1, "A did not turn");
    assert_eq!(pos_b, start.0, "B did not walk");
    assert_ne!(heading_b, start.1, "B turned");
    assert_ne!(a.view(), b.view(), "they see different things");

    // Each player alone, with the same script: the same screen as when the other played beside it.
    let (mut alone_a, mut alone_b) = (Player::new(), Player::new());
    alone_a.step(b"", 0.0);
    alone_b.step(b"", 0.0);
    for t in 0..60 {
        let now = 0.02 * t as f64;
        let (ka, kb) = script(t);
        alone_a.step(ka, now);
        alone_b.step(kb, now);
        if t % 7 == 0 {
            // Interleave a third, noisy player with A's twin: nothing it does reaches the others.
            let mut noisy = Player::new();
            noisy.step(b"ddd\x1b[C\x1b[Amc?", now);
        }
    }
    assert_eq!(alone_a.view(), a.view());
    assert_eq!(alone_b.view(), b.view());
    assert_eq!(position_and_heading(&alone_a.hud()), (pos_a, heading_a));
}

#[test]
fn a_quit_ends_one_session_only_and_a_resize_redraws_only_its_own() {
    let (mut a, mut b) = (Player::new(), Player::new());
    a.step(b"", 0.0);
    b.step(b"", 0.0);
    a.step(b"q", 0.1);
    assert!(a.session.is_over());
    assert!(!b.session.is_over());
    b.session.input(mazewalk_term::input::Input::Resize { cols: 60, rows: 20 }, 0.2);
    b.terminal.screen_mut().set_size(nz(20), nz(60));
    b.step(b"", 0.2);
    assert_eq!(b.session.screen().width(), 60);
    assert_eq!(a.session.screen().width(), usize::from(COLS));
    assert!(b.hud().contains("? help") || b.hud().contains("heading"));
}

/// One player stands ahead of another: the other's session, told where the first stands
/// (`Session::set_peers`, as a host does), shows its figure and initial in the 3D view.
#[test]
fn a_player_ahead_appears_in_the_others_view_with_its_initial() {
    use glam::Vec2;
    use mazewalk_term::frame::Color;
    use mazewalk_walk::overlay::Peer;
    let mut watcher = Player::new();
    watcher.step(b"", 0.0);
    let camera = watcher.session.app().camera;
    let before = watcher.view();
    // A figure four units straight ahead, in the watcher's own cell or the next.
    let ahead = camera.position + Vec2::from_angle(camera.yaw_deg.to_radians()) * 4.0;
    assert!(watcher.session.app().maze().cell_at(ahead).is_some(), "ahead is inside the maze");
    let peer = Peer {
        position: ahead,
        heading_deg: 180.0,
        initial: 'Z',
        color: Color::Rgb(230, 80, 50),
        cell: None,
    };
    assert!(watcher.session.set_peers(&[peer]), "a new peer: the picture must change");
    assert!(!watcher.session.set_peers(&[peer]), "the same again: nothing to redraw");
    watcher.step(b"", 1.0);
    let after = watcher.view();
    assert_ne!(before, after, "the figure changed the picture");
    let middle = COLS as usize / 2;
    let labelled = after.iter().any(|row| {
        row.char_indices().any(|(i, c)| c == 'Z' && row[..i].chars().count().abs_diff(middle) <= 3)
    });
    assert!(labelled, "its initial near the middle of the view:\n{}", after.join("\n"));
}

/// Issue #39: a session's player (local or served: `serve` runs one a player) gets the look-ahead
/// lens from the bytes of `z`, and the HUD says so; Ctrl-Z still suspends and leaves the lens alone.
#[test]
fn z_through_a_session_puts_the_look_ahead_lens_on_and_ctrl_z_still_suspends() {
    let mut player = Player::new();
    // every frame drawn (vt100 answers no flow-control query)
    let app = App::new(maze::builtin().unwrap(), RenderOptions::default(), 0.0).unwrap();
    player.session =
        Session::new(app, COLS, ROWS, SessionOptions { flow_control: false, ..Default::default() });
    player.step(b"", 0.0);
    // (off: the HUD offers the key, `z look ahead`, and says no lens is on)
    assert!(
        !player.hud().contains("° look ahead") && player.hud().contains("z look ahead"),
        "{}",
        player.hud()
    );
    player.step(b"z", 0.5);
    assert!(player.session.app().look_ahead());
    assert!(player.hud().contains("fov 30° look ahead"), "{}", player.hud());
    assert!(!player.hud().contains("z look ahead"), "{}", player.hud());
    player.step(b"\x1a", 1.0);
    assert!(player.session.take_suspend(), "Ctrl-Z suspends");
    assert!(player.session.app().look_ahead(), "Ctrl-Z is not z");
    player.step(b"Z", 1.5);
    assert!(!player.session.app().look_ahead(), "Z (Shift or Caps Lock) turns it off");
    assert!(!player.hud().contains("° look ahead"), "{}", player.hud());
}
