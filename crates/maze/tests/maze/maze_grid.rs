//! The grid format: reading hand-drawn maps, writing, round trips, and located errors.

use mazewalk_testkit as common;

use glam::{Vec3, vec2};
use mazewalk_maze::generate::{Algorithm, GenOptions, generate, generate_grid};
use mazewalk_maze::grid::{self, DEFAULT_WALL};
use mazewalk_maze::{self as maze, Format, Maze, ParseError};
use proptest::prelude::*;

fn parse(text: &str) -> Result<Maze, ParseError> {
    maze::parse("t.grid", text.as_bytes())
}

fn arb_algorithm() -> impl Strategy<Value = Algorithm> {
    prop_oneof![Just(Algorithm::Prim), Just(Algorithm::Backtracker), Just(Algorithm::Wilson)]
}

fn arb_opts() -> impl Strategy<Value = GenOptions> {
    (1u32..=16, 1u32..=16, any::<u64>(), arb_algorithm(), any::<bool>(), 0.0f32..=1.0, any::<bool>())
        .prop_map(|(width, height, seed, algorithm, exit, loops, palette)| GenOptions {
            width,
            height,
            seed,
            algorithm,
            exit,
            loops,
            palette: palette.then(|| vec![Vec3::new(0.8, 0.4, 0.2), Vec3::new(0.2, 0.4, 0.6)]),
        })
}

proptest! {
    // Each case builds, writes and reads back a whole maze.
    #![proptest_config(common::config_cases(64))]

    #[test]
    fn generated_tile_maps_round_trip_in_both_formats(o in arb_opts()) {
        let map = generate_grid(&o).unwrap();
        let text = map.to_text();
        let m = parse(&text).unwrap();
        prop_assert_eq!(&m, &map.to_maze().unwrap());
        // the grid text is canonical: reading and writing it again gives it back
        let again = maze::write(&m, Format::Grid).unwrap();
        prop_assert_eq!(parse(&again).unwrap(), m.clone());
        let cs559 = maze::write(&m, Format::Cs559).unwrap();
        prop_assert_eq!(parse(&cs559).unwrap(), m.clone());
        // tile mazes keep the layout's shape: a tree of tiles unless loops were added
        if o.loops == 0.0 {
            prop_assert!(m.is_perfect());
        }
        prop_assert!(m.is_connected());
    }
}

/// The layout in README/docs, as a test.
const DOC_EXAMPLE: &str = "mazewalk-grid 1
tile 4
facing north
A = #cc8844

##########
#@..#...E#
#.#.A.##.#
#........#
##########
";

#[test]
fn the_documented_example_reads() {
    let m = parse(DOC_EXAMPLE).unwrap();
    assert_eq!(m.cell_count(), 19);
    assert_eq!(m.viewer().pos, vec2(6.0, 14.0));
    assert_eq!(m.viewer().dir_deg, 90.0);
    assert!(m.exit().is_some());
    assert!(m.is_connected() && !m.is_perfect(), "the loop around the middle wall");
    assert_eq!(maze::detect_format(DOC_EXAMPLE), Format::Grid);
    assert_eq!(parse(&maze::write(&m, Format::Grid).unwrap()).unwrap(), m);
}

#[test]
fn arrows_set_the_heading_and_override_facing() {
    for (arrow, deg) in [('>', 0.0), ('^', 90.0), ('<', 180.0), ('v', 270.0)] {
        let m = parse(&format!("mazewalk-grid 1\nfacing south\n###\n#{arrow}#\n###\n")).unwrap();
        assert_eq!(m.viewer().dir_deg, deg, "{arrow}");
    }
    let m = parse("mazewalk-grid 1\nfacing west\n###\n#@#\n###\n").unwrap();
    assert_eq!(m.viewer().dir_deg, 180.0);
}

#[test]
fn settings_tile_eye_fov_and_legend() {
    let m = parse("mazewalk-grid 1\ntile 2.5\neye 0.25\nfov 60\n# = #000000\nB = #ff0000\nBBB\n#@ \n###\n")
        .unwrap();
    assert_eq!(m.viewer().pos, vec2(1.5 * 2.5, 1.5 * 2.5));
    assert_eq!((m.viewer().z, m.viewer().fov_deg), (0.25, 60.0));
    assert_eq!(m.cell_count(), 2);
    let colours: Vec<Vec3> = m.edges().iter().filter(|e| e.opaque).map(|e| e.color).collect();
    assert_eq!(colours.iter().filter(|&&c| c == Vec3::X).count(), 2, "the two tiles under the B row");
    assert!(colours.iter().all(|&c| c == Vec3::X || c == Vec3::ZERO));
    assert_eq!(parse(&maze::write(&m, Format::Grid).unwrap()).unwrap(), m);
}

// QA: `A=#00ff00` was read as a map row, then refused as "wall letter `A` has no colour in the
// legend": a legend line reads the same with or without the spaces around `=`.
#[test]
fn legend_lines_read_with_or_without_spaces() {
    let spaced = parse("mazewalk-grid 1\nA = #00ff00\nB = #0000ff\nAAB\n#@B\n###\n").unwrap();
    for legend in ["A=#00ff00\nB=#0000ff", "A= #00ff00\nB =#0000ff", "A =#00ff00\nB= #0000ff"] {
        let text = format!("mazewalk-grid 1\n{legend}\nAAB\n#@B\n###\n");
        assert_eq!(parse(&text).unwrap(), spaced, "{legend:?}");
    }
    // and its errors still point at the value
    let e = parse("mazewalk-grid 1\nA=red\n#@#\n").unwrap_err();
    assert_eq!((e.line, e.col), (2, 3), "{e}");
    assert!(e.to_string().contains("colour `red`: expected #rrggbb"), "{e}");
}

#[test]
fn crlf_bom_ragged_rows_and_trailing_blank_lines() {
    let text = "\u{FEFF}mazewalk-grid 1\r\n\r\n####\r\n#@.\r\n#\r\n\r\n\r\n";
    let m = parse(text).unwrap();
    // the short last row leaves the outside below the open tiles: still closed walls, default grey
    assert_eq!(m.cell_count(), 2);
    assert!(m.edges().iter().filter(|e| e.opaque).all(|e| e.color == DEFAULT_WALL));
}

#[test]
fn thin_wall_mazes_are_refused_by_the_grid_writer() {
    let m = generate(&GenOptions { width: 3, height: 3, ..GenOptions::default() }).unwrap();
    let e = maze::write(&m, Format::Grid).unwrap_err();
    assert!(e.to_string().starts_with("cannot write as grid: edge "), "{e}");
    assert!(e.to_string().ends_with("is a wall between two cells (walls are tiles here)"), "{e}");
    let real = maze::load(common::maze_path("cs559/maze-1x1-45.maze")).unwrap().maze;
    assert!(maze::write(&real, Format::Grid).unwrap_err().to_string().contains("not a square tile"));
}

#[test]
fn a_generated_tile_map_is_pinned() {
    let o = GenOptions { width: 4, height: 3, seed: 7, exit: true, ..GenOptions::default() };
    let text = generate_grid(&o).unwrap().to_text();
    assert_eq!(text.lines().collect::<Vec<_>>(), PINNED_4X3);
}

const PINNED_4X3: [&str; 11] = [
    "mazewalk-grid 1",
    "tile 4",
    "vfov 96.02558",
    "",
    "#########",
    "#.#.#E..#",
    "#.#.###.#",
    "#.....#.#",
    "###.###.#",
    "#>......#",
    "#########",
];

/// One malformed grid file per error kind: (text, line, col, message start).
const MALFORMED: &[(&str, u32, u32, &str)] = &[
    ("mazewalk-grid 2\n#@#\n", 1, 15, "unsupported grid version `2`"),
    ("mazewalk-grid\n#@#\n", 1, 14, "expected the version after `mazewalk-grid`"),
    ("mazewalk-grid 1\ntile 0\n#@#\n", 2, 6, "tile side 0 is out of range"),
    ("mazewalk-grid 1\ntile 0.5\n#@#\n", 2, 6, "tile side 0.5 is out of range: at least 0.5002 (the viewer"),
    ("mazewalk-grid 1\ntile 1001\n#@#\n", 2, 6, "tile side 1001 is out of range"),
    ("mazewalk-grid 1\ntile four\n#@#\n", 2, 6, "expected a number (tile side), found `four`"),
    // bbA #4: a number too large for an f32 is out of the setting's range, not "not a number"
    ("mazewalk-grid 1\ntile 1e308\n#@#\n", 2, 6, "tile side 1e308 is out of range: at least 0.5002"),
    ("mazewalk-grid 1\neye -1e99\n#@#\n", 2, 5, "eye height -1e99 is not strictly between -1 and 1"),
    // bbA #5: a setting with too many or too few words, or given twice, says so
    ("mazewalk-grid 1\ntile 4 4\n#@#\n", 2, 1, "`tile` takes one number: the tile side, e.g. `tile 4`"),
    ("mazewalk-grid 1\ntile\n#@#\n", 2, 1, "`tile` takes one number"),
    ("mazewalk-grid 1\n fov\n#@#\n", 2, 2, "`fov` takes one number"),
    ("mazewalk-grid 1\nfacing east west\n#@#\n", 2, 1, "`facing` takes one word: east, north, west or south"),
    (
        "mazewalk-grid 1\ntile 4\neye 0.5\n\ntile 5\n#@#\n",
        5,
        1,
        "a second `tile` setting (the first is on line 2)",
    ),
    (
        "mazewalk-grid 1\nA = #ff0000\nA = #00ff00\n#@A\n",
        3,
        1,
        "a second legend line for `A` (the first is on line 2)",
    ),
    ("mazewalk-grid 1\neye 1\n#@#\n", 2, 5, "eye height 1 is not strictly between -1 and 1"),
    ("mazewalk-grid 1\nfov 180\n#@#\n", 2, 5, "field of view 180 is not strictly between 0 and 180"),
    ("mazewalk-grid 1\nfacing up\n#@#\n", 2, 8, "facing `up`: expected east, north, west or south"),
    ("mazewalk-grid 1\ncolour 3\n#@#\n", 2, 1, "unknown setting `colour`"),
    ("mazewalk-grid 1\nA = red\n#@#\n", 2, 5, "colour `red`: expected #rrggbb"),
    ("mazewalk-grid 1\nE = #ffffff\n#@#\n", 2, 1, "legend letter `E`"),
    ("mazewalk-grid 1\n#@#\n#x#\n", 3, 2, "unknown tile `x`"),
    ("mazewalk-grid 1\n#@#\n#é#\n", 3, 2, "unknown tile `é`"),
    ("mazewalk-grid 1\n#@B\n", 2, 3, "wall letter `B` has no colour in the legend"),
    ("mazewalk-grid 1\n#@.>#\n", 2, 4, "a second start tile"),
    ("mazewalk-grid 1\n#@E.E#\n", 2, 5, "a second exit tile `E`"),
    ("mazewalk-grid 1\n#..#\n", 2, 1, "the map has no start tile"),
    ("mazewalk-grid 1\ntile 4\n\n", 4, 1, "expected the map after the settings"),
    // Old Mac line endings: one long line, said so rather than misread.
    ("mazewalk-grid 1\rtile 2\r###\r#@#\r###\r", 1, 16, "a carriage return inside a line"),
    // and after a first line ended by LF: the same, not "unknown tile `\r`"
    ("mazewalk-grid 1\n#####\r#@.E#\r#####\r", 2, 6, "a carriage return inside a line"),
    (
        "\nmazewalk-grid 1\n###\n#@#\n###\n",
        1,
        1,
        "expected `mazewalk-grid 1` on the first line (the very first",
    ),
    // QA: a tile "more than 0.5" was refused as no room to stand; the range says the true bound
    ("mazewalk-grid 1\ntile 0.50001\n\n#####\n#@.E#\n#####\n", 2, 6, "tile side 0.50001 is out of range"),
];

#[test]
fn malformed_grid_files_are_located() {
    for &(text, line, col, message) in MALFORMED {
        let e = parse(text).expect_err(text);
        assert_eq!((e.line, e.col), (line, col), "{text:?}: {e}");
        let shown = e.to_string();
        let want = format!("t.grid:{line}:{col}: {message}");
        assert!(shown.starts_with(&want), "{text:?}:\n got  {shown}\n want {want}…");
    }
}

#[test]
fn maps_beyond_the_coordinate_bound_are_refused() {
    let text = format!("mazewalk-grid 1\ntile 1000\n@{}\n", ".".repeat(1000));
    let e = parse(&text).unwrap_err();
    assert!(
        e.to_string().starts_with("t.grid:3:1: tile side × map size exceeds the coordinate bound"),
        "{e}"
    );
    let text = format!("mazewalk-grid 1\n@{}\n", "\n".repeat(5000) + &".".repeat(1000));
    let e = parse(&text).unwrap_err();
    assert!(e.to_string().contains("tiles; at most"), "{e}");
}

#[test]
fn every_example_in_mazes_loads_and_the_grid_ones_round_trip() {
    let dir = common::MAZES;
    let mut n = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            continue; // cs559/: the course files, loaded by maze_files.rs
        }
        let m = maze::load(&path).unwrap_or_else(|e| panic!("{e}")).maze;
        assert!(m.cell_at(m.viewer().pos).is_some() && m.is_connected(), "{}", path.display());
        let text = std::fs::read_to_string(&path).unwrap();
        let format = maze::detect_format(&text);
        assert_eq!(maze::parse("again", maze::write(&m, format).unwrap().as_bytes()).unwrap(), m);
        n += 1;
    }
    assert!(n >= 4, "mazes/ holds the examples");
}

#[test]
fn grid_parse_map_exposes_the_tiles() {
    let map = grid::parse_map("m", "mazewalk-grid 1\n#@\n").unwrap();
    assert_eq!((map.cols, map.rows, map.tiles.as_slice()), (2, 1, &b"#@"[..]));
}

/// The narrowest tile a file may give still lets the viewer walk down a corridor one tile wide (a
/// tile of 0.1 loaded, and the walk could not move).
#[test]
fn the_viewer_walks_a_corridor_of_the_narrowest_tile() {
    use mazewalk_maze::geometry::WALL_MARGIN;
    use mazewalk_maze::movement::{Position, step};
    let tile = grid::MIN_TILE + 0.01;
    let m = parse(&format!("mazewalk-grid 1\ntile {tile}\n######\n#@...#\n######\n")).unwrap();
    let mut at = Position::of_viewer(&m);
    let start = at.pos;
    for _ in 0..20 {
        at = step(&m, at, vec2(0.1, 0.0), WALL_MARGIN);
    }
    assert!(at.pos.x > start.x + 2.0 * tile, "from {start} to {}", at.pos);
}

/// At the bound: a tile of [`grid::MIN_TILE`] (0.5002) loads, its viewer standing where it starts,
/// clear of both walls, and walks down the corridor; the next narrower side a file can give is
/// refused as out of range (not as a viewer with no room to stand, or one that cannot walk: 0.5001 stood but was stuck at the first tile's corner).
#[test]
fn the_narrowest_tile_is_exactly_the_one_the_viewer_stands_in() {
    use mazewalk_maze::movement::{Position, is_clear, settle, step};
    assert_eq!(grid::MIN_TILE.to_string(), "0.5002");
    // a corridor near the origin running east, and one 2000 tiles out running south (where the
    // walls' coordinates carry f32 rounding of about 6e-5)
    let far = "#".repeat(2000);
    let cases = [
        ("#######\n#@...E#\n#######\n".to_string(), vec2(0.1, 0.0)),
        (format!("{far}###\n{far}#v#\n{far}#.#\n{far}#.#\n{far}#E#\n{far}###\n"), vec2(0.0, -0.1)),
    ];
    for (map, way) in cases {
        let m = parse(&format!("mazewalk-grid 1\ntile {}\n\n{map}", grid::MIN_TILE))
            .unwrap_or_else(|e| panic!("{e}"));
        let stands = settle(&m, Position::of_viewer(&m), m.clearance());
        assert!(is_clear(&m, stands, m.clearance()), "{stands:?}");
        let mut walked = stands;
        for _ in 0..20 {
            walked = step(&m, walked, way, m.clearance());
        }
        assert!(walked.pos.distance(stands.pos) > 1.0, "from {} to {}", stands.pos, walked.pos);
    }
    // every f32 just below the bound, as a file writes it
    let mut below = grid::MIN_TILE;
    for _ in 0..50 {
        below = f32::from_bits(below.to_bits() - 1);
        let text = format!("mazewalk-grid 1\ntile {below}\n\n#####\n#@.E#\n#####\n");
        let e = parse(&text).expect_err(&text).to_string();
        assert!(e.contains(&format!("tile side {below} is out of range: at least 0.5002")), "{e}");
    }
}

/// A maze of tiles narrower than a grid file's may be is not written as one (it would not read back),
/// and the writer says why.
#[test]
fn tiles_too_narrow_for_a_grid_file_are_not_written() {
    let mut map = grid::parse_map(
        "m",
        "mazewalk-grid 1
#####
#@..#
#...#
#...#
#####
",
    )
    .unwrap();
    map.tile = 0.3; // (a room of 3 × 3 tiles, 0.9 across: room for the viewer)
    let m = map.to_maze().unwrap();
    let e = maze::write(&m, Format::Grid).unwrap_err().to_string();
    assert!(e.contains("its tiles are 0.3 across; a grid file's are at least 0.5002"), "{e}");
    map.tile = 0.6;
    assert!(maze::write(&map.to_maze().unwrap(), Format::Grid).is_ok());
}

/// A mostly well-formed grid file: a few settings, then ragged rows of floor, walls and junk, with a
/// start (and maybe an exit) dropped in at random places.
fn arb_grid_text() -> impl Strategy<Value = String> {
    let setting = prop_oneof![
        "tile [0-9]{1,2}(\\.[0-9])?",
        "facing (east|north|west|south|up)",
        "[a-z]{1,3} [0-9]",
        "eye -?0\\.[0-9]",
        "fov [0-9]{1,3}",
        "[A-Z#] = #[0-9a-f]{6}",
    ];
    let rows = prop::collection::vec("[#. A..]{0,14}", 1..10);
    (
        prop::collection::vec(setting, 0..4),
        rows,
        any::<prop::sample::Index>(),
        any::<prop::sample::Index>(),
        "[@>^<v]",
        "[E.]",
    )
        .prop_map(|(settings, rows, at, exit_at, start, exit)| {
            let mut map = rows.join("\n");
            for (ix, ch) in [(at, start), (exit_at, exit)] {
                let chars: Vec<char> = map.chars().collect();
                let k = ix.index(chars.len() + 1);
                map = chars[..k]
                    .iter()
                    .chain(ch.chars().collect::<Vec<_>>().iter())
                    .chain(&chars[k..])
                    .collect();
            }
            // `A` walls need their legend line; leave it out now and then
            let legend = if map.len() % 5 == 0 { "" } else { "A = #cc8844" };
            format!("mazewalk-grid 1\n{}\n{legend}\n{map}\n", settings.join("\n"))
        })
}

proptest! {
    // Each case parses a whole tile map.
    #![proptest_config(common::config_cases(256))]

    // the reader's contract on any input: a maze or a located error, never a panic
    #[test]
    fn any_grid_text_gives_a_maze_or_a_located_error(text in arb_grid_text()) {
        match parse(&text) {
            Ok(m) => {
                prop_assert!(m.cell_at(m.viewer().pos).is_some());
                // whatever the grid reader makes, the grid writer expresses
                let again = maze::write(&m, Format::Grid).unwrap();
                prop_assert_eq!(parse(&again).unwrap(), m);
            }
            Err(e) => prop_assert!(e.line >= 1 && e.col >= 1),
        }
    }
}

// issue #13: rows of spaces at the top or bottom of the map are floor, not dropped
#[test]
fn rows_of_spaces_are_floor() {
    let m = parse("mazewalk-grid 1\n   \n @ \n   \n").unwrap();
    assert_eq!(m.cell_count(), 9, "three rows of three floor tiles");
    assert_eq!(m.viewer().pos, glam::vec2(6.0, 6.0), "the start is in the middle row");
    // an empty line is still a separator, and trailing empty lines end the map
    let m = parse("mazewalk-grid 1\n\n\n #\n @\n\n\n").unwrap();
    assert_eq!(m.cell_count(), 3, "two floor tiles and the start");
}

// bbA #3: `gen --size 1x1 --exit` wrote `exit 0` in CS559 but no `E` in grid (the start took the
// tile), so the two formats of one maze disagreed on its exit.
#[test]
fn a_generated_exit_survives_both_formats_even_on_the_start() {
    for (width, height) in [(1, 1), (1, 3), (4, 2)] {
        let o = GenOptions { width, height, exit: true, ..GenOptions::default() };
        let cs559 = parse(&maze::write(&generate(&o).unwrap(), Format::Cs559).unwrap()).unwrap();
        let text = generate_grid(&o).unwrap().to_text();
        let grid = parse(&text).unwrap();
        // the cells are numbered apart (a grid has corridor tiles): compare where the exits are
        let exit_at = |m: &Maze| {
            m.exit().map(|e| (m.cell_aabb(e.cell).min + m.cell_aabb(e.cell).max) / 2.0 - m.viewer().pos)
        };
        assert!(exit_at(&cs559).is_some(), "{width}x{height}");
        let scale = 2.0; // a grid tile is a cell's side, and cells are two tiles apart
        assert_eq!(exit_at(&cs559).map(|d| d * scale), exit_at(&grid), "{width}x{height}:\n{text}");
        // and the grid text is canonical: written again, it reads back the same
        assert_eq!(parse(&maze::write(&grid, Format::Grid).unwrap()).unwrap(), grid, "{width}x{height}");
    }
    let one = parse(
        &generate_grid(&GenOptions { width: 1, height: 1, exit: true, ..GenOptions::default() })
            .unwrap()
            .to_text(),
    )
    .unwrap();
    assert_eq!(one.exit().map(|e| e.cell), one.cell_at(one.viewer().pos), "the start is the exit");
}

/// `connected` follows portals only: two rooms joined by floor are connected both ways, a room
/// walled off is not, and a cell that does not exist is connected to nothing.
#[test]
fn cells_are_connected_through_portals_only() {
    // cells from the bottom row up, west to east: 0 1 (left room), 2 (the `E` beyond the wall)
    let maze = parse("mazewalk-grid 1\n######\n#@.#E#\n######\n").unwrap();
    assert_eq!(maze.cell_count(), 3);
    assert!(maze.connected(0, 1) && maze.connected(1, 0) && maze.connected(2, 2));
    assert!(!maze.connected(0, 2) && !maze.connected(2, 1));
    assert!(!maze.connected(0, 3) && !maze.connected(3, 3));
    let open = parse("mazewalk-grid 1\n######\n#@..E#\n######\n").unwrap();
    assert!(open.connected(0, 3) && open.connected(3, 0));
}
