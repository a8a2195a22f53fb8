//! Figures in the maze (the other players): drawn where they stand, hidden behind walls, labelled.

use glam::{Vec2, Vec3};
use mazewalk_maze::{Maze, grid};
use mazewalk_render::sprite::SPRITE_ID;
use mazewalk_render::{Camera, Charset, Culling, RenderOptions, Renderer, Sprite, Target};
use mazewalk_term::frame::{ColorDepth, Frame};

/// A corridor along the top row with a block below it; the start `>` at (6, 14) facing east.
const BLOCKED: &str = "mazewalk-grid 1
##########
#>.......#
#.####...#
#........#
##########
";

/// The same without the block.
const OPEN: &str = "mazewalk-grid 1
##########
#>.......#
#........#
#........#
##########
";

const START: Vec2 = Vec2::new(6.0, 14.0);

fn maze(text: &str) -> Maze {
    grid::parse_str("test.grid", text).unwrap()
}

fn figure(maze: &Maze, position: Vec2, label: char) -> Sprite {
    Sprite {
        position,
        cell: maze.cell_at(position).unwrap(),
        color: Vec3::new(0.9, 0.2, 0.2),
        label,
        ghost: false,
    }
}

fn options(culling: Culling, depth: ColorDepth) -> RenderOptions {
    RenderOptions { charset: Charset::Half, color_depth: depth, culling, ..RenderOptions::default() }
}

/// Renders at 80×24 half blocks; returns the frame and the sample columns each figure covers.
fn render(maze: &Maze, camera: &Camera, sprites: &[Sprite], options: RenderOptions) -> (Frame, Vec<usize>) {
    let mut renderer = Renderer::new();
    let mut frame = Frame::new(80, 24);
    let region = frame.region();
    renderer.render(maze, camera, sprites, &options, Target::Frame(&mut frame, region)).unwrap();
    let samples = renderer.samples();
    let columns = (0..samples.width())
        .filter(|&x| {
            (0..samples.height()).any(|y| {
                samples.id()[y * samples.width() + x] >= SPRITE_ID - 1023
                    && samples.id()[y * samples.width() + x] <= SPRITE_ID
            })
        })
        .collect();
    (frame, columns)
}

#[test]
fn a_figure_ahead_stands_in_the_middle_of_the_view_with_its_label() {
    let maze = maze(OPEN);
    let camera = Camera::new(START, 0.0, 90.0);
    let ahead = figure(&maze, Vec2::new(18.0, 14.0), 'K');
    let (frame, columns) = render(&maze, &camera, &[ahead], options(Culling::Portal, ColorDepth::TrueColor));
    assert!(!columns.is_empty(), "drawn");
    let (first, last) = (columns[0], columns[columns.len() - 1]);
    // 0.7 units wide at 12 units with a 90° fov over 80 samples: 80 · 0.7 / (2 · 12) ≈ 2.3 samples.
    assert!((1..=4).contains(&columns.len()), "{columns:?}");
    assert!((first + last) / 2 >= 38 && (first + last) / 2 <= 41, "centred: {columns:?}");
    assert!(frame.lines().iter().any(|line| line.contains('K')), "the label:\n{}", frame.lines().join("\n"));
    // Nearer is bigger: at 4 units it is three times as wide.
    let near = figure(&maze, Vec2::new(10.0, 14.0), 'K');
    let (_, near_columns) = render(&maze, &camera, &[near], options(Culling::Portal, ColorDepth::TrueColor));
    assert!(near_columns.len() >= 2 * columns.len(), "{near_columns:?} against {columns:?}");
}

#[test]
fn a_wall_hides_a_figure_behind_it_in_every_culling_mode() {
    // Seen from the start, (18, 6) is behind the block; without the block it is in plain view.
    let camera = Camera::new(START, -20.0, 90.0);
    for culling in [Culling::Portal, Culling::None] {
        let open = maze(OPEN);
        let (frame, columns) = render(
            &open,
            &camera,
            &[figure(&open, Vec2::new(18.0, 6.0), 'Q')],
            options(culling, ColorDepth::Ansi256),
        );
        assert!(!columns.is_empty(), "{culling:?}: in view without the block");
        assert!(frame.lines().iter().any(|l| l.contains('Q')));
        let blocked = maze(BLOCKED);
        let (frame, columns) = render(
            &blocked,
            &camera,
            &[figure(&blocked, Vec2::new(18.0, 6.0), 'Q')],
            options(culling, ColorDepth::Ansi256),
        );
        assert!(columns.is_empty(), "{culling:?}: hidden by the block, yet drawn at {columns:?}");
        assert!(!frame.lines().iter().any(|l| l.contains('Q')), "{culling:?}: no label either");
    }
}

#[test]
fn along_one_line_of_sight_a_figure_before_the_block_shows_and_one_beyond_it_does_not() {
    let maze = maze(BLOCKED);
    let camera = Camera::new(Vec2::new(34.0, 10.0), 180.0, 90.0); // east end of the middle row, facing west
    let full = figure(&maze, Vec2::new(28.0, 10.0), 'P'); // in the open part of the middle row
    let (_, in_view) = render(&maze, &camera, &[full], options(Culling::Portal, ColorDepth::TrueColor));
    assert!(!in_view.is_empty());
    // Behind the block's east face (x = 24) in the same row: hidden.
    let behind = figure(&maze, Vec2::new(6.0, 10.0), 'P');
    let (_, hidden) = render(&maze, &camera, &[behind], options(Culling::Portal, ColorDepth::TrueColor));
    assert!(hidden.is_empty(), "{hidden:?}");
}

#[test]
fn figures_behind_the_viewer_or_anywhere_odd_draw_nothing_and_never_panic() {
    let maze = maze(OPEN);
    let camera = Camera::new(START, 0.0, 90.0);
    let behind = figure(&maze, Vec2::new(5.0, 14.0), 'B');
    let (_, columns) = render(&maze, &camera, &[behind], options(Culling::Portal, ColorDepth::TrueColor));
    assert!(columns.is_empty(), "behind the eye: {columns:?}");
    // On the eye itself, NaN, far outside: nothing breaks, every frame has its size.
    let cell = maze.cell_at(START).unwrap();
    let odd = [START, Vec2::NAN, Vec2::new(1e30, -1e30), Vec2::new(6.0, 14.000_01)].map(|position| Sprite {
        position,
        cell,
        color: Vec3::new(f32::NAN, 2.0, -1.0),
        label: '\u{1b}',
        ghost: position.x.is_nan(),
    });
    for depth in [ColorDepth::None, ColorDepth::Ansi16, ColorDepth::TrueColor] {
        let (frame, _) = render(&maze, &camera, &odd, options(Culling::Portal, depth));
        assert_eq!(frame.lines().len(), 24);
        assert!(frame.cells().iter().all(|c| !c.ch.is_control()), "a label is never a control character");
    }
}

#[test]
fn many_figures_are_all_drawn_nearest_in_front() {
    let maze = maze(OPEN);
    let camera = Camera::new(START, 0.0, 90.0);
    let mut sprites: Vec<Sprite> =
        (0..50).map(|k| figure(&maze, Vec2::new(10.0 + 0.5 * k as f32, 14.0), 'M')).collect();
    sprites[0].label = 'N'; // the nearest, in front of all the others on the same line of sight
    let (frame, columns) = render(&maze, &camera, &sprites, options(Culling::Portal, ColorDepth::TrueColor));
    assert!(!columns.is_empty());
    assert!(frame.lines().iter().any(|l| l.contains('N')), "{}", frame.lines().join("\n"));
}

// issue #43: a ghost (a stored run replayed) is drawn translucent, through the same pipeline: its
// samples blend its colour over what is behind, it hides nothing, and its head is reported.
#[test]
fn a_ghost_is_translucent_and_hides_no_figure_behind_it() {
    let maze = maze(OPEN);
    let camera = Camera::new(START, 0.0, 90.0);
    let solid = figure(&maze, Vec2::new(18.0, 14.0), 'K');
    let ghost = Sprite {
        color: Vec3::new(0.2, 0.9, 0.2),
        ghost: true,
        label: 'g',
        ..figure(&maze, Vec2::new(12.0, 14.0), 'g')
    };
    let opts = options(Culling::Portal, ColorDepth::TrueColor);
    let samples_of = |sprites: &[Sprite]| {
        let mut renderer = Renderer::new();
        let mut frame = Frame::new(80, 24);
        let region = frame.region();
        renderer.render(&maze, &camera, sprites, &opts, Target::Frame(&mut frame, region)).unwrap();
        (renderer.samples().clone(), renderer.heads().to_vec())
    };
    let (bare, _) = samples_of(&[]);
    let (alone, heads) = samples_of(&[ghost]);
    let (both, _) = samples_of(&[solid, ghost]);
    assert_eq!(heads.len(), 1, "the ghost's head shows: {heads:?}");
    assert_eq!(heads[0].0, 0);
    let mut blended = 0;
    for i in 0..bare.color().len() {
        if alone.id()[i] != bare.id()[i] {
            blended += 1;
            // half of the ghost's colour over the wall's: between the two, never the ghost's alone
            assert_eq!(alone.depth()[i], bare.depth()[i], "a ghost writes no depth");
            assert!(alone.color()[i].distance(bare.color()[i]) > 0.01, "drawn at {i}");
        }
    }
    assert!(blended > 10, "the ghost covers samples: {blended}");
    // the solid figure behind the ghost still covers its samples (a ghost hides nothing)
    let solid_ids =
        |s: &mazewalk_render::SampleBuffer| (0..s.id().len()).filter(|&i| s.id()[i] == SPRITE_ID).count();
    let (only_solid, _) = samples_of(&[solid]);
    assert!(solid_ids(&only_solid) > 0);
    let under_ghost = (0..both.id().len())
        .filter(|&i| only_solid.id()[i] == SPRITE_ID && both.color()[i] != only_solid.color()[i])
        .count();
    assert!(under_ghost > 0, "the ghost blends over the figure behind it");
    assert!(
        (0..both.depth().len()).all(|i| both.depth()[i] == only_solid.depth()[i]),
        "the depths are the solid figure's and the walls'"
    );
}
