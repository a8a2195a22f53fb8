//! Frames are always the requested size and never panic: any grid from 1×1 up, pitch to ±90°, eye
//! heights right by the floor or ceiling, the extreme fields of view, every charset and projection;
//! and the whole walkthrough screen (3D view, map, HUD, boxes) at any terminal size, 1×1 included.

use mazewalk_testkit as common;

use glam::Vec2;
use mazewalk_maze as maze;
use mazewalk_render::{Camera, Charset, Culling, Projection, RenderOptions, Renderer, Target};
use mazewalk_term::frame::{Cell, ColorDepth, Frame, Region};
use mazewalk_term::input::{Key, KeyPhase};
use mazewalk_walk::App;
use mazewalk_walk::screen::{Hud, Screen, draw};
use proptest::prelude::*;

proptest! {
    // Each case renders whole frames at sizes up to 1000 columns.
    #![proptest_config(common::config_cases(300))]

    #[test]
    fn any_camera_and_grid_gives_a_frame_of_that_size(
        cols in 1usize..90,
        rows in 1usize..40,
        yaw in -720.0f32..720.0,
        pitch in prop_oneof![-90.0f32..=90.0, Just(90.0), Just(-90.0)],
        eye_z in prop_oneof![-0.999f32..0.999, Just(0.999), Just(-0.999)],
        fov in prop_oneof![10.0f32..=170.0, Just(10.0), Just(170.0)],
        charset in prop::sample::select(Charset::ALL.to_vec()),
        depth in prop::sample::select(vec![ColorDepth::None, ColorDepth::Ansi16, ColorDepth::Ansi256, ColorDepth::TrueColor]),
        ortho in any::<bool>(),
    ) {
        let maze = maze::builtin().unwrap();
        let v = maze.viewer();
        let camera = Camera {
            eye_z,
            pitch_deg: pitch,
            projection: if ortho { Projection::Orthographic } else { Projection::Perspective },
            ..Camera::new(v.pos, yaw, fov)
        };
        let options = RenderOptions { charset, color_depth: depth, ..RenderOptions::default() };
        // A sentinel all around the view's region: nothing is drawn outside it.
        let mut frame = Frame::filled(cols + 2, rows + 2, Cell::plain('¤'));
        let view = Region { col: 1, row: 1, cols, rows };
        Renderer::new().render(&maze, &camera, &[], &options, Target::Frame(&mut frame, view)).unwrap();
        for y in 0..rows + 2 {
            for x in 0..cols + 2 {
                let inside = (1..=cols).contains(&x) && (1..=rows).contains(&y);
                prop_assert_eq!(frame.get(x, y).unwrap().ch == '¤', !inside, "cell ({}, {})", x, y);
            }
        }
    }

    #[test]
    fn the_walkthrough_screen_draws_at_any_terminal_size(
        cols in 1usize..160,
        rows in 1usize..60,
        keys in prop::collection::vec(prop::sample::select(vec!['w', 'a', 's', 'd', 'm', '?', 'c', 'p', '[', ']', '+', '-']), 0..12),
    ) {
        let maze = maze::builtin().unwrap();
        let mut app = App::new(maze, RenderOptions::default(), 0.0).unwrap();
        for (i, k) in keys.iter().enumerate() {
            app.key(Key::Char(*k), KeyPhase::Press, i as f64 * 0.05);
            app.tick(i as f64 * 0.05 + 0.04);
        }
        let mut screen = Screen::default();
        let mut frame = Frame::new(cols, rows);
        draw(&app, &mut screen, &mut frame, &Hud::default());
        prop_assert_eq!((frame.width(), frame.height()), (cols, rows));
        let text = frame.lines().join("\n");
        if cols < 20 || rows < 6 {
            prop_assert!(text.contains(if cols >= 5 { "small" } else { "!" }), "{}", text);
        } else {
            prop_assert!(frame.lines()[rows - 1].ends_with("? help "), "HUD missing: {}", text);
        }
    }
}

#[test]
fn huge_frames_render() {
    let maze = maze::builtin().unwrap();
    let camera = Camera::new(Vec2::new(6.0, 50.0), 0.0, 90.0);
    for charset in [Charset::Ascii, Charset::Sextant] {
        let options = RenderOptions {
            charset,
            color_depth: ColorDepth::TrueColor,
            culling: Culling::Portal,
            ..RenderOptions::default()
        };
        let mut frame = Frame::new(1000, 300);
        let region = frame.region();
        Renderer::new().render(&maze, &camera, &[], &options, Target::Frame(&mut frame, region)).unwrap();
        assert_eq!((frame.width(), frame.height()), (1000, 300));
    }
}
