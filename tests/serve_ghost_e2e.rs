//! Issue #43, end to end: `mazewalk serve` (the built binary) and the real OpenSSH client (`ssh -tt`
//! in a pseudo-terminal read by a `vt100` emulator, `tests/common`). A finished run comes back as a
//! ghost: bob walks a corridor to the exit, his run is kept in the records (real SQLite); carol, who
//! joins after, presses `g` and bob's ghost runs ahead of her down the corridor, captioned with his
//! name and time, on her map too, and `g` again takes it away. `mazewalk records --export-run` then
//! writes his run to a file that decodes. With `--world`, a finish on one server reaches the ghost of
//! a player on another within seconds (a real `redis-server`). Loopback only; every wait has a
//! deadline.
#![cfg(unix)]

mod common;

use std::time::Duration;

use common::{Player, Scratch, Server, hud_row, on_map, playing, records};
use mazewalk_testkit::redis_server::{Persistence, RedisServer};

/// A corridor east from the start: the exit eight tiles (32 units) on.
const CORRIDOR: &str = "mazewalk-grid 1\ntile 4\nfacing east\n\n###########\n#@.......E#\n###########\n";
/// [`CORRIDOR`] with a cell behind the start, for a second player in: a walk from a spot nearer
/// the exit than the start is not kept in the records.
const CORRIDOR_AND_ONE_BEHIND: &str =
    "mazewalk-grid 1\ntile 4\nfacing east\n\n###########\n#.@......E#\n###########\n";

/// The view's rows (all but the HUD) show `text`.
fn in_view(screen: &vt100::Screen, text: &str) -> bool {
    let rows = screen.size().0.get();
    (0..rows - 1).any(|row| screen.contents_between(row, 0, row, u16::MAX).contains(text))
}

#[test]
fn a_finished_run_comes_back_as_a_ghost_on_the_next_players_screen_and_map() {
    let scratch = Scratch::new("ghost");
    let maze = scratch.maze(CORRIDOR);
    let server = Server::start(&scratch, &["--open", maze.to_str().expect("a UTF-8 path")]);
    let mut bob = Player::connect(server.port, None, "bob", 100, 30);
    bob.wait_for("bob's game", playing);
    // no run kept yet: `g` says so
    bob.send(b"g");
    bob.wait_for("no ghost yet", |s, _| hud_row(s).contains("no ghost yet"));
    bob.send(b"g");
    // Bob holds `w` (auto-repeat every 40 ms) east to the exit, about 30 units: 6 s at 5 units/s.
    for _ in 0..200 {
        bob.send(b"w");
        std::thread::sleep(Duration::from_millis(40));
        if bob.shows(|s| s.contents().contains("You found the exit in")) {
            break;
        }
    }
    bob.wait_for("bob's exit box with his rank", |s, _| s.contents().contains("Best times here (1 player)"));
    drop(bob); // (his ssh killed: he leaves)
    server.wait_log("disconnected", 1);

    let mut carol = Player::connect(server.port, None, "carol", 100, 30);
    carol.wait_for("carol's game", playing);
    assert!(!carol.shows(|s| s.contents().contains("ghost")), "no ghost until asked for");
    carol.send(b"g");
    // The ghost starts on the start with her toggle and runs east down the corridor she faces: its
    // caption over its head in the view, its name and time in the HUD, its mark on her map.
    carol.wait_for("bob's ghost ahead, captioned, and on the map", |s, _| {
        in_view(s, "ghost bob 0:0") && hud_row(s).contains("ghost bob 0:0") && on_map(s, '◌')
    });
    // it keeps running while she stands: its caption moves (a later screen differs)
    let caption_row = |s: &vt100::Screen| {
        let rows = s.size().0.get();
        (0..rows - 1).find(|&r| s.contents_between(r, 0, r, u16::MAX).contains("ghost bob"))
    };
    let first = carol.read(caption_row).expect("the caption");
    carol.wait_for("the ghost further down the corridor (smaller, its head lower)", |s, _| {
        caption_row(s).is_some_and(|row| row > first)
    });
    // `g` again: gone from the view, the HUD and the map
    carol.send(b"g");
    carol.wait_for("the ghost gone", |s, _| {
        playing(s, &[]) && !s.contents().contains("ghost") && !on_map(s, '◌')
    });

    // The run as a file: exported from the records, it decodes and is bob's.
    let run = scratch.join("bob.run");
    let exported = records(
        &scratch,
        &[maze.to_str().expect("utf-8"), "--export-run", "bob", run.to_str().expect("utf-8")],
    );
    assert!(exported.status.success(), "{exported:?}");
    let bytes = std::fs::read(&run).expect("the run file");
    let decoded = mazewalk_walk::run::Run::decode(&bytes).expect("a run");
    assert_eq!(decoded.holder, "bob");
    assert!((4.0..20.0).contains(&decoded.seconds()), "{}", decoded.seconds());
    drop(server);
}

/// Holds `w` (auto-repeat every 40 ms) until the exit box shows: the corridor's 30 units take 6 s.
fn walk_to_the_exit(player: &mut Player) {
    for _ in 0..400 {
        player.send(b"w");
        std::thread::sleep(Duration::from_millis(40));
        if player.shows(|s| s.contents().contains("You found the exit in")) {
            return;
        }
    }
    player.wait_for("the exit box", |s, _| s.contents().contains("You found the exit in"));
}

// Issue #43: with --world, a new best run made on server A reaches `g` on server B within seconds
// (the remote finish asks B's records to read the best run again), not at B's 30 s reread: B's
// player, racing with no ghost yet, sees alice's ghost well within 10 s of her finish.
#[test]
fn a_finish_on_another_server_reaches_the_ghost_within_seconds() {
    let scratch = Scratch::new("worldghost");
    let redis = RedisServer::start(Persistence::None);
    let maze = scratch.maze(CORRIDOR_AND_ONE_BEHIND); // (alice is second in)
    let server_a = Server::in_world(&scratch, "a", &maze, &redis.url(0), &[]);
    let server_b = Server::in_world(&scratch, "b", &maze, &redis.url(0), &[]);
    let mut bob = Player::connect(server_b.port, None, "bob", 100, 30);
    bob.wait_for("bob's game on server B", playing);
    bob.send(b"g");
    bob.wait_for("no ghost yet", |s, _| hud_row(s).contains("no ghost yet"));

    let mut alice = Player::connect(server_a.port, None, "alice", 100, 30);
    alice.wait_for("alice's game on server A", playing);
    walk_to_the_exit(&mut alice);
    let finished = std::time::Instant::now();
    bob.wait_for("alice's ghost on server B", |s, _| hud_row(s).contains("ghost alice 0:"));
    let took = finished.elapsed();
    assert!(took < Duration::from_secs(10), "alice's run reached server B after {took:?}");
    drop((alice, bob, server_a, server_b));
}
