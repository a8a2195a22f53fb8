//! `serve --http ADDR`: a small HTTP/1.1 listener beside the SSH one, on the same tokio runtime
//! (hyper 1). It serves `/metrics` ([`metrics`](crate::metrics)), the status page at `/` (plain
//! HTML, CSS and JS from the binary: no CDN, no third-party request; no script or style runs on it
//! but its own, by their hashes: [`policy`]), the maze's walls at
//! `/maze.json`, the best run's path at `/best-run.json` and the players' whereabouts as Server-Sent
//! Events at `/events`; every other path is
//! 404, every method but GET and HEAD 405.
//!
//! Bounded like the SSH side, whoever connects:
//! - at most [`MAX_CONNECTIONS`] connections at once; past it a newcomer pushes out the oldest
//!   connection of the address group holding the most, where that group holds at least two more than
//!   the newcomer's ([`push_out`]; the SSH side's groups: IPv4 by /24 and address, IPv6 by /48, /56
//!   and /64),
//!   or else is closed at once: one address group (or a few) holding every connection cannot keep the
//!   page and `/metrics` from anyone else, and a reverse proxy's single address is capped as before;
//! - at most [`MAX_EVENT_CLIENTS`] event streams, shared out by address as connections are (503 to a
//!   newcomer that pushes none out); each holds at most
//!   [`EVENT_BUFFER`] events not yet written: a reader too slow for that is dropped (its browser
//!   reconnects), never buffered for; at most [`EVENT_RATE`] events a second each;
//! - the request's head within [`HEADER_TIMEOUT`] (a slowloris client is cut), at most
//!   [`MAX_HEAD_BYTES`] of it (hyper answers 431 past that), and a connection lives
//!   [`CONNECTION_LIFETIME`] at most, keep-alive or not;
//! - each address group may make [`REQUEST_BURST`] requests at once, then [`REQUEST_RATE`] a second,
//!   and all the groups of a block (an IPv4 /24, an IPv6 /48) [`BLOCK_BUDGETS`] times that together
//!   ([`Requests`]; a GET of `/maze.json` counts for more, [`request_cost`]): past that the connection that asks is closed unanswered, and the group's new
//!   connections are closed as they come until its budget is back;
//! - request bodies are never read.

use std::convert::Infallible;
use std::net::{IpAddr, SocketAddr};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

use http_body_util::Full;
use hyper::body::Bytes;
use hyper::{Method, Response, StatusCode};
use hyper_util::rt::{TokioIo, TokioTimer};
use prometheus_client::registry::Registry;
use tokio::net::TcpListener;
use tokio::sync::{oneshot, watch};

/// Connections at once, at most.
pub const MAX_CONNECTIONS: usize = 64;
/// How long a client has to send a request's head.
pub const HEADER_TIMEOUT: Duration = Duration::from_secs(5);
/// The longest a connection stays open.
pub const CONNECTION_LIFETIME: Duration = Duration::from_secs(60);
/// The most bytes of a request's head (hyper's read buffer; its least is 8 KiB).
pub const MAX_HEAD_BYTES: usize = 16 * 1024;
/// Event streams at once, at most.
pub const MAX_EVENT_CLIENTS: usize = 32;
/// Events waiting to be written to one stream, at most.
pub const EVENT_BUFFER: usize = 8;
/// Events a second to one stream, at most.
pub const EVENT_RATE: u32 = 10;
/// Bytes a second to one stream, at most: after an event of n bytes the next waits n / this many
/// seconds, if that is longer than [`EVENT_RATE`]'s interval. A page of a few dozen players keeps
/// its ten events a second; a world of a thousand (~120 KB an event) gets one about every two
/// seconds (red-team pass 8: 32 streams of such a world took 39 MB/s from one address).
pub const EVENT_BYTES_PER_SECOND: usize = 64 * 1024;
/// Requests a second one address group (an IPv4 address, an IPv6 /64) may make, after a burst of
/// [`REQUEST_BURST`]; past it the connection that asks is closed unanswered. A page asks four times
/// when it loads and once every 30 s after (its event stream is one request), a Prometheus server
/// once every 15 s or so (red-team pass 10: `/metrics`, asked for as fast as 64 connections of one
/// address could, took most of a core of the runtime the game runs on).
pub const REQUEST_RATE: u32 = 20;
/// Requests one address group may make at once.
pub const REQUEST_BURST: u32 = 100;
/// How many groups' budgets of requests a block (an IPv4 /24, an IPv6 /48) has for all its groups
/// together ([`Requests`]): a campus's or a host's visitors load the page a few at a time, one
/// holder of many addresses takes no more than four.
pub const BLOCK_BUDGETS: u32 = 4;
/// A request whose answer is long counts as one request for each this many bytes of it, up to
/// [`MAX_REQUEST_COST`]: only `/maze.json` is (megabytes for a large maze: at 20 requests a second
/// one address took 43 MB/s of it, red-team pass 10).
pub const COST_BYTES: usize = 64 * 1024;
/// The most one request counts for: a page can still load its maze a few times in a row.
pub const MAX_REQUEST_COST: usize = REQUEST_BURST as usize / 4;
/// Address groups whose request budgets are kept; a group beyond them (when none of the kept ones
/// has its whole budget back) shares one budget with the others beyond.
pub const TRACKED_REQUESTERS: usize = 4096;
/// An event (or a comment) at least this often, so that proxies keep the stream open.
const EVENT_KEEPALIVE: Duration = Duration::from_secs(15);

/// The status page.
const PAGE: &str = include_str!("status.html");

/// The `Content-Security-Policy` of every answer ([`policy`] of [`PAGE`]), made once.
static POLICY: std::sync::LazyLock<hyper::header::HeaderValue> = std::sync::LazyLock::new(|| {
    hyper::header::HeaderValue::try_from(policy(PAGE)).expect("a policy is ASCII, without line breaks")
});

/// The `Content-Security-Policy` for `page`: its own inline `<script>`s and `<style>`s, each named by
/// the SHA-256 of its text as served ([`inline`]), and requests to this server (`/maze.json`, the
/// event stream); nothing else, and no frame may hold it. Red-team pass 18: `'unsafe-inline'` let
/// any script run that found its way into the page (an injected handler), where `textContent` was
/// all that stood in the way.
fn policy(page: &str) -> String {
    use base64ct::Encoding as _;
    use sha2::Digest as _;
    let sources = |tag: &str| -> String {
        inline(page, tag)
            .into_iter()
            .map(|text| format!(" 'sha256-{}'", base64ct::Base64::encode_string(&sha2::Sha256::digest(text))))
            .collect()
    };
    format!(
        "default-src 'none'; script-src{}; style-src{}; connect-src 'self'; base-uri 'none'; \
         form-action 'none'; frame-ancestors 'none'",
        sources("script"),
        sources("style")
    )
}

/// The text of each `<tag>…</tag>` in `page` whose opening tag has no attributes, as a browser
/// hashes it for the policy. That is the bytes served: the page goes out as the UTF-8 it is, and its
/// line ends are `\n` already (a browser's parser hashes a `\r\n` as `\n`; a test checks there is none).
fn inline<'a>(page: &'a str, tag: &str) -> Vec<&'a str> {
    let (open, close) = (format!("<{tag}>"), format!("</{tag}>"));
    page.split(open.as_str())
        .skip(1)
        .filter_map(|rest| rest.split_once(close.as_str()).map(|(text, _)| text))
        .collect()
}

/// Sets the headers every answer carries: the [`POLICY`]; no guessing of a type other than the one
/// said (`nosniff`: `/maze.json` is never taken for a script or a page); no `Referer` sent from the
/// page to anyone (it links nowhere today; a link added later will not tell where the page is); no
/// frame of another site holds the page (`DENY`, for browsers older than the policy's
/// `frame-ancestors`).
fn protect(headers: &mut hyper::HeaderMap) {
    use hyper::header::{self, HeaderValue};
    headers.insert(header::CONTENT_SECURITY_POLICY, POLICY.clone());
    headers.insert(header::X_CONTENT_TYPE_OPTIONS, HeaderValue::from_static("nosniff"));
    headers.insert(header::REFERRER_POLICY, HeaderValue::from_static("no-referrer"));
    headers.insert(header::X_FRAME_OPTIONS, HeaderValue::from_static("DENY"));
}

/// What the listener serves.
pub(crate) struct Site {
    /// Encoded at each scrape of `/metrics`.
    pub registry: Registry,
    /// `/maze.json`: the maze's name, bounds and walls, shared by every answer (up to
    /// [`MAX_MAP_WALLS`] walls, megabytes: red-team pass 10, a copy an answer let 64 connections
    /// that did not read hold 64 copies, 230 MB).
    pub maze: Bytes,
    /// The world's version, to wait for a change.
    pub versions: watch::Receiver<u64>,
    /// The players now, as an event's JSON.
    pub players: Box<dyn Fn() -> String + Send + Sync>,
    /// `/best-run.json`: the maze's best run's path ([`best_run_json`]).
    pub best_run: Box<dyn Fn() -> String + Send + Sync>,
    /// Event streams open now: who holds each ([`Places`]).
    pub streams: Arc<Mutex<Places>>,
    /// The server's shutdown.
    pub shutdown: watch::Receiver<bool>,
    /// Each address group's requests ([`Requests`]).
    pub requests: Mutex<Requests>,
}

/// The requests each address group may still make: a budget of [`REQUEST_BURST`] refilled at
/// [`REQUEST_RATE`] a second for each group (an IPv4 address, an IPv6 /64), and one of
/// [`BLOCK_BUDGETS`] times that for each block (an IPv4 /24, an IPv6 /48: the first of
/// [`address_prefixes`](crate::slots::address_prefixes)) that all its groups share: a request is
/// answered only if both have room (red-team pass 18: with a budget per group alone, 64 addresses of
/// one /24 took 64 budgets, a gigabyte of a large maze's `/maze.json` in 8 s, and the /64s of one
/// /48 are 65,536). At most [`TRACKED_REQUESTERS`] of each are kept (one whose budget is whole
/// again is forgotten when room is needed), and one more shared by any others. Pure: time comes in
/// as seconds.
#[derive(Debug, Default)]
pub struct Requests {
    /// Each address group's budget.
    groups: Budgets,
    /// Each block's budget, shared by its groups.
    blocks: Budgets,
}

/// Budgets of requests by key ([`Requests`]): at most [`TRACKED_REQUESTERS`], and one shared by the
/// keys beyond them.
#[derive(Debug, Default)]
struct Budgets {
    budgets: std::collections::HashMap<IpAddr, crate::limits::RateLimit>,
    /// The budget of the keys beyond [`TRACKED_REQUESTERS`].
    rest: Option<crate::limits::RateLimit>,
}

impl Budgets {
    /// `key`'s budget (`share` times [`REQUEST_RATE`] and [`REQUEST_BURST`]), made full if new.
    fn budget(&mut self, key: IpAddr, now: f64, share: u32) -> &mut crate::limits::RateLimit {
        use crate::limits::RateLimit;
        if !self.budgets.contains_key(&key) && self.budgets.len() >= TRACKED_REQUESTERS {
            self.budgets.retain(|_, budget| !budget.is_full(now));
        }
        let full = || RateLimit::new(share * REQUEST_RATE, share * REQUEST_BURST, now);
        if self.budgets.len() < TRACKED_REQUESTERS || self.budgets.contains_key(&key) {
            self.budgets.entry(key).or_insert_with(full)
        } else {
            self.rest.get_or_insert_with(full)
        }
    }

    /// Whether `key`'s budget has no request left at `now` (taking none).
    fn exhausted(&self, key: IpAddr, now: f64) -> bool {
        self.budgets
            .get(&key)
            .or(self.rest.as_ref().filter(|_| self.budgets.len() >= TRACKED_REQUESTERS))
            .is_some_and(|budget| budget.is_empty(now))
    }
}

impl Requests {
    /// Whether a request from `ip` at `now` that counts for `cost` requests may be answered
    /// (taking them from its group's budget and its block's; none if it may not).
    pub fn allow(&mut self, ip: IpAddr, now: f64, cost: usize) -> bool {
        let (group, block) = (crate::slots::address_group(ip), crate::slots::address_prefixes(ip)[0]);
        // (two fields, two budgets held at once: each looked up once)
        let (mine, blocks) =
            (self.groups.budget(group, now, 1), self.blocks.budget(block, now, BLOCK_BUDGETS));
        mine.has(cost, now) && blocks.has(cost, now) && mine.take_all(cost, now) && blocks.take_all(cost, now)
    }

    /// Whether `ip`'s group, or its block, has no request left at `now` (taking none): its new
    /// connections are closed as they come, before any work is done for them.
    pub fn exhausted(&self, ip: IpAddr, now: f64) -> bool {
        let (group, block) = (crate::slots::address_group(ip), crate::slots::address_prefixes(ip)[0]);
        self.groups.exhausted(group, now) || self.blocks.exhausted(block, now)
    }
}

/// Binds `addr` and serves `site` until `shutdown` turns true; returns the bound address and the task.
///
/// # Errors
/// The address cannot be bound.
pub(crate) async fn start(
    addr: SocketAddr,
    site: Site,
) -> std::io::Result<(SocketAddr, tokio::task::JoinHandle<()>)> {
    let shutdown = site.shutdown.clone();
    let listener = TcpListener::bind(addr)
        .await
        .map_err(|e| std::io::Error::new(e.kind(), format!("--http: cannot listen on {addr}: {e}")))?;
    let local = listener.local_addr()?;
    let task = tokio::spawn(accept_loop(listener, Arc::new(site), shutdown));
    Ok((local, task))
}

async fn accept_loop(listener: TcpListener, site: Arc<Site>, mut shutdown: watch::Receiver<bool>) {
    let open = Arc::new(Mutex::new(Places::default()));
    let started = tokio::time::Instant::now();
    loop {
        let accepted = tokio::select! {
            _ = shutdown.wait_for(|&s| s) => return,
            accepted = listener.accept() => accepted,
        };
        let Ok((stream, peer)) = accepted else {
            // Out of descriptors, say: wait a little rather than spin.
            tokio::time::sleep(Duration::from_millis(100)).await;
            continue;
        };
        let now = started.elapsed().as_secs_f64();
        if site.requests.lock().unwrap_or_else(PoisonError::into_inner).exhausted(peer.ip(), now) {
            drop(stream); // its address asked too much: its newcomers go as they come, for nothing
            continue;
        }
        let Some((id, pushed_out)) = Places::admit(&open, peer.ip(), MAX_CONNECTIONS) else {
            drop(stream); // closed unanswered: the cap holds whatever the clients do
            continue;
        };
        let guard = Held { places: Arc::clone(&open), id };
        let site = Arc::clone(&site);
        let mut shutdown = shutdown.clone();
        tokio::spawn(async move {
            let _guard = guard;
            let service = hyper::service::service_fn(move |request| {
                let site = Arc::clone(&site);
                async move {
                    let now = started.elapsed().as_secs_f64();
                    let cost = request_cost(request.method(), request.uri().path(), site.maze.len());
                    if !site.requests.lock().unwrap_or_else(PoisonError::into_inner).allow(
                        peer.ip(),
                        now,
                        cost,
                    ) {
                        // (an error ends the connection unanswered: an answer would cost as much)
                        return Err(std::io::Error::other("too many requests from this address"));
                    }
                    Ok(answer(&site, request.method(), request.uri().path(), peer.ip()))
                }
            });
            let connection = hyper::server::conn::http1::Builder::new()
                .timer(TokioTimer::new())
                .header_read_timeout(HEADER_TIMEOUT)
                .max_buf_size(MAX_HEAD_BYTES)
                .serve_connection(TokioIo::new(stream), service);
            tokio::select! {
                _ = tokio::time::timeout(CONNECTION_LIFETIME, connection) => {}
                _ = shutdown.wait_for(|&s| s) => {}
                _ = pushed_out => {} // a newcomer from an address holding fewer took its place
            }
        });
    }
}

/// Places held now (connections, or event streams), oldest first: each one's address, and the way to
/// end it.
#[derive(Default)]
pub(crate) struct Places {
    next: u64,
    held: Vec<(u64, IpAddr, oneshot::Sender<()>)>,
}

impl Places {
    /// Lets a newcomer from `ip` take a place, pushing out another holder if all `cap` are taken and
    /// [`push_out`] names one: its id, and what ends it when it is pushed out in turn. `None`: full,
    /// the newcomer is refused.
    fn admit(places: &Mutex<Places>, ip: IpAddr, cap: usize) -> Option<(u64, oneshot::Receiver<()>)> {
        let mut open = places.lock().unwrap_or_else(PoisonError::into_inner);
        if open.held.len() >= cap {
            let addresses: Vec<IpAddr> = open.held.iter().map(|&(_, a, _)| a).collect();
            let k = push_out(&addresses, ip)?;
            let (_, _, close) = open.held.remove(k);
            let _ = close.send(()); // (the connection may be ending by itself)
        }
        let id = open.next;
        open.next += 1;
        let (close, closed) = oneshot::channel();
        open.held.push((id, ip, close));
        Some((id, closed))
    }

    /// How many places are held.
    #[cfg(test)]
    fn len(places: &Mutex<Places>) -> usize {
        places.lock().unwrap_or_else(PoisonError::into_inner).held.len()
    }
}

/// Which of the places held now (their holders' addresses, oldest first: connections, or event
/// streams) a newcomer from `newcomer` pushes out when all are taken: the oldest of the address
/// group holding the most, if that group holds at least two more than the newcomer's (after the swap
/// the newcomer's holds no more than it does); `None` where no group holds that many, so the newcomer
/// is refused. Fair shares: groups holding every place between them give way, one at a time, to
/// groups holding fewer, and never to one of themselves. The groups are the SSH side's
/// ([`fair_push_out`](crate::slots::fair_push_out)): IPv4 places counted by /24, then by address;
/// IPv6 places by /48, then /56, then /64 (red-team pass 4: raw addresses let one host's /64, or one
/// /24's addresses, hold every place).
#[must_use]
pub fn push_out(open: &[IpAddr], newcomer: IpAddr) -> Option<usize> {
    let held: Vec<(IpAddr, f64)> = open.iter().enumerate().map(|(k, &ip)| (ip, k as f64)).collect();
    crate::slots::fair_push_out(&held, newcomer)
}

/// How many requests a `method` request for `path` counts for, `maze_bytes` being `/maze.json`'s
/// length: one for each [`COST_BYTES`] of a GET of the maze, at most [`MAX_REQUEST_COST`]; one for
/// anything else (the other answers are small, an event stream is paced by itself).
fn request_cost(method: &Method, path: &str, maze_bytes: usize) -> usize {
    if method == Method::GET && path == "/maze.json" {
        maze_bytes.div_ceil(COST_BYTES).clamp(1, MAX_REQUEST_COST)
    } else {
        1
    }
}

/// One place in [`Places`], given up when its holder ends.
struct Held {
    places: Arc<Mutex<Places>>,
    id: u64,
}

impl Drop for Held {
    fn drop(&mut self) {
        let mut places = self.places.lock().unwrap_or_else(PoisonError::into_inner);
        places.held.retain(|&(id, _, _)| id != self.id);
    }
}

type Body = http_body_util::combinators::BoxBody<Bytes, Infallible>;

/// The answer to a `method` request for `path` from `peer`.
fn answer(site: &Arc<Site>, method: &Method, path: &str, peer: IpAddr) -> Response<Body> {
    use http_body_util::BodyExt as _;
    let head = method == Method::HEAD;
    let respond = |status: StatusCode, content_type: &'static str, body: Bytes| {
        // A HEAD answer says how long the GET's body is (RFC 9110 §9.3.2), an event stream has none.
        let length = (head && content_type != "text/event-stream")
            .then(|| hyper::header::HeaderValue::from(body.len()));
        let body = if head { Bytes::new() } else { body };
        let mut response = Response::new(Full::new(body).boxed());
        *response.status_mut() = status;
        let headers = response.headers_mut();
        if let Some(length) = length {
            headers.insert(hyper::header::CONTENT_LENGTH, length);
        }
        headers.insert(hyper::header::CONTENT_TYPE, hyper::header::HeaderValue::from_static(content_type));
        headers.insert(hyper::header::CACHE_CONTROL, hyper::header::HeaderValue::from_static("no-store"));
        protect(headers);
        response
    };
    if !matches!(*method, Method::GET | Method::HEAD) {
        let mut response =
            respond(StatusCode::METHOD_NOT_ALLOWED, "text/plain", Bytes::from_static(b"GET or HEAD only\n"));
        response
            .headers_mut()
            .insert(hyper::header::ALLOW, hyper::header::HeaderValue::from_static("GET, HEAD"));
        return response;
    }
    match path {
        "/metrics" => respond(
            StatusCode::OK,
            crate::metrics::CONTENT_TYPE,
            crate::metrics::encode(&site.registry).into(),
        ),
        "/" => respond(StatusCode::OK, "text/html; charset=utf-8", Bytes::from_static(PAGE.as_bytes())),
        "/maze.json" => respond(StatusCode::OK, "application/json", site.maze.clone()),
        "/best-run.json" => respond(StatusCode::OK, "application/json", (site.best_run)().into()),
        "/events" if head => respond(StatusCode::OK, "text/event-stream", Bytes::new()),
        "/events" => match events(site, peer) {
            Some(body) => {
                let mut response = Response::new(body);
                let headers = response.headers_mut();
                headers.insert(
                    hyper::header::CONTENT_TYPE,
                    hyper::header::HeaderValue::from_static("text/event-stream"),
                );
                headers.insert(
                    hyper::header::CACHE_CONTROL,
                    hyper::header::HeaderValue::from_static("no-store"),
                );
                protect(headers);
                response
            }
            None => respond(
                StatusCode::SERVICE_UNAVAILABLE,
                "text/plain",
                Bytes::from_static(b"too many event streams; try again later\n"),
            ),
        },
        _ => respond(
            StatusCode::NOT_FOUND,
            "text/plain",
            Bytes::from_static(b"not found: try / or /metrics\n"),
        ),
    }
}

/// An event stream for a reader at `peer`: the players now, then again at each change of the world
/// (at most [`EVENT_RATE`] a second and [`EVENT_BYTES_PER_SECOND`]), a comment every [`EVENT_KEEPALIVE`] otherwise. `None` past
/// [`MAX_EVENT_CLIENTS`] where the newcomer pushes no other stream out ([`push_out`]).
fn events(site: &Arc<Site>, peer: IpAddr) -> Option<Body> {
    use http_body_util::BodyExt as _;
    let (id, mut pushed_out) = Places::admit(&site.streams, peer, MAX_EVENT_CLIENTS)?;
    let held = Held { places: Arc::clone(&site.streams), id };
    let (tx, rx) = tokio::sync::mpsc::channel::<Bytes>(EVENT_BUFFER);
    let site = Arc::clone(site);
    tokio::spawn(async move {
        let _stream = held;
        let mut versions = site.versions.clone();
        let mut shutdown = site.shutdown.clone();
        // (The browser reconnects this soon after the connection's lifetime ends it.)
        let mut next = Bytes::from_static(b"retry: 1000\n\n");
        loop {
            versions.borrow_and_update();
            let event = format!("{}data: {}\n\n", String::from_utf8_lossy(&next), (site.players)());
            next = Bytes::new();
            let pause = (Duration::from_secs(1) / EVENT_RATE)
                .max(Duration::from_secs_f64(event.len() as f64 / EVENT_BYTES_PER_SECOND as f64));
            // A reader whose buffer is full is too slow: its stream ends (dropped, not waited for).
            if tx.try_send(Bytes::from(event)).is_err() {
                return;
            }
            tokio::select! {
                () = tokio::time::sleep(pause) => {}
                () = tx.closed() => return,
                _ = &mut pushed_out => return, // a reader from an address holding fewer took its place
            }
            tokio::select! {
                changed = versions.changed() => if changed.is_err() { return },
                () = tokio::time::sleep(EVENT_KEEPALIVE) => {
                    if tx.try_send(Bytes::from_static(b": keepalive\n\n")).is_err() {
                        return;
                    }
                }
                _ = shutdown.wait_for(|&s| s) => return,
                () = tx.closed() => return,
                _ = &mut pushed_out => return,
            }
        }
    });
    let frames = futures_util::stream::unfold(rx, |mut rx| async move {
        rx.recv().await.map(|bytes| (Ok(hyper::body::Frame::data(bytes)), rx))
    });
    Some(http_body_util::StreamBody::new(frames).boxed())
}

/// Points of the best run's path on the page's map, at most (a longer run is thinned evenly).
pub(crate) const MAX_RUN_POINTS: usize = 600;

/// `/best-run.json`: the holder, the time and the path (`[[x, y], …]`, at most [`MAX_RUN_POINTS`])
/// of `run`, the maze's best (checked by the records thread); `{"path": []}` without one.
pub(crate) fn best_run_json(run: Option<&mazewalk_walk::run::Run>) -> String {
    let Some(run) = run else { return serde_json::json!({ "path": [] }).to_string() };
    let step = run.samples.len().div_ceil(MAX_RUN_POINTS).max(1);
    let last = run.samples.last().map(|s| [s.position.x, s.position.y]);
    let mut path: Vec<[f32; 2]> =
        run.samples.iter().step_by(step).map(|s| [s.position.x, s.position.y]).collect();
    if path.last() != last.as_ref() {
        path.extend(last); // (the finish itself, whatever the step)
    }
    serde_json::json!({ "holder": run.holder, "seconds": run.seconds(), "path": path }).to_string()
}

/// Walls drawn on the page's map, at most (a larger maze's page shows the players only).
pub const MAX_MAP_WALLS: usize = 50_000;

/// How a player joins the game this page shows.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(crate) struct Joining {
    /// The SSH server's port.
    pub ssh_port: Option<u16>,
    /// The host key's fingerprint (`SHA256:…`), so a newcomer can check what `ssh` asks about.
    pub host_key: Option<String>,
}

/// `/maze.json`: `name`, the maze's bounds, its walls as `[x1, y1, x2, y2]` (up to
/// [`MAX_MAP_WALLS`]), the exit's point, and how to join: `ssh_port` and `host_key`.
#[must_use]
pub(crate) fn maze_json(maze: &mazewalk_maze::Maze, name: &str, joining: &Joining) -> String {
    let extents = maze.extents();
    let walls: Vec<[f32; 4]> = maze
        .edges()
        .iter()
        .filter(|e| e.opaque)
        .take(MAX_MAP_WALLS + 1)
        .map(|e| {
            let (a, b) = (maze.vertex(e.start), maze.vertex(e.end));
            [a.x, a.y, b.x, b.y]
        })
        .collect();
    let walls = if walls.len() > MAX_MAP_WALLS { Vec::new() } else { walls };
    let exit = maze.exit_point().map(|p| [p.x, p.y]);
    serde_json::json!({
        "name": name,
        "min": [extents.min.x, extents.min.y],
        "max": [extents.max.x, extents.max.y],
        "walls": walls,
        "exit": exit,
        "ssh_port": joining.ssh_port,
        "host_key": joining.host_key,
    })
    .to_string()
}

/// The CSS colour (`#rrggbb`) of a player drawn in `color`, as xterm shows it: the colour the game
/// draws them in on the map and as a figure (the status page's yellow for a colour without RGB).
fn css_color(color: mazewalk_term::frame::Color) -> String {
    use mazewalk_term::frame::{Color, xterm_rgb};
    let [r, g, b] = match color {
        Color::Indexed(i) => xterm_rgb(i),
        Color::Rgb(r, g, b) => [r, g, b],
        Color::Default => [0xff, 0xcc, 0x33],
    };
    format!("#{r:02x}{g:02x}{b:02x}")
}

/// An event: every player in the world (names as the game shows them), where and facing where, in
/// the colour the game draws them in.
#[must_use]
pub(crate) fn players_json(look: &crate::world::Look) -> String {
    let players: Vec<serde_json::Value> = look
        .players
        .iter()
        .map(|(_, seen)| {
            serde_json::json!({
                "name": seen.name,
                "label": seen.label.to_string(),
                "x": seen.position.x,
                "y": seen.position.y,
                "heading": seen.heading_deg,
                "best": seen.best,
                "color": css_color(seen.color),
            })
        })
        .collect();
    let winner = look.winner.as_ref().map(|w| serde_json::json!({ "name": w.name, "seconds": w.seconds }));
    serde_json::json!({ "players": players, "winner": winner, "online": look.online }).to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    // issue #43: the status page's best run, thinned to at most MAX_RUN_POINTS, ending at the finish.
    #[test]
    fn the_best_runs_path_is_thinned_and_ends_at_the_finish() {
        use mazewalk_walk::run::{Pose, Run};
        assert_eq!(best_run_json(None), r#"{"path":[]}"#);
        let samples: Vec<Pose> = (0..=6000)
            .map(|k| Pose { position: glam::Vec2::new(k as f32 / 100.0, 1.0), yaw_deg: 0.0, pitch_deg: 0.0 })
            .collect();
        let run =
            Run { maze: mazewalk_maze::ContentHash([0; 32]), holder: "ada".into(), millis: 600_000, samples };
        let json: serde_json::Value = serde_json::from_str(&best_run_json(Some(&run))).unwrap();
        let path = json["path"].as_array().unwrap();
        assert!(path.len() <= MAX_RUN_POINTS + 1 && path.len() > MAX_RUN_POINTS / 2, "{}", path.len());
        assert_eq!(path[0], serde_json::json!([0.0, 1.0]));
        assert_eq!(path[path.len() - 1], serde_json::json!([60.0, 1.0]), "the finish");
        assert_eq!((json["holder"].as_str(), json["seconds"].as_f64()), (Some("ada"), Some(600.0)));
    }

    /// Red-team pass 18: the policy let any inline script run (`'unsafe-inline'`). Now it names the
    /// page's own script and style by their hashes, as a browser computes them (base64 of the
    /// SHA-256 of the element's text: `alert(1)`'s as `openssl dgst -sha256 -binary | base64` gives
    /// it), and nothing else inline: every `<script` and `<style` of the page is one it names.
    #[test]
    fn the_policy_names_the_pages_own_script_and_style_by_hash_and_nothing_inline_else() {
        let example = policy("<p>x</p><script>alert(1)</script><style></style>");
        assert!(
            example.contains("script-src 'sha256-bhHHL3z2vDgxUt0W3dWQOrprscmda2Y5pLsLg4GF+pI=';"),
            "{example}"
        );
        let served = policy(PAGE);
        assert!(!served.contains("unsafe"), "{served}");
        for (tag, directive) in [("script", "script-src"), ("style", "style-src")] {
            let named = inline(PAGE, tag).len();
            assert_eq!(named, PAGE.matches(&format!("<{tag}")).count(), "every <{tag} has no attributes");
            assert_eq!(named, 1, "the page's one {tag}");
            let sources = served.split("; ").find_map(|d| d.strip_prefix(directive)).expect(directive);
            assert_eq!(sources.matches(" 'sha256-").count(), named, "{served}");
        }
        assert!(!PAGE.contains('\r'), "a browser hashes a CR LF as LF: the page's line ends are LF alone");
        for directive in
            ["default-src 'none'", "frame-ancestors 'none'", "base-uri 'none'", "connect-src 'self'"]
        {
            assert!(served.split("; ").any(|d| d == directive), "{directive} in {served}");
        }
    }

    /// Every answer carries the policy, `nosniff`, `no-referrer` and `DENY` to frames: the page, the
    /// JSON, the event stream, a 404, a 405.
    #[tokio::test]
    async fn every_answer_carries_the_policy_and_the_headers_that_go_with_it() {
        let (_version, versions) = watch::channel(0u64);
        let (_stop, shutdown) = watch::channel(false);
        let site = Arc::new(bare_site(versions, shutdown));
        for (method, path) in [
            (Method::GET, "/"),
            (Method::HEAD, "/"),
            (Method::GET, "/maze.json"),
            (Method::GET, "/events"),
            (Method::GET, "/nowhere"),
            (Method::POST, "/"),
        ] {
            let response = answer(&site, &method, path, ip(1));
            let header = |name| response.headers().get(name).and_then(|v| v.to_str().ok());
            assert_eq!(
                header(hyper::header::CONTENT_SECURITY_POLICY),
                Some(policy(PAGE).as_str()),
                "{method} {path}"
            );
            assert_eq!(header(hyper::header::X_CONTENT_TYPE_OPTIONS), Some("nosniff"), "{method} {path}");
            assert_eq!(header(hyper::header::REFERRER_POLICY), Some("no-referrer"), "{method} {path}");
            assert_eq!(header(hyper::header::X_FRAME_OPTIONS), Some("DENY"), "{method} {path}");
        }
    }

    /// Red-team pass 10: each `/maze.json` answer was a copy of the maze's walls (3.6 MB for 48,840
    /// walls), so 64 connections that asked and did not read held 64 copies (the server's RSS went
    /// up by 230 MB). Every answer now hands out the one copy the site holds.
    #[tokio::test]
    async fn every_maze_json_answer_shares_the_sites_one_copy() {
        use http_body_util::BodyExt as _;
        let (_version, versions) = watch::channel(0u64);
        let (_stop, shutdown) = watch::channel(false);
        let mut site = bare_site(versions, shutdown);
        site.maze = Bytes::from(format!("{{\"walls\": [{}]}}", "[0,0,1,1],".repeat(10_000)));
        let site = Arc::new(site);
        for _ in 0..3 {
            let response = answer(&site, &Method::GET, "/maze.json", ip(1));
            assert_eq!(response.status(), StatusCode::OK);
            let body = response.into_body().collect().await.expect("a body").to_bytes();
            assert_eq!(body, site.maze, "the maze's JSON");
            assert_eq!(body.as_ptr(), site.maze.as_ptr(), "the site's own bytes, not a copy");
        }
        let head = answer(&site, &Method::HEAD, "/maze.json", ip(1));
        let length = head.headers().get(hyper::header::CONTENT_LENGTH).and_then(|v| v.to_str().ok());
        assert_eq!(length, Some(site.maze.len().to_string().as_str()), "HEAD says the GET's length");
    }

    // Red-team pass 10: requests were answered as fast as one address could ask (600,000 of
    // `/metrics` in 8 s from 64 connections, a core's worth). Each address group has a budget: a
    // burst, then the rate; another group has its own, and groups beyond those kept share one.
    #[test]
    fn each_address_group_has_its_own_budget_of_requests() {
        let mut requests = Requests::default();
        let burst = (0..2 * REQUEST_BURST).filter(|_| requests.allow(ip(1), 0.0, 1)).count();
        assert_eq!(burst, REQUEST_BURST as usize, "a burst, then none");
        assert!(requests.exhausted(ip(1), 0.0) && !requests.exhausted(ip(2), 0.0), "(asks nothing)");
        assert!(!requests.exhausted(ip(1), 0.1), "one back after 1 / REQUEST_RATE s");
        assert!(requests.allow(ip(2), 0.0, 1), "another address has its own");
        let second = (0..2 * REQUEST_BURST).filter(|_| requests.allow(ip(1), 1.0, 1)).count();
        assert_eq!(second, REQUEST_RATE as usize, "a second later: the rate");
        // one IPv6 /64 is one group, another /64 another
        let v6 = |s: &str| s.parse::<IpAddr>().expect("an IPv6 address");
        let from_64 =
            (0..REQUEST_BURST).filter(|k| requests.allow(v6(&format!("2001:db8::{k:x}")), 0.0, 1)).count();
        assert_eq!(from_64, REQUEST_BURST as usize);
        assert!(!requests.allow(v6("2001:db8::ffff"), 0.0, 1), "the same /64");
        assert!(requests.allow(v6("2001:db8:0:1::1"), 0.0, 1), "another /64");
        // many groups: the kept ones whose budget is whole again are forgotten; past the cap with
        // none of them whole, newcomers share one budget
        let mut many = Requests::default();
        let fresh = |k: usize| IpAddr::from([10, (k >> 16) as u8, (k >> 8) as u8, k as u8]);
        for k in 0..TRACKED_REQUESTERS {
            assert!(many.allow(fresh(k), 0.0, 1));
        }
        let rest = (TRACKED_REQUESTERS..TRACKED_REQUESTERS + 2 * REQUEST_BURST as usize)
            .filter(|&k| many.allow(fresh(k), 0.0, 1))
            .count();
        assert_eq!(rest, REQUEST_BURST as usize, "the groups beyond share one budget");
        assert!(many.groups.budgets.len() <= TRACKED_REQUESTERS);
        assert!(many.allow(fresh(TRACKED_REQUESTERS + 5000), 60.0, 1), "later: the whole ones forgotten");
        assert!(many.groups.budgets.len() <= TRACKED_REQUESTERS);
        // a long answer counts for more: a large maze's walls a few times, then nothing, and a
        // request refused takes nothing
        let mut costly = Requests::default();
        let walls = request_cost(&Method::GET, "/maze.json", 3_600_000);
        assert_eq!(walls, MAX_REQUEST_COST);
        let loads = (0..8).filter(|_| costly.allow(ip(1), 0.0, walls)).count();
        assert_eq!(loads, REQUEST_BURST as usize / MAX_REQUEST_COST);
        assert!(!costly.allow(ip(1), 0.0, 1), "the burst spent");
        let mut partial = Requests::default();
        assert!(partial.allow(ip(1), 0.0, 90) && !partial.allow(ip(1), 0.0, walls));
        assert!(partial.allow(ip(1), 0.0, 10), "the refused one took none of the 10 left");
        assert_eq!(request_cost(&Method::GET, "/maze.json", 100_000), 2, "a small maze: 2 × 64 KiB");
        assert_eq!(request_cost(&Method::GET, "/maze.json", 10), 1);
        assert_eq!(request_cost(&Method::HEAD, "/maze.json", 3_600_000), 1, "HEAD sends no walls");
        assert_eq!(request_cost(&Method::GET, "/metrics", 3_600_000), 1);
    }

    /// Over real sockets: one address asking for `/metrics` over and over on one connection is
    /// answered its burst, then its connection is closed; another address is answered meanwhile.
    // Red-team pass 18: each address of a /24, and each /64 of a /48, had a budget of its own, so
    // that one holder of many addresses took as many budgets (64 addresses of one /24: a gigabyte
    // of a large maze's walls in 8 s, 64 times one address's). A block's addresses share its budget.
    #[test]
    fn the_addresses_of_one_block_share_its_budget_of_requests() {
        let mut requests = Requests::default();
        let v4 = |k: u8| IpAddr::from([192, 0, 2, k]);
        let ask = |requests: &mut Requests, ip: IpAddr, now: f64| {
            (0..REQUEST_BURST).filter(|_| requests.allow(ip, now, 1)).count()
        };
        let spread: usize = (1..=64).map(|k| ask(&mut requests, v4(k), 0.0)).sum();
        assert_eq!(spread, (BLOCK_BUDGETS * REQUEST_BURST) as usize, "64 addresses of a /24: its budget");
        assert!(requests.exhausted(v4(200), 0.0), "another address of it: closed as it comes");
        assert!(requests.allow(IpAddr::from([192, 0, 3, 1]), 0.0, 1), "another /24 has its own");
        assert!(
            requests.groups.budgets.get(&v4(64)).is_some_and(|budget| budget.is_full(0.0)),
            "a request refused for its block's budget takes nothing from its address's"
        );
        let second: usize = (1..=64).map(|k| ask(&mut requests, v4(k), 1.0)).sum();
        assert_eq!(second, (BLOCK_BUDGETS * REQUEST_RATE) as usize, "a second later: the block's rate");
        let v6 = |k: u32| format!("2001:db8:7:{k:x}::1").parse::<IpAddr>().expect("an IPv6 address");
        let spread: usize = (0..256).map(|k| ask(&mut requests, v6(k), 0.0)).sum();
        assert_eq!(spread, (BLOCK_BUDGETS * REQUEST_BURST) as usize, "256 /64s of a /48: its budget");
        assert!(requests.allow("2001:db8:8::1".parse().expect("an IPv6 address"), 0.0, 1), "another /48");
        // an address alone still has its own budget, within its block's
        let mut alone = Requests::default();
        assert_eq!(ask(&mut alone, v4(1), 0.0), REQUEST_BURST as usize);
        assert_eq!(ask(&mut alone, v4(1), 0.0), 0);
    }

    #[tokio::test]
    async fn an_address_past_its_requests_is_closed_and_another_answered() {
        use tokio::io::{AsyncReadExt as _, AsyncWriteExt as _};
        let (_version, versions) = watch::channel(0u64);
        let (stop, shutdown) = watch::channel(false);
        let site = bare_site(versions, shutdown);
        let (addr, task) = start("127.0.0.1:0".parse().unwrap(), site).await.expect("listen");
        let connect = |from: u8| connect_from(addr, from);
        // one request at a time, each answer read whole before the next is asked
        let (mut flood, asked) = (tokio::io::BufReader::new(connect(1).await), 3 * REQUEST_BURST as usize);
        let (start, mut answered) = (tokio::time::Instant::now(), 0);
        for _ in 0..asked {
            use tokio::io::AsyncBufReadExt as _;
            if flood.get_mut().write_all(b"GET /metrics HTTP/1.1\r\nHost: x\r\n\r\n").await.is_err() {
                break;
            }
            let (mut line, mut length) = (String::new(), None);
            let head = tokio::time::timeout(HEADER_TIMEOUT, async {
                loop {
                    line.clear();
                    if flood.read_line(&mut line).await.unwrap_or(0) == 0 {
                        return false; // closed
                    }
                    if let Some(n) = line.to_ascii_lowercase().strip_prefix("content-length:") {
                        length = n.trim().parse::<usize>().ok();
                    }
                    if line == "\r\n" {
                        return true;
                    }
                }
            });
            if !head.await.expect("an answer or the close, in time") {
                break;
            }
            let mut body = vec![0; length.unwrap_or(0)];
            flood.read_exact(&mut body).await.expect("the body");
            answered += 1;
        }
        // the budget refilled while the requests went, at its rate
        let most = REQUEST_BURST as usize
            + (start.elapsed().as_secs_f64() * f64::from(REQUEST_RATE)).ceil() as usize;
        assert!(
            (REQUEST_BURST as usize..=most).contains(&answered) && answered < asked,
            "{answered} of {asked} answered, the burst being {REQUEST_BURST} (at most {most} in the time)"
        );
        let mut other = connect(2).await;
        other.write_all(b"GET /metrics HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n").await.unwrap();
        let mut answer = Vec::new();
        let read = tokio::time::timeout(HEADER_TIMEOUT, other.read_to_end(&mut answer)).await;
        assert!(
            read.is_ok() && answer.starts_with(b"HTTP/1.1 200"),
            "{:?}",
            String::from_utf8_lossy(&answer)
        );
        stop.send(true).expect("stop");
        task.await.expect("the listener ends");
    }

    /// A site with no metrics, no maze, no players and no best run.
    fn bare_site(versions: watch::Receiver<u64>, shutdown: watch::Receiver<bool>) -> Site {
        Site {
            registry: Registry::default(),
            maze: Bytes::new(),
            versions,
            players: Box::new(|| "{}".into()),
            best_run: Box::new(|| best_run_json(None)),
            streams: Arc::default(),
            shutdown,
            requests: Mutex::default(),
        }
    }

    fn ip(last: u8) -> IpAddr {
        IpAddr::from([127, 0, 0, last])
    }

    /// A connection to `addr` from the loopback address `127.0.0.from`.
    async fn connect_from(addr: SocketAddr, from: u8) -> tokio::net::TcpStream {
        let socket = tokio::net::TcpSocket::new_v4().expect("socket");
        socket.bind(SocketAddr::new(ip(from), 0)).expect("bind a loopback address");
        socket.connect(addr).await.expect("connect")
    }

    // A full listener: who gives way to a newcomer, by the addresses holding the connections.
    #[test]
    fn a_newcomer_pushes_out_the_oldest_of_the_address_holding_the_most() {
        let one = vec![ip(1); MAX_CONNECTIONS];
        assert_eq!(push_out(&one, ip(2)), Some(0), "one address holding all gives way, its oldest first");
        assert_eq!(push_out(&one, ip(1)), None, "but never to itself");
        let mut halves: Vec<IpAddr> = (0..MAX_CONNECTIONS).map(|k| ip(1 + (k % 2) as u8)).collect();
        assert_eq!(push_out(&halves, ip(1)), None, "an even split holds against its own");
        assert_eq!(push_out(&halves, ip(2)), None);
        assert_eq!(push_out(&halves, ip(3)), Some(0), "a third address gets in, the oldest going");
        halves[0] = ip(3);
        assert_eq!(push_out(&halves, ip(3)), Some(1), "from the address now holding the most: ip 2's oldest");
        // one newcomer after another from fresh addresses: the heaviest always gives way, and the
        // shares even out until each holds one
        let mut open = one.clone();
        for k in 0..MAX_CONNECTIONS - 1 {
            let newcomer = IpAddr::from([10, (k / 256) as u8, (k % 256) as u8, 1]); // each its own /24
            let at = push_out(&open, newcomer).expect("a fresh address gets in");
            open.remove(at);
            open.push(newcomer);
        }
        assert_eq!(open.iter().filter(|&&a| a == ip(1)).count(), 1, "the flooder keeps one, as each");
        assert_eq!(push_out(&open, ip(9)), None, "every address holds one: a newcomer is refused");
        assert_eq!(push_out(&[], ip(1)), None);
    }

    /// Over real sockets: one address holding every connection with heads that never end cannot keep
    /// another address from `/metrics`, nor get a further connection of its own in.
    #[tokio::test]
    async fn one_address_holding_every_connection_gives_way_to_another() {
        use tokio::io::{AsyncReadExt as _, AsyncWriteExt as _};
        let (_version, versions) = watch::channel(0u64);
        let (stop, shutdown) = watch::channel(false);
        let site = bare_site(versions, shutdown);
        let (addr, task) = start("127.0.0.1:0".parse().unwrap(), site).await.expect("listen");
        let connect = |from: u8| connect_from(addr, from);
        let mut holders = Vec::new();
        for _ in 0..MAX_CONNECTIONS {
            let mut s = connect(1).await;
            s.write_all(b"GET /metrics HTTP/1.1\r\nHost: x\r\n").await.expect("half a head");
            holders.push(s);
        }
        tokio::time::sleep(Duration::from_millis(300)).await; // (all accepted)
        let ask = |mut s: tokio::net::TcpStream| async move {
            s.write_all(b"GET /metrics HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n").await.ok();
            let mut answer = Vec::new();
            let read = tokio::time::timeout(HEADER_TIMEOUT / 2, s.read_to_end(&mut answer)).await;
            (read.is_ok(), String::from_utf8_lossy(&answer).into_owned())
        };
        let (ended, answer) = ask(connect(1).await).await;
        assert!(ended && answer.is_empty(), "the flooder's own newcomer is closed unanswered: {answer:?}");
        let (ended, answer) = ask(connect(2).await).await;
        assert!(
            ended && answer.starts_with("HTTP/1.1 200"),
            "another address is answered at once: {answer:?}"
        );
        // the flooder's oldest connection was the one closed
        let mut first = holders.remove(0);
        let mut sink = Vec::new();
        let closed = tokio::time::timeout(Duration::from_secs(1), first.read_to_end(&mut sink)).await;
        assert!(closed.is_ok_and(|r| r.is_ok_and(|n| n == 0)), "its oldest connection was closed");
        stop.send(true).expect("stop");
        task.await.expect("the listener ends");
    }

    /// Event streams are shared out as connections are: one address holding every stream gives one
    /// up to a reader from another address (that stream ends), never to itself.
    #[tokio::test]
    async fn one_address_holding_every_event_stream_gives_way_to_another() {
        use http_body_util::BodyExt as _;
        let (_version, versions) = watch::channel(0u64);
        let (_stop, shutdown) = watch::channel(false);
        let site = Arc::new(bare_site(versions, shutdown));
        let mut held: Vec<Body> =
            (0..MAX_EVENT_CLIENTS).map(|_| events(&site, ip(1)).expect("a stream within the cap")).collect();
        assert_eq!(Places::len(&site.streams), MAX_EVENT_CLIENTS);
        assert!(events(&site, ip(1)).is_none(), "the same address: refused (503)");
        let mut newcomer = events(&site, ip(2)).expect("another address's reader gets a stream");
        assert_eq!(Places::len(&site.streams), MAX_EVENT_CLIENTS, "one of ip 1's gave way");
        // the newcomer's stream runs; the oldest of the flood's ends after what it was sent
        let first = tokio::time::timeout(Duration::from_secs(5), newcomer.frame()).await;
        assert!(first.is_ok_and(|f| f.is_some()), "the newcomer's first event");
        let mut oldest = held.remove(0);
        let ended = tokio::time::timeout(Duration::from_secs(5), async {
            while let Some(frame) = oldest.frame().await {
                assert!(frame.is_ok());
            }
        })
        .await;
        assert!(ended.is_ok(), "the flood's oldest stream ended");
        drop((held, newcomer));
    }

    /// Red-team pass 4, F2: the listener counted raw addresses, so one IPv6 host's /64 (or one
    /// customer's /56) supplied a fresh address for every event stream and held them all. Now they
    /// count as the SSH side's groups do: the 32 streams of 32 addresses of one /56 give way to a
    /// reader from another customer, and not to a 33rd address of their own /64.
    #[tokio::test]
    async fn one_customers_many_ipv6_addresses_hold_the_event_streams_as_one() {
        let (_version, versions) = watch::channel(0u64);
        let (_stop, shutdown) = watch::channel(false);
        let site = Arc::new(bare_site(versions, shutdown));
        let v6 = |s: String| s.parse::<IpAddr>().expect("an IPv6 address");
        let held: Vec<Body> = (0..MAX_EVENT_CLIENTS)
            .map(|k| events(&site, v6(format!("2001:db8:0:ab{:02x}::{k:x}", k % 4))).expect("a stream"))
            .collect();
        assert_eq!(Places::len(&site.streams), MAX_EVENT_CLIENTS);
        assert!(events(&site, v6("2001:db8:0:ab00::ffff".into())).is_none(), "their own /64: refused (503)");
        assert!(events(&site, v6("2001:db8:1::1".into())).is_some(), "another customer's reader: let in");
        assert!(events(&site, ip(9)).is_some(), "an IPv4 reader: let in");
        assert_eq!(Places::len(&site.streams), MAX_EVENT_CLIENTS);
        drop(held);
    }

    /// Red-team pass 4, left then: 32 IPv4 addresses held the 32 event streams, each counted apart.
    /// Now an IPv4 address counts by its /24 first (where one host's rented addresses sit): the
    /// streams of 32 addresses of one /24 give way to a reader from another /24, not to a 33rd
    /// address of their own.
    #[tokio::test]
    async fn many_ipv4_addresses_of_one_24_hold_the_event_streams_as_one() {
        let (_version, versions) = watch::channel(0u64);
        let (_stop, shutdown) = watch::channel(false);
        let site = Arc::new(bare_site(versions, shutdown));
        let v4 = |a: [u8; 4]| IpAddr::from(a);
        let held: Vec<Body> = (0..MAX_EVENT_CLIENTS)
            .map(|k| events(&site, v4([198, 51, 100, k as u8])).expect("a stream"))
            .collect();
        assert_eq!(Places::len(&site.streams), MAX_EVENT_CLIENTS);
        assert!(events(&site, v4([198, 51, 100, 200])).is_none(), "their own /24: refused (503)");
        assert!(events(&site, v4([198, 51, 101, 1])).is_some(), "a reader from another /24: let in");
        assert!(events(&site, v4([203, 0, 113, 7])).is_some(), "and another");
        assert_eq!(Places::len(&site.streams), MAX_EVENT_CLIENTS);
        // each /24 holding one now but the flood's, which holds 30: a third outsider gets in too
        assert!(events(&site, v4([192, 0, 2, 1])).is_some());
        drop(held);
    }

    /// A reader that never reads: its stream holds [`EVENT_BUFFER`] events, then ends (the count of
    /// streams goes back down) however often the world changes; nothing more is buffered for it.
    #[tokio::test]
    async fn a_reader_too_slow_is_dropped_not_buffered_for() {
        let (version, versions) = watch::channel(0u64);
        let (_stop, shutdown) = watch::channel(false);
        let site = Arc::new(bare_site(versions, shutdown));
        let body = events(&site, ip(1)).expect("a stream");
        assert_eq!(Places::len(&site.streams), 1);
        let deadline = tokio::time::Instant::now() + Duration::from_secs(20);
        let mut changes = 0;
        while Places::len(&site.streams) > 0 {
            assert!(tokio::time::Instant::now() < deadline, "still streaming after {changes} changes");
            version.send_modify(|v| *v += 1);
            changes += 1;
            tokio::time::sleep(Duration::from_secs(1) / EVENT_RATE + Duration::from_millis(20)).await;
        }
        assert!(changes > EVENT_BUFFER, "dropped after {changes} changes");
        drop(body);
    }
    /// Red-team pass 8: a world of a thousand players makes each event ~120 KB; a stream of it
    /// ten times a second gave one reader 1.2 MB/s (32 streams from one address, 39 MB/s). A
    /// stream keeps within its bytes a second whatever the events' size, and small events still
    /// come at the full rate.
    #[tokio::test]
    async fn a_stream_keeps_within_its_bytes_a_second() {
        use http_body_util::BodyExt as _;
        const SECONDS: u64 = 3;
        let rate = EVENT_RATE as usize * SECONDS as usize;
        for (players, least, most) in [(120_000, 2, 3), (200, rate * 7 / 10, rate + 1)] {
            let (version, versions) = watch::channel(0u64);
            let (_stop, shutdown) = watch::channel(false);
            let mut site = bare_site(versions, shutdown);
            site.players = Box::new(move || format!("\"{}\"", "x".repeat(players)));
            let site = Arc::new(site);
            let mut body = events(&site, ip(1)).expect("a stream");
            let (start, mut events, mut bytes) = (tokio::time::Instant::now(), 0, 0);
            while start.elapsed() < Duration::from_secs(SECONDS) {
                version.send_modify(|v| *v += 1); // the world changes all the time
                tokio::time::sleep(Duration::from_millis(20)).await;
                while let Some(Some(Ok(frame))) = futures_util::FutureExt::now_or_never(body.frame()) {
                    let data = frame.into_data().unwrap_or_default();
                    events += usize::from(data.windows(6).any(|w| w == b"data: "));
                    bytes += data.len();
                }
            }
            let budget = SECONDS as usize * EVENT_BYTES_PER_SECOND + players + 64;
            assert!(bytes <= budget, "{bytes} bytes in {SECONDS} s of {players}-byte events");
            assert!((least..=most).contains(&events), "{events} events of {players} bytes in {SECONDS} s");
        }
    }
}
