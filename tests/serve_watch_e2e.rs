//! End to end, issue #43: a spectator (`ssh watch@HOST`) watches two players with the stock OpenSSH
//! client, each `ssh -tt` in a pty read by a `vt100` emulator (`tests/common`). Loopback only; every
//! wait has a deadline; children are killed on drop.
//!
//! Checks: before anyone plays the spectator sees a calm "waiting" screen; it follows the first
//! player (no exit: the first to join leads) and its 3D view is that player's own; the player's turn
//! turns it, the spectator's own walking keys do nothing to it nor to anyone; Tab follows the other
//! player; the spectator is no one in the players' maze (not counted, not listed, no figure or
//! label); the spectator never took a player's slot (two players in with `--max-players 2`), and
//! `--max-spectators 1` refuses a second spectator with a message of its own, even with a player's
//! slot free; `q` stops watching. With `--world`, a spectator on one server follows a player on
//! another: the same view, turning when she turns.
#![cfg(unix)]

mod common;

use common::{Player, Scratch, Server, hud_row, playing};
use mazewalk_testkit::redis_server::{Persistence, RedisServer};

/// A corridor east from the start, and at its end a passage south (no exit: the first to join leads).
const CORRIDOR_AND_BEND: &str =
    "mazewalk-grid 1\ntile 4\nfacing east\n\n#######\n#@....#\n####..#\n####..#\n####..#\n#######\n";

/// The 3D view's rows below the corner map (a third of the screen down) and above the HUD, as they
/// look ([`common::looks`]): what a player and a spectator following it both show.
fn view_rows(screen: &vt100::Screen) -> common::Cells {
    let rows = screen.size().0.get();
    common::looks(screen, rows / 3..rows - 1)
}

/// Whether two screens' views (`view_rows`) look alike: the same glyphs, each colour the same or, for
/// palette entries, within the encoder's default tolerance of it (a screen may keep a cell whose entry
/// changed to a near one, and two screens' histories differ).
fn same_view(a: &common::Cells, b: &common::Cells) -> bool {
    use mazewalk_term::Color;
    use mazewalk_term::encoder::DEFAULT_TOLERANCE;
    let alike = |x: vt100::Color, y: vt100::Color| match (x, y) {
        (vt100::Color::Idx(m), vt100::Color::Idx(n)) => {
            m == n || Color::Indexed(m).within(Color::Indexed(n), DEFAULT_TOLERANCE)
        }
        _ => x == y,
    };
    a.len() == b.len()
        && a.iter().zip(b).all(|(ra, rb)| {
            ra.len() == rb.len()
                && ra.iter().zip(rb).all(|(ca, cb)| ca.0 == cb.0 && alike(ca.1, cb.1) && alike(ca.2, cb.2))
        })
}

/// The heading the HUD shows ("heading 90° N").
fn heading(screen: &vt100::Screen) -> Option<String> {
    let hud = hud_row(screen);
    let at = hud.find("heading ")?;
    Some(hud[at..].split("  ").next()?.to_string())
}

#[test]
fn a_spectator_watches_two_players_and_is_no_one_in_their_maze() {
    let scratch = Scratch::new("watch");
    let maze = scratch.maze(CORRIDOR_AND_BEND);
    let maze = maze.to_str().expect("a UTF-8 path");
    let server = Server::start(&scratch, &["--open", "--max-players", "2", "--max-spectators", "1", maze]);

    let mut watcher = Player::connect(server.port, None, "watch", 100, 30);
    watcher.wait_for("the waiting screen", |s, _| {
        playing(s, &[]) && s.contents().contains("Waiting for a player") && hud_row(s).contains("0 in")
    });
    // The spectator holds no player's slot: both players get in with --max-players 2.
    let mut alice = Player::connect(server.port, None, "alice", 100, 30);
    alice.wait_for("alice's game", playing);
    let mut bob = Player::connect(server.port, None, "bob", 100, 30);
    bob.wait_for("bob's game", playing);
    watcher.wait_for("alice followed, two in", |s, _| {
        let hud = hud_row(s);
        hud.contains("watching alice") && hud.contains("2 in") && !s.contents().contains("Waiting for")
    });
    alice.wait_for("two in, the spectator not counted", |s, _| hud_row(s).contains("2 in"));
    watcher.wait_for("alice's view on the spectator's screen", |s, _| {
        same_view(&view_rows(s), &alice.read(view_rows))
    });

    // Alice turns (a snap turn right): the spectator's view turns with her.
    let before = watcher.read(heading);
    alice.send(b".");
    alice.wait_for("alice turned", |s, _| heading(s) != before);
    watcher.wait_for("the spectator's view turned too", |s, _| {
        heading(s) == alice.read(heading) && same_view(&view_rows(s), &alice.read(view_rows))
    });
    // The spectator's walking keys move nothing: not its view, not alice (once her turn is over:
    // a snap turn takes 0.15 s, and the two may have matched on its way).
    std::thread::sleep(std::time::Duration::from_millis(400));
    watcher
        .wait_for("the turn over on both screens", |s, _| same_view(&view_rows(s), &alice.read(view_rows)));
    let (alice_hud, watched) = (alice.read(hud_row), watcher.read(view_rows));
    watcher.send(b"wwwasd\x1b[A\x1b[B,.");
    std::thread::sleep(std::time::Duration::from_millis(600));
    assert!(watcher.read(view_rows) == watched, "the spectator's keys moved its view");
    assert_eq!(alice.read(hud_row), alice_hud, "the spectator's keys moved alice");

    // Tab: bob's view.
    watcher.send(b"\t");
    watcher.wait_for("bob followed", |s, _| hud_row(s).contains("watching bob"));
    watcher.wait_for("bob's view on the spectator's screen", |s, _| {
        same_view(&view_rows(s), &bob.read(view_rows))
    });

    // No one in the players' maze: not in the list, no label on the map or in the view.
    alice.send(b"\t");
    alice.wait_for("alice's player list", |s, _| s.contents().contains("Players: 2"));
    assert!(!alice.shows(|s| s.contents().contains("watch")), "the spectator is listed");
    alice.send(b"\t");
    for player in [&alice, &bob] {
        player.wait_for("the list closed", |s, _| playing(s, &[]) && !s.contents().contains("Players:"));
        // (above the HUD, whose compass may say W)
        let above_hud = |s: &vt100::Screen| s.contents_between(0, 0, s.size().0.get() - 2, u16::MAX);
        assert!(!player.shows(|s| above_hud(s).contains('W')), "a figure or label for the spectator");
    }

    // The spectators' cap. Both full: a newcomer, spectator or player, is told so before logging in.
    for user in ["watch", "carol"] {
        let (status, _, stderr) = server.ssh_batch(None, user, &["-tt"]);
        assert_eq!(status.code(), Some(255), "{stderr}");
        assert!(stderr.contains("the server is full (2 players, 1 watching); try again later"), "{stderr}");
    }
    // A player's slot free: a second spectator still gets no place, and is told so its own way.
    bob.send(b"q");
    assert!(bob.wait_exit().success());
    watcher.wait_for("one in", |s, _| hud_row(s).contains("1 in"));
    let (status, _, stderr) = server.ssh_batch(None, "watch", &["-tt"]);
    assert_eq!(status.code(), Some(255), "{stderr}");
    assert!(stderr.contains("every spectator's place is taken (1 watching); try again later"), "{stderr}");
    server.wait_log("refused: spectators full", 1);
    assert!(watcher.shows(|s| hud_row(s).contains("1 in")), "the spectator refused did not play");

    watcher.send(b"q");
    assert!(watcher.wait_exit().success(), "q ends the spectator's ssh with 0");
    watcher
        .wait_for("goodbye", |s, _| !s.alternate_screen() && s.contents().contains("Thanks for watching."));
    alice.send(b"q");
    assert!(alice.wait_exit().success());
}

// issue #43: with --world, a spectator follows players on other servers, drawn from the world's word.
#[test]
fn a_spectator_follows_a_player_on_another_server() {
    let scratch = Scratch::new("watchworld");
    let redis = RedisServer::start(Persistence::None);
    let maze = scratch.maze(CORRIDOR_AND_BEND);
    let server_a = Server::in_world(&scratch, "a", &maze, &redis.url(0), &[]);
    let server_b = Server::in_world(&scratch, "b", &maze, &redis.url(0), &[]);
    let mut alice = Player::connect(server_a.port, None, "alice", 100, 30);
    alice.wait_for("alice's game on server A", playing);
    let watcher = Player::connect(server_b.port, None, "watch", 100, 30);
    watcher.wait_for("alice (server A) followed on server B", |s, _| {
        let hud = hud_row(s);
        hud.contains("watching alice") && hud.contains("1 in")
    });
    watcher.wait_for("alice's view on server B", |s, _| same_view(&view_rows(s), &alice.read(view_rows)));
    let before = watcher.read(heading);
    alice.send(b".");
    alice.wait_for("alice turned", |s, _| heading(s) != before);
    watcher.wait_for("the view on server B turned with her", |s, _| {
        heading(s) == alice.read(heading) && same_view(&view_rows(s), &alice.read(view_rows))
    });
}
