//! The exit clock as text: what the HUD, the exit box, the player list and the records print.

/// `m:ss` for the exit clock while it runs: it ticks once a second.
#[must_use]
pub(crate) fn running_clock_text(seconds: f64) -> String {
    let whole = seconds.max(0.0).floor() as u64;
    format!("{}:{:02}", whole / 60, whole % 60)
}

/// `m:ss.s` for the exit screen.
#[must_use]
pub fn clock_text(seconds: f64) -> String {
    let minutes = (seconds / 60.0).floor();
    format!("{}:{:04.1}", minutes as u64, seconds - minutes * 60.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clock_text_reads_minutes_and_seconds() {
        assert_eq!(clock_text(0.0), "0:00.0");
        assert_eq!(clock_text(75.25), "1:15.2");
    }

    #[test]
    fn the_running_clock_ticks_whole_seconds() {
        assert_eq!(running_clock_text(83.9), "1:23");
        assert_eq!(running_clock_text(0.0), "0:00");
        assert_eq!(running_clock_text(3600.0), "60:00");
    }
}
