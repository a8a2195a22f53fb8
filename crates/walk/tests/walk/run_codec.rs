//! Issue #43: a run's codec. Any run the format can hold comes back from its bytes as it went in
//! (rounded to the format's steps once, then exactly); any bytes decode to a run that encodes back to
//! the same bytes, or to an error, never a panic.

use glam::Vec2;
use mazewalk_maze::ContentHash;
use mazewalk_walk::run::{MAX_BYTES, MAX_NAME, MAX_SECONDS, Pose, RATE, Run};
use proptest::prelude::*;

/// A pose inside a 4000-unit maze, any heading, any pitch.
fn arb_pose() -> impl Strategy<Value = Pose> {
    (0.0f32..4000.0, 0.0f32..4000.0, 0.0f32..360.0, -90.0f32..=90.0).prop_map(|(x, y, yaw, pitch)| Pose {
        position: Vec2::new(x, y),
        yaw_deg: yaw,
        pitch_deg: pitch,
    })
}

/// A run of up to a minute: a random walk of small steps from a random start (as a walk moves), or
/// jumps anywhere (as no walk does, but the format holds).
fn arb_run() -> impl Strategy<Value = Run> {
    (1u32..60_000, "[a-z]{0,32}", any::<[u8; 32]>(), arb_pose(), any::<bool>(), any::<u64>()).prop_map(
        |(millis, holder, hash, start, jumps, seed)| {
            let count = (millis / (1000 / RATE)) as usize + 1;
            let mut rng = seed;
            let mut next = move || {
                rng = rng.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                (rng >> 40) as f32 / (1u64 << 24) as f32 // 0..1
            };
            let mut pose = start;
            let samples = (0..count)
                .map(|_| {
                    let step = if jumps { 4000.0 } else { 0.5 };
                    pose.position = (pose.position + Vec2::new(next() - 0.5, next() - 0.5) * step)
                        .clamp(Vec2::ZERO, Vec2::splat(4000.0));
                    pose.yaw_deg =
                        (pose.yaw_deg + (next() - 0.5) * if jumps { 720.0 } else { 20.0 }).rem_euclid(360.0);
                    pose.pitch_deg = (next() - 0.5) * 180.0;
                    pose
                })
                .collect();
            Run { maze: ContentHash(hash), holder, millis, samples }
        },
    )
}

proptest! {
    // Each case encodes and decodes a whole run, up to a minute of poses: 256 cases.
    #![proptest_config(mazewalk_testkit::config_cases(256))]

    #[test]
    fn a_run_comes_back_from_its_bytes(run in arb_run()) {
        let bytes = run.encode().unwrap();
        prop_assert!(bytes.len() <= MAX_BYTES);
        let back = Run::decode(&bytes).unwrap();
        let quantized: Vec<Pose> = run.samples.iter().map(|p| p.quantized()).collect();
        prop_assert_eq!(&back.samples, &quantized);
        prop_assert_eq!((&back.holder, back.millis, back.maze), (&run.holder, run.millis, run.maze));
        prop_assert_eq!(back.encode().unwrap(), bytes, "one encoding per run");
        // (rounding moves a position by at most half a 1/256 step, an angle by half a 1/16°)
        for (a, b) in run.samples.iter().zip(&back.samples) {
            prop_assert!(a.position.distance(b.position) <= 0.5f32.hypot(0.5) / 256.0 + 1e-3);
            let turn = (a.yaw_deg - b.yaw_deg + 180.0).rem_euclid(360.0) - 180.0;
            prop_assert!(turn.abs() <= 0.5 / 16.0 + 1e-3);
        }
    }

    #[test]
    fn any_bytes_decode_to_a_run_or_an_error(bytes in proptest::collection::vec(any::<u8>(), 0..512)) {
        if let Ok(run) = Run::decode(&bytes) {
            prop_assert!(run.millis <= MAX_SECONDS * 1000 && run.holder.len() <= MAX_NAME);
            prop_assert_eq!(run.encode().unwrap(), bytes);
        }
    }

    #[test]
    fn a_runs_bytes_cut_or_flipped_never_panic(run in arb_run(), cut in any::<prop::sample::Index>(), flip in any::<prop::sample::Index>(), bit in 0u8..8) {
        let bytes = run.encode().unwrap();
        prop_assert!(Run::decode(&bytes[..cut.index(bytes.len())]).is_err(), "a run cut short");
        let mut flipped = bytes.clone();
        let at = flip.index(flipped.len());
        flipped[at] ^= 1 << bit;
        if let Ok(other) = Run::decode(&flipped) {
            prop_assert_eq!(other.encode().unwrap(), flipped);
        }
    }
}
