//! Peak memory (and wall time) of generating, writing or loading one maze, in a process of its own.
//!
//! ```sh
//! cargo run --release -p mazewalk-bench --example peak_mem -- gen prim 1000        # generate only
//! cargo run --release -p mazewalk-bench --example peak_mem -- write prim 1000 FILE  # generate, write CS559 to FILE
//! cargo run --release -p mazewalk-bench --example peak_mem -- load FILE             # maze::load
//! ```
//!
//! Algorithms: `prim`, `dfs`, `wilson`, or `prim-loops` (Prim's with loops 0.5). Prints one line:
//! what was done, the seconds it took, and the peak resident set (`VmHWM` from `/proc/self/status`,
//! Linux only; the whole process, so the baseline of an idle process, about 2 MB, is included).

use std::time::Instant;

use mazewalk_maze as maze;
use mazewalk_maze::generate::{Algorithm, GenOptions, generate};

fn options(algo: &str, side: u32) -> GenOptions {
    let (algorithm, loops) = match algo {
        "prim" => (Algorithm::Prim, 0.0),
        "dfs" => (Algorithm::Backtracker, 0.0),
        "wilson" => (Algorithm::Wilson, 0.0),
        "prim-loops" => (Algorithm::Prim, 0.5),
        _ => usage(),
    };
    GenOptions { width: side, height: side, seed: 1, algorithm, loops, ..GenOptions::default() }
}

fn usage() -> ! {
    eprintln!("usage: peak_mem gen ALGO SIDE | write ALGO SIDE FILE | load FILE");
    std::process::exit(2)
}

/// The process's peak resident set in MiB, if the kernel tells.
fn peak_rss_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let before = peak_rss_mib();
    let start = Instant::now();
    let what = match args.iter().map(String::as_str).collect::<Vec<_>>().as_slice() {
        ["gen", algo, side] => {
            let maze = generate(&options(algo, side.parse()?))?;
            format!("gen {algo} {side}: {} cells, {} edges", maze.cell_count(), maze.edges().len())
        }
        ["write", algo, side, file] => {
            let maze = generate(&options(algo, side.parse()?))?;
            let mut out = std::io::BufWriter::new(std::fs::File::create(file)?);
            maze::cs559::write_to(&maze, &mut out)?;
            std::io::Write::flush(&mut out)?;
            format!("write {algo} {side} to {file}")
        }
        ["load", file] => {
            let maze = maze::load(file)?.maze;
            let size = std::fs::metadata(file)?.len();
            format!("load {file} ({size} bytes): {} cells", maze.cell_count())
        }
        _ => usage(),
    };
    let seconds = start.elapsed().as_secs_f64();
    match (before, peak_rss_mib()) {
        (Some(b), Some(p)) => println!("{what}: {seconds:.3} s, peak RSS {p:.1} MiB (at start {b:.1} MiB)"),
        _ => println!("{what}: {seconds:.3} s, peak RSS unknown (no /proc/self/status)"),
    }
    Ok(())
}
