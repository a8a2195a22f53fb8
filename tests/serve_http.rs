//! End to end: `mazewalk serve --http 127.0.0.1:0 --log-format json` (the built binary), scraped over
//! loopback, while a real `ssh -tt` player (`tests/common`'s: in a pty, answering the
//! device-attributes queries as a terminal does) joins, walks and quits. Checks: `/metrics` counts the join, the frames, the bytes and
//! the key-to-frame times, and the player leaving; Prometheus' own `promtool check metrics` accepts the
//! text (when promtool is on PATH: Debian's `prometheus` package); every log line is one JSON object
//! with the player's address and name; hostile HTTP gets 4xx (unknown path, other methods, a head
//! too large) and a client that never finishes its head is cut; past the connection cap a newcomer is
//! closed at once; the key exchange's CPU time is clocked. And the status page in a headless Chromium
//! (Debian's `chromium`, when on PATH), loaded once and driven over the DevTools protocol: two ssh
//! players shown, each step they take in the page's DOM within 1 s (the median), nothing logged to
//! the console, nothing refused by the page's Content-Security-Policy, and a handler injected into
//! the page refused by it. A maze file's folders reach no visitor and no player: the page, the JSON,
//! the metrics, the events and the player's terminal name the file alone. Every wait has a
//! deadline; the children are killed on drop.
#![cfg(unix)]

use std::fs::File;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use mazewalk_serve::http::{HEADER_TIMEOUT, MAX_CONNECTIONS, MAX_EVENT_CLIENTS, MAX_HEAD_BYTES};

mod common;
use common::{Player, TIMEOUT, lock};

/// The server and a scratch folder, both gone on drop.
struct Serve {
    child: Child,
    ssh_port: u16,
    /// The host key's fingerprint, as the server printed it.
    host_key: String,
    http: SocketAddr,
    log: Arc<Mutex<String>>,
    dir: PathBuf,
}

impl Serve {
    /// Starts a server of the built-in maze whose scratch folder is named after `test`.
    fn start(test: &str) -> Serve {
        Serve::start_with(test, |_| Vec::new())
    }

    /// Starts a server whose scratch folder is named after `test`, with the arguments `more` gives
    /// for that folder (a maze file it put there, say).
    fn start_with(test: &str, more: impl FnOnce(&std::path::Path) -> Vec<std::ffi::OsString>) -> Serve {
        let dir = std::env::temp_dir().join(format!("mazewalk-serve-http-{test}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("scratch folder");
        let more = more(&dir);
        let mut child = Command::new(env!("CARGO_BIN_EXE_mazewalk"))
            .args([
                "serve",
                "--open",
                "--listen",
                "127.0.0.1:0",
                "--http",
                "127.0.0.1:0",
                "--log-format",
                "json",
            ])
            .args(more)
            .arg("--host-key")
            .arg(dir.join("host_key"))
            .arg("--records")
            .arg(dir.join("records.sqlite"))
            .env("HOME", &dir)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start mazewalk serve");
        let stdout = BufReader::new(child.stdout.take().expect("stdout"));
        let (mut ssh_port, mut http, mut host_key) = (None, None, None);
        for line in stdout.lines() {
            let line = line.expect("a line of stdout");
            if let Some(rest) = line.strip_prefix("host key ") {
                host_key = rest.split_whitespace().next().map(str::to_string);
            }
            if let Some(rest) = line.strip_prefix("mazewalk: serving on ") {
                ssh_port = rest.rsplit_once(':').and_then(|(_, p)| p.parse::<u16>().ok());
            }
            if let Some(rest) = line.strip_prefix("metrics at http://") {
                http = rest.strip_suffix("/metrics").and_then(|a| a.parse().ok());
                break;
            }
        }
        let log = Arc::new(Mutex::new(String::new()));
        let stderr = child.stderr.take().expect("stderr");
        let sink = Arc::clone(&log);
        std::thread::spawn(move || {
            for line in BufReader::new(stderr).lines() {
                let Ok(line) = line else { break };
                lock(&sink).push_str(&(line + "\n"));
            }
        });
        Serve {
            child,
            ssh_port: ssh_port.expect("the SSH port on stdout"),
            host_key: host_key.expect("`host key SHA256:…` on stdout"),
            http: http.expect("`metrics at http://ADDR/metrics` on stdout"),
            log,
            dir,
        }
    }

    /// One HTTP request (`request` is its whole head and body); the whole answer.
    fn answer(&self, request: &[u8]) -> String {
        let mut stream = TcpStream::connect(self.http).expect("connect to --http");
        stream.set_read_timeout(Some(TIMEOUT)).expect("timeout");
        stream.write_all(request).expect("send the request");
        let mut answer = Vec::new();
        let _ = stream.read_to_end(&mut answer);
        String::from_utf8_lossy(&answer).into_owned()
    }

    /// One HTTP request (`request` is its whole head and body); the status and the body.
    fn http(&self, request: &[u8]) -> (u16, String) {
        let answer = self.answer(request);
        let status = answer.split(' ').nth(1).and_then(|s| s.parse().ok()).unwrap_or(0);
        let body = answer.split_once("\r\n\r\n").map(|(_, b)| b.to_string()).unwrap_or_default();
        (status, body)
    }

    fn scrape(&self) -> String {
        let (status, body) =
            self.http(b"GET /metrics HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n\r\n");
        assert_eq!(status, 200, "{body}");
        body
    }

    /// The value of the sample named exactly `name` (labels included) in the last scrape.
    fn value(&self, name: &str) -> f64 {
        let text = self.scrape();
        text.lines()
            .find_map(|l| l.strip_prefix(name).and_then(|rest| rest.strip_prefix(' ')))
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("no sample {name} in:\n{text}"))
    }

    /// Waits until `name`'s value satisfies `ok`.
    fn wait_value(&self, name: &str, ok: impl Fn(f64) -> bool) -> f64 {
        let deadline = Instant::now() + TIMEOUT;
        loop {
            let value = self.value(name);
            if ok(value) {
                return value;
            }
            assert!(Instant::now() < deadline, "{name} stayed at {value}");
            std::thread::sleep(Duration::from_millis(50));
        }
    }
}

/// An event stream from `/events`, read as it comes.
struct Events {
    lines: BufReader<TcpStream>,
}

impl Events {
    fn open(addr: SocketAddr) -> Events {
        let mut stream = TcpStream::connect(addr).expect("connect to --http");
        stream.set_read_timeout(Some(TIMEOUT)).expect("timeout");
        stream.write_all(b"GET /events HTTP/1.1\r\nHost: localhost\r\n\r\n").expect("ask for events");
        Events { lines: BufReader::new(stream) }
    }

    /// The status line.
    fn status(&mut self) -> String {
        let mut line = String::new();
        self.lines.read_line(&mut line).expect("the status line");
        line.trim().to_string()
    }

    /// The next event's data that satisfies `ok`.
    fn next(&mut self, ok: impl Fn(&serde_json::Value) -> bool) -> serde_json::Value {
        let deadline = Instant::now() + TIMEOUT;
        let mut last = serde_json::Value::Null;
        loop {
            assert!(Instant::now() < deadline, "no such event; the last: {last}");
            let mut line = String::new();
            assert!(self.lines.read_line(&mut line).expect("an event") > 0, "the stream ended");
            if let Some(data) = line.trim_end().strip_prefix("data: ") {
                let event: serde_json::Value = serde_json::from_str(data).expect("an event's JSON");
                last.clone_from(&event);
                if ok(&event) {
                    return event;
                }
            }
        }
    }
}

impl Drop for Serve {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

#[test]
fn metrics_follow_a_real_player_and_the_listener_stays_bounded() {
    let serve = Serve::start("metrics");
    assert_eq!(serve.value("mazewalk_joins_total"), 0.0);
    assert_eq!(serve.value("mazewalk_players"), 0.0);

    let mut player = Player::connect(serve.ssh_port, None, "walker", 80, 24);
    serve.wait_value("mazewalk_players", |v| v == 1.0);
    assert_eq!(serve.value("mazewalk_joins_total"), 1.0);
    let frames = serve.wait_value("mazewalk_frames_sent_total", |v| v > 0.0);
    let bytes = serve.value("mazewalk_sent_bytes_total");
    assert!(bytes > 1000.0, "a frame is more than a few bytes: {bytes}");
    // The player's key exchange, clocked once: some CPU time, far below a second.
    assert_eq!(serve.value("mazewalk_handshake_cpu_seconds_count"), 1.0, "one connection, one exchange");
    let kex = serve.value("mazewalk_handshake_cpu_seconds_sum");
    assert!(kex > 0.0 && kex < 1.0, "the key exchange took {kex} s of CPU");
    // Keys, a pause between them so that each gets a frame of its own.
    for _ in 0..3 {
        player.send(b"\x1b[A");
        std::thread::sleep(Duration::from_millis(150));
    }
    serve.wait_value("mazewalk_key_to_frame_seconds_count", |v| v >= 1.0);

    // The status page, the maze and the players live.
    let (status, page) = serve.http(b"GET / HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
    assert_eq!(status, 200);
    assert!(
        page.contains("new EventSource(\"/events\")")
            && !page.contains("http://")
            && !page.contains("https://"),
        "{page}"
    );
    // Red-team pass 18: no script or style runs on the page but its own, named by hash; no frame
    // holds it, no type is guessed, no referrer is sent.
    let answer = serve.answer(b"GET / HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
    let head = answer.split_once("\r\n\r\n").map_or("", |(head, _)| head).to_ascii_lowercase();
    for header in [
        "content-security-policy: default-src 'none'; script-src 'sha256-",
        "; style-src 'sha256-",
        "; frame-ancestors 'none'",
        "x-content-type-options: nosniff",
        "referrer-policy: no-referrer",
        "x-frame-options: deny",
    ] {
        assert!(head.contains(header) && !head.contains("unsafe"), "{header} in {head}");
    }
    let (status, maze) = serve.http(b"GET /maze.json HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
    assert_eq!(status, 200);
    let maze: serde_json::Value = serde_json::from_str(&maze).expect("the maze's JSON");
    assert!(maze["walls"].as_array().is_some_and(|w| w.len() > 10), "{maze}");
    assert_eq!(maze["name"], mazewalk_maze::BUILTIN_NAME, "the maze as the host named it");
    // How to join: the SSH port and the host key a newcomer's `ssh` will show.
    assert_eq!(maze["ssh_port"], serve.ssh_port, "{maze}");
    assert_eq!(maze["host_key"], serve.host_key.as_str(), "{maze}");
    assert!(serve.host_key.starts_with("SHA256:"), "{}", serve.host_key);
    // issue #43: no finish yet, no best run's path
    let (status, best) = serve.http(b"GET /best-run.json HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
    assert_eq!((status, best.as_str()), (200, r#"{"path":[]}"#));
    let mut events = Events::open(serve.http);
    assert_eq!(events.status(), "HTTP/1.1 200 OK");
    let walker = |e: &serde_json::Value| {
        e["players"].as_array().is_some_and(|p| p.len() == 1 && p[0]["name"] == "walker")
    };
    let first = events.next(walker)["players"][0].clone();
    let step = Instant::now();
    player.send(b"\x1b[D"); // turn left
    let turned = events.next(|e| walker(e) && e["players"][0]["heading"] != first["heading"]);
    eprintln!("the page heard a turn in {:?}: {first} -> {}", step.elapsed(), turned["players"][0]);
    // The streams are capped: past the cap, 503.
    let mut streams: Vec<Events> = (1..MAX_EVENT_CLIENTS).map(|_| Events::open(serve.http)).collect();
    for stream in &mut streams {
        assert_eq!(stream.status(), "HTTP/1.1 200 OK");
    }
    assert_eq!(Events::open(serve.http).status(), "HTTP/1.1 503 Service Unavailable");
    drop(streams);
    drop(events);
    assert!(serve.value("mazewalk_frames_sent_total") > frames, "the keys brought frames");
    assert!(serve.value("mazewalk_key_to_frame_seconds_sum") < 3.0 * TIMEOUT.as_secs_f64());
    assert!(player.raw().len() > 1000, "the player saw the game");

    // Prometheus' own parser and linter, when installed.
    let text = serve.scrape();
    match Command::new("promtool")
        .args(["check", "metrics"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
    {
        Ok(mut promtool) => {
            promtool.stdin.take().expect("stdin").write_all(text.as_bytes()).expect("feed promtool");
            let out = promtool.wait_with_output().expect("promtool");
            assert!(
                out.status.success(),
                "promtool check metrics: {}{}\n{text}",
                String::from_utf8_lossy(&out.stdout),
                String::from_utf8_lossy(&out.stderr)
            );
        }
        Err(err) => eprintln!("promtool not run ({err}): install Debian's `prometheus` for it"),
    }

    player.send(b"q");
    player.wait_exit();
    serve.wait_value("mazewalk_players", |v| v == 0.0);

    // The log: one JSON object a line, the player's lines with its address and name.
    let deadline = Instant::now() + TIMEOUT;
    while !lock(&serve.log).contains("\"disconnected\"") {
        assert!(Instant::now() < deadline, "no disconnect line:\n{}", lock(&serve.log));
        std::thread::sleep(Duration::from_millis(20));
    }
    let log = lock(&serve.log).clone();
    let lines: Vec<serde_json::Value> =
        log.lines().map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{e}: {l:?}"))).collect();
    let connected = lines.iter().find(|l| l["event"] == "connected").expect("a connected line");
    assert_eq!(connected["player"], "walker");
    assert!(connected["address"].as_str().is_some_and(|a| a.starts_with("127.0.0.1:")), "{connected}");
    assert!(lines.iter().all(|l| l["time"].is_string() && l["level"].is_string()), "{log}");
    let disconnected = lines.iter().find(|l| l["event"] == "disconnected").expect("a disconnected line");
    assert!(
        disconnected["seconds"].is_f64() && disconnected["bytes_out"].is_u64(),
        "numbers: {disconnected}"
    );

    // Hostile HTTP: 4xx, and the server goes on.
    let (status, _) = serve.http(b"GET /../../etc/passwd HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
    assert_eq!(status, 404);
    let (status, _) =
        serve.http(b"POST /metrics HTTP/1.1\r\nHost: x\r\nContent-Length: 3\r\nConnection: close\r\n\r\nabc");
    assert_eq!(status, 405);
    let big = format!(
        "GET /metrics HTTP/1.1\r\nHost: x\r\nX-Big: {}\r\nConnection: close\r\n\r\n",
        "a".repeat(2 * MAX_HEAD_BYTES)
    );
    let (status, _) = serve.http(big.as_bytes());
    assert_eq!(status, 431, "a head too large");
    let (status, _) = serve.http(b"\x16\x03\x01\x02\x00garbage\r\n\r\n");
    assert_eq!(status, 400, "not HTTP");
    // HEAD: the GET's head, the length of its body included, and no body.
    for path in ["/", "/maze.json", "/nowhere"] {
        let (_, body) =
            serve.http(format!("GET {path} HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n").as_bytes());
        let answer =
            serve.answer(format!("HEAD {path} HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n").as_bytes());
        let (head, rest) = answer.split_once("\r\n\r\n").expect("a head");
        let length = head
            .lines()
            .find_map(|l| l.to_ascii_lowercase().strip_prefix("content-length: ").map(str::to_owned));
        assert_eq!(length, Some(body.len().to_string()), "HEAD {path}: {head}");
        assert!(rest.is_empty(), "HEAD {path} sent a body");
    }

    // Slow clients: every connection slot held by a head that never ends; the next is closed at
    // once, and the holders are cut after the header timeout, leaving room again.
    let started = Instant::now();
    let holders: Vec<TcpStream> = (0..MAX_CONNECTIONS)
        .map(|_| {
            let mut s = TcpStream::connect(serve.http).expect("connect");
            s.write_all(b"GET /metrics HTTP/1.1\r\nHost: x\r\n").expect("half a head");
            s
        })
        .collect();
    std::thread::sleep(Duration::from_millis(300)); // (all accepted)
    let mut late = TcpStream::connect(serve.http).expect("connect");
    late.set_read_timeout(Some(TIMEOUT)).expect("timeout");
    let _ = late.write_all(b"GET /metrics HTTP/1.1\r\nHost: x\r\n\r\n");
    let mut answer = Vec::new();
    let _ = late.read_to_end(&mut answer);
    assert!(answer.is_empty(), "past the cap, closed unanswered: {:?}", String::from_utf8_lossy(&answer));
    for mut holder in holders {
        holder.set_read_timeout(Some(TIMEOUT)).expect("timeout");
        let mut sink = Vec::new();
        let _ = holder.read_to_end(&mut sink); // closed by the server (with a 408, or without a word)
    }
    let waited = started.elapsed();
    assert!(waited >= HEADER_TIMEOUT && waited < HEADER_TIMEOUT + TIMEOUT, "{waited:?}");
    assert_eq!(serve.value("mazewalk_players"), 0.0, "and /metrics answers again");
}

/// Red-team pass 18: `/maze.json` and so the status page named the maze by its path as given to
/// `serve` (`/home/alice/private/…`), telling anyone who could reach the page the host's folders.
/// They show the file's name now; nothing else a visitor or a player gets holds its folders: the
/// page (and, in Chromium when on PATH, what its script shows), `/metrics`, `/best-run.json`, an
/// event, a player's terminal (the game and its help).
#[test]
fn the_maze_files_folders_reach_no_visitor_and_no_player() {
    const FOLDER: &str = "alices-private-mazes";
    let serve = Serve::start_with("path", |dir| {
        let maze = dir.join(FOLDER).join("tiny.maze");
        std::fs::create_dir_all(dir.join(FOLDER)).expect("the maze's folder");
        std::fs::copy(concat!(env!("CARGO_MANIFEST_DIR"), "/mazes/tiny.maze"), &maze).expect("a maze");
        vec![maze.into_os_string()]
    });
    let get = |path: &str| {
        let request = format!("GET {path} HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
        let (status, body) = serve.http(request.as_bytes());
        assert_eq!(status, 200, "{path}: {body}");
        body
    };
    let maze: serde_json::Value = serde_json::from_str(&get("/maze.json")).expect("the maze's JSON");
    assert_eq!(maze["name"], "tiny.maze", "the file's name, without its folders: {}", maze["name"]);
    let mut player = Player::connect(serve.ssh_port, None, "walker", 80, 24);
    player.wait_for("the game", common::playing);
    let game = player.read(vt100::Screen::contents);
    player.send(b"?");
    player.wait_for("the help", |screen, _| screen.contents().contains("Keys"));
    let help = player.read(vt100::Screen::contents);
    let event = Events::open(serve.http).next(|e| e["players"].as_array().is_some_and(|p| p.len() == 1));
    let raw = String::from_utf8_lossy(&player.raw()).into_owned();
    for (what, text) in [
        ("/", get("/")),
        ("/metrics", get("/metrics")),
        ("/best-run.json", get("/best-run.json")),
        ("an event", event.to_string()),
        ("the game's screen", game),
        ("the help", help),
        ("the player's terminal", raw),
    ] {
        assert!(!text.contains(FOLDER), "{what} names the maze's folder: {text}");
    }
    let Some(chromium) = chromium() else {
        eprintln!("chromium not on PATH: the status page was not checked in a browser");
        return;
    };
    let mut browser = Browser::open(chromium, &serve.dir.join("profile"), &format!("http://{}/", serve.http));
    let deadline = Instant::now() + TIMEOUT;
    while browser.eval("document.getElementById('name')?.textContent") != "mazewalk: tiny.maze" {
        assert!(Instant::now() < deadline, "the page's heading: {}", browser.eval("document.body.innerText"));
        std::thread::sleep(Duration::from_millis(20));
    }
    let shown = browser.eval("document.title + document.documentElement.outerHTML + document.body.innerText");
    assert!(!shown.to_string().contains(FOLDER), "the page shows the maze's folder: {shown}");
    assert!(browser.console.is_empty(), "the page logged: {:?}", browser.console);
    assert_eq!(browser.violations(), Vec::<String>::new(), "the policy refused some of the page");
}

/// The browser's window, as the README's picture shows the page.
const WINDOW: &str = "960,540";

/// The Chromium on PATH (Debian's `chromium`), if any.
fn chromium() -> Option<&'static str> {
    ["chromium", "chromium-browser"]
        .into_iter()
        .find(|c| Command::new(c).arg("--version").output().is_ok_and(|o| o.status.success()))
}

/// A headless Chromium's screenshot of `url` (a page load of its own): its pixels' RGB, and what
/// Chromium logged (the page's console among it).
fn screenshot(chromium: &str, url: &str, png: &std::path::Path) -> (Vec<[u8; 3]>, String) {
    let out = Command::new(chromium)
        .args([
            "--headless=new",
            "--no-sandbox",
            "--disable-gpu",
            "--hide-scrollbars",
            "--enable-logging=stderr",
        ])
        .args(["--v=0", &format!("--window-size={WINDOW}"), "--timeout=3000"])
        .arg(format!("--screenshot={}", png.display()))
        .arg(url)
        .stdin(Stdio::null())
        .output()
        .expect("run chromium");
    let log = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "chromium: {log}");
    let decoder = png::Decoder::new(BufReader::new(File::open(png).expect("the screenshot")));
    let mut reader = decoder.read_info().expect("a PNG");
    let mut buf = vec![0; reader.output_buffer_size().expect("its size")];
    let info = reader.next_frame(&mut buf).expect("its pixels");
    let channels = info.color_type.samples();
    assert!(channels >= 3, "{:?}", info.color_type);
    let mut pixels = Vec::new();
    for y in 0..info.height {
        let row = &buf[y as usize * info.line_size..][..info.line_size];
        pixels.extend(
            (0..info.width as usize)
                .map(|x| [row[x * channels], row[x * channels + 1], row[x * channels + 2]]),
        );
    }
    (pixels, log)
}

/// How many of `pixels` are exactly `rgb`.
fn count(pixels: &[[u8; 3]], rgb: [u8; 3]) -> usize {
    pixels.iter().filter(|&&p| p == rgb).count()
}

/// A CSS colour as `getComputedStyle` gives it, `rgb(R, G, B)`.
fn css_rgb(css: &str) -> [u8; 3] {
    let inner = css.trim().strip_prefix("rgb(").and_then(|s| s.strip_suffix(')')).expect("rgb(…)");
    let parts: Vec<u8> = inner.split(',').map(|p| p.trim().parse().expect("a channel")).collect();
    parts.try_into().expect("three channels")
}

/// A headless Chromium with one page open, driven over the DevTools protocol on a pipe
/// (`--remote-debugging-pipe`: JSON messages, each ended by a NUL, on the browser's descriptors 3
/// and 4 — here its stdin and stdout, moved there by `sh`). The page stays loaded: what it shows
/// later came to it live. Killed on drop.
struct Browser {
    child: Child,
    to: std::process::ChildStdin,
    from: BufReader<std::process::ChildStdout>,
    /// The page's session.
    session: String,
    next_id: u64,
    /// What the page reported: console calls, uncaught exceptions, log entries.
    console: Vec<String>,
}

impl Browser {
    /// Opens `url` in a new headless Chromium whose profile lives in `dir`.
    fn open(chromium: &str, dir: &std::path::Path, url: &str) -> Browser {
        let mut child = Command::new("sh")
            .args(["-c", r#"exec "$0" "$@" 3<&0 4>&1 0</dev/null 1>/dev/null"#, chromium])
            .args(["--headless=new", "--no-sandbox", "--disable-gpu", "--hide-scrollbars"])
            .args(["--remote-debugging-pipe", &format!("--window-size={WINDOW}")])
            .arg(format!("--user-data-dir={}", dir.display()))
            .arg("about:blank")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("start chromium");
        let to = child.stdin.take().expect("a piped stdin");
        let from = BufReader::new(child.stdout.take().expect("a piped stdout"));
        let mut browser =
            Browser { child, to, from, session: String::new(), next_id: 0, console: Vec::new() };
        let deadline = Instant::now() + TIMEOUT;
        let page = loop {
            let targets = browser.call(None, "Target.getTargets", serde_json::json!({}));
            let page = targets["targetInfos"].as_array().and_then(|t| {
                t.iter()
                    .find(|t| t["type"] == "page")
                    .and_then(|t| t["targetId"].as_str())
                    .map(str::to_string)
            });
            if let Some(page) = page {
                break page;
            }
            assert!(Instant::now() < deadline, "no page in {targets}");
            std::thread::sleep(Duration::from_millis(50));
        };
        let attached = browser.call(
            None,
            "Target.attachToTarget",
            serde_json::json!({ "targetId": page, "flatten": true }),
        );
        browser.session = attached["sessionId"].as_str().expect("a session").to_string();
        // Everything the page reports from the first byte on, then the page. What its policy
        // refuses goes to `__violations` too (from a script of the browser's, not the page's: the
        // policy does not bind it), as the directive and what it refused.
        browser.call_page("Runtime.enable", serde_json::json!({}));
        browser.call_page("Log.enable", serde_json::json!({}));
        browser.call_page("Page.enable", serde_json::json!({}));
        browser.call_page(
            "Page.addScriptToEvaluateOnNewDocument",
            serde_json::json!({ "source": "window.__violations = []; document.addEventListener(\
                'securitypolicyviolation', e => __violations.push(e.effectiveDirective + ' ' + e.blockedURI));" }),
        );
        browser.call_page("Page.navigate", serde_json::json!({ "url": url }));
        browser
    }

    /// Sends a command (to the page's `session`, or the browser's) and returns its result; events
    /// met meanwhile are kept where they say something about the page.
    fn call(&mut self, session: Option<&str>, method: &str, params: serde_json::Value) -> serde_json::Value {
        self.next_id += 1;
        let id = self.next_id;
        let mut message = serde_json::json!({ "id": id, "method": method, "params": params });
        if let Some(session) = session {
            message["sessionId"] = session.into();
        }
        let mut bytes = message.to_string().into_bytes();
        bytes.push(0);
        self.to.write_all(&bytes).expect("write to chromium");
        loop {
            let mut raw = Vec::new();
            let n = self.from.read_until(0, &mut raw).expect("read from chromium");
            assert!(n > 0 && raw.pop() == Some(0), "chromium closed its pipe");
            let reply: serde_json::Value = serde_json::from_slice(&raw).expect("chromium's JSON");
            match reply["method"].as_str() {
                Some("Runtime.consoleAPICalled" | "Runtime.exceptionThrown" | "Log.entryAdded") => {
                    self.console.push(reply["params"].to_string());
                }
                _ if reply["id"] == id => {
                    assert!(reply.get("error").is_none(), "{method}: {reply}");
                    return reply["result"].clone();
                }
                _ => {}
            }
        }
    }

    fn call_page(&mut self, method: &str, params: serde_json::Value) -> serde_json::Value {
        let session = self.session.clone();
        self.call(Some(&session), method, params)
    }

    /// The value of the JavaScript expression `js` on the page.
    fn eval(&mut self, js: &str) -> serde_json::Value {
        let result = self
            .call_page("Runtime.evaluate", serde_json::json!({ "expression": js, "returnByValue": true }));
        assert!(result.get("exceptionDetails").is_none(), "{js}: {result}");
        result["result"]["value"].clone()
    }

    /// What the page's `Content-Security-Policy` refused so far: each directive and what it refused.
    fn violations(&mut self) -> Vec<String> {
        serde_json::from_value(self.eval("window.__violations")).expect("a list of the refused")
    }

    /// The page's list of players as its DOM shows it: name → position (its text, "x, y").
    fn players(&mut self) -> std::collections::BTreeMap<String, String> {
        let rows = self.eval(
            "Array.from(document.querySelectorAll('#players tr'), r => Array.from(r.cells, c => c.textContent))",
        );
        rows.as_array()
            .into_iter()
            .flatten()
            .filter_map(|row| Some((row[1].as_str()?.to_string(), row[2].as_str()?.to_string())))
            .collect()
    }

    /// Polls the page's list until `ok` holds; the list then.
    fn wait_players(
        &mut self,
        what: &str,
        ok: impl Fn(&std::collections::BTreeMap<String, String>) -> bool,
    ) -> std::collections::BTreeMap<String, String> {
        let deadline = Instant::now() + TIMEOUT;
        loop {
            let players = self.players();
            if ok(&players) {
                return players;
            }
            assert!(Instant::now() < deadline, "the page never showed {what}: {players:?}");
            std::thread::sleep(Duration::from_millis(2));
        }
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The status page in a real browser (Debian's `chromium`, when on PATH), loaded once and left
/// open: two stock-ssh players appear on it, and each of their steps shows in the page's own list
/// within 1 s (the median of eight, from the key written to ssh's terminal to the DOM's new
/// position) — which only the live event stream can do, as the page is never reloaded. Nothing is
/// logged to its console. Each player is listed and drawn in a colour of their own, and the whole
/// map fits the 960×540 window. A screenshot of a fresh load shows the two players drawn each in
/// their colour; with `MAZEWALK_STATUS_PNG=PATH` it is kept there (README's picture:
/// `docs/images/status-page.png`).
#[test]
fn a_headless_chromium_shows_two_players_walking_live_on_the_status_page() {
    let Some(chromium) = chromium() else {
        eprintln!("chromium not on PATH: the status page was not checked in a browser");
        return;
    };
    let serve = Serve::start("chromium");
    let url = format!("http://{}/", serve.http);
    let png = serve.dir.join("page.png");
    let (empty, log) = screenshot(chromium, &url, &png);
    let console: Vec<&str> = log.lines().filter(|l| l.contains(":CONSOLE")).collect();
    assert!(console.is_empty(), "the page logged: {console:?}");

    let mut browser = Browser::open(chromium, &serve.dir.join("profile"), &url);
    browser.wait_players("the empty list", |p| p.is_empty());
    // The page's script runs under its policy: its first event shown, nothing refused.
    let deadline = Instant::now() + TIMEOUT;
    while browser.eval("document.getElementById('state')?.textContent") != "0 players" {
        let refused = browser.violations();
        assert!(Instant::now() < deadline, "the page's script never ran; the policy refused {refused:?}");
        std::thread::sleep(Duration::from_millis(20));
    }
    assert_eq!(browser.violations(), Vec::<String>::new(), "the policy refused some of the page");
    let mut players: Vec<(&str, Player)> = ["ada", "bob"]
        .into_iter()
        .map(|name| (name, Player::connect(serve.ssh_port, None, name, 80, 24)))
        .collect();
    serve.wait_value("mazewalk_players", |v| v == 2.0);
    browser.wait_players("both players", |p| p.contains_key("ada") && p.contains_key("bob"));
    // Each in a colour of their own (the list's label as the map's dot), none on the empty page.
    let listed = browser.eval(
        "Object.fromEntries(Array.from(document.querySelectorAll('#players tr'), \
         r => [r.cells[1].textContent, getComputedStyle(r.cells[0]).color]))",
    );
    let colour = |name: &str| css_rgb(listed[name].as_str().expect("a colour"));
    let colours = [colour("ada"), colour("bob")];
    assert_ne!(colours[0], colours[1], "ada and bob in one colour: {listed}");
    for rgb in colours {
        assert_eq!(count(&empty, rgb), 0, "nobody played yet, yet {rgb:?} on the page");
    }
    // The whole map within the window (the maze's start and exit without scrolling).
    let fits = browser.eval(
        "(() => { const r = document.getElementById('map').getBoundingClientRect(); \
         return [r.bottom, r.right, window.innerHeight, window.innerWidth]; })()",
    );
    let f = |i: usize| fits[i].as_f64().expect("a number");
    assert!(f(0) <= f(2) && f(1) <= f(3), "the map (bottom, right; window height, width): {fits}");
    // … and still when the window is made lower than the map was (a laptop's browser beside a
    // terminal), once the page has had its resize.
    browser.call_page(
        "Emulation.setDeviceMetricsOverride",
        serde_json::json!({ "width": 960, "height": 360, "deviceScaleFactor": 1, "mobile": false }),
    );
    let deadline = Instant::now() + TIMEOUT;
    loop {
        let fits = browser.eval(
            "(() => { const r = document.getElementById('map').getBoundingClientRect(); \
             return [r.bottom, window.innerHeight]; })()",
        );
        let (bottom, height) = (fits[0].as_f64().expect("a number"), fits[1].as_f64().expect("a number"));
        if height == 360.0 && bottom <= height {
            break;
        }
        assert!(Instant::now() < deadline, "in a window 360 high the map ends at {bottom} ({height})");
        std::thread::sleep(Duration::from_millis(20));
    }
    browser.call_page("Emulation.clearDeviceMetricsOverride", serde_json::json!({}));

    // Each player in turn steps forward, then back (a spawn faces an opening, and a step back
    // returns where it came from: every step moves). A step is timed from the key to the page's
    // new position; the next waits for the glide to end.
    let mut times = Vec::new();
    for round in 0..4 {
        for (name, player) in &mut players {
            let before = browser.players()[*name].clone();
            let sent = Instant::now();
            player.send(if round % 2 == 0 { b"w" } else { b"s" });
            let moved = browser.wait_players(&format!("{name} leave {before}"), |p| p[*name] != before);
            times.push(sent.elapsed());
            let mut last = (moved[*name].clone(), Instant::now());
            while last.1.elapsed() < Duration::from_millis(400) {
                let now = browser.players()[*name].clone();
                if now != last.0 {
                    last = (now, Instant::now());
                }
                assert!(sent.elapsed() < TIMEOUT, "{name} never stopped");
                std::thread::sleep(Duration::from_millis(20));
            }
        }
    }
    times.sort();
    let median = times[times.len() / 2];
    eprintln!("from a key to the page's new position: median {median:?}, each {times:?}");
    assert!(
        median <= Duration::from_secs(1),
        "a player walking over ssh took {median:?} (median of {}) to move on the page: {times:?}",
        times.len()
    );
    assert!(browser.console.is_empty(), "the page logged: {:?}", browser.console);
    // Red-team pass 18: the policy allowed any inline script (`'unsafe-inline'`). The page's own
    // script ran (the list above is its work) and nothing was refused; a handler injected into
    // the page now is, and the browser says so.
    assert_eq!(browser.violations(), Vec::<String>::new(), "the policy refused some of the page");
    let injected = browser.eval(
        "(() => { const d = document.createElement('div'); d.setAttribute('onclick', 'window.__ran = 1'); \
         document.body.append(d); d.click(); d.remove(); return window.__ran === 1; })()",
    );
    assert_eq!(injected, false, "an injected inline handler ran");
    let deadline = Instant::now() + TIMEOUT;
    while !browser.violations().iter().any(|v| v.starts_with("script-src-attr")) {
        assert!(Instant::now() < deadline, "no violation reported: {:?}", browser.violations());
        std::thread::sleep(Duration::from_millis(20));
    }

    // A fresh load draws both players (Chromium may take its picture before the first event
    // arrives: again, a few times).
    let mut drawn = [0, 0];
    for _ in 0..10 {
        let (shot, log) = screenshot(chromium, &url, &png);
        let console: Vec<&str> = log.lines().filter(|l| l.contains(":CONSOLE")).collect();
        assert!(console.is_empty(), "the page logged: {console:?}");
        drawn = colours.map(|rgb| count(&shot, rgb));
        if drawn.iter().all(|&n| n > 20) {
            break;
        }
    }
    assert!(drawn.iter().all(|&n| n > 20), "ada and bob drawn in {colours:?}: {drawn:?} pixels");
    if let Some(keep) = std::env::var_os("MAZEWALK_STATUS_PNG") {
        std::fs::copy(&png, &keep).expect("keep the screenshot");
    }
}
