//! One served player's input path, without sockets (`mazewalk_serve::player::Player`): any bytes and
//! window changes, in any order and any chunks, with time passing and other players moving about.
//! Asserts: no panic and no hang; the screen never exceeds the size limits; a frame's bytes stay
//! within a fixed bound per cell; leaving always ends with the full restore sequence.

#![no_main]

use glam::Vec2;
use libfuzzer_sys::fuzz_target;
use mazewalk_serve::player::{ClientTerminal, Player};
use mazewalk_serve::world::{PlayerId, World};

#[path = "common/served.rs"]
mod served;
use served::Step;

fuzz_target!(|bytes: &[u8]| {
    let limits = served::limits();
    let Some(((cols, rows), steps)) = served::steps(bytes) else { return };
    let maze = mazewalk_maze::builtin().expect("built-in maze");
    let Ok(mut player) =
        Player::new(maze, &ClientTerminal::new("xterm-256color"), (cols, rows), &limits, 0.0)
    else {
        return;
    };
    let mut world = World::new();
    let (position, heading, cell) = player.whereabouts();
    player.joined(world.join("me", position, heading, cell, 0.0));
    let others: Vec<PlayerId> =
        (0..8).map(|i| world.join(&format!("p{i}"), Vec2::ZERO, 0.0, cell, 0.0)).collect();
    let mut out = Vec::new();
    player.enter(&mut out);
    let mut t = 0.0;
    for step in steps {
        match step {
            Step::Keys(chunk) => {
                let _ = player.feed(chunk, t);
            }
            Step::Resize(cols, rows) => player.resize(cols, rows, t),
            Step::Wait(seconds) => t += seconds,
            Step::World(n) => {
                // The others move about (some to the exit), as a look at the world shows them.
                let (position, heading, _) = player.whereabouts();
                for (i, &id) in others.iter().enumerate().take(n % 9) {
                    let at = position + Vec2::new(i as f32 - 3.0, (n % 5) as f32 - 2.0);
                    world.moved(id, at, n as f32 * 7.0 + heading, cell);
                    if n % 7 == i {
                        world.finished(id, t);
                    }
                }
                player.world_changed(t);
                if player.look_due(t) {
                    player.look(&world.look(), t);
                }
            }
        }
        out.clear();
        player.frame(t, &mut out);
        served::check_frame(player.session().screen(), &out, &limits);
        if player.is_over() {
            break;
        }
        served::check_wake(player.next_wake(t));
    }
    out.clear();
    player.leave(Some("bye"), &mut out);
    served::check_goodbye(&out);
});
