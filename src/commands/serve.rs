//! `mazewalk serve`: checks the maze, the host key and who may play, then hosts the maze over SSH
//! (the serve crate) until a signal ends it.

use std::process::ExitCode;

use crate::cli::ServeArgs;

/// `mazewalk serve`: checks the maze, the host key and who may play before listening, prints where and
/// how to connect, then serves until SIGINT, SIGTERM or SIGHUP (exit 128 + n, as the walk).
#[cfg(all(unix, feature = "serve"))]
pub fn run(args: &ServeArgs) -> anyhow::Result<ExitCode> {
    use std::io::Write;

    use anyhow::{Context as _, bail};
    use mazewalk_render::RenderOptions;
    use mazewalk_serve::recording::RecordOptions;
    use mazewalk_serve::shared::{Bounds, Caps, WorldConfig};
    use mazewalk_serve::{Access, Limits, ServeOptions, host_key};
    use mazewalk_walk::App;

    use super::{Usage, load_maze};
    use crate::guard;
    let maze = load_maze(&args.maze)?;
    // Paths the host named: their folders must be there (a typo must not make a tree), said
    // before anything is made.
    if let (Some(path), false, None) = (&args.records, args.no_records, &args.world)
        && let Some(dir) = missing_folder(path)
    {
        return Err(Usage(format!(
            "--records {}: no folder {} (it is not made: make it first)",
            path.display(),
            dir.display()
        ))
        .into());
    }
    if let Some(dir) = args.record_dir.as_deref().filter(|d| !d.is_dir())
        && let Some(parent) = missing_folder(dir)
    {
        return Err(Usage(format!(
            "--record-dir {}: no folder {} (only DIR itself is made)",
            dir.display(),
            parent.display()
        ))
        .into());
    }
    App::new(maze.clone(), RenderOptions::default(), 0.0)?; // a start in no cell fails here, not per player
    let env = |k: &str| std::env::var(k).ok();
    let key_path = match &args.host_key {
        Some(path) => path.clone(),
        None => host_key::default_path(env)?,
    };
    let (host_key, made) = host_key::load_or_create(&key_path).context("host key")?;
    let access = if args.open {
        Access::Open
    } else {
        let path = match &args.authorized_keys {
            Some(path) => path.clone(),
            None => std::path::PathBuf::from(env("HOME").unwrap_or_default()).join(".ssh/authorized_keys"),
        };
        let read = host_key::read_authorized_keys(&path)
            .with_context(|| "who may play (give --authorized-keys FILE, or --open to let anyone in)")?;
        // (The comments, options and reasons hold the file's text: quoted, control characters escaped.)
        let quote = mazewalk_maze::quote;
        for skipped in &read.skipped {
            let _ = writeln!(
                std::io::stderr(),
                "mazewalk: {}:{}: skipped: {}",
                path.display(),
                skipped.line,
                skipped.why
            );
        }
        for left in &read.left_out {
            let _ = writeln!(
                std::io::stderr(),
                "mazewalk: {}:{}: the key of {} is limited by `{}`, which mazewalk does not enforce: it may not play",
                path.display(),
                left.line,
                quote(&left.comment),
                quote(&left.option)
            );
        }
        if read.keys.is_empty() {
            bail!("{}: no keys that may play, so nobody could (add some, or use --open)", path.display());
        }
        Access::Keys(read.keys)
    };
    let fingerprint = host_key::fingerprint(host_key.public_key());
    let listen = resolve("--listen", &args.listen)?;
    let http = match &args.http {
        Some(http) => {
            let addr = *resolve("--http", http)?.first().expect("resolve gives at least one address");
            Some((addr, super::public_maze_name(&args.maze)))
        }
        None => None,
    };
    let limits = Limits {
        max_players: args.max_players as usize,
        max_spectators: args.max_spectators as usize,
        max_spectators_per_address: args.max_spectators_per_address as usize,
        max_handshakes: args.max_handshakes as usize,
        max_per_address: args.max_per_address as usize,
        render_total: args.render_total.unwrap_or_else(mazewalk_serve::limits::render_total_default),
        idle_timeout: args.idle_timeout,
        ..Limits::default()
    };
    let log = tracing_subscriber::fmt().with_writer(std::io::stderr).with_target(false);
    match args.log_format {
        crate::cli::LogFormat::Text => log.init(),
        crate::cli::LogFormat::Json => log.event_format(mazewalk_serve::logs::JsonLines).init(),
    }
    let world = match &args.world {
        None => None,
        Some(url) => {
            let ca = args.world_ca.as_deref().map(super::read_world_ca).transpose()?;
            // A URL that is not Redis's, or a CA for one without TLS, is a bad flag value (exit 2),
            // told before listening; the link connects to nothing here.
            mazewalk_serve::shared::redis::Link::new(url, "", ca.as_deref())
                .map_err(|e| Usage(e.to_string()))?;
            let caps =
                Caps { servers: args.max_remote_servers as usize, players: args.max_remote_players as usize };
            Some(WorldConfig {
                ca,
                caps,
                ..WorldConfig::new(url, &maze.content_hash().to_string(), Bounds::of(&maze))
            })
        }
    };
    let records = match (&world, args.no_records) {
        (_, true) => None,
        // (the world's records are read by every server's host: the file's name, not its folders)
        (Some(world), false) => keep_world_records(world, &maze, super::public_maze_name(&args.maze)),
        (None, false) => {
            let path = args.records.clone().unwrap_or_else(|| key_path.with_file_name("records.sqlite"));
            keep_records(&path, &maze, super::maze_name(&args.maze))
        }
    };
    let mut record_dir_made = false;
    let record = match &args.record_dir {
        None => None,
        Some(dir) => {
            if args.record_max_bytes < 1024 {
                return Err(Usage(format!(
                    "--record-max-bytes {}: at least 1K (a cast's header alone takes hundreds)",
                    args.record_max_bytes
                ))
                .into());
            }
            if args.record_max_total < args.record_max_bytes {
                return Err(Usage(format!(
                    "--record-max-total {} is less than --record-max-bytes {}: not even one cast would fit",
                    args.record_max_total, args.record_max_bytes
                ))
                .into());
            }
            if !dir.is_dir() {
                if let Ok(there) = std::fs::symlink_metadata(dir) {
                    // (made, it would fail "File exists", a message that does not say what to fix)
                    return Err(Usage(format!(
                        "--record-dir {}: {} is there, not a folder",
                        dir.display(),
                        not_a_folder(there.file_type())
                    ))
                    .into());
                }
                // the last component only (its folder was checked above), private as the casts
                use std::os::unix::fs::DirBuilderExt as _;
                std::fs::DirBuilder::new()
                    .mode(0o700)
                    .create(dir)
                    .with_context(|| format!("--record-dir {}", dir.display()))?;
                record_dir_made = true;
            }
            Some(RecordOptions {
                dir: dir.clone(),
                max_bytes: args.record_max_bytes,
                max_total: args.record_max_total,
                max_per_address: args.record_max_per_address as usize,
                max_files: args.record_max_files as usize,
            })
        }
    };
    let options = ServeOptions { maze, listen, host_key, access, limits, records: records.clone(), record };
    let announced = std::cell::Cell::new(false);
    let served = mazewalk_serve::run_with(options, world, http, |addrs, http| {
        announced.set(true);
        let made = if made { ", made now" } else { "" };
        let list: Vec<String> = addrs.iter().map(ToString::to_string).collect();
        let addr = addrs[0];
        // for the host to read; a closed pipe (`serve | head -1`) must not end the server
        let mut out = std::io::stdout().lock();
        let _ = writeln!(out, "mazewalk: serving on {}", list.join(", "))
            .and_then(|()| writeln!(out, "host key {fingerprint} ({}{made})", key_path.display()))
            .and_then(|()| {
                // Listening on every address: the players need one of this machine's names.
                let host = match addr.ip() {
                    ip if ip.is_unspecified() => "THIS-HOST".to_string(),
                    std::net::IpAddr::V6(ip) => format!("{ip}"),
                    ip => ip.to_string(),
                };
                writeln!(out, "players connect with: ssh -p {} {host}", addr.port())?;
                if args.max_spectators > 0 {
                    writeln!(out, "spectators watch with: ssh -p {} watch@{host}", addr.port())?;
                }
                Ok(())
            })
            .and_then(|()| match http {
                Some(http) => {
                    writeln!(out, "status page at http://{http}/\nmetrics at http://{http}/metrics")
                }
                None => Ok(()),
            })
            .and_then(|()| match &args.record_dir {
                Some(dir) => {
                    let made = if record_dir_made { ", made now" } else { "" };
                    writeln!(
                        out,
                        "recording each player's session in {}{made} (their HUD says so)",
                        dir.display()
                    )
                }
                None => Ok(()),
            })
            .and_then(|()| out.flush());
    });
    // (its errors say what failed: "cannot listen on 127.0.0.1:2222: Address already in use")
    let signal = served.inspect_err(|_| {
        if made && !announced.get() {
            // A start that failed before it served leaves no key it made: the next start makes
            // one and says so ("made now"), rather than serving a key its host was never told of.
            let _ = std::fs::remove_file(&key_path);
        }
    })?;
    if let Some(keeper) = records {
        // The finishes handed over before the end are written (a few at most; bounded anyway).
        let _ = keeper.records.close(std::time::Duration::from_secs(3));
    }
    Ok(ExitCode::from(u8::try_from(guard::exit_code_for_signal(signal)).unwrap_or(1)))
}

/// The folder `path` would be in, when there is none (`a/b` for `a/b/c`; a bare name is in the
/// working folder, which is there).
#[cfg(all(unix, feature = "serve"))]
fn missing_folder(path: &std::path::Path) -> Option<&std::path::Path> {
    path.parent().filter(|d| !d.as_os_str().is_empty() && !d.is_dir())
}

/// The records of `maze` in the SQLite file at `path`, on their thread; what fails is said and the
/// server goes on without records (a damaged file is kept aside and a new one made).
#[cfg(all(unix, feature = "serve"))]
fn keep_records(
    path: &std::path::Path,
    maze: &mazewalk_maze::Maze,
    name: String,
) -> Option<mazewalk_serve::records::Keeper> {
    use mazewalk_serve::records::{Keeper, Race, Records, Report, Sqlite, SqliteOptions};
    let (db, aside) = match Sqlite::open(path, SqliteOptions::default()) {
        Ok(opened) => opened,
        Err(err) => {
            tracing::warn!("records: {err}; serving without records");
            return None;
        }
    };
    if let Some(aside) = aside {
        tracing::warn!(
            "records: {} was damaged: kept as {}; a new one is made",
            path.display(),
            aside.display()
        );
    }
    let report: Report = std::sync::Arc::new(|line: &str| tracing::warn!("{line}"));
    let hash = maze.content_hash();
    // the maze's best run, offered to its players as a ghost (`g`)
    let race = Race { maze: hash, extents: maze.extents() };
    match Records::start_racing(db, report, Some(race)) {
        Ok(records) => Some(Keeper { records, maze: hash, maze_name: name }),
        Err(err) => {
            tracing::warn!("records: cannot start their thread: {err}; serving without records");
            None
        }
    }
}

/// The records of `maze` in the shared world's Redis (`--world`), on their thread; what fails is
/// said and the server goes on without records.
#[cfg(all(unix, feature = "serve"))]
fn keep_world_records(
    world: &mazewalk_serve::shared::WorldConfig,
    maze: &mazewalk_maze::Maze,
    name: String,
) -> Option<mazewalk_serve::records::Keeper> {
    use mazewalk_serve::records::{Keeper, Race, Records, Report};
    use mazewalk_serve::shared::records::RedisStore;
    let hash = maze.content_hash();
    let store = match RedisStore::new(&world.url, world.ca.as_deref(), hash) {
        Ok(store) => store,
        Err(err) => {
            tracing::warn!("records: {err}; serving without records");
            return None;
        }
    };
    let report: Report = std::sync::Arc::new(|line: &str| tracing::warn!("{line}"));
    let race = Race { maze: hash, extents: maze.extents() };
    match Records::start_racing(store, report, Some(race)) {
        Ok(records) => Some(Keeper { records, maze: hash, maze_name: name }),
        Err(err) => {
            tracing::warn!("records: cannot start their thread: {err}; serving without records");
            None
        }
    }
}

/// The addresses of `flag`'s value `listen` (a host name's, looked up now).
#[cfg(all(unix, feature = "serve"))]
fn resolve(flag: &str, listen: &str) -> anyhow::Result<Vec<std::net::SocketAddr>> {
    use std::net::ToSocketAddrs as _;
    let mut addrs: Vec<std::net::SocketAddr> = listen
        .to_socket_addrs()
        .map_err(|e| anyhow::anyhow!("{flag} {}: cannot look it up: {e}", mazewalk_maze::quote(listen)))?
        .collect();
    addrs.dedup();
    anyhow::ensure!(!addrs.is_empty(), "{flag} {}: the name has no addresses", mazewalk_maze::quote(listen));
    Ok(addrs)
}

/// Without `serve` (or off Unix): says why it cannot.
#[cfg(not(all(unix, feature = "serve")))]
pub fn run(_: &ServeArgs) -> anyhow::Result<ExitCode> {
    if cfg!(unix) {
        anyhow::bail!(
            "this mazewalk was built without `serve` (build it with the default features to host a maze)"
        );
    }
    anyhow::bail!("`mazewalk serve` runs on Unix only");
}

/// What is at a path that is not a folder, as `--record-dir` says it.
fn not_a_folder(kind: std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt as _;
    if kind.is_symlink() {
        "a symbolic link to no folder"
    } else if kind.is_fifo() {
        "a FIFO"
    } else if kind.is_socket() {
        "a socket"
    } else if kind.is_block_device() || kind.is_char_device() {
        "a device"
    } else {
        "a file"
    }
}
