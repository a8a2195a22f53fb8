//! The server's limits against abuse, each with its default (README "Host a maze" lists them), and
//! the input rate limiter. Pure: time comes in as seconds.

use std::time::Duration;

/// Every limit a server enforces. [`Limits::default`] is what `mazewalk serve` uses unless told.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// Players at once (`--max-players`): connections that logged in. More are told why and closed.
    pub max_players: usize,
    /// Spectators at once (`--max-spectators`): connections that logged in as `watch`. They have
    /// their own slots, never a player's.
    pub max_spectators: usize,
    /// Spectators at once from one address group (an IPv4 address, an IPv6 /64;
    /// `--max-spectators-per-address`): with no idle timeout, one address holding every spectator's
    /// place would hold it for good.
    pub max_spectators_per_address: usize,
    /// Connections still in the handshake (key exchange and authentication) at once, in all
    /// (`--max-handshakes`): they never take a player's slot. When these are all taken, a newcomer
    /// takes the slot of the one that has gone longest without progress ([`Slots`](crate::slots)).
    pub max_handshakes: usize,
    /// Connections at once from one address (`--max-per-address`), players, spectators and handshakes: an IPv4
    /// address, or an IPv6 /64 ([`address_group`](crate::slots::address_group)).
    pub max_per_address: usize,
    /// New connections a second from one address, once it has opened `2 × max_per_address` at once;
    /// more are refused.
    pub connect_rate: f64,
    /// From the TCP connection to a started game: key exchange, authentication, pty and shell.
    pub handshake_timeout: Duration,
    /// From the TCP connection to the keys exchanged: a client that has not finished its key
    /// exchange by then gives its slot up (a player's takes milliseconds, a few round trips).
    pub kex_timeout: Duration,
    /// After the game ends (the player quit or closed the channel) the connection is closed if the
    /// client has not closed it by then: a game's connection carries one game (issue #34: a client
    /// holding it open kept a player's slot).
    pub after_game: Duration,
    /// A player who sends nothing for this long is disconnected (`--idle-timeout`).
    pub idle_timeout: Duration,
    /// The largest terminal drawn, columns; a larger pty is drawn at this size (top-left).
    pub max_cols: u16,
    /// The largest terminal drawn, rows.
    pub max_rows: u16,
    /// Samples one address group's served screens (players' and spectators') draw a second
    /// together, at most: each screen gets an equal share (this over the group's logged-in
    /// connections, [`address_group`](crate::slots::address_group), as `max_per_address` counts
    /// them), never less than [`SCREEN_RATE_FLOOR`] ([`screen_share`]). A frame's samples are its
    /// cells × its glyphs' samples per cell (2 for half blocks and ASCII, 4 quadrants, 6 sextants), so a larger screen, a finer charset or more screens from one
    /// address draw at a lower frame rate, never above 60
    /// ([`SessionOptions::sample_rate`](mazewalk_walk::SessionOptions::sample_rate)). At the default
    /// ([`RENDER_RATE`]) a lone 200×60 screen in half blocks keeps 60 frames a second, a lone 400×150
    /// one gets 12, and 400×150 in sextants 4; 4 of those from one address get 4 between them, 16 of
    /// them about half a frame a second each (the floor), and 16 players at 120 × 40 behind one
    /// address 20 each.
    /// (Red-team pass 3: 16 connections from one address at 400×150 with textures and culling off
    /// took a core of the server and pushed another player's key-to-frame p99 from 10 ms to 771 ms;
    /// with a budget per screen they still took 1.16 cores.)
    pub render_rate: u32,
    /// Samples all served screens draw a second together, at most: each screen that is drawing
    /// (it drew in this second or the last, [`DrawMeter`]) gets an equal share of it, when that is
    /// less than its address group's ([`render_rate`](Self::render_rate)). Red-team pass 5: the
    /// budget per address group left many addresses (one screen each from 128 addresses, or 16 of
    /// one /24) free to take the whole machine, another player's key-to-frame p99 1.3 s; now they
    /// share this. The default, [`RENDER_TOTAL_PER_CORE`] for each core the server may use, is about
    /// 0.8 of a core's serving of 120 × 40 half-block screens (about 29 M samples a second a core,
    /// drawn, encoded and sent) and half a core's of 400 × 150 ones (about 42 M): 100 players at
    /// 120 × 40 turning in half blocks got 41–44 frames a second on two cores (49–52 without it) at
    /// `070be1f`, 37–40 with the foveated view at `72a5255`.
    pub render_total: u32,
    /// Window changes a screen follows a second, at most: one that comes sooner waits, and of those
    /// waiting only the latest size is drawn when its turn comes. (Each size drawn reallocates a
    /// screen of up to `max_cols × max_rows` cells: a flood of window changes alternating two sizes,
    /// 15,000 a second, cost the server half a core.) 0 follows every one.
    pub resize_rate: f64,
    /// Input bytes per second a player may send, sustained; beyond it input is dropped.
    pub input_rate: u32,
    /// Input bytes a player may send at once (the rate limiter's bucket).
    pub input_burst: u32,
    /// A keepalive goes to a client silent for this long …
    pub keepalive_interval: Duration,
    /// … and a client that leaves this many unanswered in a row is dropped (a half-open connection).
    pub keepalive_max: usize,
    /// A frame that cannot be written for this long (a client that stopped reading) drops the player.
    pub write_timeout: Duration,
    /// The kernel's send buffer per connection, bytes (`SO_SNDBUF`; Linux doubles it for its own
    /// bookkeeping): with the SSH window's worth in russh, all a client that stops reading can make
    /// the server hold.
    pub send_buffer: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            max_players: 256,
            max_spectators: 16,
            max_spectators_per_address: 4,
            max_handshakes: 128,
            max_per_address: 16,
            connect_rate: 8.0,
            handshake_timeout: Duration::from_secs(20),
            kex_timeout: Duration::from_secs(6),
            after_game: Duration::from_secs(2),
            idle_timeout: Duration::from_secs(30 * 60),
            max_cols: 400,
            max_rows: 150,
            render_rate: RENDER_RATE,
            render_total: render_total_default(),
            resize_rate: 10.0,
            input_rate: 16 * 1024,
            input_burst: 64 * 1024,
            keepalive_interval: Duration::from_secs(15),
            keepalive_max: 3,
            write_timeout: Duration::from_secs(10),
            send_buffer: 128 * 1024,
        }
    }
}

/// [`Limits::render_rate`]'s default: a 200 × 60 screen in half blocks (2 samples a cell) at 60
/// frames a second, an address group's.
pub const RENDER_RATE: u32 = 200 * 60 * 2 * 60;

/// The least share of [`Limits::render_rate`] a screen gets however many share its address group: a
/// 120 × 40 screen in half blocks at 20 frames a second. Many players behind one address (a
/// classroom's NAT) each keep a playable rate; an attacker's many large screens cost at most this
/// each (16 screens of 400 × 150 sextants: about half a frame a second each).
pub const SCREEN_RATE_FLOOR: u32 = 120 * 40 * 2 * 20;

/// [`Limits::render_total`]'s default for each core the server may use
/// (`std::thread::available_parallelism`): 16 lone 200 × 60 half-block screens at 60 frames a second.
pub const RENDER_TOTAL_PER_CORE: u32 = 16 * RENDER_RATE;

/// [`Limits::render_total`]'s default: [`RENDER_TOTAL_PER_CORE`] times the cores the process may use.
#[must_use]
pub fn render_total_default() -> u32 {
    let cores = std::thread::available_parallelism().map_or(1, std::num::NonZero::get);
    RENDER_TOTAL_PER_CORE.saturating_mul(u32::try_from(cores).unwrap_or(u32::MAX))
}

/// How many served screens are drawing now, for their share of [`Limits::render_total`]: the
/// screens that drew a frame in this second of the server's clock or in the last one, counted once
/// each (an idle screen, or a thousand, takes no share). Each screen keeps the second it last
/// counted itself in ([`DrawMeter::drew`]).
#[derive(Clone, Copy, Debug, Default)]
pub struct DrawMeter {
    /// The second counting now.
    second: u64,
    /// Screens that drew in it, and in the one before.
    now: u32,
    last: u32,
}

impl DrawMeter {
    /// A screen that last counted itself in second `mine` (`None`: never) drew a frame at `now`
    /// (seconds): counted in this second if it was not yet; its second to keep.
    pub fn drew(&mut self, mine: Option<u64>, now: f64) -> u64 {
        let second = now.max(0.0) as u64;
        if second != self.second {
            self.last = if second == self.second + 1 { self.now } else { 0 };
            (self.second, self.now) = (second, 0);
        }
        if mine != Some(second) {
            self.now = self.now.saturating_add(1);
        }
        second
    }

    /// The screens drawing at `now`: of this second or the last, the more; at least 1.
    #[must_use]
    pub fn drawing(&self, now: f64) -> u32 {
        let second = now.max(0.0) as u64;
        let counted = match second.checked_sub(self.second) {
            Some(0) => self.now.max(self.last),
            Some(1) => self.now,
            _ => 0,
        };
        counted.max(1)
    }
}

/// The samples a second a screen may draw: its address group's share ([`screen_share`]), but no more
/// than an equal share of `render_total` among the `drawing` screens ([`DrawMeter`]).
#[must_use]
pub fn drawing_share(render_rate: u32, group_screens: usize, render_total: u32, drawing: u32) -> u32 {
    screen_share(render_rate, group_screens).min(render_total / drawing.max(1))
}

/// The samples a second each of `screens` screens of one address group may draw under a group budget
/// of `render_rate`: an equal share, but never less than [`SCREEN_RATE_FLOOR`] (nor more than the
/// budget itself).
#[must_use]
pub fn screen_share(render_rate: u32, screens: usize) -> u32 {
    let equal = render_rate / u32::try_from(screens.max(1)).unwrap_or(u32::MAX);
    equal.max(SCREEN_RATE_FLOOR.min(render_rate))
}

/// A token bucket over bytes: `rate` a second, at most `burst` at once.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RateLimit {
    rate: f64,
    burst: f64,
    tokens: f64,
    last: f64,
}

impl RateLimit {
    /// A full bucket at time `now`.
    #[must_use]
    pub fn new(rate: u32, burst: u32, now: f64) -> RateLimit {
        RateLimit::per_second(f64::from(rate), burst, now)
    }

    /// A full bucket at time `now` that refills by one every `interval` seconds.
    #[must_use]
    pub(crate) fn new_per_interval(interval: f64, burst: u32, now: f64) -> RateLimit {
        RateLimit::per_second(1.0 / interval.max(1e-9), burst, now)
    }

    /// A full bucket at time `now` that refills at `rate` a second (a fraction allowed).
    #[must_use]
    pub(crate) fn per_second(rate: f64, burst: u32, now: f64) -> RateLimit {
        let burst = f64::from(burst.max(1));
        RateLimit { rate: rate.max(0.0), burst, tokens: burst, last: now }
    }

    /// Whether the bucket is full again at `now` (it has forgotten everything taken).
    #[must_use]
    pub(crate) fn is_full(&self, now: f64) -> bool {
        self.tokens + (now - self.last).max(0.0) * self.rate >= self.burst
    }

    /// Whether nothing may pass at `now` (less than one left, refilled as of `now`).
    #[must_use]
    pub(crate) fn is_empty(&self, now: f64) -> bool {
        self.tokens + (now - self.last).max(0.0) * self.rate < 1.0
    }

    /// Whether all of `n` could pass at `now` (taking none).
    #[must_use]
    pub(crate) fn has(&self, n: usize, now: f64) -> bool {
        (self.tokens + (now - self.last).max(0.0) * self.rate).min(self.burst) >= n as f64
    }

    /// Whether all of `n` may pass at `now`: taken if so, else nothing is.
    pub(crate) fn take_all(&mut self, n: usize, now: f64) -> bool {
        if now > self.last {
            self.tokens = (self.tokens + (now - self.last) * self.rate).min(self.burst);
            self.last = now;
        }
        let whole = self.tokens >= n as f64;
        if whole {
            self.tokens -= n as f64;
        }
        whole
    }

    /// How many of `n` bytes arriving at `now` may pass (the rest are dropped).
    pub fn take(&mut self, n: usize, now: f64) -> usize {
        if now > self.last {
            self.tokens = (self.tokens + (now - self.last) * self.rate).min(self.burst);
            self.last = now;
        }
        let allowed = (n as f64).min(self.tokens.floor()).max(0.0);
        self.tokens -= allowed;
        allowed as usize
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bucket_passes_a_burst_then_the_rate() {
        let mut bucket = RateLimit::new(100, 1000, 0.0);
        assert_eq!(bucket.take(600, 0.0), 600);
        assert_eq!(bucket.take(600, 0.0), 400, "the rest of the burst");
        assert_eq!(bucket.take(600, 0.0), 0, "empty");
        assert_eq!(bucket.take(600, 1.0), 100, "refilled at the rate");
        assert_eq!(bucket.take(5000, 100.0), 1000, "never more than the burst");
        assert_eq!(bucket.take(10, 50.0), 0, "a clock going back refills nothing");
        assert!(bucket.is_empty(50.0) && bucket.is_empty(100.0009), "nothing left, a tenth short of one");
        assert!(!bucket.is_empty(100.01), "one again");
        let mut bucket = RateLimit::new(10, 100, 0.0);
        assert!(bucket.take_all(60, 0.0));
        assert!(!bucket.take_all(60, 0.0), "40 left: none taken");
        assert!(bucket.take_all(40, 0.0), "… all 40 still there");
        assert!(!bucket.take_all(1, 0.0) && bucket.take_all(10, 1.0), "refilled at the rate");
    }

    /// A bucket is full again exactly when what was taken has come back at the rate, and empty
    /// while less than one is left; a clock going back refills nothing.
    #[test]
    fn the_bucket_is_full_and_empty_on_the_dot() {
        let mut bucket = RateLimit::new(4, 8, 0.0);
        assert!(bucket.is_full(0.0) && !bucket.is_empty(0.0), "a new bucket");
        assert_eq!(bucket.take(8, 0.0), 8);
        assert!(bucket.is_empty(0.0) && bucket.is_empty(0.2) && !bucket.is_empty(0.25), "one back at 1/4 s");
        assert!(!bucket.is_full(1.75) && bucket.is_full(2.0), "all 8 back at 2 s");
        assert!(!bucket.is_full(-10.0) && bucket.is_empty(-10.0), "an earlier time refills nothing");
        let mut slow = RateLimit::new_per_interval(4.0, 2, 0.0);
        assert_eq!(slow.take(3, 0.0), 2);
        assert!(slow.is_empty(3.9) && !slow.is_empty(4.0), "one every 4 s");
        assert!(!slow.is_full(7.9) && slow.is_full(8.0));
    }

    /// At the turn of a second the screens of the last one still count until as many have drawn in
    /// this one; after a second with nobody drawing, none do.
    #[test]
    fn the_last_seconds_screens_count_until_this_ones_pass_them() {
        let mut meter = DrawMeter::default();
        let mut seconds = [None; 10];
        for mine in &mut seconds {
            *mine = Some(meter.drew(*mine, 5.5));
        }
        assert_eq!(meter.drawing(5.9), 10);
        seconds[0] = Some(meter.drew(seconds[0], 6.0));
        assert_eq!(meter.drawing(6.0), 10, "one of this second, ten of the last");
        for mine in &mut seconds[1..] {
            *mine = Some(meter.drew(*mine, 6.5));
        }
        assert_eq!(meter.drawing(7.2), 10, "the last second's ten");
        meter.drew(seconds[0], 9.0);
        assert_eq!(meter.drawing(9.0), 1, "a second with none between: only this one's");
        let mut meter = DrawMeter::default();
        meter.drew(None, 0.5);
        meter.drew(None, 0.6);
        meter.drew(None, 1.5);
        assert_eq!(meter.drawing(1.5), 2, "from the very first second too");
    }

    /// Frames a second of a `cols × rows` screen of `samples` samples a cell on a share.
    fn fps(share: u32, cols: u32, rows: u32, samples: u32) -> f64 {
        f64::from(share) / f64::from(cols * rows * samples)
    }

    #[test]
    fn a_groups_screens_share_the_budget_down_to_a_playable_floor() {
        let all = screen_share(RENDER_RATE, 1);
        assert_eq!(all, RENDER_RATE, "a lone screen draws at the whole budget");
        assert_eq!(screen_share(RENDER_RATE, 0), RENDER_RATE, "no screen counted yet: as one");
        // four 400 × 150 sextant screens from one address: one budget between them, 1 frame a second each
        assert_eq!(screen_share(RENDER_RATE, 4), RENDER_RATE / 4);
        assert!((fps(screen_share(RENDER_RATE, 4), 400, 150, 6) - 1.0).abs() < 1e-9);
        // sixteen players at 120 × 40 behind one NAT keep 20 frames a second each, not 9
        for screens in [16, 100, 10_000, usize::MAX] {
            let share = screen_share(RENDER_RATE, screens);
            assert_eq!(share, SCREEN_RATE_FLOOR, "{screens} screens");
            assert!((fps(share, 120, 40, 2) - 20.0).abs() < 1e-9);
            assert!(fps(share, 400, 150, 6) < 1.0, "a large fine screen stays under a frame a second");
        }
        // a host's budget below the floor is never exceeded by one screen
        assert_eq!(screen_share(100_000, 1), 100_000);
        assert_eq!(screen_share(100_000, 50), 100_000);
        // the share falls with the screens until the floor, never below it
        let shares: Vec<u32> = (1..40).map(|n| screen_share(RENDER_RATE, n)).collect();
        assert!(shares.windows(2).all(|w| w[1] <= w[0]));
        assert!(shares.iter().all(|&s| s >= SCREEN_RATE_FLOOR));
    }

    /// Red-team pass 5: one screen from each of 128 addresses each drew a whole group's budget and
    /// took the machine. Screens that draw share the server's total; idle ones take no share, and a
    /// screen counts once however many frames it draws.
    #[test]
    fn drawing_screens_share_the_servers_total_and_idle_ones_take_none() {
        let total = 16 * RENDER_RATE;
        let mut meter = DrawMeter::default();
        assert_eq!(meter.drawing(0.0), 1, "nobody drawing yet: a newcomer's share is the whole");
        // 128 screens drawing 12 frames a second each, for three seconds
        let mut seconds = [None; 128];
        for frame in 0..36 {
            let now = 10.0 + f64::from(frame) / 12.0;
            for mine in &mut seconds {
                *mine = Some(meter.drew(*mine, now));
            }
            assert_eq!(meter.drawing(now), 128, "at {now}: each counted once");
        }
        let attacked = drawing_share(RENDER_RATE, 1, total, meter.drawing(12.9));
        assert_eq!(attacked, total / 128, "each a 128th of the total, not a whole group budget");
        assert!(fps(attacked, 120, 40, 2) >= 15.0, "a player at 120 × 40 among them still plays");
        // they stop: a second later their count is last second's, two seconds later nothing
        assert_eq!(meter.drawing(13.5), 128);
        assert_eq!(meter.drawing(14.2), 1);
        let mut lone = None;
        lone = Some(meter.drew(lone, 14.2));
        assert_eq!(meter.drawing(14.3), 1, "a lone screen again: its group's budget");
        assert_eq!(drawing_share(RENDER_RATE, 1, total, meter.drawing(14.3)), RENDER_RATE);
        assert_eq!(meter.drew(lone, 14.9), 14, "the same second: counted once");
        assert_eq!(meter.drawing(14.9), 1);
        // a clock that goes back or jumps counts no one twice and panics nowhere
        assert_eq!(meter.drew(None, -5.0), 0);
        assert!(meter.drawing(f64::MAX) >= 1 && meter.drawing(f64::NAN) >= 1);
        // the group's share still binds where it is the smaller
        assert_eq!(drawing_share(RENDER_RATE, 16, total, 2), SCREEN_RATE_FLOOR);
        assert_eq!(drawing_share(RENDER_RATE, 1, 0, 5), 0, "a zero total draws nothing");
        assert!(render_total_default() >= RENDER_TOTAL_PER_CORE);
        // a core's total: 16 lone screens drawing keep a whole group's budget each, a 17th shares
        assert_eq!(drawing_share(RENDER_RATE, 1, RENDER_TOTAL_PER_CORE, 16), RENDER_RATE);
        assert!(drawing_share(RENDER_RATE, 1, RENDER_TOTAL_PER_CORE, 17) < RENDER_RATE);
    }
}
