//! The slow link in real time (issue #33, BENCHMARKS.md "The slow link in real time"): the real
//! `mazewalk` binary in a pty behind a metered link ([`pty_link`]), holding → for 2 s (auto-repeat 33
//! a second after 500 ms) at 120×40 in truecolor. For each binary given, alternating, `--runs` times
//! over a 125,000 B/s link and over a 10 MB/s one, both 50 ms each way; prints the medians as a
//! markdown table. Then the same with two of the far end's answers lost on the way back, which is
//! what a harness that misses a query, or bytes dropped by a server's rate limit, does.
//! `--link BYTES_PER_S,ONE_WAY_MS` (repeatable) measures those links instead, e.g. `--link 16000,150`
//! for 128 kbit/s and a 300 ms round trip; `--color DEPTH` walks in that colour depth (truecolor
//! unless said).
//!
//! ```sh
//! cargo build --release
//! cargo run --release -p mazewalk-bench --example slow_link_pty -- \
//!     --binary before=/tmp/walk-before/target/release/mazewalk --binary after=target/release/mazewalk
//! ```

use mazewalk_testkit::pty_link;

use std::path::PathBuf;

use pty_link::{Hold, Link, Outcome, measure};

const SLOW: Link = Link { bytes_per_s: 125_000.0, one_way: 0.050, lost_answers: &[] };
const FAST: Link = Link { bytes_per_s: 10_000_000.0, one_way: 0.050, lost_answers: &[] };
/// Two answers lost during the hold: the first query to arrive 1 s after the key went down, and the
/// first 1.5 s after.
const LOST: &[f64] = &[1.0, 1.5];
const HOLD: Hold = Hold { key: b"\x1b[C", hold: 2.0, repeat_delay: 0.5, repeat_every: 1.0 / 33.0 };

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 { v[n / 2] } else { (v[n / 2 - 1] + v[n / 2]) / 2.0 }
}

fn main() {
    let mut binaries: Vec<(String, PathBuf)> = Vec::new();
    let mut runs = 5;
    let mut asked: Vec<(String, Link)> = Vec::new();
    let mut color = String::from("truecolor");
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--binary" => {
                let spec = args.next().expect("--binary NAME=PATH");
                let (name, path) = spec.split_once('=').expect("--binary NAME=PATH");
                binaries.push((name.to_string(), PathBuf::from(path)));
            }
            "--runs" => runs = args.next().and_then(|n| n.parse().ok()).expect("--runs N"),
            "--color" => color = args.next().expect("--color DEPTH"),
            "--link" => {
                let spec = args.next().expect("--link BYTES_PER_S,ONE_WAY_MS");
                let parsed =
                    spec.split_once(',').and_then(|(rate, ms)| Some((rate.parse().ok()?, ms.parse().ok()?)));
                let (bytes_per_s, one_way_ms): (f64, f64) = parsed.expect("--link BYTES_PER_S,ONE_WAY_MS");
                let link = Link { bytes_per_s, one_way: one_way_ms / 1e3, lost_answers: &[] };
                asked.push((format!("{bytes_per_s:.0} B/s, {one_way_ms:.0} ms each way"), link));
            }
            other => panic!("unknown argument {other}"),
        }
    }
    if binaries.is_empty() {
        binaries.push(("this".into(), PathBuf::from("target/release/mazewalk")));
    }
    let env = [("TERM", "xterm-256color"), ("LANG", "C.UTF-8")];
    let args = ["--color", color.as_str()];
    println!(
        "| binary | link | tail after release (median, min–max) | degrees after release | last frame's gap | degrees turned | bytes |"
    );
    println!("|---|---|---:|---:|---:|---:|---:|");
    let links: Vec<(String, Link)> = if asked.is_empty() {
        vec![
            ("125,000 B/s".into(), SLOW),
            ("10 MB/s".into(), FAST),
            ("125,000 B/s, 2 answers lost".into(), Link { lost_answers: LOST, ..SLOW }),
            ("10 MB/s, 2 answers lost".into(), Link { lost_answers: LOST, ..FAST }),
        ]
    } else {
        asked
    };
    for (link_name, link) in links {
        let mut results: Vec<Vec<Outcome>> = binaries.iter().map(|_| Vec::new()).collect();
        for run in 0..runs {
            for (i, (name, binary)) in binaries.iter().enumerate() {
                let outcome = measure(binary, &args, &env, 120, 40, link, HOLD);
                eprintln!(
                    "{name} {link_name} run {run}: tail {:.2} s, {:.0}° after, gap {:.2} s, {:.0}° in all, {} frames, {} B",
                    outcome.tail(),
                    outcome.degrees_after_release(),
                    outcome.last_gap(),
                    outcome.degrees_turned(),
                    outcome.seen.frames.len(),
                    outcome.seen.bytes
                );
                if std::env::var_os("SLOW_LINK_DEBUG").is_some() {
                    eprintln!("press {:.3} release {:.3}", outcome.press, outcome.release);
                    eprintln!(
                        "frames {:?}",
                        outcome.seen.frames.iter().map(|t| format!("{t:.3}")).collect::<Vec<_>>()
                    );
                    eprintln!(
                        "headings {:?}",
                        outcome.seen.headings.iter().map(|(t, h)| format!("{t:.3}:{h}")).collect::<Vec<_>>()
                    );
                }
                results[i].push(outcome);
            }
        }
        for ((name, _), outcomes) in binaries.iter().zip(&results) {
            let tails: Vec<f64> = outcomes.iter().map(Outcome::tail).collect();
            let (lo, hi) = tails.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &t| (lo.min(t), hi.max(t)));
            println!(
                "| {name} | {link_name} | {:.2} s ({lo:.2}–{hi:.2}) | {:.0}° | {:.2} s | {:.0}° | {:.0} KB |",
                median(tails.clone()),
                median(outcomes.iter().map(|o| f64::from(o.degrees_after_release())).collect()),
                median(outcomes.iter().map(Outcome::last_gap).collect()),
                median(outcomes.iter().map(|o| f64::from(o.degrees_turned())).collect()),
                median(outcomes.iter().map(|o| o.seen.bytes as f64).collect()) / 1e3,
            );
        }
    }
}
