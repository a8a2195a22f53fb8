//! The server's limits against abuse, each with its default (README "Host a maze" lists them), and
//! the input rate limiter. Pure: time comes in as seconds.

use std::time::Duration;

/// Every limit a server enforces. [`Limits::default`] is what `mazewalk serve` uses unless told.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// Connections at once, in all (`--max-players`); more are told why and closed.
    pub max_players: usize,
    /// Connections at once from one IP address (`--max-per-address`).
    pub max_per_address: usize,
    /// From the TCP connection to a started game: key exchange, authentication, pty and shell.
    pub handshake_timeout: Duration,
    /// A player who sends nothing for this long is disconnected (`--idle-timeout`).
    pub idle_timeout: Duration,
    /// The largest terminal drawn, columns; a larger pty is drawn at this size (top-left).
    pub max_cols: u16,
    /// The largest terminal drawn, rows.
    pub max_rows: u16,
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
            max_per_address: 16,
            handshake_timeout: Duration::from_secs(20),
            idle_timeout: Duration::from_secs(30 * 60),
            max_cols: 400,
            max_rows: 150,
            input_rate: 16 * 1024,
            input_burst: 64 * 1024,
            keepalive_interval: Duration::from_secs(15),
            keepalive_max: 3,
            write_timeout: Duration::from_secs(10),
            send_buffer: 128 * 1024,
        }
    }
}

/// A token bucket over bytes: `rate` a second, at most `burst` at once.
#[derive(Clone, Copy, Debug)]
pub struct RateLimit {
    rate: f64,
    burst: f64,
    tokens: f64,
    last: f64,
}

impl RateLimit {
    /// A full bucket at time `now`.
    #[must_use]
    pub fn new(rate: u32, burst: u32, now: f64) -> RateLimit {
        let burst = f64::from(burst.max(1));
        RateLimit { rate: f64::from(rate), burst, tokens: burst, last: now }
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
    }
}
