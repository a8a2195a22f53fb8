//! Malformed CS559 input: one case per error kind, each with its message and `FILE:LINE:COL`.

use mazewalk_maze::{self as maze, MazeError, ParseErrorKind};

/// One room, 4 × 4, as the original writes it: vertices, edges, one cell, viewer.
const ROOM: &str = "4
0 0
4 0
0 4
4 4
4
0 1 0 -1 1 0.5 0.5 0.5
2 3 -1 0 1 0.5 0.5 0.5
0 2 -1 0 1 0.5 0.5 0.5
1 3 0 -1 1 0.5 0.5 0.5
1
3 1 2 0
2 2 0 90 90
";

/// `ROOM` with the `n`th line (1-based) replaced.
fn room_with(n: usize, line: &str) -> String {
    ROOM.lines().enumerate().map(|(i, l)| if i + 1 == n { line } else { l }).collect::<Vec<_>>().join("\n")
}

fn error(bytes: impl AsRef<[u8]>) -> String {
    match maze::parse("f.maze", bytes.as_ref()) {
        Ok(_) => panic!("parsed: {:?}", String::from_utf8_lossy(bytes.as_ref())),
        Err(e) => e.to_string(),
    }
}

#[test]
fn the_room_itself_is_valid() {
    let m = maze::parse("f.maze", ROOM.as_bytes()).unwrap();
    assert_eq!((m.cell_count(), m.wall_count(), m.portal_count()), (1, 4, 0));
}

#[test]
fn malformed_files_give_file_line_col_and_what_is_wrong() {
    let table: Vec<(Vec<u8>, &str)> = vec![
        // lexical
        (b"".to_vec(), "f.maze:1:1: unexpected end of file: expected vertex count"),
        (b"4\n0 0\n4".to_vec(), "f.maze:3:2: unexpected end of file: expected vertex 1 y"),
        (b"4\n0 x".to_vec(), "f.maze:2:3: expected a number (vertex 0 y), found `x`"),
        (b"2.5".to_vec(), "f.maze:1:1: expected an integer (vertex count), found `2.5`"),
        (b"-3".to_vec(), "f.maze:1:1: vertex count is -3, out of range (0 or more)"),
        (b"1000000000000 0 0".to_vec(), "f.maze:1:1: the file claims 1000000000000 vertices; at most 4294967294 are supported"),
        (b"1000000000 0 0".to_vec(), "f.maze:1:15: unexpected end of file: expected vertex 1 x"),
        (b"1\nnan 0".to_vec(), "f.maze:2:1: vertex 0 x nan is not a finite number"),
        (b"1\n0 -inf".to_vec(), "f.maze:2:3: vertex 0 y -inf is not a finite number"),
        // bbA #4: a number too large for an f32 is told the field's range, not the f32's
        (b"1\n0 1e39".to_vec(), "f.maze:2:3: vertex 0 y is 1e39, out of range (within ±1000000)"),
        (room_with(7, "0 1 0 -1 1 0.5 1e39 0.5").into_bytes(), "f.maze:7:16: edge 0 green is 1e39, out of range (0..=1)"),
        (room_with(13, "2 2 0 1e300 90").into_bytes(), "f.maze:13:7: viewer direction is 1e300, out of range (within ±1000000)"),
        (room_with(13, "2 2 -1e99 0 90").into_bytes(), "f.maze:13:5: viewer z is -1e99, out of range (strictly between -1 and 1)"),
        (b"99999999999999999999".to_vec(), "f.maze:1:1: vertex count is 99999999999999999999, out of range (a 64-bit integer"),
        (b"-99999999999999999999".to_vec(), "f.maze:1:1: vertex count is -99999999999999999999, out of range"),
        (b"4\n0\xff 0".to_vec(), "f.maze:2:2: invalid UTF-8 (byte 0xff)"),
        (room_with(7, "0 1 0 -1 2 0.5 0.5 0.5").into_bytes(), "f.maze:7:10: edge 0 opaque flag is 2, out of range (0 or 1)"),
        (room_with(7, "0 1 -2 -1 1 0.5 0.5 0.5").into_bytes(), "f.maze:7:5: edge 0 left cell is -2, out of range"),
        (room_with(12, "3 1 2 0 7").into_bytes(), "f.maze:13:3: the viewer's eye height 2 is not strictly between"),
        // the model, pointing at the field at fault (issue #13)
        (room_with(2, "0 1e7").into_bytes(), "f.maze:2:3: vertex 0 has a coordinate that is not finite or beyond"),
        (room_with(7, "0 9 0 -1 1 0.5 0.5 0.5").into_bytes(), "f.maze:7:3: edge 0 names vertex 9, but there are only 4 vertices"),
        (room_with(7, "0 0 0 -1 1 0.5 0.5 0.5").into_bytes(), "f.maze:7:3: edge 0 has zero length"),
        (room_with(7, "0 1 3 -1 1 0.5 0.5 0.5").into_bytes(), "f.maze:7:5: edge 0 names cell 3, but there is only 1 cell"),
        (room_with(7, "0 1 -1 -1 1 0.5 0.5 0.5").into_bytes(), "f.maze:7:5: edge 0 borders no cell"),
        (room_with(7, "0 1 0 -1 0 0.5 0.5 0.5").into_bytes(), "f.maze:7:10: edge 0 is transparent but leads outside the maze"),
        (room_with(7, "0 1 0 -1 1 0.5 1.5 0.5").into_bytes(), "f.maze:7:16: edge 0 has a colour component outside 0..1"),
        (room_with(12, "3 1 2 -1").into_bytes(), "f.maze:7:5: edge 0 lists cell 0 on its left but cell 0 does not list edge 0"),
        (room_with(12, "3 1 2 7").into_bytes(), "f.maze:12:7: cell 0 lists edge 7, but there are only 4 edges"),
        (room_with(12, "3 1 2 2").into_bytes(), "f.maze:12:7: cell 0 lists edge 2 twice"),
        (
            room_with(7, "0 1 -1 0 1 0.5 0.5 0.5").into_bytes(),
            "f.maze:12:1: cell 0's edges do not form one closed loop",
        ),
        (
            room_with(5, "1 1").into_bytes(), // pull a corner in: the quad turns concave
            "f.maze:12:1: cell 0 is not convex (at vertex 3)",
        ),
        (b"4 0 0 4 0 0 4 4 4 4 0 1 -1 0 1 .5 .5 .5 2 3 0 -1 1 .5 .5 .5 0 2 0 -1 1 .5 .5 .5 1 3 -1 0 1 .5 .5 .5 1 0 1 2 3 2 2 0 0 90".to_vec(),
            "f.maze:1:103: cell 0 winds clockwise or has no area"),
        (room_with(13, "9 9 0 90 90").into_bytes(), "f.maze:13:1: the viewer at (9, 9) is in no cell"),
        (room_with(13, "2 2 1 90 90").into_bytes(), "f.maze:13:5: the viewer's eye height 1 is not strictly between"),
        (room_with(13, "2 2 0 90 180").into_bytes(), "f.maze:13:10: the viewer's field of view 180° is not strictly between 0 and 180"),
        // the exit extension
        (format!("{ROOM}exit 3\n").into_bytes(), "f.maze:14:1: the exit names cell 3, but there is only 1 cell"),
        (format!("{ROOM}exit 9 9\n").into_bytes(), "f.maze:14:1: the exit point (9, 9) is in no cell"),
        (format!("{ROOM}exit 1 2 3\n").into_bytes(), "f.maze:14:1: expected `exit CELL` or `exit X Y`, found `exit 1 2 3`"),
        // bbA #5: a second exit line was ignored; a grid header in capitals read as a vertex count
        (format!("{ROOM}exit 0\n\n  exit 0\n").into_bytes(), "f.maze:16:3: a second `exit` line (the first is on line 14)"),
        // QA: an `exit` in capitals or on the viewer's line was dropped without a word (no exit)
        (format!("{ROOM}EXIT 0\n").into_bytes(), "f.maze:14:1: expected `exit` in lower case, found `EXIT`"),
        (format!("{ROOM}  Exit 0\n").into_bytes(), "f.maze:14:3: expected `exit` in lower case, found `Exit`"),
        (format!("{ROOM}VFOV 60\n").into_bytes(), "f.maze:14:1: expected `vfov` in lower case, found `VFOV`"),
        (
            room_with(13, "2 2 0 90 90 exit 0").into_bytes(),
            "f.maze:13:13: expected `exit` on a line of its own, after the viewer's line, found `exit`",
        ),
        (
            room_with(13, "2 2 0 90 90 vfov 60").into_bytes(),
            "f.maze:13:13: expected `vfov` on a line of its own",
        ),
        // lines ended by CR alone (classic Mac OS): one line to the reader, whose `exit` is refused
        // at the CR that ends the viewer's line, not as an `exit` on the viewer's line
        (
            format!("{ROOM}exit 0\n").replace('\n', "\r").into_bytes(),
            "f.maze:1:134: a carriage return inside a line: lines end in LF or CRLF, not CR alone",
        ),
        // the least vertical field of view's extension
        (format!("{ROOM}vfov 151\n").into_bytes(), "f.maze:14:6: least vertical field of view is 151, out of range (within 0..=150)"),
        (format!("{ROOM}vfov -1\n").into_bytes(), "f.maze:14:6: least vertical field of view is -1, out of range"),
        (format!("{ROOM}vfov wide\n").into_bytes(), "f.maze:14:6: expected a number (least vertical field of view), found `wide`"),
        (format!("{ROOM}vfov 96 97\n").into_bytes(), "f.maze:14:1: expected `vfov DEG`, found `vfov 96 97`"),
        (format!("{ROOM}vfov 96\nexit 0\nvfov 96\n").into_bytes(), "f.maze:16:1: a second `vfov` line (the first is on line 14)"),
        (b"Mazewalk-Grid 1\n#@#\n".to_vec(), "f.maze:1:1: `Mazewalk-Grid` looks like a grid file's header, which is `mazewalk-grid 1` in lower case"),
    ];
    for (input, expected) in table {
        let got = error(&input);
        assert!(
            got.starts_with(expected),
            "\n input: {:?}\n   got: {got}\nwanted: {expected}",
            String::from_utf8_lossy(&input)
        );
    }
}

#[test]
fn crossing_and_overlapping_edges_are_named() {
    // two rooms side by side sharing the wall x = 4, but the second room's wall is a separate,
    // overlapping edge: a collinear overlap
    let text = "6 0 0 4 0 8 0 0 4 4 4 8 4
        8
        0 1 0 -1 1 .5 .5 .5
        3 4 -1 0 1 .5 .5 .5
        0 3 -1 0 1 .5 .5 .5
        1 4 0 -1 1 .5 .5 .5
        1 2 1 -1 1 .5 .5 .5
        4 5 -1 1 1 .5 .5 .5
        1 4 -1 1 1 .5 .5 .5
        2 5 1 -1 1 .5 .5 .5
        2  0 1 2 3  4 5 6 7
        2 2 0 0 90";
    assert_eq!(error(text), "f.maze:9:9: edges 3 and 6 overlap (collinear)");
    // two rooms overlapping: their walls cross
    let text = "8  0 0 4 0 0 4 4 4  2 2 6 2 2 6 6 6
        8
        0 1 0 -1 1 .5 .5 .5
        2 3 -1 0 1 .5 .5 .5
        0 2 -1 0 1 .5 .5 .5
        1 3 0 -1 1 .5 .5 .5
        4 5 1 -1 1 .5 .5 .5
        6 7 -1 1 1 .5 .5 .5
        4 6 -1 1 1 .5 .5 .5
        5 7 1 -1 1 .5 .5 .5
        2  3 1 2 0  7 5 6 4
        1 1 0 0 90";
    let e = maze::parse("f.maze", text.as_bytes()).unwrap_err();
    assert!(matches!(e.kind, ParseErrorKind::Invalid(MazeError::EdgesCross { a: 1 | 3, b: 4 | 6 })), "{e}");
}

/// A room inside a room: no edges cross, but the cells share area (the walk went through the inner
/// walls, and the renderers disagreed on what stood there). Refused at the inner cell's line,
/// whichever order the file lists them in, and whichever cell's centre lies in the other.
#[test]
fn a_cell_inside_another_is_refused() {
    let nested = |inner_first: bool, inner: [f32; 2]| {
        let cells = if inner_first { ["4 5 6 7", "0 1 2 3"] } else { ["0 1 2 3", "4 5 6 7"] };
        let [lo, hi] = inner;
        let (o, i) = if inner_first { (1, 0) } else { (0, 1) };
        format!(
            "8  0 0 10 0 10 10 0 10  {lo} {lo} {hi} {lo} {hi} {hi} {lo} {hi}
            8
            0 1 {o} -1 1 .5 .5 .5
            1 2 {o} -1 1 .5 .5 .5
            2 3 {o} -1 1 .5 .5 .5
            3 0 {o} -1 1 .5 .5 .5
            4 5 {i} -1 1 .5 .5 .5
            5 6 {i} -1 1 .5 .5 .5
            6 7 {i} -1 1 .5 .5 .5
            7 4 {i} -1 1 .5 .5 .5
            2
            {}
            {}
            0.5 0.5 0 45 90",
            cells[0], cells[1]
        )
        .lines()
        .map(str::trim)
        .collect::<Vec<_>>()
        .join("\n")
    };
    // The inner box round the outer one's centre (4..6), and off it (1..3).
    for (inner, centred) in [([4.0, 6.0], true), ([1.0, 3.0], false)] {
        for inner_first in [false, true] {
            let text = nested(inner_first, inner);
            let (line, cell, other) = if inner_first { (12, 0, 1) } else { (13, 1, 0) };
            let want = format!("f.maze:{line}:1: cell {cell} lies inside cell {other}");
            assert!(
                error(&text).starts_with(&want),
                "centred {centred}, inner first {inner_first}: {}",
                error(&text)
            );
        }
    }
    // Side by side, sharing a wall: fine; also when one is a sliver, whose centre lies within the
    // point location's tolerance of the other.
    assert!(maze::parse("f.maze", crate_two_rooms().as_bytes()).is_ok());
    let sliver = crate_two_rooms().replacen("8 0 0 4 4 4 8 4", "4.00005 0 0 4 4 4 4.00005 4", 1);
    assert!(sliver.contains("4.00005 4"), "the premise");
    let m = maze::parse("f.maze", sliver.as_bytes());
    assert!(m.as_ref().is_ok_and(|m| m.cell_count() == 2), "{:?}", m.err());
}

/// Two 4 × 4 rooms sharing the wall x = 4 (a portal).
fn crate_two_rooms() -> String {
    "6 0 0 4 0 8 0 0 4 4 4 8 4
    7
    0 1 0 -1 1 .5 .5 .5
    1 2 1 -1 1 .5 .5 .5
    3 4 -1 0 1 .5 .5 .5
    4 5 -1 1 1 .5 .5 .5
    0 3 -1 0 1 .5 .5 .5
    1 4 0 1 0 .5 .5 .5
    2 5 1 -1 1 .5 .5 .5
    2  5 2 4 0  6 3 5 1
    2 2 0 0 90"
        .to_string()
}

#[test]
fn a_viewer_on_a_wall_two_cells_away_is_refused() {
    // issue #13: five triangles fanned round the viewer's vertex; the one wall among the spokes
    // borders neither the cell the viewer is found in nor that cell's portal neighbours
    let text = "6  0 0  10 0  3 9  -8 6  -8 -6  3 -9
        10
        0 1 0 4 0 .5 .5 .5
        0 2 1 0 0 .5 .5 .5
        0 3 2 1 0 .5 .5 .5
        0 4 3 2 1 .5 .5 .5
        0 5 4 3 0 .5 .5 .5
        1 2 0 -1 1 .5 .5 .5
        2 3 1 -1 1 .5 .5 .5
        3 4 2 -1 1 .5 .5 .5
        4 5 3 -1 1 .5 .5 .5
        5 1 4 -1 1 .5 .5 .5
        5  0 5 1 -1  1 6 2 -1  2 7 3 -1  3 8 4 -1  4 9 0 -1
        0 0 0 0 90";
    assert_eq!(error(text), "f.maze:14:9: the viewer at (0, 0) stands on wall 3; place it inside a cell");
}

/// The walk keeps the viewer 0.25 from every wall (the renderer's near plane lies inside that margin):
/// a room narrower than 0.5 has no place for it, and from its middle every wall was cut away by the
/// near plane (a blank frame, silently). Refused at the viewer's line; a room just wide enough loads.
#[test]
fn a_room_too_narrow_for_the_viewer_is_refused() {
    let room =
        |w: f32| ROOM.replace("\n4 0\n", &format!("\n{w} 0\n")).replace("\n4 4\n", &format!("\n{w} 4\n"));
    let at = |w: f32| room(w).replace("2 2 0 90 90", &format!("{} 2 0 90 90", w / 2.0));
    assert!(room(0.4).contains("0.4 4"), "the premise");
    for w in [0.08, 0.3, 0.45] {
        let want = format!("f.maze:13:1: the viewer at ({}, 2) has no room to stand", w / 2.0);
        assert!(error(at(w)).starts_with(&want), "{w}: {}", error(at(w)));
        assert!(matches!(
            maze::parse("f.maze", at(w).as_bytes()).unwrap_err().kind,
            ParseErrorKind::Invalid(MazeError::ViewerNoRoom { cell: 0, .. })
        ));
    }
    // Room enough, even from a viewer put against the wall: the walk starts 0.25 from it.
    for (w, x) in [(0.55, 0.275), (0.55, 0.01), (1.0, 0.5)] {
        let text = room(w).replace("2 2 0 90 90", &format!("{x} 2 0 90 90"));
        assert!(maze::parse("f.maze", text.as_bytes()).is_ok(), "{w} from {x}");
    }
}

#[test]
fn crlf_bom_and_trailing_junk_are_fine() {
    let crlf = format!("\u{feff}{}", ROOM.replace('\n', "\r\n"));
    assert!(maze::parse("f", crlf.as_bytes()).is_ok());
    // a CRLF file's error columns count characters, not the \r
    let bad = room_with(2, "0 x").replace('\n', "\r\n");
    assert_eq!(error(bad), "f.maze:2:3: expected a number (vertex 0 y), found `x`");
    // the original ignores everything after the viewer, binary included
    let junk = [ROOM.as_bytes(), b"trailing words 1 2 3\n\x00\xff\xfe garbage"].concat();
    assert!(maze::parse("f", &junk).is_ok());
    // a BOM does not shift columns
    assert_eq!(error("\u{feff}x"), "f.maze:1:1: expected an integer (vertex count), found `x`");
}

#[test]
fn the_exit_extension_reads_a_cell_or_a_point() {
    let m = maze::parse("f", format!("{ROOM}\nexit 0\n").as_bytes()).unwrap();
    assert_eq!(m.exit().map(|x| (x.cell, x.point)), Some((0, None)));
    let m = maze::parse("f", format!("{ROOM}some note\nexit 3 1.5\n").as_bytes()).unwrap();
    assert_eq!(m.exit().map(|x| (x.cell, x.point)), Some((0, Some(glam::vec2(3.0, 1.5)))));
    let text = maze::write(&m, maze::Format::Cs559).unwrap();
    assert!(text.ends_with("2 2 0 90 90\nexit 3 1.5\n"), "{text}");
    assert_eq!(maze::parse("f", text.as_bytes()).unwrap(), m);
}

#[test]
fn errors_carry_a_kind_for_programs() {
    let e = maze::parse("f", room_with(7, "0 1 -1 -1 1 0.5 0.5 0.5").as_bytes()).unwrap_err();
    assert_eq!((e.line, e.col), (7, 5), "the left cell field");
    assert_eq!(e.kind, ParseErrorKind::Invalid(MazeError::EdgeNoCell { edge: 0 }));
}

#[test]
fn load_reports_an_unreadable_file() {
    let e = maze::load("/nonexistent/x.maze").unwrap_err();
    assert!(matches!(e, maze::LoadError::Io { .. }));
    assert!(e.to_string().starts_with("/nonexistent/x.maze: cannot read:"), "{e}");
}
