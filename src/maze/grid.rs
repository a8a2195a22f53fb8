//! Grid format (to be written).
use super::{Maze, ParseError, WriteError};
/// The first word of a grid file.
pub const MAGIC: &str = "mazewalk-grid";
/// Parses grid text.
pub fn parse_str(_file: &str, _text: &str) -> Result<Maze, ParseError> { todo!() }
/// Writes grid text.
pub fn write(_maze: &Maze) -> Result<String, WriteError> { todo!() }
