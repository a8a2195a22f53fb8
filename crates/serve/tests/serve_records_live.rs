//! Issue #40: the records file broken while a server runs — replaced by a folder (which stops root
//! too), then deleted — while players walk into the exit: the server keeps serving, every exit box
//! ranks its finish (from memory while the file fails), the log says each change once, and the file
//! made again gets the finishes it missed first. An in-process server on loopback, russh clients, real
//! SQLite; the test stops by itself.
#![cfg(target_os = "linux")]

use mazewalk_testkit::load;

use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::PoisonError;
use std::time::{Duration, Instant};

use mazewalk_serve::records::{Keeper, Records, Sqlite, SqliteOptions, Store as _};
use mazewalk_serve::{Access, Limits, ServeOptions, Server};
use russh::ChannelMsg;

/// A corridor from the start east to the exit, 6 units away.
const SHORT_RUN: &str = "mazewalk-grid 1\ntile 4\nfacing east\n\n#####\n#@.E#\n#####\n";

/// Each test's deadline.
const DEADLINE: Duration = Duration::from_secs(120);

/// Connects as `user`, holds `w` (a key every 40 ms, as a terminal's auto-repeat) into the exit, and
/// returns the screen once the exit box shows its best times.
async fn walk_to_the_exit(addr: SocketAddr, user: &str) -> String {
    let load::Connected { handle, mut channel } =
        load::connect(addr, user, (100, 30)).await.expect("connect");
    let size = |n: u16| std::num::NonZeroU16::new(n).expect("non-zero");
    let mut screen = vt100::Parser::new(size(30), size(100), 0);
    let deadline = Instant::now() + Duration::from_secs(30);
    loop {
        assert!(
            Instant::now() < deadline,
            "{user}'s exit box: the screen shows\n{}",
            screen.screen().contents()
        );
        let _ = channel.data(&b"w"[..]).await;
        let until = tokio::time::Instant::now() + Duration::from_millis(40);
        while let Ok(message) = tokio::time::timeout_at(until, channel.wait()).await {
            match message {
                Some(ChannelMsg::Data { data }) => {
                    screen.process(&data);
                    // (answer the frames' device-attributes queries, as a terminal does)
                    for _ in 0..data.windows(3).filter(|w| *w == b"\x1b[c").count() {
                        let _ = channel.data(&b"\x1b[?62;22c"[..]).await;
                    }
                }
                Some(_) => {}
                None => panic!("{user}'s connection closed"),
            }
        }
        let text = screen.screen().contents();
        if text.contains("Best times here") && text.contains("you") {
            drop(handle);
            return text;
        }
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_records_file_broken_while_serving_neither_stops_the_game_nor_its_ranking() {
    tokio::time::timeout(DEADLINE, async {
        let dir = std::env::temp_dir().join(format!("mazewalk-records-live-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("scratch folder");
        let path: PathBuf = dir.join("records.sqlite");
        let (report, said) = mazewalk_testkit::collector();
        let (db, _) = Sqlite::open(&path, SqliteOptions::default()).expect("open the records");
        let maze = mazewalk_maze::grid::parse_str("short.grid", SHORT_RUN).expect("the maze");
        let keeper = Keeper {
            records: Records::start(db, report).expect("the records thread"),
            maze: maze.content_hash(),
            maze_name: "short.grid".into(),
        };
        let options = ServeOptions {
            records: Some(keeper),
            ..load::loopback_options(maze, Access::Open, Limits::default())
        };
        let server = Server::start(options).await.expect("start the server");
        let addr = server.local_addr();
        let lines = || said.lock().unwrap_or_else(PoisonError::into_inner).clone();

        let alice = walk_to_the_exit(addr, "alice").await;
        assert!(alice.contains("Best times here (1 player)"), "{alice}");
        // The file turns into a folder: no SQLite, no root, can write it.
        std::fs::rename(&path, dir.join("moved.sqlite")).expect("move the file");
        std::fs::create_dir(&path).expect("a folder in its place");
        let bob = walk_to_the_exit(addr, "bob").await;
        assert!(bob.contains("Best times here (2 players)"), "ranked among alice's too:\n{bob}");
        assert!(bob.contains("alice") && bob.contains("bob"), "{bob}");
        let reported = lines();
        assert_eq!(reported.len(), 2, "the change and the fault, once each: {reported:?}");
        assert!(reported[0].contains("cannot be opened again"), "{reported:?}");
        // The folder goes: a new file, made at the next finish, with bob's finish in it too.
        std::fs::remove_dir(&path).expect("remove the folder");
        let carol = walk_to_the_exit(addr, "carol").await;
        assert!(
            carol.contains("Best times here (2 players)"),
            "bob's too, not alice's (in the old file):\n{carol}"
        );
        assert!(carol.contains("bob") && !carol.contains("alice  "), "{carol}");
        assert!(
            lines().iter().any(|l| l.contains("was deleted while serving; a new one is made")),
            "{:?}",
            lines()
        );
        server.shutdown().await;
        let kept = Sqlite::open_to_read(&path).expect("the new file").mazes(None).expect("its records");
        let mut names: Vec<&str> = kept[0].top.iter().map(|b| b.player.as_str()).collect();
        names.sort_unstable();
        assert_eq!(names, ["bob", "carol"], "the finish made while it failed, kept");
        let _ = std::fs::remove_dir_all(&dir);
    })
    .await
    .expect("ran over its deadline");
}
