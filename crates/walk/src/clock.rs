//! The exit clock as text: what the HUD, the exit box, the player list and the records print. One
//! function each for the two forms, used everywhere: a time is rounded first, then split into
//! minutes and seconds, so that 59.96 s reads `1:00.0`, never `0:60.0`.

/// `m:ss` for the exit clock while it runs: it ticks once a second (whole seconds, not rounded:
/// the clock shows `0:59` until a minute has passed).
#[must_use]
pub(crate) fn running_clock_text(seconds: f64) -> String {
    let whole = seconds.max(0.0).floor() as u64;
    format!("{}:{:02}", whole / 60, whole % 60)
}

/// `m:ss.s` for a finish: the time rounded to the tenth, then split (59.96 → `1:00.0`, 3599.96 →
/// `60:00.0`: minutes go on past the hour). A negative or NaN time reads `0:00.0`.
#[must_use]
pub fn clock_text(seconds: f64) -> String {
    // (`as` saturates: an absurd time reads as a huge one, never wraps or panics)
    let tenths = (seconds.max(0.0) * 10.0).round() as u64;
    let (minutes, tenths) = (tenths / 600, tenths % 600);
    format!("{minutes}:{:02}.{}", tenths / 10, tenths % 10)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn clock_text_reads_minutes_and_seconds() {
        assert_eq!(clock_text(0.0), "0:00.0");
        assert_eq!(clock_text(75.24), "1:15.2");
        assert_eq!(clock_text(75.25), "1:15.3", "a half rounds up");
        assert_eq!(clock_text(-3.0), "0:00.0");
        assert_eq!(clock_text(f64::NAN), "0:00.0");
    }

    // The QA report's 59.96 s read "0:60.0": rounding came after the split.
    #[test]
    fn a_time_rounds_up_into_the_next_minute() {
        assert_eq!(clock_text(59.96), "1:00.0");
        assert_eq!(clock_text(59.94), "0:59.9");
        assert_eq!(clock_text(119.96), "2:00.0");
        assert_eq!(clock_text(3599.96), "60:00.0");
    }

    #[test]
    fn the_running_clock_ticks_whole_seconds() {
        assert_eq!(running_clock_text(83.9), "1:23");
        assert_eq!(running_clock_text(59.96), "0:59");
        assert_eq!(running_clock_text(0.0), "0:00");
        assert_eq!(running_clock_text(3600.0), "60:00");
    }

    /// `m:ss.s` back to seconds, checking its form: `None` if it is not that form.
    fn parse(text: &str) -> Option<(u64, f64)> {
        let (minutes, seconds) = text.split_once(':')?;
        let (whole, tenth) = seconds.split_once('.')?;
        if whole.len() != 2
            || tenth.len() != 1
            || !(whole.chars().chain(tenth.chars())).all(|c| c.is_ascii_digit())
        {
            return None;
        }
        Some((minutes.parse().ok()?, seconds.parse().ok()?))
    }

    proptest! {
        #![proptest_config(mazewalk_testkit::config())]

        #[test]
        fn clock_text_parses_back_to_within_a_twentieth(seconds in 0.0f64..100_000.0) {
            let text = clock_text(seconds);
            let (minutes, secs) = parse(&text).ok_or_else(|| TestCaseError::fail(format!("{seconds} → {text}")))?;
            prop_assert!(secs < 60.0, "{} → {}", seconds, text);
            let back = minutes as f64 * 60.0 + secs;
            prop_assert!((back - seconds).abs() <= 0.05 + 1e-9, "{} → {} → {}", seconds, text, back);
        }

        #[test]
        fn near_a_minute_the_clock_never_reads_sixty_seconds(minute in 0u64..200, under in 0.0f64..0.1) {
            let seconds = minute as f64 * 60.0 - under;
            let text = clock_text(seconds);
            let (_, secs) = parse(&text).ok_or_else(|| TestCaseError::fail(format!("{seconds} → {text}")))?;
            prop_assert!(secs < 60.0, "{} → {}", seconds, text);
        }
    }
}
