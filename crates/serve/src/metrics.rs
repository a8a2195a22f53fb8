//! What `serve --http` shows at `/metrics`, in Prometheus' text format (0.0.4), encoded by the
//! official client crate (`prometheus-client`). Two kinds of numbers:
//!
//! - **Counted as it happens** ([`Metrics`]): joins, refusals by reason, frames and bytes sent to
//!   players, the time from a key to the frame that follows it, the CPU time of each connection's
//!   key exchange; spectators now, their joins and refusals. Atomics, cheap enough to keep whether
//!   or not anyone scrapes.
//! - **Read at each scrape** ([`Snapshot`], through [`Live`]): players and handshakes now, the
//!   records' writes and failures, the shared world's messages (`--world`). They are kept elsewhere
//!   already; the scrape asks for them.
//!
//! Names follow Prometheus' conventions: `mazewalk_` first, base units (`_seconds`, `_bytes`),
//! counters end in `_total`. Beside them, the standard process metrics every Prometheus client
//! library exports (`process_cpu_seconds_total`, `process_resident_memory_bytes`, …: [`Process`]),
//! unprefixed, so that a dashboard made for any service shows this one's CPU, memory and files.

use prometheus_client::collector::Collector;
use prometheus_client::encoding::{DescriptorEncoder, EncodeMetric as _};
use prometheus_client::metrics::counter::{ConstCounter, Counter};
use prometheus_client::metrics::family::Family;
use prometheus_client::metrics::gauge::{ConstGauge, Gauge};
use prometheus_client::metrics::histogram::{Histogram, exponential_buckets};
use prometheus_client::metrics::info::Info;
use prometheus_client::registry::{Registry, Unit};

use std::sync::{Mutex, PoisonError};
use std::time::{Duration, Instant};

use crate::slots::{Refusal, Role};

/// A refusal's reason as a label.
type Reason = Vec<(&'static str, &'static str)>;

/// The numbers counted as they happen (see the module's doc). Clones share them.
#[derive(Clone, Debug)]
pub struct Metrics {
    joins: Counter,
    refusals: Family<Reason, Counter>,
    frames: Counter,
    bytes: Counter,
    key_to_frame: Histogram,
    /// Spectators watching now, and those let in and refused so far (issue #43).
    spectators: Gauge,
    spectator_joins: Counter,
    spectator_refusals: Counter,
    /// Players and spectators pushed out of their places by newcomers, by role.
    pushed_out: Family<Reason, Counter>,
    handshake_cpu: Histogram,
    /// Players' sessions recorded (`--record-dir`): started, not started for want of room, and
    /// stopped early — a file not made or a write failed, a cap reached, a write dropped because
    /// the recording's queue was full.
    recordings: Counter,
    recording_refusals: Counter,
    recording_errors: Counter,
    recordings_capped: Counter,
    recording_drops: Counter,
}

/// Every refusal's reason, as its label says it.
const REASONS: [&str; 4] = ["slots", "per_address", "handshakes", "rate"];

/// Every role a newcomer may push out of its place, as its label says it.
const ROLES: [&str; 2] = ["player", "spectator"];

impl Default for Metrics {
    fn default() -> Metrics {
        let refusals = Family::<Reason, Counter>::default();
        for reason in REASONS {
            let _ = refusals.get_or_create(&vec![("reason", reason)]); // shown at 0 from the start
        }
        let pushed_out = Family::<Reason, Counter>::default();
        for role in ROLES {
            let _ = pushed_out.get_or_create(&vec![("role", role)]); // shown at 0 from the start
        }
        Metrics {
            joins: Counter::default(),
            refusals,
            frames: Counter::default(),
            bytes: Counter::default(),
            // 0.5 ms to 1 s, doubling: a frame on a LAN is a few ms, a slow link's hundreds.
            key_to_frame: Histogram::new(exponential_buckets(0.0005, 2.0, 12)),
            spectators: Gauge::default(),
            spectator_joins: Counter::default(),
            spectator_refusals: Counter::default(),
            pushed_out,
            // 50 µs to 0.4 s, doubling: a stock OpenSSH client's exchange is about 1 ms of CPU.
            handshake_cpu: Histogram::new(exponential_buckets(0.000_05, 2.0, 14)),
            recordings: Counter::default(),
            recording_refusals: Counter::default(),
            recording_errors: Counter::default(),
            recordings_capped: Counter::default(),
            recording_drops: Counter::default(),
        }
    }
}

impl Metrics {
    /// A player joined the maze.
    pub(crate) fn joined(&self) {
        self.joins.inc();
    }

    /// A connection was refused for `refusal`.
    pub(crate) fn refused(&self, refusal: &Refusal) {
        let reason = match refusal {
            Refusal::Spectators(_) | Refusal::SpectatorsFromThisAddress(_) => {
                self.spectator_refusals.inc();
                return;
            }
            Refusal::Full(_) | Refusal::AllFull(..) => REASONS[0],
            Refusal::FromThisAddress(_) => REASONS[1],
            Refusal::Busy => REASONS[2],
            Refusal::TooFast => REASONS[3],
        };
        self.refusals.get_or_create(&vec![("reason", reason)]).inc();
    }

    /// `bytes` were handed to a player's channel; `frame`: they held a frame; `key`: the seconds since
    /// the first key that frame answers.
    pub(crate) fn sent(&self, bytes: usize, frame: bool, key: Option<f64>) {
        self.bytes.inc_by(bytes as u64);
        if frame {
            self.frames.inc();
        }
        if let Some(seconds) = key {
            self.key_to_frame.observe(seconds);
        }
    }

    /// A newcomer pushed out a `role` of the address holding the most (the server was full).
    pub(crate) fn pushed_out(&self, role: Role) {
        let role = match role {
            Role::Player => ROLES[0],
            Role::Spectator => ROLES[1],
        };
        self.pushed_out.get_or_create(&vec![("role", role)]).inc();
    }

    /// A spectator began watching.
    pub(crate) fn spectator_joined(&self) {
        self.spectator_joins.inc();
        self.spectators.inc();
    }

    /// A spectator stopped watching.
    pub(crate) fn spectator_left(&self) {
        self.spectators.dec();
    }

    /// A connection's key exchange ended (done, or the connection closed before it was): `cpu`, the
    /// CPU time the SSH library spent on the connection until then.
    pub(crate) fn key_exchange(&self, cpu: std::time::Duration) {
        self.handshake_cpu.observe(cpu.as_secs_f64());
    }

    /// A player's session began to be recorded.
    pub(crate) fn recording_started(&self) {
        self.recordings.inc();
    }

    /// A player's session was not recorded: no room in the directory.
    pub(crate) fn recording_refused(&self) {
        self.recording_refusals.inc();
    }

    /// A cast could not be made or written (the recording stopped there).
    pub(crate) fn recording_failed(&self) {
        self.recording_errors.inc();
    }

    /// A cast reached its byte cap (the recording stopped there).
    pub(crate) fn recording_capped(&self) {
        self.recordings_capped.inc();
    }

    /// A write to a cast was dropped: its queue was full (the recording stopped there).
    pub(crate) fn recording_dropped(&self) {
        self.recording_drops.inc();
    }

    /// Recordings started, and (refused, failed, capped, dropped) so far.
    #[must_use]
    pub fn recordings(&self) -> (u64, [u64; 4]) {
        let stopped = [
            &self.recording_refusals,
            &self.recording_errors,
            &self.recordings_capped,
            &self.recording_drops,
        ];
        (self.recordings.get(), stopped.map(Counter::get))
    }

    /// Joins so far.
    #[must_use]
    pub fn joins(&self) -> u64 {
        self.joins.get()
    }
}

/// The numbers read at each scrape (see the module's doc).
#[derive(Clone, Copy, Debug, Default)]
pub struct Snapshot {
    /// Players in the maze on this server now.
    pub players: usize,
    /// Connections still logging in now.
    pub handshakes: usize,
    /// The records' (written, failed, dropped) so far, when records are kept.
    pub records: Option<(u64, u64, u64)>,
    /// The shared world's task, with `--world`.
    pub world: Option<crate::shared::Stats>,
}

/// Reads a [`Snapshot`] at each scrape.
pub struct Live(pub Box<dyn Fn() -> Snapshot + Send + Sync>);

impl std::fmt::Debug for Live {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Live")
    }
}

fn gauge(encoder: &mut DescriptorEncoder, name: &str, help: &str, value: i64) -> std::fmt::Result {
    let gauge = ConstGauge::new(value);
    gauge.encode(encoder.encode_descriptor(name, help, None, gauge.metric_type())?)
}

fn counter(
    encoder: &mut DescriptorEncoder,
    name: &str,
    help: &str,
    unit: Option<&Unit>,
    value: u64,
) -> std::fmt::Result {
    let counter = ConstCounter::new(value);
    counter.encode(encoder.encode_descriptor(name, help, unit, counter.metric_type())?)
}

impl Collector for Live {
    fn encode(&self, mut encoder: DescriptorEncoder) -> std::fmt::Result {
        let now = (self.0)();
        let whole = |n: usize| i64::try_from(n).unwrap_or(i64::MAX);
        gauge(&mut encoder, "players", "Players in the maze on this server now.", whole(now.players))?;
        gauge(
            &mut encoder,
            "handshakes",
            "Connections still logging in (key exchange, authentication) now.",
            whole(now.handshakes),
        )?;
        if let Some((written, failed, dropped)) = now.records {
            counter(&mut encoder, "records_written", "Finishes written to the records.", None, written)?;
            counter(
                &mut encoder,
                "records_failed",
                "Finishes the records store failed to write (kept in memory, written later).",
                None,
                failed,
            )?;
            counter(
                &mut encoder,
                "records_dropped",
                "Finishes dropped because the records queue was full.",
                None,
                dropped,
            )?;
        }
        if let Some(world) = now.world {
            let heard = world.heard;
            let received =
                heard.applied + heard.own + heard.stale + heard.dropped + heard.unknown + world.too_long;
            counter(
                &mut encoder,
                "world_messages_received",
                "Messages heard from the shared world.",
                None,
                received,
            )?;
            counter(
                &mut encoder,
                "world_messages_dropped",
                "Messages from the shared world dropped: malformed, out of bounds, another maze or too long.",
                None,
                heard.dropped + world.too_long,
            )?;
            counter(
                &mut encoder,
                "world_messages_published",
                "Messages this server published to the shared world.",
                None,
                world.published,
            )?;
            counter(
                &mut encoder,
                "world_received",
                "Bytes heard from the shared world.",
                Some(&Unit::Bytes),
                world.heard_bytes,
            )?;
            counter(
                &mut encoder,
                "world_published",
                "Bytes published to the shared world.",
                Some(&Unit::Bytes),
                world.published_bytes,
            )?;
            gauge(
                &mut encoder,
                "world_online",
                "Whether the shared world (Redis) answers now (1) or not (0).",
                i64::from(world.online),
            )?;
            counter(
                &mut encoder,
                "world_outages",
                "Times the shared world went offline.",
                None,
                world.outages,
            )?;
        }
        Ok(())
    }
}

/// The standard process metrics of Prometheus' client libraries, read at a scrape at most once a
/// [`PROCESS_REFRESH`]: CPU time (the process's CPU clock), and from Linux's `/proc/self` the
/// resident and virtual memory, the threads, the open files and their limit. Where a figure cannot
/// be read (another system, a `/proc` not mounted) it is left out. The start time is when the
/// registry was made, at the server's start (`/proc` gives the process's own only in clock ticks
/// since boot).
#[derive(Debug)]
pub struct Process {
    /// Seconds since the Unix epoch when the registry was made.
    started: f64,
    /// The figures last read, and when.
    last: Mutex<Option<(Instant, ProcessFigures)>>,
}

/// The process's figures are read again at a scrape only when the last reading is this old: a
/// reading costs two `/proc` files and a listing of every open descriptor (red-team pass 10:
/// `/metrics` asked for as fast as 64 connections of one address could took 0.6–0.9 of a core, 60 %
/// of it in `/proc`, and a player's median key-to-frame time from 1 ms to 114–140 ms). Prometheus
/// scrapes every 15 s or so; a second is fresh enough for it.
pub const PROCESS_REFRESH: Duration = Duration::from_secs(1);

impl Process {
    fn now() -> Process {
        let since = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH);
        Process { started: since.map_or(0.0, |d| d.as_secs_f64()), last: Mutex::new(None) }
    }

    /// The figures at `now`: the last reading if it is younger than [`PROCESS_REFRESH`], else
    /// `read()`'s, kept for the next scrapes.
    fn figures(&self, now: Instant, read: impl FnOnce() -> ProcessFigures) -> ProcessFigures {
        let mut last = self.last.lock().unwrap_or_else(PoisonError::into_inner);
        match *last {
            Some((at, figures)) if now.saturating_duration_since(at) < PROCESS_REFRESH => figures,
            _ => {
                let figures = read();
                *last = Some((now, figures));
                figures
            }
        }
    }
}

/// The figures [`Process`] reads, each `None` where it could not be read.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct ProcessFigures {
    cpu_seconds: Option<f64>,
    resident_bytes: Option<u64>,
    virtual_bytes: Option<u64>,
    threads: Option<u64>,
    open_fds: Option<u64>,
    max_fds: Option<u64>,
}

/// At most this many bytes of a `/proc` file are read (`status` and `limits` are under 2 KiB).
const PROC_FILE_LIMIT: u64 = 16 * 1024;

fn read_proc(name: &str) -> Option<String> {
    use std::io::Read as _;
    let mut text = String::new();
    let file = std::fs::File::open(format!("/proc/self/{name}")).ok()?;
    file.take(PROC_FILE_LIMIT).read_to_string(&mut text).ok()?;
    Some(text)
}

/// `VmRSS`, `VmSize` (in bytes) and `Threads` of a `/proc/PID/status` text.
fn status_figures(status: &str) -> (Option<u64>, Option<u64>, Option<u64>) {
    let field = |name: &str| {
        let line = status.lines().find_map(|line| line.strip_prefix(name)?.strip_prefix(':'))?;
        let mut words = line.split_whitespace();
        let value: u64 = words.next()?.parse().ok()?;
        match words.next() {
            Some("kB") => value.checked_mul(1024),
            None => Some(value),
            Some(_) => None,
        }
    };
    (field("VmRSS"), field("VmSize"), field("Threads"))
}

/// The soft limit of open files of a `/proc/PID/limits` text (`None` where it is unlimited).
fn max_open_files(limits: &str) -> Option<u64> {
    let line = limits.lines().find_map(|line| line.strip_prefix("Max open files"))?;
    line.split_whitespace().next()?.parse().ok()
}

impl ProcessFigures {
    fn read() -> ProcessFigures {
        #[cfg(unix)]
        let cpu_seconds = cpu_time::ProcessTime::try_now().ok().map(|t| t.as_duration().as_secs_f64());
        #[cfg(not(unix))]
        let cpu_seconds = None;
        let (resident_bytes, virtual_bytes, threads) =
            read_proc("status").map_or((None, None, None), |status| status_figures(&status));
        let open_fds = std::fs::read_dir("/proc/self/fd").ok().map(|dir| dir.count() as u64);
        let max_fds = read_proc("limits").and_then(|limits| max_open_files(&limits));
        ProcessFigures { cpu_seconds, resident_bytes, virtual_bytes, threads, open_fds, max_fds }
    }
}

impl Collector for Process {
    fn encode(&self, mut encoder: DescriptorEncoder) -> std::fmt::Result {
        encode_process(&mut encoder, self.started, self.figures(Instant::now(), ProcessFigures::read))
    }
}

fn encode_process(encoder: &mut DescriptorEncoder, started: f64, now: ProcessFigures) -> std::fmt::Result {
    let whole = |n: u64| i64::try_from(n).unwrap_or(i64::MAX);
    if let Some(seconds) = now.cpu_seconds {
        let counter = ConstCounter::new(seconds);
        let help = "Total user and system CPU time spent in seconds.";
        counter.encode(encoder.encode_descriptor(
            "process_cpu_seconds",
            help,
            None,
            counter.metric_type(),
        )?)?;
    }
    let figures = [
        ("process_resident_memory_bytes", "Resident memory size in bytes.", now.resident_bytes),
        ("process_virtual_memory_bytes", "Virtual memory size in bytes.", now.virtual_bytes),
        ("process_threads", "Number of OS threads in the process.", now.threads),
        ("process_open_fds", "Number of open file descriptors.", now.open_fds),
        ("process_max_fds", "Maximum number of open file descriptors.", now.max_fds),
    ];
    for (name, help, value) in figures {
        if let Some(value) = value {
            gauge(encoder, name, help, whole(value))?;
        }
    }
    let start = ConstGauge::new(started);
    let help = "Start time of the process since unix epoch in seconds.";
    start.encode(encoder.encode_descriptor("process_start_time_seconds", help, None, start.metric_type())?)
}

/// The registry `/metrics` encodes: `metrics`, what `live` reads, the build's version, and the
/// process's own figures ([`Process`]).
#[must_use]
pub fn registry(metrics: &Metrics, live: Live) -> Registry {
    let mut root = Registry::default();
    root.register_collector(Box::new(Process::now()));
    let registry = root.sub_registry_with_prefix("mazewalk");
    registry.register("joins", "Players who joined the maze", metrics.joins.clone());
    registry.register(
        "refusals",
        "Connections refused, by reason: slots (every player's slot taken), per_address, handshakes (every handshake slot taken), rate",
        metrics.refusals.clone(),
    );
    registry.register(
        "pushed_out",
        "Players (role=player) and spectators (role=spectator) pushed out of their places by newcomers: the server was full and their address held the most places",
        metrics.pushed_out.clone(),
    );
    registry.register("frames_sent", "Frames handed to players' SSH channels", metrics.frames.clone());
    registry.register_with_unit(
        "sent",
        "Bytes handed to players' SSH channels (frames, terminal set-up and goodbyes)",
        Unit::Bytes,
        metrics.bytes.clone(),
    );
    registry.register_with_unit(
        "key_to_frame",
        "Time from a key's arrival to the next frame handed to the player's SSH channel",
        Unit::Seconds,
        metrics.key_to_frame.clone(),
    );
    registry.register("spectators", "Spectators watching on this server now", metrics.spectators.clone());
    registry.register("spectator_joins", "Spectators who began watching", metrics.spectator_joins.clone());
    registry.register(
        "spectator_refusals",
        "Spectators refused because every spectator's slot, or every one its address may take, was taken",
        metrics.spectator_refusals.clone(),
    );
    registry.register_with_unit(
        "handshake_cpu",
        "CPU time the SSH library spent on a connection's key exchange (thread CPU time between its reads and writes, until the keys were exchanged or the connection closed); one observation for each connection let in (refused ones have none)",
        Unit::Seconds,
        metrics.handshake_cpu.clone(),
    );
    registry.register("recordings", "Players' sessions recorded (--record-dir)", metrics.recordings.clone());
    registry.register(
        "recording_refusals",
        "Players' sessions not recorded: the recordings in progress left no room under --record-max-total, their address had --record-max-per-address recordings in progress, or the directory held --record-max-files casts",
        metrics.recording_refusals.clone(),
    );
    registry.register(
        "recording_errors",
        "Casts that could not be made or written (each stopped there; the game went on)",
        metrics.recording_errors.clone(),
    );
    registry.register(
        "recordings_capped",
        "Casts that reached --record-max-bytes (each stopped there, whole lines)",
        metrics.recordings_capped.clone(),
    );
    registry.register(
        "recording_drops",
        "Casts stopped because their write queue was full (the disk slower than the game)",
        metrics.recording_drops.clone(),
    );
    registry.register("build", "The mazewalk build", Info::new(vec![("version", env!("CARGO_PKG_VERSION"))]));
    registry.register_collector(Box::new(live));
    root
}

/// `registry` in Prometheus' text format.
#[must_use]
pub fn encode(registry: &Registry) -> String {
    let mut text = String::new();
    // (Writing to a String cannot fail; an encoder's own error would leave what it wrote.)
    let _ = prometheus_client::encoding::prometheus_text::encode(&mut text, registry);
    text
}

/// The `Content-Type` of [`encode`]'s text.
pub const CONTENT_TYPE: &str = prometheus_client::encoding::prometheus_text::CONTENT_TYPE;

#[cfg(test)]
mod tests {
    use super::*;

    /// The names and values a scrape shows, counted and read live alike.
    #[test]
    fn the_text_has_the_counted_and_the_live_numbers() {
        let metrics = Metrics::default();
        metrics.joined();
        metrics.joined();
        metrics.recording_started();
        metrics.recording_started();
        metrics.recording_dropped();
        metrics.refused(&Refusal::Full(4));
        metrics.refused(&Refusal::FromThisAddress(2));
        metrics.refused(&Refusal::FromThisAddress(2));
        metrics.sent(1000, true, Some(0.003));
        metrics.sent(24, false, None);
        metrics.spectator_joined();
        metrics.spectator_joined();
        metrics.spectator_left();
        metrics.refused(&Refusal::Spectators(1));
        metrics.key_exchange(std::time::Duration::from_micros(300));
        let live =
            Live(Box::new(|| Snapshot { players: 3, handshakes: 1, records: Some((5, 1, 0)), world: None }));
        let text = encode(&registry(&metrics, live));
        for line in [
            "mazewalk_joins_total 2",
            "mazewalk_refusals_total{reason=\"slots\"} 1",
            "mazewalk_refusals_total{reason=\"per_address\"} 2",
            "mazewalk_refusals_total{reason=\"handshakes\"} 0",
            "mazewalk_frames_sent_total 1",
            "mazewalk_sent_bytes_total 1024",
            "mazewalk_key_to_frame_seconds_count 1",
            "mazewalk_key_to_frame_seconds_bucket{le=\"0.004\"} 1",
            "mazewalk_key_to_frame_seconds_bucket{le=\"0.002\"} 0",
            "mazewalk_handshake_cpu_seconds_count 1",
            "mazewalk_handshake_cpu_seconds_sum 0.0003",
            "mazewalk_handshake_cpu_seconds_bucket{le=\"0.0004\"} 1",
            "mazewalk_handshake_cpu_seconds_bucket{le=\"0.0002\"} 0",
            "mazewalk_players 3",
            "mazewalk_handshakes 1",
            "mazewalk_records_written_total 5",
            "mazewalk_records_failed_total 1",
            "mazewalk_spectators 1",
            "mazewalk_spectator_joins_total 2",
            "mazewalk_spectator_refusals_total 1",
            "mazewalk_refusals_total{reason=\"rate\"} 0",
            "mazewalk_recordings_total 2",
            "mazewalk_recording_drops_total 1",
            "mazewalk_recording_errors_total 0",
            "mazewalk_recordings_capped_total 0",
            "mazewalk_recording_refusals_total 0",
        ] {
            assert!(text.lines().any(|l| l == line), "no line {line:?} in:\n{text}");
        }
        assert!(
            text.contains(&format!("mazewalk_build_info{{version=\"{}\"}} 1", env!("CARGO_PKG_VERSION"))),
            "{text}"
        );
        assert!(!text.contains("world_"), "no world without --world:\n{text}");
    }

    /// A family's every label is shown from the start, at 0, so that a scrape before the first
    /// push-out (or refusal) already has the series a dashboard or an alert asks for.
    #[test]
    fn labelled_counters_show_zero_from_the_start() {
        let metrics = Metrics::default();
        let live = Live(Box::new(|| Snapshot { players: 0, handshakes: 0, records: None, world: None }));
        let text = encode(&registry(&metrics, live));
        for line in [
            "mazewalk_pushed_out_total{role=\"player\"} 0",
            "mazewalk_pushed_out_total{role=\"spectator\"} 0",
            "mazewalk_refusals_total{reason=\"slots\"} 0",
        ] {
            assert!(text.lines().any(|l| l == line), "no line {line:?} in:\n{text}");
        }
        metrics.pushed_out(Role::Spectator);
        let live = Live(Box::new(|| Snapshot { players: 0, handshakes: 0, records: None, world: None }));
        let text = encode(&registry(&metrics, live));
        assert!(text.lines().any(|l| l == "mazewalk_pushed_out_total{role=\"spectator\"} 1"), "{text}");
    }

    /// The process's own figures, unprefixed under their standard names, read from this test's
    /// process: its memory and files are there and plausible, the CPU time counts, the start
    /// time is when the registry was made.
    #[test]
    #[cfg(target_os = "linux")]
    fn the_text_has_the_standard_process_metrics() {
        let before =
            std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).unwrap().as_secs_f64();
        let live = Live(Box::new(Snapshot::default));
        let text = encode(&registry(&Metrics::default(), live));
        let value = |name: &str| -> f64 {
            let line = text.lines().find(|l| l.split(' ').next() == Some(name));
            line.and_then(|l| l.split(' ').nth(1))
                .and_then(|v| v.parse().ok())
                .unwrap_or_else(|| panic!("no {name} in:\n{text}"))
        };
        assert!(value("process_resident_memory_bytes") >= 1024.0 * 1024.0, "{text}");
        assert!(value("process_virtual_memory_bytes") >= value("process_resident_memory_bytes"), "{text}");
        assert!(value("process_threads") >= 1.0, "{text}");
        // stdin, stdout, stderr at least, and this process's limit above them
        assert!(
            value("process_open_fds") >= 3.0 && value("process_max_fds") >= value("process_open_fds"),
            "{text}"
        );
        assert!(value("process_cpu_seconds_total") > 0.0, "{text}");
        let started = value("process_start_time_seconds");
        assert!((before - 1.0..before + 60.0).contains(&started), "{started} against {before}");
        for kind in ["# TYPE process_cpu_seconds_total counter", "# TYPE process_open_fds gauge"] {
            assert!(text.lines().any(|l| l == kind), "no {kind:?} in:\n{text}");
        }
        assert!(!text.contains("mazewalk_process"), "{text}");
    }

    // red-team pass 10: a flood of scrapes read /proc at each (0.8 of a core from one address)
    #[test]
    fn the_process_figures_are_read_at_most_once_a_refresh() {
        let process = Process::now();
        let reads = std::cell::Cell::new(0u64);
        let read = || {
            reads.set(reads.get() + 1);
            ProcessFigures { threads: Some(reads.get()), ..ProcessFigures::default() }
        };
        let start = Instant::now();
        let first = process.figures(start, read);
        for k in 0..1000 {
            let now = start + PROCESS_REFRESH * k / 1000; // a thousand scrapes within the refresh
            assert_eq!(process.figures(now, read), first, "scrape {k}: the first reading again");
        }
        assert_eq!(reads.get(), 1, "one reading for a thousand scrapes");
        let later = process.figures(start + PROCESS_REFRESH, read);
        assert_eq!((reads.get(), later.threads), (2, Some(2)), "read again once it is a refresh old");
        let earlier = process.figures(start, read); // (a clock that went back: no reading, no panic)
        assert_eq!((reads.get(), earlier), (2, later));
    }

    /// `/proc/self/status` and `limits` as Linux writes them are read; anything else gives nothing.
    #[test]
    fn proc_texts_are_read_and_garbage_gives_nothing() {
        let status = "Name:\tmazewalk\nVmSize:\t  123456 kB\nVmRSS:\t    2048 kB\nThreads:\t7\n";
        assert_eq!(status_figures(status), (Some(2048 * 1024), Some(123_456 * 1024), Some(7)));
        assert_eq!(status_figures("VmRSS: lots kB\nVmSize: 1 MB\n"), (None, None, None));
        assert_eq!(status_figures("VmRSS: 99999999999999999999 kB"), (None, None, None));
        assert_eq!(status_figures(""), (None, None, None));
        let limits = "Limit                     Soft Limit           Hard Limit           Units     \n\
                      Max open files            1024                 524288               files     \n";
        assert_eq!(max_open_files(limits), Some(1024));
        assert_eq!(
            max_open_files("Max open files            unlimited            unlimited            files"),
            None
        );
        assert_eq!(max_open_files("garbage"), None);
    }
}
