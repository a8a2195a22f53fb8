//! What a spectator costs beside a player (issue #43), in process: one player turns a step each
//! frame (a new view every frame) in a generated 16 × 16 maze, and `S` spectators follow it at the
//! player's size and colour depth, sharing their views ([`SharedViews`]): the first spectator to draw
//! a frame renders the view, the others copy it. The server's own work per frame — the player's
//! frame, each spectator's look at the world and frame — without the SSH and the network around it.
//!
//! ```sh
//! cargo build --release -p mazewalk-bench --example watch_cost
//! ./target/release/examples/watch_cost 8 300            # medians per frame, by role
//! # instruction counts: the same run with 0, 1 and 8 spectators; the differences are theirs
//! for s in 0 1 8; do valgrind --tool=callgrind --callgrind-out-file=/tmp/watch$s.cg \
//!     ./target/release/examples/watch_cost $s 300; done
//! ```
//!
//! Arguments: spectators (default 8), frames (300), columns (120), rows (40), colour depth (256),
//! `shared` (the server's way) or `own` (each spectator renders its own view: the baseline).
//! Prints the median time of a player's frame, of the spectator's frame that rendered the view and
//! of a spectator's frame that copied it, their ratios to the player's, and the views rendered and
//! copied.

use std::sync::Arc;
use std::time::Instant;

use mazewalk_maze::generate::{GenOptions, generate};
use mazewalk_serve::Limits;
use mazewalk_serve::player::{ClientTerminal, Player};
use mazewalk_serve::spectator::{Audience, Spectator};
use mazewalk_serve::world::World;

/// The terminal's answer to each frame's flow-control query.
const ANSWER: &[u8] = b"\x1b[?62;22c";

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, default: &str| args.get(i).cloned().unwrap_or_else(|| default.to_owned());
    let spectators: usize = arg(0, "8").parse().expect("spectators");
    let frames: usize = arg(1, "300").parse().expect("frames");
    let (cols, rows): (u32, u32) =
        (arg(2, "120").parse().expect("cols"), arg(3, "40").parse().expect("rows"));
    let term = match arg(4, "256").as_str() {
        "16" => "xterm",
        "none" => "vt100",
        _ => "xterm-256color",
    };

    let own = arg(5, "shared") == "own";
    let options = GenOptions { width: 16, height: 16, exit: true, ..GenOptions::default() };
    let maze = Arc::new(generate(&options).expect("a maze"));
    let limits = Limits::default();
    let audience = Audience::new(&maze, 16);
    let mut world = World::new();
    let mut player = Player::new(Arc::clone(&maze), &ClientTerminal::new(term), (cols, rows), &limits, 0.0)
        .expect("a player");
    let (position, heading, cell) = player.whereabouts();
    let id = world.join("ada", position, heading, cell, 0.0);
    player.joined(id);
    let mut watching: Vec<Spectator> = (0..spectators)
        .map(|_| {
            let apart = Audience::new(&maze, 16);
            let audience = if own { &apart } else { &audience };
            Spectator::new(
                Arc::clone(&maze),
                &ClientTerminal::new(term),
                (cols, rows),
                &limits,
                audience,
                0.0,
            )
            .expect("a spectator")
        })
        .collect();

    let (mut player_times, mut rendered, mut copied) = (Vec::new(), Vec::new(), Vec::new());
    let mut out = Vec::with_capacity(1 << 16);
    for i in 0..frames {
        let now = i as f64 / 30.0;
        player.feed(ANSWER, now);
        player.feed(b"\x1b[D", now); // a step left: a new view every frame
        let started = Instant::now();
        let drew = player.frame(now + 0.02, &mut out);
        if drew {
            player_times.push(started.elapsed().as_secs_f64());
        }
        out.clear();
        let news = player.news();
        world.moved(id, news.position, news.heading_deg, news.cell);
        world.pitched(id, news.pitch_deg);
        let look = world.look();
        for (n, spectator) in watching.iter_mut().enumerate() {
            let started = Instant::now();
            spectator.feed(ANSWER, now);
            spectator.world_changed(now + 0.02);
            spectator.look(look.clone(), now + 0.02);
            let drew = spectator.frame(now + 0.02, &mut out);
            if drew {
                let seconds = started.elapsed().as_secs_f64();
                if n == 0 { rendered.push(seconds) } else { copied.push(seconds) }
            }
            out.clear();
        }
    }
    let (p, r, c) = (median(player_times.clone()), median(rendered.clone()), median(copied.clone()));
    let how = if own { "each rendering its own view" } else { "sharing views" };
    println!(
        "{frames} frames at {cols}×{rows} ({term}), {spectators} spectators following one player, {how}"
    );
    println!("player's frame                   median {:8.3} ms  ({} frames)", p * 1e3, player_times.len());
    println!(
        "spectator's frame, rendering     median {:8.3} ms  {:.2}× the player's  ({} frames)",
        r * 1e3,
        r / p,
        rendered.len()
    );
    println!(
        "spectator's frame, the others    median {:8.3} ms  {:.2}× the player's  ({} frames)",
        c * 1e3,
        c / p,
        copied.len()
    );
    let (renders, hits) = audience.views.counts();
    println!("views rendered {renders}, copied {hits}");
}
