//! End-to-end flow control: never more than [`MAX_UNACKED`] frames on their way to the terminal.
//!
//! SSH and TCP buffer megabytes, so a walk that draws faster than the link carries would fall
//! seconds behind the keys and keep drawing after a key is let go. Each frame is therefore followed
//! by a query, primary device attributes ([`QUERY`], `CSI c`), which every terminal answers — and
//! only after it has processed everything sent before it. A reply means "that frame is on screen".
//! (A tick of the exit clock, a digit or two of the HUD's row, goes without one: it needs no pacing.)
//! With [`MAX_UNACKED`] frames unanswered the session stops drawing; input is still read and the
//! walk still simulated, so when a reply comes the next frame shows the **latest** state: frames
//! coalesce, they never queue.
//!
//! Replies come back in order, so each one is counted against the oldest frame in flight. A reply that
//! never comes (bytes dropped on the way in: a server's input rate limit; a frame that was never
//! written) would leave the count one too high for good, and two of them would stall the walk until
//! the timeout below — seconds of a frozen picture, then a jump. So while the link answers (a reply
//! came after the oldest frame in flight was sent), that frame's reply is taken as lost once it is
//! [overdue](FlowControl::overdue_at): a couple of round trips late, which a reply that is merely slow
//! is not. (Counting one frame too few is harmless: a frame
//! more goes on its way, and the surplus reply later finds no frame to answer.)
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

/// The query sent after each frame: primary device attributes (`CSI c`).
pub use mazewalk_term::modes::DEVICE_ATTRIBUTES_QUERY as QUERY;

/// Frames that may be on their way at once: one on screen-bound, one queued behind it keeps the
/// link busy without letting a backlog build.
pub const MAX_UNACKED: usize = 2;

/// How long (seconds) to wait for a reply before drawing without flow control.
pub const ACK_TIMEOUT: f64 = 2.0;

/// A query every terminal answers, after everything sent before it (`DSR 5`, "status?"): sent last
/// by a quitting walk, its answer ([`LAST_ANSWER`], `CSI 0 n`, "OK") says that the answers to every
/// frame's query are in, whatever the frames' count says (a terminal that stopped reading for a
/// while had its frames' answers counted lost, and they came after the walk had given the terminal
/// back: typed onto the shell's line, `^[[?62;22c`).
pub use mazewalk_term::modes::STATUS_QUERY as LAST_QUERY;

/// The answer to [`LAST_QUERY`].
pub use mazewalk_term::modes::STATUS_OK as LAST_ANSWER;

/// Watches a terminal's input for [`LAST_ANSWER`], which may come cut across reads.
#[derive(Clone, Debug, Default)]
pub struct LastAnswer {
    /// The last bytes read, fewer than the answer.
    tail: Vec<u8>,
    seen: bool,
}

impl LastAnswer {
    /// Takes the next bytes read; whether the answer has come, in them or before.
    pub fn read(&mut self, bytes: &[u8]) -> bool {
        if !self.seen {
            self.tail.extend_from_slice(bytes);
            self.seen = self.tail.windows(LAST_ANSWER.len()).any(|w| w == LAST_ANSWER);
            self.tail.drain(..self.tail.len().saturating_sub(LAST_ANSWER.len() - 1));
        }
        self.seen
    }
}

/// A reply is overdue (taken as lost) after this many round trips…
pub(crate) const OVERDUE_ROUND_TRIPS: f64 = 2.0;

/// … and at least this long (seconds) more than one round trip (the round trip varies with a frame's
/// size: a full repaint takes longer to carry than the frames that set the average).
pub(crate) const OVERDUE_MARGIN: f64 = 0.1;

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
    /// Replies taken as lost ([`overdue_at`](Self::overdue_at)) or forgotten ([`resync`](Self::resync)).
    lost: u64,
    /// When the last reply came.
    last_reply: Option<f64>,
}

impl FlowControl {
    /// Whether a frame may be sent at `now`. Past [`ACK_TIMEOUT`] without a reply, the terminal is
    /// taken as one that never answers (see [`silent`](Self::silent)).
    pub fn may_send(&mut self, now: f64) -> bool {
        while !self.silent && self.overdue_at().is_some_and(|at| now >= at) {
            self.sent.pop_front(); // its reply was lost
            self.lost += 1;
        }
        if !self.silent && self.sent.len() >= MAX_UNACKED {
            if now - self.sent[0] < ACK_TIMEOUT {
                return false;
            }
            self.silent = true;
            self.sent.clear();
        }
        self.deadline().is_none_or(|at| now >= at)
    }

    /// When the oldest frame in flight's reply counts as lost: after [`OVERDUE_ROUND_TRIPS`] round
    /// trips, and at least [`OVERDUE_MARGIN`] more than one, if the link has answered since that frame
    /// was sent (else the link is quiet, not losing replies: see [`ACK_TIMEOUT`]), and never later
    /// than [`ACK_TIMEOUT`]. `None` with nothing in flight or no round trip known.
    #[must_use]
    pub(crate) fn overdue_at(&self) -> Option<f64> {
        let (rtt, &oldest) = (self.round_trip?, self.sent.front()?);
        if self.last_reply.is_none_or(|reply| reply < oldest) {
            return None;
        }
        let wait = (OVERDUE_ROUND_TRIPS * rtt).max(rtt + OVERDUE_MARGIN);
        Some(oldest + wait).filter(|&at| at < oldest + ACK_TIMEOUT)
    }

    /// When a frame held back now may be sent even without a reply; `None` if none is held back.
    #[must_use]
    pub fn deadline(&self) -> Option<f64> {
        if self.silent {
            // Quiet after answering: a stall. One frame an ACK_TIMEOUT (see the module's notes).
            return self.round_trip.and(self.sent.back().map(|&at| at + ACK_TIMEOUT));
        }
        (self.sent.len() >= MAX_UNACKED).then(|| self.overdue_at().unwrap_or(self.sent[0] + ACK_TIMEOUT))
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
        self.last_reply = Some(now);
        let Some(at) = self.sent.pop_front() else { return }; // a reply to someone else's query
        let sample = (now - at).max(0.0);
        // An exponential average: follows a link that gets slower within a few frames.
        self.round_trip = Some(self.round_trip.map_or(sample, |rtt| 0.7 * rtt + 0.3 * sample));
    }

    /// Bytes from the terminal were dropped (a rate limit): replies may have gone with them, so the
    /// frames in flight are forgotten rather than waited for (a late reply then answers nothing).
    pub fn resync(&mut self) {
        self.lost += self.sent.len() as u64;
        self.sent.clear();
    }

    /// Replies taken as lost so far.
    #[must_use]
    pub fn lost(&self) -> u64 {
        self.lost
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

    // issue #33: two lost replies left two frames "in flight" for good: the walk stalled for the whole
    // ACK_TIMEOUT (the picture went on turning 1.5 s after the key was let go, on a slow link).
    #[test]
    fn a_lost_reply_is_given_up_after_a_few_round_trips_not_the_timeout() {
        // A frame whenever one may go (at most every 0.1 s), each answered 0.2 s later, two of the
        // replies lost: the count, one off after the first, is two off after the second.
        let mut flow = FlowControl::default();
        let (mut t, mut sent, mut longest_wait, mut waiting_since) = (0.0, 0, 0.0f64, None);
        let mut replies = std::collections::VecDeque::new();
        while sent < 40 {
            while replies.front().is_some_and(|&at| at <= t) {
                flow.answered(replies.pop_front().unwrap());
            }
            if flow.may_send(t) {
                longest_wait = longest_wait.max(waiting_since.map_or(0.0, |since| t - since));
                waiting_since = None;
                flow.sent(t);
                if sent != 8 && sent != 12 {
                    replies.push_back(t + 0.2);
                }
                sent += 1;
                t += 0.1;
            } else {
                waiting_since.get_or_insert(t);
                t += 0.01;
            }
        }
        // (one stale frame may stay counted: a frame fewer in flight, no stall)
        assert!((1..=2).contains(&flow.lost()), "{} taken as lost", flow.lost());
        assert!(!flow.silent());
        assert!(longest_wait < 0.5, "waited {longest_wait} s for a slot");

        // A reply that is merely slow (a full repaint) is not taken for lost before it could come.
        let mut slow = FlowControl::default();
        slow.sent(0.0);
        slow.answered(0.05); // a fast link: 50 ms
        slow.sent(0.05);
        slow.sent(0.06);
        assert_eq!(slow.overdue_at(), Some(0.05 + 0.15), "at least a round trip and the margin");
        // Without a round trip known, only the timeout.
        let mut new = FlowControl::default();
        new.sent(0.0);
        new.sent(0.0);
        assert_eq!((new.overdue_at(), new.deadline()), (None, Some(ACK_TIMEOUT)));
        // A very slow link: the timeout comes first.
        let mut crawl = FlowControl::default();
        crawl.sent(0.0);
        crawl.answered(1.5);
        crawl.sent(1.5);
        crawl.sent(1.6);
        assert_eq!(crawl.overdue_at(), None);
        assert_eq!(crawl.deadline(), Some(1.5 + ACK_TIMEOUT));
    }

    #[test]
    fn a_gap_in_the_input_forgets_the_frames_in_flight() {
        let mut flow = FlowControl::default();
        flow.sent(0.0);
        flow.sent(0.1);
        assert!(!flow.may_send(0.2));
        flow.resync();
        assert!(flow.may_send(0.2) && flow.in_flight() == 0 && flow.lost() == 2);
        flow.answered(0.3); // a late reply answers nothing
        assert_eq!(flow.in_flight(), 0);
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
    /// The last answer is seen whole, in one read or cut across several, among other bytes.
    #[test]
    fn the_last_answer_is_seen_in_one_read_or_cut_across_several() {
        let input = [b"\x1b[?62;22c".as_slice(), LAST_ANSWER, b"q"].concat();
        for cut in 0..=input.len() {
            for second in cut..=input.len() {
                let mut watch = LastAnswer::default();
                let seen =
                    [&input[..cut], &input[cut..second], &input[second..]].map(|part| watch.read(part));
                assert!(seen[2], "cut at {cut} and {second}");
            }
        }
        let mut watch = LastAnswer::default();
        assert!(!watch.read(b"\x1b[?62;22c\x1b[0") && !watch.read(b"m") && !watch.read(b"\x1b[c"));
    }
}
