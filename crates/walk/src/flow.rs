//! End-to-end flow control: never more than [`MAX_UNACKED`] frames on their way to the terminal.
//!
//! SSH and TCP buffer megabytes, so a walk that draws faster than the link carries would fall
//! seconds behind the keys and keep drawing after a key is let go. Each frame is therefore followed
//! by a query, primary device attributes ([`QUERY`], `CSI c`), which every terminal answers — and
//! only after it has processed everything sent before it. A reply means "that frame is on screen".
//! With [`MAX_UNACKED`] frames unanswered the session stops drawing; input is still read and the
//! walk still simulated, so when a reply comes the next frame shows the **latest** state: frames
//! coalesce, they never queue.
//!
//! A terminal that never answers must not freeze the walk: after [`ACK_TIMEOUT`] without a reply the
//! session draws as if there were no flow control, still sending queries, and takes up flow control
//! again at the first reply. A terminal that *has* answered and then goes quiet is not one of those:
//! its link stalled, or its ssh client was stopped (Ctrl-Z, a laptop's lid). Frames sent at full
//! rate would only fill buffers (and get a server's player dropped for not reading), so then one
//! frame and its query go every [`ACK_TIMEOUT`] until a reply comes — which also recovers a reply
//! that was lost (an input rate limit drops bytes).
//!
//! Pure: time comes in as seconds.
//!
//! ```
//! use mazewalk_walk::flow::{FlowControl, MAX_UNACKED};
//! let mut flow = FlowControl::default();
//! for _ in 0..MAX_UNACKED {
//!     assert!(flow.may_send(0.0));
//!     flow.sent(0.0);
//! }
//! assert!(!flow.may_send(0.1)); // two frames in flight: wait
//! flow.answered(0.3); // the first is on screen, 0.3 s after it was sent
//! assert!(flow.may_send(0.3));
//! assert_eq!(flow.round_trip(), Some(0.3));
//! ```

use std::collections::VecDeque;

/// The query sent after each frame: primary device attributes.
pub const QUERY: &[u8] = b"\x1b[c";

/// Frames that may be on their way at once: one on screen-bound, one queued behind it keeps the
/// link busy without letting a backlog build.
pub const MAX_UNACKED: usize = 2;

/// How long (seconds) to wait for a reply before drawing without flow control.
pub const ACK_TIMEOUT: f64 = 2.0;

/// At most this many queries are remembered (a terminal that stopped answering can't grow it).
const MAX_REMEMBERED: usize = 64;

/// Which frames are on their way, and how fast the terminal answers.
#[derive(Clone, Debug, Default)]
pub struct FlowControl {
    /// When each unanswered query was sent, oldest first.
    sent: VecDeque<f64>,
    /// No reply for [`ACK_TIMEOUT`]: draw without waiting until one comes.
    silent: bool,
    /// Smoothed time from a query to its reply (seconds).
    round_trip: Option<f64>,
}

impl FlowControl {
    /// Whether a frame may be sent at `now`. Past [`ACK_TIMEOUT`] without a reply, the terminal is
    /// taken as one that never answers (see [`silent`](Self::silent)).
    pub fn may_send(&mut self, now: f64) -> bool {
        if !self.silent && self.sent.len() >= MAX_UNACKED {
            if now - self.sent[0] < ACK_TIMEOUT {
                return false;
            }
            self.silent = true;
            self.sent.clear();
        }
        self.deadline().is_none_or(|at| now >= at)
    }

    /// When a frame held back now may be sent even without a reply; `None` if none is held back.
    #[must_use]
    pub fn deadline(&self) -> Option<f64> {
        if self.silent {
            // Quiet after answering: a stall. One frame an ACK_TIMEOUT (see the module's notes).
            return self.round_trip.and(self.sent.back().map(|&at| at + ACK_TIMEOUT));
        }
        (self.sent.len() >= MAX_UNACKED).then(|| self.sent[0] + ACK_TIMEOUT)
    }

    /// A frame and its [`QUERY`] went out at `now`.
    pub fn sent(&mut self, now: f64) {
        if self.sent.len() == MAX_REMEMBERED {
            self.sent.pop_front();
        }
        self.sent.push_back(now);
    }

    /// The terminal answered a query at `now`: the oldest frame in flight is on screen.
    pub fn answered(&mut self, now: f64) {
        self.silent = false;
        let Some(at) = self.sent.pop_front() else { return }; // a reply to someone else's query
        let sample = (now - at).max(0.0);
        // An exponential average: follows a link that gets slower within a few frames.
        self.round_trip = Some(self.round_trip.map_or(sample, |rtt| 0.7 * rtt + 0.3 * sample));
    }

    /// Whether the terminal has not answered for [`ACK_TIMEOUT`] (frames are not held back then).
    #[must_use]
    pub fn silent(&self) -> bool {
        self.silent
    }

    /// Frames sent and not answered yet.
    #[must_use]
    pub fn in_flight(&self) -> usize {
        self.sent.len()
    }

    /// The smoothed time from a frame's query to its reply, once one came: the link's round trip
    /// plus the time to carry and draw a frame.
    #[must_use]
    pub fn round_trip(&self) -> Option<f64> {
        self.round_trip
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_wait_for_replies_then_go_on() {
        let mut flow = FlowControl::default();
        flow.sent(0.0);
        flow.sent(0.1);
        assert!(!flow.may_send(0.2));
        assert_eq!(flow.deadline(), Some(ACK_TIMEOUT));
        flow.answered(0.25);
        assert!(flow.may_send(0.25));
        assert_eq!(flow.in_flight(), 1);
        assert_eq!(flow.deadline(), None);
    }

    #[test]
    fn a_terminal_that_never_answers_falls_back_after_the_timeout_and_a_reply_restores_it() {
        let mut flow = FlowControl::default();
        flow.sent(0.0);
        flow.sent(0.0);
        assert!(!flow.may_send(ACK_TIMEOUT - 0.01));
        assert!(flow.may_send(ACK_TIMEOUT));
        assert!(flow.silent());
        for i in 0..100 {
            flow.sent(3.0 + f64::from(i));
            assert!(flow.may_send(3.0 + f64::from(i)), "never waits while silent");
        }
        assert!(flow.in_flight() <= MAX_REMEMBERED);
        flow.answered(200.0);
        assert!(!flow.silent());
    }

    #[test]
    fn a_terminal_that_answered_and_went_quiet_gets_one_frame_a_timeout() {
        let mut flow = FlowControl::default();
        flow.sent(0.0);
        flow.answered(0.1); // it answers
        flow.sent(1.0);
        flow.sent(1.1); // then nothing comes back (a stopped ssh client)
        assert!(!flow.may_send(1.0 + ACK_TIMEOUT - 0.01));
        assert!(flow.may_send(1.0 + ACK_TIMEOUT), "the timeout: one frame");
        assert!(flow.silent());
        flow.sent(3.0);
        for t in [3.1, 4.0, 4.99] {
            assert!(!flow.may_send(t), "not a flood at {t}");
            assert_eq!(flow.deadline(), Some(3.0 + ACK_TIMEOUT));
        }
        assert!(flow.may_send(3.0 + ACK_TIMEOUT), "the next probe");
        flow.sent(5.0);
        flow.answered(5.2); // the link is back (or a lost reply was made up for)
        assert!(!flow.silent() && flow.may_send(5.2) && flow.deadline().is_none());
    }

    #[test]
    fn the_round_trip_follows_the_replies() {
        let mut flow = FlowControl::default();
        flow.sent(0.0);
        flow.answered(0.1);
        assert_eq!(flow.round_trip(), Some(0.1));
        for t in 1..20 {
            flow.sent(f64::from(t));
            flow.answered(f64::from(t) + 0.5);
        }
        assert!((flow.round_trip().unwrap() - 0.5).abs() < 0.01);
    }
}
