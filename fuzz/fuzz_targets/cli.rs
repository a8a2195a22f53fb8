//! Feeds arbitrary argument lists to the command line's parser, and arbitrary settings lines to the
//! grid format's header. Asserts: no panic and no hang; a parsed `render` whose flags passed clap
//! never yields a camera or options the renderer would panic on (it may still refuse them: a typed
//! error); a grid error points inside the text it was given.

#![no_main]

use clap::Parser as _;
use libfuzzer_sys::fuzz_target;
use mazewalk::cli::{Cli, Command};
use mazewalk_maze as maze;
use mazewalk_render::{Camera, Renderer, Target};

fuzz_target!(|bytes: &[u8]| {
    // Up to the first 0xFF: the arguments, separated by NUL bytes; after it: grid settings lines.
    let (args, settings) = match bytes.iter().position(|&b| b == 0xFF) {
        Some(at) => (&bytes[..at], &bytes[at + 1..]),
        None => (bytes, &[][..]),
    };
    let args: Vec<String> =
        args.split(|&b| b == 0).map(|a| String::from_utf8_lossy(a).into_owned()).collect();
    if let Ok(cli) = Cli::try_parse_from(std::iter::once("mazewalk".to_string()).chain(args)) {
        if let Some(Command::Render(render)) = cli.command {
            let maze = maze::builtin().expect("the built-in maze loads");
            let viewer = maze.viewer();
            let camera = Camera {
                eye_z: render.height.unwrap_or(viewer.z),
                pitch_deg: render.pitch,
                projection: render.projection,
                fovea: !render.no_fovea, // the foveated view's tiles, as `render` draws them
                ..Camera::new(
                    render.at.unwrap_or(viewer.pos),
                    render.heading.unwrap_or(viewer.dir_deg),
                    render.fov.unwrap_or(viewer.fov_deg),
                )
            };
            let (cols, rows) = render.size;
            // Keep each run cheap: the size limit is the CLI's own check, tested elsewhere.
            if camera.validate().is_ok() && cols * rows <= 4_000 {
                let options = render.look.options(render.culling, render.look.charset());
                let mut frame = mazewalk_term::frame::Frame::new(cols, rows);
                let region = frame.region();
                let _ =
                    Renderer::new().render(&maze, &camera, &[], &options, Target::Frame(&mut frame, region));
            }
        }
    }
    let mut text = b"mazewalk-grid 1\n".to_vec();
    text.extend_from_slice(settings);
    let header = text.len();
    text.extend_from_slice(b"\n\n#####\n#@..#\n#####\n");
    if let Err(err) = maze::parse("fuzz.grid", &text) {
        let lines = text.split(|&b| b == b'\n').count() as u32;
        assert!(
            err.line >= 1 && err.line <= lines + 1,
            "{err} (the text has {lines} lines, header {header} bytes)"
        );
    }
});
