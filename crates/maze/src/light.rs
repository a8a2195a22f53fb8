//! The exit's light through the maze, as block light in a voxel game (Minecraft's torches): the exit
//! cell has [`EXIT_LIGHT`], and each cell one step of path further, through an opening (a portal),
//! one level less, so the light follows corridors round corners and never passes through a wall.
//! Issue #39: with the map off nothing in the view said which way the exit was; a faint glow that
//! grows toward it is a trail a player can follow.
//!
//! Pure and bounded: one breadth-first search over the cell graph from the exit, which stops where the
//! light runs out, so its cost is that of the cells it lights (O(cells) at worst).

use crate::{Aabb, CellId, Maze};
use std::collections::{HashMap, VecDeque};

/// The exit cell's light level. A cell `d` openings from the exit has `EXIT_LIGHT − d`, at least 0: the
/// light reaches `EXIT_LIGHT − 1` cells of path from the exit (twenty-seven at 28). Issue #39: at 8
/// (seven cells) the glow first showed about five cells by path from the exit; at 16 (fifteen cells,
/// 35–68 of a 20 × 15 maze's 300 cells round its exit over ten seeds) a new player whose exit was
/// 38–39 openings from the start still spent most of a trial without any cue. Twenty-seven cells
/// light 125–231 of those 300 cells (the same ten seeds; their exits 33–42 openings from the start:
/// the last 27 of the way are lit); the search stays bounded by the
/// reach on any maze (at most 2 · 27² + 2 · 27 + 1 = 1,513 cells on a grid, whatever its size).
pub const EXIT_LIGHT: u8 = 28;

/// The exit's light levels of the cells it reaches: [`EXIT_LIGHT`] at the exit cell, one less per
/// opening crossed on the shortest path from it, none (level 0) beyond. Only the lit cells are kept,
/// so the search and the table are bounded by the light's reach, not by the maze: a 1000 × 1000 grid
/// pays for the few hundred cells round its exit.
#[derive(Clone, Debug, PartialEq)]
pub struct ExitLight {
    /// (cell, level), sorted by cell, every level > 0.
    lit: Vec<(CellId, u8)>,
    /// The box round the lit cells (empty when none is lit): a point outside it is dark.
    bounds: Aabb,
}

impl Default for ExitLight {
    fn default() -> ExitLight {
        ExitLight { lit: Vec::new(), bounds: Aabb::EMPTY }
    }
}

impl ExitLight {
    /// The exit's light in `maze` (none in a maze without an exit).
    #[must_use]
    pub fn of(maze: &Maze) -> ExitLight {
        let cells = maze.cell_count();
        let Some(exit) = maze.exit().filter(|exit| (exit.cell as usize) < cells) else {
            return ExitLight::default();
        };
        let mut level: HashMap<CellId, u8> = HashMap::from([(exit.cell, EXIT_LIGHT)]);
        let mut queue = VecDeque::from([exit.cell]);
        while let Some(cell) = queue.pop_front() {
            let next = level[&cell].saturating_sub(1);
            if next == 0 {
                continue; // the light goes no further from here
            }
            for &e in maze.cell_edges(cell) {
                let edge = maze.edge(e);
                if edge.opaque {
                    continue; // walls block it
                }
                let Some(other) = edge.other_side(cell) else { continue };
                if (other as usize) < cells && !level.contains_key(&other) {
                    level.insert(other, next); // breadth first: the first visit is the shortest path
                    queue.push_back(other);
                }
            }
        }
        let mut lit: Vec<(CellId, u8)> = level.into_iter().collect();
        lit.sort_unstable();
        let bounds = lit.iter().fold(Aabb::EMPTY, |b, &(c, _)| {
            let cell = maze.cell_aabb(c);
            b.union_point(cell.min).union_point(cell.max)
        });
        ExitLight { lit, bounds }
    }

    /// The level of `cell`: 0..=[`EXIT_LIGHT`].
    #[must_use]
    pub fn level(&self, cell: CellId) -> u8 {
        self.lit.binary_search_by_key(&cell, |&(c, _)| c).map_or(0, |k| self.lit[k].1)
    }

    /// The box round the lit cells ([`Aabb::EMPTY`] when none is): every point of a lit cell is in it.
    #[must_use]
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// How many cells the light reaches.
    #[must_use]
    pub fn lit_cells(&self) -> usize {
        self.lit.len()
    }

    /// The lit cell the light comes into through edge `e` of `maze`, if `e` is an opening between
    /// two lit cells one level apart: the dimmer of the two, whose way one step nearer the exit is
    /// through `e` (the light of a cell arrives through the opening to its brighter neighbour). `None`
    /// for a wall, an opening to the outside or to a dark cell, and an opening between cells of one
    /// level (a loop's far side).
    #[must_use]
    pub fn lit_through(&self, maze: &Maze, e: u32) -> Option<CellId> {
        if e as usize >= maze.edges().len() {
            return None;
        }
        let edge = maze.edge(e);
        let (Some(a), Some(b), false) = (edge.left, edge.right, edge.opaque) else { return None };
        let (la, lb) = (self.level(a), self.level(b));
        match la.min(lb) {
            0 => None,
            _ if la + 1 == lb => Some(a),
            _ if lb + 1 == la => Some(b),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::{GenOptions, generate};
    use proptest::prelude::*;

    /// Path distance (openings crossed) from the exit to every cell, by a plain BFS with no cut-off.
    fn distances(maze: &Maze) -> Vec<Option<u32>> {
        let mut dist = vec![None; maze.cell_count()];
        let exit = maze.exit().expect("exit").cell;
        dist[exit as usize] = Some(0);
        let mut queue = VecDeque::from([exit]);
        while let Some(c) = queue.pop_front() {
            for &e in maze.cell_edges(c) {
                let edge = maze.edge(e);
                if let (false, Some(o)) = (edge.opaque, edge.other_side(c))
                    && dist[o as usize].is_none()
                {
                    dist[o as usize] = Some(dist[c as usize].unwrap() + 1);
                    queue.push_back(o);
                }
            }
        }
        dist
    }

    proptest! {
        // Each case generates a maze and searches its light: 32 cases.
        #![proptest_config(mazewalk_testkit::config_cases(32))]

        // The level is EXIT_LIGHT minus the path distance through openings, zero beyond the reach;
        // two cells side by side with a wall between differ by more than one step only when the wall
        // blocks the light (their path distance differs by more than one).
        #[test]
        fn the_level_falls_by_one_per_opening_and_walls_block_it(
            (width, height, seed) in (2u32..=40, 2u32..=30, any::<u64>()),
        ) {
            let maze = generate(&GenOptions::walk(width, height, seed)).expect("maze");
            let light = ExitLight::of(&maze);
            let level: Vec<u8> = (0..maze.cell_count() as u32).map(|c| light.level(c)).collect();
            let dist = distances(&maze);
            for (c, (&l, d)) in level.iter().zip(&dist).enumerate() {
                let want = d.map_or(0, |d| u32::from(EXIT_LIGHT).saturating_sub(d)) as u8;
                prop_assert_eq!(l, want, "cell {}: distance {:?}", c, d);
            }
            // monotone: a neighbour through an opening differs by at most one step
            for e in 0..maze.edges().len() as u32 {
                let edge = maze.edge(e);
                if let (false, Some(a), Some(b)) = (edge.opaque, edge.left, edge.right) {
                    prop_assert!(level[a as usize].abs_diff(level[b as usize]) <= 1);
                }
            }
        }
    }

    #[test]
    fn a_wall_stops_the_light_where_an_opening_would_pass_it() {
        // A 2×1 maze: two cells side by side. Generated mazes connect them; walling the opening off
        // leaves the second cell dark.
        let maze =
            generate(&GenOptions { width: 2, height: 1, seed: 1, exit: true, ..GenOptions::default() })
                .expect("maze");
        let level = [ExitLight::of(&maze).level(0), ExitLight::of(&maze).level(1)];
        let exit = maze.exit().expect("exit").cell as usize;
        assert_eq!(level[exit], EXIT_LIGHT);
        assert_eq!(level[1 - exit], EXIT_LIGHT - 1, "one opening away");
        let mut edges = crate::Edges::new();
        let mut walled_off = 0;
        for e in 0..maze.edges().len() {
            let mut edge = maze.edge(e as u32);
            if !edge.opaque {
                edge.opaque = true;
                walled_off += 1;
            }
            edges.push(edge);
        }
        assert_eq!(walled_off, 1, "two cells, one opening");
        let walled = Maze::new(
            maze.vertices().to_vec(),
            edges,
            maze.cells().clone(),
            *maze.viewer(),
            maze.exit().copied(),
        )
        .expect("the same maze, walled");
        let level = [ExitLight::of(&walled).level(0), ExitLight::of(&walled).level(1)];
        assert_eq!(level[exit], EXIT_LIGHT);
        assert_eq!(level[1 - exit], 0, "through a wall: no light");
    }

    #[test]
    fn the_maze_keeps_its_light_and_the_box_holds_every_lit_cell() {
        // (large enough that the box, at most 55 cells a side, leaves most of the maze out)
        let maze = generate(&GenOptions::walk(100, 80, 71)).expect("maze");
        let kept: *const ExitLight = maze.exit_light();
        assert!(std::ptr::eq(kept, maze.exit_light()), "searched once, then kept");
        let light = ExitLight::of(&maze);
        assert_eq!(*maze.exit_light(), light);
        assert!(light.lit_cells() > 8, "{}", light.lit_cells());
        let bounds = light.bounds();
        let mut dark_outside = 0;
        for c in 0..maze.cell_count() as u32 {
            let cell = maze.cell_aabb(c);
            let inside = bounds.contains(&cell);
            if light.level(c) > 0 {
                assert!(inside, "lit cell {c} {cell:?} outside {bounds:?}");
            } else if !bounds.intersects(&cell) {
                dark_outside += 1;
            }
        }
        assert!(
            dark_outside > maze.cell_count() / 2,
            "the box is the light's, not the maze's: {dark_outside}"
        );
        assert!(ExitLight::default().bounds().is_empty());
    }

    /// Issue #39: the light reaches twenty-seven cells of path (the exit's own and twenty-seven more
    /// levels), on a maze of any size, and the search and the box stay the light's: on a 300 × 300
    /// grid the lit cells are at most the 1,513 within twenty-seven steps of the exit by any route,
    /// the farthest twenty-seven openings away, and the box at most 55 cells a side.
    #[test]
    fn the_light_reaches_twenty_seven_cells_of_path_and_no_more_on_a_large_maze() {
        assert_eq!(EXIT_LIGHT, 28);
        let reach = u32::from(EXIT_LIGHT) - 1;
        let maze = generate(&GenOptions::walk(300, 300, 7)).expect("maze");
        let light = ExitLight::of(&maze);
        let dist = distances(&maze);
        let within: Vec<u32> =
            (0..maze.cell_count() as u32).filter(|&c| dist[c as usize].is_some_and(|d| d <= reach)).collect();
        assert_eq!(light.lit_cells(), within.len());
        let most = 2 * reach * reach + 2 * reach + 1;
        assert_eq!(most, 1513);
        assert!(light.lit_cells() <= most as usize, "{}", light.lit_cells());
        assert!(
            within.iter().any(|&c| dist[c as usize] == Some(reach)),
            "a corridor twenty-seven cells long from the exit"
        );
        assert!(within.iter().all(|&c| u32::from(light.level(c)) == 28 - dist[c as usize].unwrap()));
        let size = light.bounds().max - light.bounds().min;
        let cell = crate::generate::CELL_SIZE;
        let side = (2 * reach + 1) as f32 * cell + 1e-3;
        assert!(size.x <= side && size.y <= side, "{size:?}");
    }

    proptest! {
        // Each case generates a maze and searches its light: 16 cases.
        #![proptest_config(mazewalk_testkit::config_cases(16))]

        // An opening the light comes through leads its dimmer cell one step nearer the exit by path,
        // and from every lit cell but the exit's, the light comes in through at least one opening (a
        // way on); an opening it does not come through joins cells not one step apart, or a dark one.
        #[test]
        fn the_light_comes_into_a_cell_through_its_way_toward_the_exit(
            (width, height, seed) in (2u32..=30, 2u32..=20, any::<u64>()),
        ) {
            let maze = generate(&GenOptions::walk(width, height, seed)).expect("maze");
            let light = ExitLight::of(&maze);
            let dist = distances(&maze);
            let exit = maze.exit().expect("exit").cell;
            for e in 0..maze.edges().len() as u32 {
                let edge = maze.edge(e);
                match light.lit_through(&maze, e) {
                    Some(dim) => {
                        prop_assert!(!edge.opaque);
                        let other = edge.other_side(dim).expect("an opening between two cells");
                        prop_assert!(light.level(dim) >= 1);
                        prop_assert_eq!(dist[other as usize].map(|d| d + 1), dist[dim as usize]);
                    }
                    None => {
                        if let (false, Some(a), Some(b)) = (edge.opaque, edge.left, edge.right) {
                            let (la, lb) = (light.level(a), light.level(b));
                            prop_assert!(la.min(lb) == 0 || la == lb, "edge {}: {} {}", e, la, lb);
                        }
                    }
                }
            }
            for cell in (0..maze.cell_count() as u32).filter(|&c| light.level(c) > 0 && c != exit) {
                prop_assert!(
                    maze.cell_edges(cell).iter().any(|&e| light.lit_through(&maze, e) == Some(cell)),
                    "lit cell {} has no way in for the light", cell
                );
            }
            prop_assert_eq!(light.lit_through(&maze, u32::MAX), None);
        }
    }

    #[test]
    fn no_exit_no_light() {
        let maze =
            generate(&GenOptions { width: 4, height: 3, seed: 2, exit: false, ..GenOptions::default() })
                .expect("maze");
        assert_eq!(ExitLight::of(&maze).lit_cells(), 0);
    }
}
