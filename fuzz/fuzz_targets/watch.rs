//! One spectator's input path, without sockets (`mazewalk_serve::spectator::Spectator`, issue #43):
//! any bytes and window changes, in any order and any chunks, with time passing and players joining,
//! moving, finishing and leaving. Asserts: no panic and no hang; the screen never exceeds the size
//! limits; a frame's bytes stay within a fixed bound per cell; whom it shows is in the world; leaving
//! always ends with the full restore sequence.

#![no_main]

use glam::Vec2;
use libfuzzer_sys::fuzz_target;
use mazewalk_serve::Limits;
use mazewalk_serve::player::REMOTE;
use mazewalk_serve::spectator::{Audience, Spectator};
use mazewalk_serve::world::{PlayerId, World};
use mazewalk_term::modes::restore_sequence;

/// Generous upper bound of a frame's bytes per screen cell (glyph, colours, cursor moves), plus the
/// fixed part (synchronized output, the query).
const MAX_BYTES_PER_CELL: usize = 64;

fuzz_target!(|bytes: &[u8]| {
    let limits = Limits { max_cols: 160, max_rows: 60, ..Limits::default() }; // keeps runs quick
    let Some((&size, mut rest)) = bytes.split_first() else { return };
    let (cols, rows) = (u32::from(size & 0x0f) * 13, u32::from(size >> 4) * 5);
    let maze = mazewalk_maze::builtin().expect("built-in maze");
    let audience = Audience::new(&maze, 4);
    let (position, heading) = (maze.viewer().pos, maze.viewer().dir_deg);
    let Some(cell) = maze.cell_at(position) else { return };
    let Ok(mut player) = Spectator::new(maze, "xterm-256color", None, (cols, rows), &limits, &audience, 0.0)
    else {
        return;
    };
    let mut world = World::new();
    let mut others: Vec<PlayerId> = Vec::new();
    let mut last = world.look(); // the last look the spectator had
    let mut out = Vec::new();
    player.enter(&mut out);
    let mut t = 0.0;
    // Each op: its first byte's low 2 bits say what, the rest of that byte how much.
    while let Some((&op, tail)) = rest.split_first() {
        rest = tail;
        let n = usize::from(op >> 2);
        match op & 3 {
            0 => {
                let (chunk, tail) = rest.split_at(n.min(rest.len()));
                let _ = player.feed(chunk, t);
                rest = tail;
            }
            1 => {
                let (dims, tail) = rest.split_at(8.min(rest.len()));
                let mut b = [0u8; 8];
                b[..dims.len()].copy_from_slice(dims);
                let cols = u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
                let rows = u32::from_le_bytes([b[4], b[5], b[6], b[7]]);
                player.resize(cols, rows, t);
                rest = tail;
            }
            2 => t += n as f64 / 20.0,
            _ => {
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
        let screen = player.session().screen();
        assert!(
            screen.width() <= usize::from(limits.max_cols) && screen.height() <= usize::from(limits.max_rows)
        );
        assert!(
            out.len() <= 256 + screen.width() * screen.height() * MAX_BYTES_PER_CELL,
            "{} bytes",
            out.len()
        );
        let looked = |id: PlayerId| last.players.iter().any(|(p, _)| *p == id);
        assert!(player.shown().is_none_or(looked), "it shows someone its last look did not");
        if player.is_over() {
            break;
        }
        // A wake before now (even -inf: "a frame is due") means at once; the server clamps the wait.
        if let Some(wake) = player.next_wake(t) {
            assert!(!wake.is_nan() && wake < f64::INFINITY);
        }
    }
    out.clear();
    player.leave(Some("bye"), &mut out);
    let restore = restore_sequence(REMOTE);
    assert!(out.starts_with(restore.as_bytes()) && out.ends_with(b"bye\r\n"));
});
