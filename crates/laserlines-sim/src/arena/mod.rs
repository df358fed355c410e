//! RoboCup Rescue arena layouts (`.raf` files) as simulator worlds, cut at the laser's
//! height.
//!
//! A `.raf` file is XML: `<elements>` holding `<element type="T" rotation="R" x="X" y="Y"/>`
//! (optionally `offset-x`, `offset-y` in grid units and a `mount-point` index). Elements
//! stand on a grid of [`ARENA_GRID`] = 1.2 m cells: the centre of element `(X, Y)` is at
//! `(1.2 X, 1.2 Y)` metres in the arena frame (plus `1.2` times the offsets), and the
//! element is turned by `yaw = -R` degrees about that centre, as the arena designer of
//! `hector_nist_arenas_gazebo` places its models.
//!
//! Every element type of that set that stands in the arena is modelled with the geometry of
//! its public model (the facts are in the source, `elements.rs`), and what a horizontal
//! laser sees of it is its cut at the laser's height [`ArenaOptions::laser_height`]
//! (default [`DEFAULT_LASER_HEIGHT`] = 0.45 m):
//!
//! - walls are thin plates on one edge of their cell: at `R = 0` on the `+y` edge, at
//!   `R = 90` on the `+x` edge, at `R = 180` on the `-y` edge, at `R = 270` on the `-x`
//!   edge, [`WallLength::Full`] (1.2 m, closing the corners; the default) or
//!   [`WallLength::Mesh`] (1.0 m centred on the edge); the holes of `wall_holes1` and
//!   `small_wall_triple_holes` open them where the plane crosses a hole;
//! - `wall_diag_120` is a plate along its cell's diagonal, `corner_diag_120` two plates
//!   from the cell centre to the corners of one edge; `veil_wall` nine hanging strips;
//! - barrels are half barrels on a cell edge (0.29 m radius, from 0.30 m up; two back to
//!   back make one disc); `fiducial_barrel_high` stands on an elevated floor, above the
//!   plane;
//! - ramps are solid wedges (`half_ramp` up to 0.17 m, `full_ramp` to 0.34 m) seen where
//!   their surface meets the plane, `simple_elev_ramp` a board up to 1.18 m, cut where it
//!   crosses the plane; `stairs_120` five open treads (0.2 m to 1.0 m); `elevated_floor_120`
//!   a table top at 1.08-1.2 m on four corner legs; `manip_storage` two shelves (0.5 m,
//!   1.0 m); `spectator_120` a box from 1.07 m to 1.7 m; `victim_with_box1` a box 0.4 m high
//!   on the wall of its cell at the mount point, or on the floor;
//! - step fields and small items lying on the floor are known by their height only: below
//!   the plane they leave nothing, and a laser lower than them skips them.
//!
//! The report ([`ArenaReport`]) counts, by type, the elements that left something in the
//! plane, those that did not (wholly above or below it), and those skipped: unknown types
//! and known ones whose shape at that height the loader does not have. Nothing is dropped
//! silently.
//!
//! The simulated robot collides with what the plane holds and nothing else: it drives over
//! ramps and step fields lower than its laser as over flat floor, and through the open
//! treads of stairs between the laser's height and the floor.
//!
//! ```
//! use laserlines_sim::arena::{ArenaOptions, parse_raf};
//! let text = r#"<?xml version="1.0"?>
//! <elements>
//!   <element type="small_wall" rotation="0" x="0" y="0"/>
//!   <element type="wall_diag_120" rotation="0" x="1" y="0"/>
//!   <element type="half_ramp" rotation="90" x="1" y="0"/>
//!   <element type="mystery" rotation="0" x="2" y="0"/>
//! </elements>"#;
//! let arena = parse_raf(text, "doc", &ArenaOptions::default()).unwrap();
//! // One wall on the +y edge of cell (0, 0): from (-0.6, 0.6) to (0.6, 0.6), and the
//! // diagonal of cell (1, 0) from (0.6, -0.6) to (1.8, 0.6).
//! assert_eq!(arena.world.walls.len(), 2);
//! assert!((arena.world.walls[0].a.y - 0.6).abs() < 1e-12);
//! assert!((arena.world.walls[1].b.x - 1.8).abs() < 1e-12);
//! // The ramp (at most 0.17 m high) is below the laser at 0.45 m; the unknown type is
//! // skipped, and said so.
//! assert_eq!(arena.report.out_of_plane.get("half_ramp"), Some(&1));
//! assert_eq!(arena.report.skipped.get("mystery"), Some(&1));
//! ```

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use laserlines::math::{Isometry2, Point2, Vector2};

mod cut;
mod element;
mod elements;
mod outline;
mod start;
mod tags;
mod views;

use cut::{Builder, Piece, cut_solid, cut_wall};
use element::Element;
use elements::{Kind, element_type};
pub use outline::{ArenaOutline, OUTLINE_CELL, SEAL_GAP};
pub use start::{START_SEARCH_CELL, interior_start};
use tags::Tags;
pub use views::{JOIN_TOLERANCE, SCENE_CLEARANCE, arena_scenes, join_collinear_walls};

use crate::world::World;

/// The arena grid, m: one element cell is 1.2 m x 1.2 m.
pub const ARENA_GRID: f64 = 1.2;

/// The laser's height above the floor the arenas are cut at by default, m: a URG-04LX on
/// top of a rescue robot of NAJI V's size, above the ramps (0.17 m and 0.34 m) and step
/// fields (0.40 m) it drives over.
pub const DEFAULT_LASER_HEIGHT: f64 = 0.45;

/// The element types the loader models (the others are skipped and reported).
#[must_use]
pub fn known_types() -> Vec<&'static str> {
    elements::TYPES.iter().map(|t| t.name).collect()
}

/// How long a wall element's segment is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum WallLength {
    /// The whole cell edge, 1.2 m: neighbouring walls meet, corners are closed (the safe
    /// choice for a laser simulator).
    #[default]
    Full,
    /// 1.0 m centred on the cell edge, as the mesh of the plate: 0.1 m gaps at every corner.
    Mesh,
}

impl WallLength {
    /// The segment's length, m.
    #[must_use]
    pub fn metres(self) -> f64 {
        match self {
            Self::Full => ARENA_GRID,
            Self::Mesh => 1.0,
        }
    }
}

/// Options of the loader.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArenaOptions {
    /// Length of a wall element's segment (default [`WallLength::Full`]).
    pub wall_length: WallLength,
    /// Height of the laser's scan plane above the floor, m (default
    /// [`DEFAULT_LASER_HEIGHT`]); the arena is what that plane cuts. Not finite or not
    /// above 0: the default.
    pub laser_height: f64,
}

impl Default for ArenaOptions {
    fn default() -> Self {
        Self {
            wall_length: WallLength::Full,
            laser_height: DEFAULT_LASER_HEIGHT,
        }
    }
}

impl ArenaOptions {
    fn height(&self) -> f64 {
        if self.laser_height.is_finite() && self.laser_height > 0.0 {
            self.laser_height
        } else {
            DEFAULT_LASER_HEIGHT
        }
    }
}

/// What the loader made of the elements of one arena.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ArenaReport {
    /// Number of `<element>`s read.
    pub elements: usize,
    /// The height the arena was cut at, m.
    pub laser_height_m: f64,
    /// Elements that left something in the laser's plane (walls, diagonal pieces, barrels,
    /// legs, ramps crossing it, ...), by type.
    pub in_plane: BTreeMap<String, usize>,
    /// Elements modelled that leave nothing at the laser's height (wholly below or above
    /// it), by type.
    pub out_of_plane: BTreeMap<String, usize>,
    /// Elements not modelled, by type: types the loader does not know, and known ones
    /// whose shape at the laser's height it does not have (a step field taller than the
    /// laser's height).
    pub skipped: BTreeMap<String, usize>,
    /// Wall elements read (plates on a cell edge).
    pub wall_elements: usize,
    /// Segments that repeated one already placed (the same cell edge written twice, e.g.
    /// by both cells it separates); each becomes one wall.
    pub duplicate_walls: usize,
    /// Whole barrels: two half barrels back to back, made one disc.
    pub barrels: usize,
}

impl ArenaReport {
    /// Total number of skipped elements.
    #[must_use]
    pub fn skipped_count(&self) -> usize {
        self.skipped.values().sum()
    }

    /// The skipped types the loader does not know at all (see [`known_types`]).
    #[must_use]
    pub fn unknown_types(&self) -> Vec<&str> {
        self.skipped
            .keys()
            .map(String::as_str)
            .filter(|t| element_type(t).is_none())
            .collect()
    }
}

/// An arena: its world and the loader's report.
#[derive(Debug, Clone, PartialEq)]
pub struct Arena {
    /// Name (the file name for [`load_raf`]).
    pub name: String,
    /// What the laser's plane cuts: walls and discs, metres, arena frame.
    pub world: World,
    /// What the loader read, made and skipped.
    pub report: ArenaReport,
}

/// Errors of the `.raf` loader.
#[derive(Debug, thiserror::Error)]
pub enum ArenaError {
    /// The file could not be read.
    #[error("cannot read arena {path}: {source}")]
    Io {
        /// the file
        path: PathBuf,
        /// why
        source: std::io::Error,
    },
    /// The text is not the XML the loader expects.
    #[error("{name}:{line}: {message}")]
    Xml {
        /// arena name (file)
        name: String,
        /// line, 1-based
        line: usize,
        /// what was wrong
        message: String,
    },
    /// An `<element>` lacks an attribute.
    #[error("{name}:{line}: element has no {attribute:?} attribute")]
    MissingAttribute {
        /// arena name (file)
        name: String,
        /// line, 1-based
        line: usize,
        /// the attribute
        attribute: &'static str,
    },
    /// An attribute has a value the loader does not understand.
    #[error("{name}:{line}: {attribute}={value:?} is not {expected}")]
    BadAttribute {
        /// arena name (file)
        name: String,
        /// line, 1-based
        line: usize,
        /// the attribute
        attribute: &'static str,
        /// its value
        value: String,
        /// what was expected
        expected: &'static str,
    },
    /// Nothing of the arena is in the laser's plane.
    #[error(
        "arena {name} is empty at the laser's height of {height} m: nothing among its {elements} elements is there (below or above it: {out_of_plane}; skipped: {skipped})"
    )]
    Empty {
        /// arena name (file)
        name: String,
        /// elements read
        elements: usize,
        /// the laser's height, m
        height: f64,
        /// the types out of the plane with counts, `type x count, ...`
        out_of_plane: String,
        /// the skipped types with counts, `type x count, ...`
        skipped: String,
    },
}

/// Reads a `.raf` file, see the [module docs](self).
///
/// # Errors
/// [`ArenaError::Io`] when the file cannot be read, any error of [`parse_raf`] otherwise.
pub fn load_raf(path: &Path, options: &ArenaOptions) -> Result<Arena, ArenaError> {
    let bytes = std::fs::read(path).map_err(|source| ArenaError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let name = path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    if let Some(message) = binary(&bytes) {
        return Err(ArenaError::Xml {
            name: path.display().to_string(),
            line: 1,
            message,
        });
    }
    let text = String::from_utf8_lossy(&bytes);
    // The arena is called by its file name; an error names the file as it was given.
    parse_raf(&text, &name, options).map_err(|e| e.in_file(path))
}

/// What is wrong with `bytes` that are not text at all (a compressed file, a log given by
/// mistake), before the XML parser reads them as tags; `None` for text.
fn binary(bytes: &[u8]) -> Option<String> {
    const LAYOUT: &str = "not an arena layout (a .raf file is XML text)";
    if bytes.starts_with(&[0x1f, 0x8b]) {
        return Some(format!(
            "a gzip-compressed file: {LAYOUT}; decompress it first"
        ));
    }
    let head = &bytes[..bytes.len().min(4096)];
    let bad = match std::str::from_utf8(head) {
        // A character cut by the 4 kB boundary is not binary.
        Err(e) if e.error_len().is_some() => Some(e.valid_up_to()),
        _ => head.iter().position(|&b| b == 0),
    };
    bad.map(|at| format!("binary data (byte {at} is not text): {LAYOUT}"))
}

impl ArenaError {
    /// The error with the file `path` in place of the arena's name.
    fn in_file(mut self, path: &Path) -> Self {
        match &mut self {
            Self::Io { .. } => {}
            Self::Xml { name, .. }
            | Self::MissingAttribute { name, .. }
            | Self::BadAttribute { name, .. }
            | Self::Empty { name, .. } => *name = path.display().to_string(),
        }
        self
    }
}

/// The line of an `<elements>` opening tag that no `</elements>` closes: a file cut between
/// two elements is still well-formed up to its end, but holds only part of the arena.
fn unclosed_root(text: &str) -> Option<usize> {
    let start = text.find("<elements")?;
    let tag_end = start + text[start..].find('>')?;
    let empty = text[..tag_end].ends_with('/');
    let closed = text[tag_end..].contains("</elements");
    (!empty && !closed).then(|| 1 + text[..start].matches('\n').count())
}

/// Parses the text of a `.raf` file named `name` (used in errors), see the
/// [module docs](self).
///
/// # Errors
/// [`ArenaError::Xml`] for malformed markup (an unclosed tag or comment, a bad attribute,
/// an `<elements>` that the file ends without closing) and for text with neither
/// `<elements>` nor `<element>` tags and for an empty file,
/// [`ArenaError::MissingAttribute`] or [`ArenaError::BadAttribute`] for an element without
/// `type`, `rotation`, `x` or `y`, or with a rotation other than a multiple of 90, a
/// coordinate that is not an integer grid index, an offset that is not a number or a
/// mount point that is not an integer, and [`ArenaError::Empty`] when nothing is in the
/// laser's plane.
pub fn parse_raf(text: &str, name: &str, options: &ArenaOptions) -> Result<Arena, ArenaError> {
    let elements = read_elements(text, name)?;
    let height = options.height();
    let mut report = ArenaReport {
        elements: elements.len(),
        laser_height_m: height,
        ..ArenaReport::default()
    };
    let mut builder = Builder::default();
    let mut pieces = Vec::new();
    for el in &elements {
        pieces.clear();
        let tally = match element_type(&el.kind) {
            None => &mut report.skipped,
            Some(t) => {
                if matches!(t.kind, Kind::Wall { .. }) {
                    report.wall_elements += 1;
                }
                match place(
                    el,
                    t.kind,
                    &elements,
                    options.wall_length,
                    height,
                    &mut pieces,
                ) {
                    None => &mut report.skipped,
                    Some(pose) => {
                        builder.add(&pose, &pieces);
                        if pieces.is_empty() {
                            &mut report.out_of_plane
                        } else {
                            &mut report.in_plane
                        }
                    }
                }
            }
        };
        *tally.entry(el.kind.clone()).or_insert(0) += 1;
    }
    report.duplicate_walls = builder.duplicates;
    let (world, barrels) = builder.finish();
    report.barrels = barrels;
    if world.walls.is_empty() && world.discs.is_empty() {
        return Err(empty_arena(name, &report));
    }
    Ok(Arena {
        name: name.to_owned(),
        world,
        report,
    })
}

/// What a file that is no arena is told.
const NOT_AN_ARENA: &str = "not an arena layout (a .raf file is XML, <elements> holding \
                            <element type=\"T\" rotation=\"R\" x=\"X\" y=\"Y\"/>)";

/// The `<element>` tags of `text`; an error for an empty file, malformed markup, text with neither
/// `<elements>` nor `<element>` tags, and for an `<elements>` the file ends without closing.
fn read_elements(text: &str, name: &str) -> Result<Vec<Element>, ArenaError> {
    let mut elements = Vec::new();
    // Whether an `<elements>` or `<element>` tag came yet: markup that fails before one is
    // text of another kind (source code, a README) rather than an arena cut short.
    let mut arena = false;
    for tag in Tags::new(text) {
        let tag = tag.map_err(|(line, message)| ArenaError::Xml {
            name: name.to_owned(),
            line,
            // Before any arena tag, and without one begun on the lines up to the fault (a
            // file cut inside its `<elements` is an arena cut short).
            message: if !arena && !text.lines().take(line).any(|l| l.contains("<element")) {
                format!("{message} before any <elements> or <element> tag: {NOT_AN_ARENA}")
            } else if message == "unclosed tag" {
                // A tag without its `>` runs to the end of the file: a file cut short.
                format!(
                    "unclosed tag: the file ends inside it, after {} elements (cut short?)",
                    elements.len()
                )
            } else {
                message
            },
        })?;
        arena |= tag.name == "elements" || tag.name == "element";
        if tag.name == "element" {
            elements.push(Element::from_tag(&tag, name)?);
        }
    }
    if text.trim().is_empty() {
        return Err(ArenaError::Xml {
            name: name.to_owned(),
            line: 1,
            message: format!("an empty file: {NOT_AN_ARENA}"),
        });
    }
    if elements.is_empty() && !text.contains("<elements") {
        return Err(ArenaError::Xml {
            name: name.to_owned(),
            line: 1,
            message: format!("no <elements> and no <element> tag: {NOT_AN_ARENA}"),
        });
    }
    if let Some(line) = unclosed_root(text) {
        return Err(ArenaError::Xml {
            name: name.to_owned(),
            line,
            message: format!(
                "unclosed <elements>: the file ends after {} elements without </elements> \
                 (cut short?)",
                elements.len()
            ),
        });
    }
    Ok(elements)
}

/// The error for an arena with nothing in the laser's plane, listing what was out of it
/// and what was skipped.
fn empty_arena(name: &str, report: &ArenaReport) -> ArenaError {
    let list = |m: &BTreeMap<String, usize>| {
        if m.is_empty() {
            "none".to_owned()
        } else {
            m.iter()
                .map(|(t, n)| format!("{t} x {n}"))
                .collect::<Vec<_>>()
                .join(", ")
        }
    };
    ArenaError::Empty {
        name: name.to_owned(),
        elements: report.elements,
        height: report.laser_height_m,
        out_of_plane: list(&report.out_of_plane),
        skipped: list(&report.skipped),
    }
}

/// Cuts element `el` of kind `kind` at height `h` into `pieces` (element frame) and
/// returns where the element stands; `None` when its shape at that height is not known.
fn place(
    el: &Element,
    kind: Kind,
    all: &[Element],
    wall_length: WallLength,
    h: f64,
    pieces: &mut Vec<Piece>,
) -> Option<Isometry2> {
    let turn = turn(el.rotation);
    let mut centre = cell_centre(el.x, el.y) + el.offset * ARENA_GRID;
    match kind {
        Kind::Wall { holes, .. } => cut_wall(wall_length.metres(), holes, h, pieces),
        Kind::Solids(solids) => solids.iter().for_each(|s| cut_solid(s, 0.0, h, pieces)),
        Kind::Mountable(solids) => {
            // On the first wall of the cell with the same rotation, at its mount point
            // (the first when none is given); on the floor at the cell centre without one.
            let mount = all
                .iter()
                .find(|w| {
                    w.x == el.x
                        && w.y == el.y
                        && w.rotation == el.rotation
                        && element_type(&w.kind)
                            .is_some_and(|t| matches!(t.kind, Kind::Wall { .. }))
                })
                .and_then(|w| match element_type(&w.kind).map(|t| t.kind) {
                    Some(Kind::Wall { mounts, .. }) => {
                        usize::try_from(el.mount_point.unwrap_or(0).max(0))
                            .ok()
                            .and_then(|k| mounts.get(k))
                    }
                    _ => None,
                });
            let dz = match mount {
                Some(m) => {
                    let along = m.along - 0.5 * ARENA_GRID;
                    centre += turn * Vector2::new(along, 0.0);
                    m.z
                }
                None => 0.0,
            };
            solids.iter().for_each(|s| cut_solid(s, dz, h, pieces));
        }
        Kind::Low { top } => {
            if h <= top {
                return None;
            }
        }
    }
    Some(Isometry2::from_parts(
        nalgebra::Translation2::from(centre.coords),
        turn,
    ))
}

/// The turn of an element at `rotation_deg` (a multiple of 90): by `-rotation_deg`, with
/// exact sines and cosines.
fn turn(rotation_deg: u16) -> nalgebra::UnitComplex<f64> {
    let (c, s) = match rotation_deg % 360 {
        0 => (1.0, 0.0),
        90 => (0.0, -1.0),
        180 => (-1.0, 0.0),
        _ => (0.0, 1.0),
    };
    nalgebra::UnitComplex::from_cos_sin_unchecked(c, s)
}

/// The centre of grid cell `(x, y)`, m.
#[must_use]
pub fn cell_centre(x: i64, y: i64) -> Point2 {
    Point2::new(ARENA_GRID * x as f64, ARENA_GRID * y as f64)
}

/// The wall segment of a wall element in cell `(x, y)` at `rotation_deg` (0, 90, 180 or
/// 270), m, arena frame: on the `+y` edge at 0, turned by `-rotation_deg` about the cell
/// centre.
#[must_use]
pub fn wall_segment(x: i64, y: i64, rotation_deg: u16, length: WallLength) -> (Point2, Point2) {
    let c = cell_centre(x, y);
    let half_edge = 0.5 * ARENA_GRID;
    let half_len = 0.5 * length.metres();
    // Outward normal of the edge and the direction along it, exact for right angles.
    let (normal, along) = match rotation_deg % 360 {
        0 => (Vector2::new(0.0, 1.0), Vector2::new(1.0, 0.0)),
        90 => (Vector2::new(1.0, 0.0), Vector2::new(0.0, -1.0)),
        180 => (Vector2::new(0.0, -1.0), Vector2::new(-1.0, 0.0)),
        _ => (Vector2::new(-1.0, 0.0), Vector2::new(0.0, 1.0)),
    };
    let mid = c + normal * half_edge;
    (mid - along * half_len, mid + along * half_len)
}

#[cfg(test)]
mod tests;
