//! Golden frames: every example maze and every original course file, rendered from the viewer stored
//! in the file, as text. Ascii (readable with no colour at all) and sextant glyphs without colour.
//! Review a changed snapshot with `cargo insta review` (or read the `.snap.new` beside it).

use mazewalk_maze::{self as maze, Maze};
use mazewalk_render::{Camera, Charset, Culling, RenderOptions, Renderer, Target};
use mazewalk_term::frame::{ColorDepth, Frame};

fn files() -> Vec<(String, Maze)> {
    let mut paths: Vec<std::path::PathBuf> = Vec::new();
    for dir in [mazewalk_testkit::maze_path(""), mazewalk_testkit::maze_path("cs559")] {
        for entry in std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("{dir}: {e}")) {
            let path = entry.unwrap().path();
            if matches!(path.extension().and_then(|e| e.to_str()), Some("maze" | "grid")) {
                paths.push(path);
            }
        }
    }
    paths.sort();
    paths
        .into_iter()
        .map(|p| (p.file_name().unwrap().to_string_lossy().replace('.', "_"), maze::load(&p).unwrap().maze))
        .collect()
}

fn frame(maze: &Maze, charset: Charset, culling: Culling) -> String {
    let v = maze.viewer();
    let camera = Camera { eye_z: v.z, ..Camera::new(v.pos, v.dir_deg, v.fov_deg) };
    let options =
        RenderOptions { charset, color_depth: ColorDepth::None, culling, ..RenderOptions::default() };
    let mut out = Frame::new(64, 20);
    let region = out.region();
    Renderer::new().render(maze, &camera, &[], &options, Target::Frame(&mut out, region)).unwrap();
    out.lines().join("\n")
}

#[test]
fn golden_frames_from_the_stored_viewers() {
    let files = files();
    assert!(files.len() >= 10, "expected the example mazes and the three course files");
    for (name, maze) in &files {
        for charset in [Charset::Ascii, Charset::Sextant] {
            let text = frame(maze, charset, Culling::Portal);
            // The portal pass and brute force agree on these views.
            assert_eq!(text, frame(maze, charset, Culling::None), "{name} {charset:?}: portal ≠ brute force");
            insta::assert_snapshot!(format!("{name}_{}", charset), text);
        }
    }
}
