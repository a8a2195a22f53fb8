//! `mazewalk records`: the best times `serve` kept, of one maze (named as it was served: a file,
//! `--gen WxH --seed N`, `--builtin`) or of every maze in the records file; with `--world URL`, of the
//! named maze in that shared world's Redis.

use crate::cli::RecordsArgs;

/// `mazewalk records`: prints each maze's best times (read only; the file is not changed).
#[cfg(all(unix, feature = "serve"))]
pub fn run(args: &RecordsArgs) -> anyhow::Result<()> {
    use std::io::Write as _;

    use anyhow::Context as _;
    use mazewalk_serve::host_key;
    use mazewalk_serve::identity::player_name;
    use mazewalk_serve::records::{Sqlite, Store};
    use mazewalk_serve::shared::WorldError;

    use super::{load_maze, maze_name, stdout_open};
    use crate::cli::{MazeArgs, ReadArgs};
    let path = match &args.records {
        Some(path) => path.clone(),
        None => host_key::default_path(|k| std::env::var(k).ok())?.with_file_name("records.sqlite"),
    };
    let maze = if args.maze.is_some() || args.generate.is_some() || args.builtin {
        let named = MazeArgs {
            maze: args.maze.clone(),
            more: Vec::new(),
            generate: args.generate,
            seed: args.seed,
            read: ReadArgs { max_file_size: args.read.max_file_size },
        };
        Some((load_maze(&named)?.content_hash(), maze_name(&named)))
    } else {
        None
    };
    // (a usage error, exit 2, said before any store is opened: the flags alone say it)
    let need_maze = |flag: &str, why: &str| {
        maze.clone().ok_or_else(|| {
            super::Usage(format!(
                "records {flag}: name the maze (MAZE, --gen WxH --seed N or --builtin){why}"
            ))
        })
    };
    let world_maze = args
        .world
        .as_ref()
        .map(|_| need_maze("--world", ": a world's records are kept by maze"))
        .transpose()?;
    let export_maze = args.export_run.as_ref().map(|_| need_maze("--export-run", "")).transpose()?;
    // (`world_maze` is `Some` exactly when `--world` is: the records file otherwise)
    let (mut store, place): (Box<dyn Store>, String) = match (&args.world, &world_maze) {
        (Some(url), Some((hash, _))) => {
            let ca = args.world_ca.as_deref().map(super::read_world_ca).transpose()?;
            let store =
                mazewalk_serve::shared::records::RedisStore::new(url, ca.as_deref(), *hash).map_err(|e| {
                    match e {
                        // not a Redis URL, or a CA without TLS: a bad flag value (exit 2)
                        WorldError::Url { .. } | WorldError::CaWithoutTls { .. } => {
                            anyhow::Error::new(super::Usage(format!("records: {e}")))
                        }
                        e => anyhow::Error::new(e).context("records"),
                    }
                })?;
            let place = format!("the world at {}", mazewalk_serve::shared::redis::redacted(url));
            (Box::new(store), place)
        }
        _ => {
            let db = Sqlite::open_to_read(&path).map_err(anyhow::Error::new).context("records")?;
            (Box::new(db), mazewalk_maze::quote_path(&path.display().to_string()))
        }
    };
    // (`export_maze` is `Some` exactly when `--export-run` is)
    if let (Some(export), Some((hash, name))) = (&args.export_run, &export_maze) {
        return export_run(&mut *store, *hash, name, export);
    }
    stdout_open()?;
    let mazes = store.mazes(maze.as_ref().map(|(hash, _)| hash)).context("records")?;
    let mut out = std::io::stdout().lock();
    if let Some((hash, name)) = &maze {
        if mazes.is_empty() {
            writeln!(out, "{name}: no finishes kept in {place} (maze {hash})")?;
            return Ok(());
        }
    } else if mazes.is_empty() {
        writeln!(out, "no finishes kept in {place}")?;
        return Ok(());
    }
    for (i, kept) in mazes.iter().enumerate() {
        if i > 0 {
            writeln!(out)?;
        }
        writeln!(out, "{}", heading(kept))?;
        // (names as every screen shows them: the file may hold anything, escapes too; issue #40)
        let names: Vec<String> = kept.top.iter().map(|b| player_name(&b.player)).collect();
        let width = names.iter().map(|n| n.chars().count()).max().unwrap_or(0);
        for (rank, (best, name)) in (1..).zip(kept.top.iter().zip(&names)) {
            let clock = mazewalk_walk::clock::clock_text(best.seconds);
            // (a world's best kept while its records were away has no date: 0)
            let when = if best.at > 0 { date(best.at) } else { "-".to_string() };
            writeln!(out, "{rank:>4}. {name:<width$}  {clock:>8}  {when}")?;
        }
    }
    out.flush()?;
    Ok(())
}

/// The line above a maze's best times: its name, the start of its hash, how many players and
/// finishes. Each string is the file's, which may hold anything (a hash too short, not hex, with
/// escapes: red-team pass 8, the local side, finding 3): each is quoted as any text from outside.
#[cfg(all(unix, feature = "serve"))]
fn heading(kept: &mazewalk_serve::records::MazeRecords) -> String {
    let players =
        if kept.players == 1 { "1 player".to_string() } else { format!("{} players", kept.players) };
    let finishes =
        if kept.finishes == 1 { "1 finish".to_string() } else { format!("{} finishes", kept.finishes) };
    // (12 characters of the hash, escapes counted, then `…`; a shorter one whole)
    let hash = mazewalk_maze::quote_within(&kept.maze, 12);
    format!("{} (maze {hash}): {players}, {finishes}", mazewalk_maze::quote(&kept.name))
}

/// `--export-run [RANK|NAME] FILE`: the run of the player at RANK (1 if omitted) or of NAME on the
/// maze of hash `hash`, checked as any stored run is (it came from a file or a Redis), written to FILE.
#[cfg(all(unix, feature = "serve"))]
fn export_run(
    store: &mut dyn mazewalk_serve::records::Store,
    hash: mazewalk_maze::ContentHash,
    name: &str,
    export: &[String],
) -> anyhow::Result<()> {
    use anyhow::Context as _;
    use mazewalk_walk::run::Run;
    let (who, file) = match export {
        [file] => ("1", file),
        [who, file] => (who.as_str(), file),
        _ => anyhow::bail!("records --export-run: give [RANK|NAME] FILE"),
    };
    let player = match who.parse::<usize>() {
        Ok(rank) => {
            let mazes = store.mazes(Some(&hash)).context("records")?;
            let top = mazes.first().map(|m| m.top.as_slice()).unwrap_or_default();
            let Some(best) = rank.checked_sub(1).and_then(|i| top.get(i)) else {
                anyhow::bail!(
                    "records --export-run: {name} has no rank {rank} (it has {} best times)",
                    top.len()
                );
            };
            best.player.clone()
        }
        Err(_) => who.to_string(),
    };
    let shown = mazewalk_serve::identity::player_name(&player);
    let stored = store
        .run(&hash, Some(&player))
        .context("records")?
        .with_context(|| format!("records --export-run: no run of {shown} kept for {name}"))?;
    let run = Run::decode(&stored.bytes)
        .with_context(|| format!("records --export-run: {shown}'s run of {name} is damaged"))?;
    write_run(std::path::Path::new(file), &stored.bytes)?;
    let file = mazewalk_maze::quote_path(file);
    eprintln!(
        "{shown}'s run of {name} ({}, {} samples) written to {file}",
        mazewalk_walk::clock::clock_text(run.seconds()),
        run.samples.len()
    );
    Ok(())
}

/// Writes `bytes` to the file at `path` (made, or its contents replaced), opened as `--save-run`'s
/// and `--record`'s are: never through a symbolic link, never a FIFO or a device (red-team pass 8,
/// the local side, finding 7: `std::fs::write` followed a link over the file it named).
#[cfg(all(unix, feature = "serve"))]
fn write_run(path: &std::path::Path, bytes: &[u8]) -> anyhow::Result<()> {
    use std::io::Write as _;

    use anyhow::Context as _;
    use mazewalk_maze::files::open_to_write;
    let cannot = || format!("--export-run {}", mazewalk_maze::quote_path(&path.display().to_string()));
    let (mut file, _) = open_to_write(path).map_err(|e| anyhow::Error::new(e).context(cannot()))?;
    file.set_len(0).and_then(|()| file.write_all(bytes)).with_context(cannot)
}

/// `YYYY-MM-DD` (UTC) of Unix time `at` (days from the civil calendar: Howard Hinnant's algorithm).
#[cfg(all(unix, feature = "serve"))]
fn date(at: i64) -> String {
    let days = at.div_euclid(86_400);
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02}")
}

/// Without `serve` (or off Unix): says why it cannot.
#[cfg(not(all(unix, feature = "serve")))]
pub fn run(_: &RecordsArgs) -> anyhow::Result<()> {
    anyhow::bail!(
        "this mazewalk was built without `serve`, which keeps the records (build it with the default features)"
    );
}

#[cfg(all(test, unix, feature = "serve"))]
mod tests {
    #[test]
    fn dates_are_civil_utc() {
        assert_eq!(super::date(0), "1970-01-01");
        assert_eq!(super::date(951_782_400), "2000-02-29");
        assert_eq!(super::date(1_800_000_000), "2027-01-15");
    }

    fn kept(name: &str, hash: &str) -> mazewalk_serve::records::MazeRecords {
        mazewalk_serve::records::MazeRecords {
            maze: hash.to_string(),
            name: name.to_string(),
            players: 1,
            finishes: 2,
            top: Vec::new(),
        }
    }

    /// Red-team pass 8 (local side), finding 3: the hash was sliced to its first 12 bytes, so a
    /// records file holding a short one (`abc`) or one with a multibyte character before byte 12
    /// made `records` panic (exit 101), and one holding escapes sent them to the terminal raw.
    #[test]
    fn a_maze_heading_shows_any_hash_the_file_holds_quoted() {
        let hex = "0123456789abcdef".repeat(4);
        assert_eq!(
            super::heading(&kept("a.maze", &hex)),
            "a.maze (maze 0123456789ab…): 1 player, 2 finishes"
        );
        assert_eq!(super::heading(&kept("a.maze", "abc")), "a.maze (maze abc): 1 player, 2 finishes");
        assert_eq!(
            super::heading(&kept("a.maze", "0123456789aébcdef")),
            "a.maze (maze 0123456789aé…): 1 player, 2 finishes"
        );
        let hostile = super::heading(&kept("\x1b]2;name\x07", &format!("\x1b]2;pwn\x07\x1b[8m{hex}")));
        assert!(!hostile.contains('\x1b') && !hostile.contains('\x07'), "{hostile:?}");
        assert!(hostile.starts_with("\\u{1b}]2;name\\u{7} (maze \\u{1b}]2;pwn…)"), "{hostile:?}");
    }
}
