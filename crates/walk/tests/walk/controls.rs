//! Tap = step, hold = glide (issue #14): scripted key timings played into the pure [`App`], the way a
//! terminal without key releases (auto-repeat only) or with them (kitty protocol) would send them, with a
//! tick at every frame as the event loop does.

use mazewalk_maze as maze;
use mazewalk_render::RenderOptions;
use mazewalk_term::input::{Key, KeyPhase};
use mazewalk_walk::App;
use mazewalk_walk::controls::{REPEAT_HOLD_INTERVALS, REPEAT_HOLD_RANGE, TAP_BURST};
use mazewalk_walk::state::{Motion, SNAP_ALIGN_DEG, SNAP_SECONDS, TURN_SPEED, TURN_STEP_DEG, WALK_STEP};

/// Frames per second of the scripted event loop.
const FPS: f64 = 60.0;
/// Headings are f32 degrees summed over up to a few hundred frames: a few thousandths of a degree.
const DEG_TOL: f32 = 0.01;

/// The built-in maze: the viewer starts in the middle of a tile, heading 0° (east, +x), down a corridor.
fn app(releases: bool) -> App {
    let mut app = App::new(maze::builtin().unwrap(), RenderOptions::default(), 0.0).unwrap();
    app.releases = releases;
    assert_eq!(app.camera.yaw_deg, 0.0);
    app
}

/// What happens at a time in a script.
#[derive(Clone, Copy, Debug)]
enum Event {
    Press(Key),
    Release(Key),
}

/// Plays `events` (sorted by time) into `app` with a tick every frame from `from` to `to` and one at
/// `to`, the way the session does: each event at its time, ticks between. Returns the heading after
/// each tick.
fn play(app: &mut App, events: &[(f64, Event)], from: f64, to: f64) -> Vec<f32> {
    let mut events = events.iter().peekable();
    let frames = ((from * FPS).ceil() as u32..).map(|n| f64::from(n) / FPS).take_while(|&t| t < to);
    let mut headings = Vec::new();
    for now in frames.chain([to]) {
        while let Some(&(t, event)) = events.next_if(|(t, _)| *t <= now) {
            match event {
                Event::Press(key) => app.key(key, KeyPhase::Press, t),
                Event::Release(key) => app.key(key, KeyPhase::Release, t),
            };
        }
        app.tick(now);
        headings.push(app.camera.yaw_deg);
    }
    assert!(events.next().is_none(), "events after the end of the script");
    headings
}

/// The heading turned left from 0°, in (-180, 180].
fn turned(app: &App) -> f32 {
    let d = app.camera.yaw_deg.rem_euclid(360.0);
    if d > 180.0 { d - 360.0 } else { d }
}

/// How far the heading turned left over `headings` (one a frame), unwrapped.
fn unwrapped(start: f32, headings: &[f32]) -> f32 {
    let mut prev = start;
    headings
        .iter()
        .map(|&h| {
            let d = (h - prev + 180.0).rem_euclid(360.0) - 180.0;
            prev = h;
            d
        })
        .sum()
}

/// A key held without releases: pressed at `t0`, auto-repeated after `delay` every `interval` until `end`.
/// Returns the events and the time of the last repeat.
fn held(key: Key, t0: f64, delay: f64, interval: f64, end: f64) -> (Vec<(f64, Event)>, f64) {
    let mut events = vec![(t0, Event::Press(key))];
    let mut t = t0 + delay;
    while t <= end {
        events.push((t, Event::Press(key)));
        t += interval;
    }
    let last = events.last().unwrap().0;
    (events, last)
}

#[test]
fn without_releases_a_tap_turns_exactly_one_step() {
    let mut app = app(false);
    assert!(app.key(Key::Left, KeyPhase::Press, 1.0));
    assert_eq!(turned(&app), TURN_STEP_DEG, "at once");
    play(&mut app, &[], 1.0, 3.0);
    assert_eq!(turned(&app), TURN_STEP_DEG, "and no further");
    assert!(!app.is_animating(3.0));
    assert_eq!(app.held.next_expiry(), None);
}

#[test]
fn without_releases_four_taps_150_ms_apart_turn_four_steps() {
    let mut app = app(false);
    let taps: Vec<_> = (0..4).map(|i| (1.0 + 0.15 * f64::from(i), Event::Press(Key::Left))).collect();
    play(&mut app, &taps, 1.0, 2.5);
    assert!((turned(&app) - 4.0 * TURN_STEP_DEG).abs() < DEG_TOL, "{}", turned(&app));
    // Six taps, even faster ones (130 ms apart), make a right angle.
    let mut app = self::app(false);
    let taps: Vec<_> = (0..6).map(|i| (1.0 + 0.13 * f64::from(i), Event::Press(Key::Left))).collect();
    play(&mut app, &taps, 1.0, 2.5);
    assert!((turned(&app) - 90.0).abs() < DEG_TOL, "{}", turned(&app));
}

/// Holds ← with auto-repeat every `interval` after a 500 ms delay, for repeats until 2.5 s, and checks
/// the turn: the first step, then from the first repeat on `speed × time` (the first repeat's step
/// standing for its share), until the glide stops within [`REPEAT_HOLD_INTERVALS`] of the last repeat.
fn hold_turns_by_speed_and_stops(interval: f64, motion: Motion) {
    hold_with_delay_turns_by_speed_and_stops(0.5, interval, motion);
}

/// [`hold_turns_by_speed_and_stops`] with the auto-repeat's initial `delay`.
fn hold_with_delay_turns_by_speed_and_stops(delay: f64, interval: f64, motion: Motion) {
    let mut app = app(false);
    app.motion = motion;
    let (events, last) = held(Key::Left, 1.0, delay, interval, 2.5);
    let headings = play(&mut app, &events, 1.0, last);
    let hold = (REPEAT_HOLD_INTERVALS * interval).clamp(REPEAT_HOLD_RANGE.0, REPEAT_HOLD_RANGE.1);
    let stop = app.held.next_expiry().expect("gliding, with a time to stop");
    assert!((stop - (last + hold)).abs() < 1e-9, "stops {} s after the last repeat", stop - last);
    assert!(app.is_animating(last));
    play(&mut app, &[], last + 1.0 / FPS, last + 1.0);
    assert!(!app.is_animating(last + 1.0));
    let glide = (stop - (1.0 + delay)) as f32; // from the first repeat to the stop
    let expected = motion.turn_step_deg + motion.turn_speed_deg * glide;
    assert!(
        (turned(&app) - expected).abs() < DEG_TOL,
        "{interval} s repeats after {delay} s: turned {}, expected {expected}",
        turned(&app)
    );
    // Never a step per repeat: after the two steps (the tap, the first repeat), no frame turns by more
    // than a frame's worth of speed.
    let per_frame = motion.turn_speed_deg / FPS as f32 + DEG_TOL;
    let jumps = headings.windows(2).filter(|w| (w[1] - w[0]).abs() > per_frame).count();
    assert!(jumps <= 1, "{jumps} jumps"); // the first step happened before the first frame
}

// issue #33: taps 60–100 ms apart were taken for auto-repeat (anything under 125 ms was): four of them
// turned 36–55° and walked less than four steps.
#[test]
fn without_releases_four_quick_taps_turn_and_walk_four_steps() {
    for interval in [0.06, 0.075, 0.09, 0.1] {
        let mut app = app(false);
        let taps: Vec<_> = (0..4).map(|i| (1.0 + interval * f64::from(i), Event::Press(Key::Left))).collect();
        play(&mut app, &taps, 1.0, 2.5);
        assert!((turned(&app) - 4.0 * TURN_STEP_DEG).abs() < DEG_TOL, "{interval} s: {}", turned(&app));
        assert!(!app.is_animating(2.5));

        let mut app = self::app(false);
        let start = app.camera.position;
        let taps: Vec<_> =
            (0..4).map(|i| (1.0 + interval * f64::from(i), Event::Press(Key::Char('w')))).collect();
        play(&mut app, &taps, 1.0, 2.5);
        let moved = app.camera.position - start;
        assert!((moved.x - 4.0 * WALK_STEP).abs() < 1e-4 && moved.y.abs() < 1e-4, "{interval} s: {moved}");
    }
}

// issue #33: a person's taps are irregular; each of them is a step, whatever the rhythm within
// 60–100 ms, and taps that reach the walk together (held up on the way) are steps too.
#[test]
fn without_releases_irregular_quick_taps_are_each_a_step() {
    for gaps in [
        &[0.06, 0.1, 0.07, 0.09, 0.06][..],
        &[0.1, 0.06, 0.06, 0.1],
        &[0.0, 0.0, 0.0],
        &[0.08, 0.0, 0.0, 0.2],
    ] {
        let mut app = app(false);
        let mut t = 1.0;
        let mut taps = vec![(t, Event::Press(Key::Left))];
        for gap in gaps {
            t += gap;
            taps.push((t, Event::Press(Key::Left)));
        }
        play(&mut app, &taps, 1.0, t + 1.0);
        let expected = taps.len() as f32 * TURN_STEP_DEG;
        assert!((turned(&app) - expected).abs() < DEG_TOL, "{gaps:?}: {} for {expected}", turned(&app));
    }
}

// A paste (or a script) of many presses at once walks no further than a stalled link's worth of
// taps: a race was won in half a second by pasting the way to the exit (738 bytes), and 12 `w` pasted
// walked 12 units at once. At most `TAP_BURST` step at once, then (red-team pass 6) one each step's
// time, as a hold glides: taps 60 ms apart right after a burst count at that pace; with releases the
// same.
#[test]
fn a_burst_of_presses_steps_no_more_than_a_person_can_tap() {
    for releases in [false, true] {
        let mut app = app(releases);
        let start = app.camera.position;
        let mut events: Vec<_> =
            (0..200).map(|i| (1.0 + 1e-5 * f64::from(i), Event::Press(Key::Char('w')))).collect();
        if releases {
            events = (0..200)
                .flat_map(|i| {
                    let t = 1.0 + 1e-5 * f64::from(2 * i);
                    [(t, Event::Press(Key::Char('w'))), (t + 1e-5, Event::Release(Key::Char('w')))]
                })
                .collect();
        }
        play(&mut app, &events, 1.0, 1.5);
        let burst = app.camera.position.distance(start);
        assert!(
            (burst - TAP_BURST as f32 * WALK_STEP).abs() < 1e-3,
            "releases {releases}: 200 presses at once walked {burst}, not {TAP_BURST} steps"
        );
        // then a person's fastest taps, one every 60 ms for 3 s: a step each step's time
        let mut app_turn = self::app(releases);
        let mut taps: Vec<_> =
            (0..50).map(|i| (1.0 + 1e-5 * f64::from(i), Event::Press(Key::Left))).collect();
        taps.extend((1..=50).map(|i| (1.0 + 0.06 * f64::from(i), Event::Press(Key::Left))));
        if releases {
            taps =
                taps.into_iter().flat_map(|(t, e)| [(t, e), (t + 1e-6, Event::Release(Key::Left))]).collect();
        }
        let headings = play(&mut app_turn, &taps, 1.0, 4.5);
        let steps = unwrapped(0.0, &headings) / TURN_STEP_DEG;
        let paced = 3.0 / f64::from(TURN_STEP_DEG / TURN_SPEED);
        let expected = TAP_BURST + paced;
        assert!(
            (f64::from(steps) - expected).abs() <= 1.5,
            "releases {releases}: {steps} steps for {expected} (the burst and a step each step's time)"
        );
    }
}

/// Red-team pass 6: a script tapping `w` every 58 ms (as fast as taps are told from a repeat) walked
/// 3× as far as holding `w` did and won a served race. Now however often it taps it walks no further
/// than a hold of the same time, bar the burst.
#[test]
fn a_script_tapping_fast_walks_no_further_than_a_hold() {
    let corridor = || {
        let opts = maze::generate::GenOptions { width: 25, height: 1, ..Default::default() };
        let mut app =
            App::new(maze::generate::generate(&opts).unwrap(), RenderOptions::default(), 0.0).unwrap();
        app.camera.yaw_deg = 0.0;
        app
    };
    let walked = |events: &[(f64, Event)], releases: bool| {
        let mut app = corridor();
        app.releases = releases;
        let start = app.camera.position;
        play(&mut app, events, 1.0, 11.5);
        app.camera.position.x - start.x
    };
    let hold: Vec<_> = [(1.0, Event::Press(Key::Char('w'))), (11.0, Event::Release(Key::Char('w')))].into();
    let held = walked(&hold, true);
    assert!((held - 50.0).abs() < 0.5, "a hold of 10 s walked {held}");
    for gap in [0.058, 0.06, 0.08, 0.125] {
        let taps: Vec<_> = (0..)
            .map(|k| 1.0 + gap * f64::from(k))
            .take_while(|&t| t < 11.0)
            .map(|t| (t, Event::Press(Key::Char('w'))))
            .collect();
        let tapped = walked(&taps, false);
        assert!(tapped <= held + TAP_BURST as f32 * WALK_STEP + 1.0, "taps {gap} s apart walked {tapped}");
        assert!(tapped >= held - 2.0, "taps {gap} s apart walked only {tapped}");
    }
}

// issue #33: a terminal's auto-repeat (30–50 ms apart after a 250–600 ms delay) still glides.
#[test]
fn without_releases_common_auto_repeat_settings_glide_and_stop() {
    for delay in [0.25, 0.4, 0.6] {
        for interval in [0.03, 0.04, 0.05] {
            hold_with_delay_turns_by_speed_and_stops(delay, interval, Motion::default());
        }
    }
}

// issue #39: bursts of four ← taps 80 ms apart with 0.3–0.7 s between bursts turned about 45° each
// after the first (the pause was taken for auto-repeat's delay, the taps after it for repeats).
#[test]
fn without_releases_bursts_of_taps_after_pauses_turn_a_step_a_tap() {
    let mut app = app(false);
    let mut events = Vec::new();
    let mut t = 1.0;
    for pause in [0.3, 0.5, 0.7, 0.4] {
        for _ in 0..4 {
            events.push((t, Event::Press(Key::Left)));
            t += 0.08;
        }
        t += pause - 0.08;
    }
    play(&mut app, &events, 1.0, t + 1.0);
    assert!((turned(&app) - 16.0 * TURN_STEP_DEG + 360.0).abs() < DEG_TOL, "{}", turned(&app));
    assert!(!app.is_animating(t + 1.0));
}

// issue #39: four `w` taps 100 ms (and 110 ms) apart after a 0.5 s pause walked 2.3–2.5 units.
#[test]
fn without_releases_walking_taps_after_a_pause_walk_a_step_each() {
    for gap in [0.1, 0.11] {
        let mut app = app(false);
        let start = app.camera.position;
        let mut taps = vec![(1.0, Event::Press(Key::Char('w')))];
        taps.extend((0..4).map(|i| (1.5 + gap * f64::from(i), Event::Press(Key::Char('w')))));
        play(&mut app, &taps, 1.0, 3.0);
        let moved = app.camera.position - start;
        assert!((moved.x - 5.0 * WALK_STEP).abs() < 1e-4 && moved.y.abs() < 1e-4, "{gap} s: {moved}");
    }
}

// issue #39: over a link that stalls now and then (an SSH connection on a busy network), a hold's
// repeats arrive in a bunch: the first after a pause longer than a tap's gap (a step, as a tap would
// be), the rest with it. Those are the held key, not taps: the turn stays near the hold's
// `speed × time`, never a step per repeat.
#[test]
fn without_releases_a_hold_whose_repeats_arrive_in_bunches_still_glides() {
    for (stall_at, stall) in [(2.0, 0.1), (2.0, 0.2), (1.7, 0.3)] {
        let mut app = app(false);
        let (events, last) = held(Key::Left, 1.0, 0.5, 0.033, 3.0);
        // what is sent while the link stalls arrives when it ends, together
        let held_up = |t: f64| if (stall_at..stall_at + stall).contains(&t) { stall_at + stall } else { t };
        let events: Vec<_> = events.into_iter().map(|(t, e)| (held_up(t), e)).collect();
        let headings = play(&mut app, &events, 1.0, last + 1.0);
        let glide = 2.0 * TURN_STEP_DEG + TURN_SPEED * (last - 1.5) as f32; // the hold's, no stall
        let turned = unwrapped(0.0, &headings);
        // the bunch's first press took a step, and the glide stopped for the stall (up to 0.3 s)
        assert!(
            (turned - glide).abs() < TURN_STEP_DEG + TURN_SPEED * stall as f32,
            "a {stall} s stall at {stall_at} s: turned {turned}°, the hold's glide {glide}°"
        );
    }
}

/// A terminal whose auto-repeat starts sooner than any common setting (150 ms) is still seen as one:
/// presses 30 ms apart come faster than anyone taps.
#[test]
fn without_releases_a_short_repeat_delay_glides_after_a_step_or_two() {
    let mut app = app(false);
    let (events, last) = held(Key::Left, 1.0, 0.15, 0.03, 2.5);
    let headings = play(&mut app, &events, 1.0, last + 1.0);
    let per_frame = TURN_SPEED / FPS as f32 + DEG_TOL;
    let jumps = headings.windows(2).filter(|w| (w[1] - w[0]).abs() > per_frame).count();
    assert!(jumps <= 1, "{jumps} jumps");
    assert!(turned(&app) > 2.0 * TURN_STEP_DEG + TURN_SPEED, "glided: {}", turned(&app));
}

#[test]
fn without_releases_a_hold_with_30_ms_repeats_glides_and_stops() {
    hold_turns_by_speed_and_stops(0.03, Motion::default());
}

// issue #39: a terminal repeating every 100 ms sends what a person tapping every 100 ms after a pause
// sends; taps always count, so each such repeat is a step (this test used to expect a glide).
#[test]
fn without_releases_repeats_100_ms_apart_are_taps() {
    let mut app = app(false);
    let (events, _) = held(Key::Left, 1.0, 0.5, 0.1, 2.5);
    play(&mut app, &events, 1.0, 3.5);
    let expected = (events.len() as f32 * TURN_STEP_DEG).rem_euclid(360.0);
    assert!((app.camera.yaw_deg - expected).abs() < DEG_TOL, "{} for {expected}", app.camera.yaw_deg);
    assert!(!app.is_animating(3.5));
}

#[test]
fn turn_speed_and_step_are_per_app_settings() {
    let motion = Motion { turn_speed_deg: 45.0, turn_step_deg: 5.0, ..Motion::default() };
    hold_turns_by_speed_and_stops(0.04, motion);
    let mut app = app(false);
    app.motion.turn_step_deg = 90.0;
    app.key(Key::Right, KeyPhase::Press, 1.0);
    assert_eq!(app.camera.yaw_deg, 270.0);
}

#[test]
fn with_releases_a_tap_is_one_step_and_a_hold_glides_until_the_release() {
    let mut app = app(true);
    let tap = [(1.0, Event::Press(Key::Left)), (1.04, Event::Release(Key::Left))];
    play(&mut app, &tap, 1.0, 2.0);
    assert_eq!(turned(&app), TURN_STEP_DEG, "a quick tap is not lost");
    // Held for 1 s: as far as the speed takes it in 1 s (the step being the start of it).
    let mut app = self::app(true);
    let hold = [(1.0, Event::Press(Key::Left)), (2.0, Event::Release(Key::Left))];
    play(&mut app, &hold, 1.0, 3.0);
    assert!((turned(&app) - TURN_SPEED).abs() < DEG_TOL, "{}", turned(&app));
    assert!(!app.is_animating(3.0));
    // Repeats reported by the protocol change nothing.
    let mut app = self::app(true);
    app.key(Key::Left, KeyPhase::Press, 1.0);
    for i in 1..10 {
        app.key(Key::Left, KeyPhase::Repeat, 1.0 + 0.1 * f64::from(i));
    }
    app.key(Key::Left, KeyPhase::Release, 2.0);
    assert!((turned(&app) - TURN_SPEED).abs() < DEG_TOL, "{}", turned(&app));
}

#[test]
fn a_snap_turn_is_90_degrees_animated_and_stays_on_the_grid() {
    let mut app = app(false);
    assert!(app.key(Key::Char('.'), KeyPhase::Press, 1.0));
    assert!(app.is_animating(1.0), "the loop keeps drawing");
    app.tick(1.0 + SNAP_SECONDS / 2.0);
    assert!((turned(&app) + 45.0).abs() < DEG_TOL, "half way at half time: {}", turned(&app));
    app.tick(1.0 + SNAP_SECONDS);
    assert_eq!(app.camera.yaw_deg, 270.0, "exactly 90° right");
    assert!(!app.is_animating(1.0 + SNAP_SECONDS));
    // Four snaps left, one after the other: exactly back, each on a multiple of 90°.
    for i in 0..4 {
        let t = 2.0 + f64::from(i);
        app.key(Key::Char(','), KeyPhase::Press, t);
        play(&mut app, &[], t, t + 0.5);
        assert_eq!(app.camera.yaw_deg % 90.0, 0.0, "{}", app.camera.yaw_deg);
    }
    assert_eq!(app.camera.yaw_deg, 270.0);
    // A little off the grid (a mouse drag of 2 cells = 4°): the snap lands back on it.
    app.drag(-2, 0);
    assert_eq!(app.camera.yaw_deg, 274.0);
    app.key(Key::Char('<'), KeyPhase::Press, 7.0);
    play(&mut app, &[], 7.0, 7.5);
    assert_eq!(app.camera.yaw_deg, 0.0);
    // A tap off the grid (15°) is kept: the snap turns exactly 90° from there.
    app.key(Key::Left, KeyPhase::Press, 8.0);
    app.key(Key::Char('>'), KeyPhase::Press, 8.5);
    play(&mut app, &[], 8.5, 9.0);
    assert!((turned(&app) - (15.0 - 90.0)).abs() < DEG_TOL, "{}", turned(&app));
}

#[test]
fn snaps_in_a_row_add_up_and_a_held_snap_key_stays_on_the_grid() {
    let mut app = app(false);
    app.key(Key::Char(','), KeyPhase::Press, 1.0);
    app.tick(1.05);
    app.key(Key::Char(','), KeyPhase::Press, 1.08);
    play(&mut app, &[], 1.08, 2.0);
    assert_eq!(app.camera.yaw_deg, 180.0, "two snaps: half a turn");
    // Held, with auto-repeat every 30 ms: never more than half a turn behind, always landing on the grid.
    let (events, last) = held(Key::Char('.'), 3.0, 0.5, 0.03, 4.0);
    let headings = play(&mut app, &events, 3.0, last + 1.0);
    assert_eq!(app.camera.yaw_deg % 90.0, 0.0, "{}", app.camera.yaw_deg);
    // At most 180° (and the alignment) ahead, eased by smoothstep, whose speed peaks at 1.5× average.
    let per_frame = (180.0 + SNAP_ALIGN_DEG) / (SNAP_SECONDS * FPS) as f32 * 1.5 + DEG_TOL;
    for w in headings.windows(2) {
        let d = (w[1] - w[0]).rem_euclid(360.0);
        let d = d.min(360.0 - d);
        assert!(d <= per_frame, "{} → {}", w[0], w[1]);
    }
}

#[test]
fn a_walking_tap_moves_one_step_and_never_through_a_wall() {
    let mut app = app(false);
    let start = app.camera.position;
    app.key(Key::Char('w'), KeyPhase::Press, 1.0);
    play(&mut app, &[], 1.0, 2.0);
    let moved = app.camera.position - start;
    assert!((moved.x - WALK_STEP).abs() < 1e-5 && moved.y.abs() < 1e-5, "{moved}");
    assert!(!app.is_animating(2.0));
    // Back toward the wall behind the start (2 units: half a tile): taps stop at the maze's clearance.
    let wall_x = start.x - 2.0;
    for i in 0..6 {
        let t = 3.0 + 0.2 * f64::from(i);
        app.key(Key::Char('s'), KeyPhase::Press, t);
        assert!(
            app.camera.position.x >= wall_x + app.maze().clearance() - 1e-4,
            "{} at tap {i}",
            app.camera.position
        );
        assert_eq!(app.maze().cell_at(app.camera.position), Some(app.cell));
    }
    assert!(
        (app.camera.position.x - (wall_x + app.maze().clearance())).abs() < 1e-3,
        "{}",
        app.camera.position
    );
}

#[test]
fn other_continuous_keys_step_too() {
    let mut app = app(false);
    let (pitch, z, fov) = (app.camera.pitch_deg, app.camera.eye_z, app.camera.hfov_deg);
    app.key(Key::Up, KeyPhase::Press, 1.0);
    app.key(Key::Char(']'), KeyPhase::Press, 1.0);
    app.key(Key::Char('-'), KeyPhase::Press, 1.0);
    play(&mut app, &[], 1.0, 2.0);
    assert!(app.camera.pitch_deg > pitch && app.camera.eye_z > z && app.camera.hfov_deg < fov);
    assert!(!app.is_animating(2.0));
}

/// Presses `key` (one-shot keys act on the press).
fn press(app: &mut App, key: Key) {
    app.key(key, KeyPhase::Press, 1.0);
}

#[test]
fn esc_closes_the_help_and_quits_only_with_no_help_shown() {
    let (mut esc, mut q) = (app(false), app(false));
    press(&mut esc, Key::Char('?'));
    assert!(esc.help);
    press(&mut esc, Key::Esc);
    assert!(!esc.help && !esc.quit, "Esc over the help closes it");
    press(&mut esc, Key::Esc);
    assert!(esc.quit, "Esc with nothing open quits");
    press(&mut q, Key::Char('?'));
    press(&mut q, Key::Char('q'));
    assert!(q.quit, "q quits even over the help");
}

/// QA finding 10: the full-screen map looks like a box that Esc would close, as it closes the help:
/// it does (back to the corner map), and quits only after.
#[test]
fn esc_brings_the_full_map_back_to_its_corner_then_quits() {
    use mazewalk_walk::MapMode;
    let mut walk = app(false);
    press(&mut walk, Key::Char('m'));
    assert_eq!(walk.map, MapMode::Full);
    press(&mut walk, Key::Esc);
    assert_eq!((walk.map, walk.quit), (MapMode::Corner, false), "Esc over the full map closes it");
    press(&mut walk, Key::Esc);
    assert!(walk.quit, "Esc with nothing open quits");
    let mut q = app(false);
    press(&mut q, Key::Char('m'));
    press(&mut q, Key::Char('q'));
    assert!(q.quit, "q quits even over the full map");
}

#[test]
fn the_help_never_hides_under_the_exit_box() {
    // two cells, the exit in the one the viewer does not start in
    let opts = maze::generate::GenOptions { width: 2, height: 1, exit: true, ..Default::default() };
    let mut app = App::new(maze::generate::generate(&opts).unwrap(), RenderOptions::default(), 0.0).unwrap();
    app.releases = true;
    let to_exit = app.maze().exit_point().unwrap() - app.camera.position;
    app.camera.yaw_deg = to_exit.to_angle().to_degrees();
    press(&mut app, Key::Char('?'));
    let mut t = 1.0;
    while app.finished.is_none() && t < 10.0 {
        app.key(Key::Char('w'), KeyPhase::Press, t);
        app.key(Key::Char('w'), KeyPhase::Release, t);
        t += 1.0;
    }
    assert!(app.finished.is_some(), "walked to the exit");
    assert!(app.exit_box && !app.help, "the exit box takes the help's place");
    // (issue #33) a key closes the exit box; `?` then does not pop the help up as well
    app.key(Key::Char('?'), KeyPhase::Press, t + 1.0);
    assert!(!app.exit_box && !app.help, "`?` closes the exit box, no more");
    app.key(Key::Char('?'), KeyPhase::Press, t + 2.0);
    assert!(app.help, "with the box closed the help works again");
    app.key(Key::Char('r'), KeyPhase::Press, t + 3.0);
    assert!(app.finished.is_none(), "the walk starts again");
}

mod properties {
    use super::*;
    use mazewalk_testkit as common;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(common::config())]

        // issue #33: any rhythm of 2–8 taps, each 60–100 ms after the one before, is that many steps.
        #[test]
        fn quick_taps_are_each_one_step(gaps in prop::collection::vec(0.06f64..=0.1, 1..8)) {
            let mut app = app(false);
            let mut t = 1.0;
            let mut taps = vec![(t, Event::Press(Key::Left))];
            for gap in &gaps {
                t += gap;
                taps.push((t, Event::Press(Key::Left)));
            }
            play(&mut app, &taps, 1.0, t + 1.0);
            let expected = (taps.len() as f32 * TURN_STEP_DEG).rem_euclid(360.0);
            prop_assert!((app.camera.yaw_deg - expected).abs() < DEG_TOL, "{} for {expected}", app.camera.yaw_deg);
        }

        // issue #33: a terminal's auto-repeat — an initial delay of 250–600 ms, then a press every
        // 30–50 ms, each a few ms early or late on the way — glides: two steps (the press and the first
        // repeat), then never more than a frame's worth of speed between frames, and it stops within
        // the longest hold of the last repeat. The jitter is ±3 ms a press, so presses stay under
        // HOLD_GAP (58 ms) apart: since issue #39 a press 60 ms after the one before is a tap, and
        // a repeat later than 58 ms is taken for one (a step that stands for its share of the glide).
        #[test]
        fn auto_repeat_glides(
            delay in 0.25f64..=0.6,
            interval in 0.03f64..=0.05,
            jitter in prop::collection::vec(-0.003f64..=0.003, 80),
        ) {
            let mut app = app(false);
            let mut events = vec![(1.0, Event::Press(Key::Left))];
            let mut t = 1.0 + delay;
            for j in &jitter {
                if t > 2.5 {
                    break;
                }
                events.push((t + j, Event::Press(Key::Left)));
                t += interval;
            }
            let last = events.last().unwrap().0;
            let headings = play(&mut app, &events, 1.0, last + 1.0);
            let per_frame = TURN_SPEED / FPS as f32 + DEG_TOL;
            let jumps = headings.windows(2).filter(|w| {
                let d = (w[1] - w[0]).rem_euclid(360.0);
                d.min(360.0 - d) > per_frame
            }).count();
            prop_assert!(jumps <= 1, "{jumps} jumps");
            let turned = |h: f32| h.rem_euclid(360.0);
            let glided = turned(*headings.last().unwrap()) - 2.0 * TURN_STEP_DEG;
            let least = TURN_SPEED * ((last - (1.0 + delay)) as f32 - 0.15);
            prop_assert!(glided >= least, "glided {glided}°, expected at least {least}°");
            prop_assert!(!app.is_animating(last + REPEAT_HOLD_RANGE.1 + 1e-6));
        }
    }
}

/// Issue #39's rule as a property: any mix of taps (presses 60–300 ms apart), pauses (0.3–5 s) and holds
/// (auto-repeat after a 250–600 ms delay, every 30–50 ms), in any order, turns or walks exactly one
/// step per tap, and each hold two steps (its press and its first repeat: a tap after a pause to look
/// at) and a glide that starts once the second step's time is up and stops within
/// [`REPEAT_HOLD_RANGE`] of its last repeat (sooner when the next press comes first).
mod taps_always_count {
    use super::*;
    use mazewalk_maze::generate::{GenOptions, generate};
    use mazewalk_testkit as common;
    use mazewalk_walk::controls::HOLD_GAP;
    use mazewalk_walk::state::WALK_SPEED;
    use proptest::prelude::*;

    /// One piece of a script for one key, `gap` seconds after the previous press.
    #[derive(Clone, Copy, Debug)]
    enum Piece {
        Tap { gap: f64 },
        Hold { gap: f64, delay: f64, interval: f64, repeats: u32 },
    }

    /// The time from one press to the next piece: a quick tap's, or a pause.
    fn arb_gap() -> impl Strategy<Value = f64> {
        prop_oneof![0.06f64..=0.3, 0.3f64..=5.0]
    }

    fn arb_piece() -> impl Strategy<Value = Piece> {
        prop_oneof![
            arb_gap().prop_map(|gap| Piece::Tap { gap }),
            (arb_gap(), 0.25f64..=0.6, 0.03f64..=0.05, 0u32..=30)
                .prop_map(|(gap, delay, interval, repeats)| Piece::Hold { gap, delay, interval, repeats }),
        ]
    }

    fn arb_script() -> impl Strategy<Value = Vec<Piece>> {
        prop::collection::vec(arb_piece(), 1..8)
    }

    /// A hold as played: its first and last repeat, and when the next press came (if one did).
    struct Played {
        first: f64,
        last: f64,
        next: f64,
    }

    /// The script's presses of `key` from 1 s on, the steps it should take, and its holds that glide
    /// (two repeats or more; with one, a hold is two taps).
    fn presses(script: &[Piece], key: Key) -> (Vec<(f64, Event)>, u32, Vec<Played>) {
        let (mut events, mut steps, mut holds) = (Vec::new(), 0, Vec::<Played>::new());
        let mut t = 1.0 - 0.06;
        for piece in script {
            let (Piece::Tap { gap } | Piece::Hold { gap, .. }) = *piece;
            t += gap;
            for hold in holds.iter_mut().filter(|h| h.next.is_infinite()) {
                hold.next = t;
            }
            events.push((t, Event::Press(key)));
            steps += 1;
            if let Piece::Hold { delay, interval, repeats, .. } = *piece {
                let first = t + delay;
                for k in 0..repeats {
                    t = first + interval * f64::from(k);
                    events.push((t, Event::Press(key)));
                }
                steps += repeats.min(1);
                if repeats >= 2 {
                    holds.push(Played { first, last: t, next: f64::INFINITY });
                }
            }
        }
        (events, steps, holds)
    }

    /// The least and most seconds of glide the holds make, for a step taking `step_seconds`.
    fn glide_bounds(holds: &[Played], step_seconds: f64) -> (f64, f64) {
        // the second repeat (≤ 50 ms after the first) comes before the first's step time is up
        assert!(step_seconds > 0.05);
        let glide = |h: &Played, hold: f64| ((h.last + hold).min(h.next) - (h.first + step_seconds)).max(0.0);
        holds.iter().fold((0.0, 0.0), |(lo, hi), h| {
            (lo + glide(h, REPEAT_HOLD_RANGE.0), hi + glide(h, REPEAT_HOLD_RANGE.1))
        })
    }

    /// A straight corridor 25 cells (100 units) long, the viewer at its west end facing east.
    fn corridor() -> App {
        let opts = GenOptions { width: 25, height: 1, ..Default::default() };
        let mut app = App::new(generate(&opts).unwrap(), RenderOptions::default(), 0.0).unwrap();
        app.camera.yaw_deg = 0.0;
        app
    }

    // Headings are f32 degrees, each frame's turn added to one below 360°: up to a few thousand frames
    // of rounding at 360 × 2⁻²⁴ each stay under 0.05°. Positions below 100 units: 1e-3.
    const TURN_TOL: f32 = 0.05;
    const WALK_TOL: f32 = 1e-3;

    proptest! {
        #![proptest_config(common::config())]

        #[test]
        fn turning(script in arb_script()) {
            let mut app = app(false);
            let (events, steps, holds) = presses(&script, Key::Left);
            let end = events.last().unwrap().0 + 1.0;
            let headings = play(&mut app, &events, 1.0, end);
            prop_assert!(!app.is_animating(end));
            let turned = unwrapped(0.0, &headings);
            let step_seconds = f64::from(TURN_STEP_DEG / TURN_SPEED);
            let (lo, hi) = glide_bounds(&holds, step_seconds);
            let stepped = steps as f32 * TURN_STEP_DEG;
            let (lo, hi) = (stepped + TURN_SPEED * lo as f32, stepped + TURN_SPEED * hi as f32);
            prop_assert!(
                turned >= lo - TURN_TOL && turned <= hi + TURN_TOL,
                "turned {turned}°, expected {lo}..={hi}° ({steps} steps)"
            );
        }

        #[test]
        fn walking(script in arb_script()) {
            let mut app = corridor();
            let start = app.camera.position;
            let (events, steps, holds) = presses(&script, Key::Char('w'));
            let end = events.last().unwrap().0 + 1.0;
            play(&mut app, &events, 1.0, end);
            let moved = app.camera.position - start;
            let (lo, hi) = glide_bounds(&holds, f64::from(WALK_STEP / WALK_SPEED));
            let stepped = steps as f32 * WALK_STEP;
            let (lo, hi) = (stepped + WALK_SPEED * lo as f32, stepped + WALK_SPEED * hi as f32);
            prop_assert!(hi < 100.0 - 4.0, "the script walks past the corridor's end: {hi}");
            prop_assert!(moved.y.abs() < WALK_TOL, "{moved}");
            prop_assert!(
                moved.x >= lo - WALK_TOL && moved.x <= hi + WALK_TOL,
                "walked {}, expected {lo}..={hi} ({steps} steps)", moved.x
            );
        }

        // With the kitty protocol's releases the rule was always kept: a tap (released after 20 ms to
        // just under the next press) is one step, a hold a step and then `speed × time` from the step's
        // time to the release, however they mix.
        #[test]
        fn with_releases(script in arb_script(), down in 0.02f64..=HOLD_GAP) {
            let mut app = app(true);
            let (mut events, mut expected, mut t) = (Vec::new(), 0.0f32, 1.0 - 0.06);
            let step_seconds = f64::from(TURN_STEP_DEG / TURN_SPEED);
            for piece in &script {
                let (Piece::Tap { gap } | Piece::Hold { gap, .. }) = *piece;
                t += gap;
                let press = t;
                let up = match *piece {
                    Piece::Tap { .. } => press + down, // before the next press, at least 60 ms on
                    Piece::Hold { delay, interval, repeats, .. } => {
                        t += delay + interval * f64::from(repeats); // the next piece's gap from here
                        t
                    }
                };
                events.extend([(press, Event::Press(Key::Left)), (up, Event::Release(Key::Left))]);
                expected += TURN_STEP_DEG + TURN_SPEED * ((up - press) - step_seconds).max(0.0) as f32;
            }
            let end = events.last().unwrap().0 + 1.0;
            let headings = play(&mut app, &events, 1.0, end);
            let turned = unwrapped(0.0, &headings);
            prop_assert!((turned - expected).abs() < TURN_TOL, "turned {turned}°, expected {expected}°");
        }
    }
}
