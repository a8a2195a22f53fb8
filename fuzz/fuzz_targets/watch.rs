//! One spectator's input path, without sockets (`mazewalk_serve::spectator::Spectator`, issue #43):
//! any bytes and window changes, in any order and any chunks, with time passing and players joining,
//! moving, finishing and leaving. Asserts: no panic and no hang; the screen never exceeds the size
//! limits; a frame's bytes stay within a fixed bound per cell; whom it shows is in the world; leaving
//! always ends with the full restore sequence.

#![no_main]

use glam::Vec2;
use libfuzzer_sys::fuzz_target;
use mazewalk_serve::player::ClientTerminal;
use mazewalk_serve::spectator::{Audience, Spectator};
use mazewalk_serve::world::{PlayerId, World};

#[path = "common/served.rs"]
mod served;
use served::Step;

fuzz_target!(|bytes: &[u8]| {
    let limits = served::limits();
    let Some(((cols, rows), steps)) = served::steps(bytes) else { return };
    let maze = mazewalk_maze::builtin().expect("built-in maze");
    let audience = Audience::new(&maze, 4);
    let (position, heading) = (maze.viewer().pos, maze.viewer().dir_deg);
    let Some(cell) = maze.cell_at(position) else { return };
    let Ok(mut player) =
        Spectator::new(maze, &ClientTerminal::new("xterm-256color"), (cols, rows), &limits, &audience, 0.0)
    else {
        return;
    };
    let mut world = World::new();
    let mut others: Vec<PlayerId> = Vec::new();
    let mut last = world.look(); // the last look the spectator had
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
                // Players come, move about (some to the exit) and go, as a look at the world shows them.
                if n % 11 == 0 && others.len() < 8 {
                    others.push(world.join(&format!("p{n}"), position, heading, cell, t));
                } else if n % 13 == 0 && !others.is_empty() {
                    world.leave(others.remove(n % others.len()));
                }
                for (i, &id) in others.iter().enumerate().take(n % 9) {
                    let at = position + Vec2::new(i as f32 - 3.0, (n % 5) as f32 - 2.0);
                    world.moved(id, at, n as f32 * 7.0 + heading, cell);
                    if n % 7 == i {
                        world.finished(id, t);
                    }
                }
                player.world_changed(t);
                if player.look_due(t) {
                    last = world.look();
                    player.look(last.clone(), t);
                }
            }
        }
        out.clear();
        player.frame(t, &mut out);
        served::check_frame(player.session().screen(), &out, &limits);
        let looked = |id: PlayerId| last.players.iter().any(|(p, _)| *p == id);
        assert!(player.shown().is_none_or(looked), "it shows someone its last look did not");
        if player.is_over() {
            break;
        }
        served::check_wake(player.next_wake(t));
    }
    out.clear();
    player.leave(Some("bye"), &mut out);
    served::check_goodbye(&out);
});
