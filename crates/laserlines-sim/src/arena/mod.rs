//! RoboCup Rescue arena layouts (`.raf` files) as simulator worlds.
//!
//! A `.raf` file is XML: `<elements>` holding `<element type="T" rotation="R" x="X" y="Y"/>`.
//! Elements stand on a grid of [`ARENA_GRID`] = 1.2 m cells: the centre of element `(X, Y)`
//! is at `(1.2 X, 1.2 Y)` metres in the arena frame, and the element is turned by
//! `yaw = -R` degrees about that centre. A wall element is a thin vertical plate on one edge
//! of its cell: at `R = 0` on the `+y` edge, at `R = 90` on the `+x` edge, at `R = 180` on
//! the `-y` edge, at `R = 270` on the `-x` edge. For a horizontal 2D laser it is one
//! segment on that edge, [`WallLength::Full`] (1.2 m, closing the corners; the default) or
//! [`WallLength::Mesh`] (1.0 m centred on the edge, as the plate's mesh).
//!
//! Barrels become [`crate::Disc`]s at their cell centre. Every other element (floor
//! features such as ramps and step fields, victims and hazmat markers, the diagonal wall
//! pieces whose geometry the format does not give, and any type this loader does not know)
//! is ignored, and counted by type in [`ArenaReport::ignored`]: nothing is dropped silently.
//!
//! ```
//! use laserlines_sim::arena::{ArenaOptions, parse_raf};
//! let text = r#"<?xml version="1.0"?>
//! <elements>
//!   <element type="small_wall" rotation="0" x="0" y="0"/>
//!   <element type="half_ramp" rotation="90" x="1" y="0"/>
//! </elements>"#;
//! let arena = parse_raf(text, "doc", &ArenaOptions::default()).unwrap();
//! // One wall on the +y edge of cell (0, 0): from (-0.6, 0.6) to (0.6, 0.6).
//! assert_eq!(arena.world.walls.len(), 1);
//! assert!((arena.world.walls[0].a.y - 0.6).abs() < 1e-12);
//! assert_eq!(arena.report.ignored.get("half_ramp"), Some(&1));
//! ```

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use laserlines::math::{Point2, Vector2};

mod start;
mod tags;

pub use start::{START_SEARCH_CELL, interior_start};
use tags::{Tag, Tags};

use crate::world::World;

/// The arena grid, m: one element cell is 1.2 m x 1.2 m.
pub const ARENA_GRID: f64 = 1.2;

/// Element types that stand up as walls for a horizontal 2D laser.
pub const WALL_TYPES: &[&str] = &[
    "small_wall",
    "small_wall_no_tex",
    "small_wall_qr",
    "small_wall_triple_holes",
    "small_wall_gap_no_tex",
    "small_wall_start_check",
    "wall_holes1",
    "tall_wall",
    "veil_wall",
];

/// Barrel element types and their radius, m (round obstacles standing at the cell centre).
pub const BARREL_TYPES: &[(&str, f64)] = &[
    ("fiducial_barrel", 0.15),
    ("fiducial_barrel_high", 0.15),
    ("red_barrel", 0.3),
];

/// Element types this loader knows and deliberately ignores: floor features, markers, and
/// the diagonal pieces whose geometry the format does not give. They are still counted in
/// [`ArenaReport::ignored`]; types in neither list are counted there too and listed by
/// [`ArenaReport::unknown_types`].
pub const KNOWN_IGNORED_TYPES: &[&str] = &[
    "half_ramp",
    "full_ramp",
    "simple_elev_ramp",
    "elevated_floor_120",
    "stairs_120",
    "stepfield",
    "stepfield_red",
    "stepfield_red_diagonal",
    "floor_tile",
    "victim_1",
    "victim_with_box1",
    "hazmat",
    "wall_diag_120",
    "corner_diag_120",
];

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
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ArenaOptions {
    /// Length of a wall element's segment (default [`WallLength::Full`]).
    pub wall_length: WallLength,
}

/// What the loader made of the elements of one arena.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ArenaReport {
    /// Number of `<element>`s read.
    pub elements: usize,
    /// Wall elements read (before merging duplicates).
    pub wall_elements: usize,
    /// Wall elements that repeated a wall already placed (the same cell edge written twice,
    /// e.g. by both cells it separates); each edge becomes one wall.
    pub duplicate_walls: usize,
    /// Barrel elements (become discs).
    pub barrels: usize,
    /// Ignored elements, by type: every element that is neither a wall nor a barrel.
    pub ignored: BTreeMap<String, usize>,
}

impl ArenaReport {
    /// Total number of ignored elements.
    #[must_use]
    pub fn ignored_count(&self) -> usize {
        self.ignored.values().sum()
    }

    /// The ignored types that are in none of the loader's lists ([`WALL_TYPES`],
    /// [`BARREL_TYPES`], [`KNOWN_IGNORED_TYPES`]): perhaps walls the loader does not know.
    #[must_use]
    pub fn unknown_types(&self) -> Vec<&str> {
        self.ignored
            .keys()
            .map(String::as_str)
            .filter(|t| !KNOWN_IGNORED_TYPES.contains(t))
            .collect()
    }
}

/// An arena: its world and the loader's report.
#[derive(Debug, Clone, PartialEq)]
pub struct Arena {
    /// Name (the file name for [`load_raf`]).
    pub name: String,
    /// Walls and barrels, metres, arena frame.
    pub world: World,
    /// What the loader read, made and ignored.
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
    /// The arena has no wall and no barrel: nothing a laser could see.
    #[error(
        "arena {name} is empty: no walls or barrels among its {elements} elements (ignored: {ignored})"
    )]
    Empty {
        /// arena name (file)
        name: String,
        /// elements read
        elements: usize,
        /// the ignored types with counts, `type x count, ...`
        ignored: String,
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
    let text = String::from_utf8_lossy(&bytes);
    parse_raf(&text, &name, options)
}

/// Parses the text of a `.raf` file named `name` (used in errors), see the
/// [module docs](self).
///
/// # Errors
/// [`ArenaError::Xml`] for malformed markup (an unclosed tag or comment, a bad attribute),
/// [`ArenaError::MissingAttribute`] or [`ArenaError::BadAttribute`] for an element without
/// `type`, `rotation`, `x` or `y`, or with a rotation other than 0, 90, 180, 270 or a
/// coordinate that is not an integer grid index, and [`ArenaError::Empty`] when no element
/// is a wall or a barrel.
pub fn parse_raf(text: &str, name: &str, options: &ArenaOptions) -> Result<Arena, ArenaError> {
    let mut world = World::new();
    let mut report = ArenaReport::default();
    let mut placed: std::collections::HashSet<[i64; 4]> = std::collections::HashSet::new();
    for tag in Tags::new(text) {
        let tag = tag.map_err(|(line, message)| ArenaError::Xml {
            name: name.to_owned(),
            line,
            message,
        })?;
        if tag.name != "element" {
            continue;
        }
        report.elements += 1;
        let el = Element::from_tag(&tag, name)?;
        if WALL_TYPES.contains(&el.kind.as_str()) {
            report.wall_elements += 1;
            let (a, b) = wall_segment(el.x, el.y, el.rotation, options.wall_length);
            // Key: both ends rounded to the millimetre, in a fixed order.
            let key = segment_key(a, b);
            if placed.insert(key) {
                world.add_segment(a, b);
            } else {
                report.duplicate_walls += 1;
            }
        } else if let Some(&(_, radius)) = BARREL_TYPES.iter().find(|(t, _)| *t == el.kind) {
            report.barrels += 1;
            world.add_disc(cell_centre(el.x, el.y), radius);
        } else {
            *report.ignored.entry(el.kind).or_insert(0) += 1;
        }
    }
    if world.walls.is_empty() && world.discs.is_empty() {
        let ignored = report
            .ignored
            .iter()
            .map(|(t, n)| format!("{t} x {n}"))
            .collect::<Vec<_>>()
            .join(", ");
        return Err(ArenaError::Empty {
            name: name.to_owned(),
            elements: report.elements,
            ignored: if ignored.is_empty() {
                "none".to_owned()
            } else {
                ignored
            },
        });
    }
    Ok(Arena {
        name: name.to_owned(),
        world,
        report,
    })
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

fn segment_key(a: Point2, b: Point2) -> [i64; 4] {
    let q = |v: f64| (v * 1000.0).round() as i64;
    let (ka, kb) = ([q(a.x), q(a.y)], [q(b.x), q(b.y)]);
    let (lo, hi) = if ka <= kb { (ka, kb) } else { (kb, ka) };
    [lo[0], lo[1], hi[0], hi[1]]
}

/// One `<element>` of a `.raf` file.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Element {
    kind: String,
    rotation: u16,
    x: i64,
    y: i64,
}

impl Element {
    fn from_tag(tag: &Tag<'_>, name: &str) -> Result<Self, ArenaError> {
        let get = |attribute: &'static str| {
            tag.attribute(attribute)
                .ok_or_else(|| ArenaError::MissingAttribute {
                    name: name.to_owned(),
                    line: tag.line,
                    attribute,
                })
        };
        let bad = |attribute: &'static str, value: &str, expected: &'static str| {
            ArenaError::BadAttribute {
                name: name.to_owned(),
                line: tag.line,
                attribute,
                value: value.to_owned(),
                expected,
            }
        };
        let kind = get("type")?;
        if kind.trim().is_empty() {
            return Err(bad("type", &kind, "a non-empty element type"));
        }
        let rot_text = get("rotation")?;
        let rotation = match rot_text.trim().parse::<i64>() {
            Ok(r) if r.rem_euclid(90) == 0 => r.rem_euclid(360) as u16,
            _ => {
                return Err(bad(
                    "rotation",
                    &rot_text,
                    "one of 0, 90, 180, 270 (degrees)",
                ));
            }
        };
        let coord = |attribute: &'static str| -> Result<i64, ArenaError> {
            let v = get(attribute)?;
            v.trim()
                .parse::<i64>()
                .ok()
                .filter(|i| i.abs() <= 1_000_000)
                .ok_or_else(|| bad(attribute, &v, "an integer grid index"))
        };
        Ok(Self {
            kind: kind.trim().to_owned(),
            rotation,
            x: coord("x")?,
            y: coord("y")?,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tags::decode_entities;

    fn parse(text: &str) -> Result<Arena, ArenaError> {
        parse_raf(text, "test.raf", &ArenaOptions::default())
    }

    fn close(a: Point2, x: f64, y: f64) -> bool {
        (a.x - x).abs() < 1e-12 && (a.y - y).abs() < 1e-12
    }

    #[test]
    fn rotations_put_the_wall_on_the_documented_edge() {
        let (a, b) = wall_segment(0, 0, 0, WallLength::Full);
        assert!(close(a, -0.6, 0.6) && close(b, 0.6, 0.6));
        let (a, b) = wall_segment(0, 0, 90, WallLength::Full);
        assert!(close(a, 0.6, 0.6) && close(b, 0.6, -0.6));
        let (a, b) = wall_segment(0, 0, 180, WallLength::Full);
        assert!(close(a, 0.6, -0.6) && close(b, -0.6, -0.6));
        let (a, b) = wall_segment(0, 0, 270, WallLength::Full);
        assert!(close(a, -0.6, -0.6) && close(b, -0.6, 0.6));
        let (a, b) = wall_segment(2, -1, 90, WallLength::Mesh);
        assert!(close(a, 3.0, -0.7) && close(b, 3.0, -1.7));
    }

    #[test]
    fn duplicate_edges_become_one_wall() {
        // The +x edge of (0, 0) is the -x edge of (1, 0).
        let a = parse(
            r#"<elements><element type="small_wall" rotation="90" x="0" y="0"/>
            <element type="tall_wall" rotation="270" x="1" y="0"/></elements>"#,
        )
        .unwrap();
        assert_eq!(a.world.walls.len(), 1);
        assert_eq!(a.report.wall_elements, 2);
        assert_eq!(a.report.duplicate_walls, 1);
    }

    #[test]
    fn barrels_are_discs_and_the_rest_is_reported() {
        let a = parse(
            "<?xml version='1.0'?>\n<!-- a comment with <element> inside -->\n<elements>\n\
             <element type='fiducial_barrel' rotation='0' x='1' y='2'/>\n\
             <element type=\"victim_1\" rotation=\"0\" x=\"-14\" y=\"-4\" offset-x=\"-0.04\"/>\n\
             <element type=\"mystery_box\" rotation=\"0\" x=\"0\" y=\"0\"/>\n</elements>",
        )
        .unwrap();
        assert_eq!(a.world.discs.len(), 1);
        assert!(close(a.world.discs[0].centre, 1.2, 2.4));
        assert_eq!(a.report.ignored.get("victim_1"), Some(&1));
        assert_eq!(a.report.ignored.get("mystery_box"), Some(&1));
        assert_eq!(a.report.unknown_types(), vec!["mystery_box"]);
        assert_eq!(a.report.elements, 3);
    }

    #[test]
    fn bad_input_is_an_error_naming_the_line() {
        let e = parse("<elements>\n<element type=\"small_wall\" rotation=\"45\" x=\"0\" y=\"0\"/>")
            .unwrap_err();
        assert!(
            matches!(
                e,
                ArenaError::BadAttribute {
                    line: 2,
                    attribute: "rotation",
                    ..
                }
            ),
            "{e}"
        );
        let e =
            parse("<element type=\"small_wall\" rotation=\"0\" x=\"1.5\" y=\"0\"/>").unwrap_err();
        assert!(
            matches!(e, ArenaError::BadAttribute { attribute: "x", .. }),
            "{e}"
        );
        let e = parse("<element type=\"small_wall\" rotation=\"0\" x=\"1\"/>").unwrap_err();
        assert!(
            matches!(e, ArenaError::MissingAttribute { attribute: "y", .. }),
            "{e}"
        );
        let e = parse("<elements>\n<element type=\"small_wall").unwrap_err();
        assert!(matches!(e, ArenaError::Xml { line: 2, .. }), "{e}");
        let e = parse("<!-- never closed").unwrap_err();
        assert!(matches!(e, ArenaError::Xml { .. }), "{e}");
        let e = parse("<element type=small_wall/>").unwrap_err();
        assert!(matches!(e, ArenaError::Xml { .. }), "{e}");
        let e = parse("<element type=\"a&bogus;\" rotation=\"0\" x=\"0\" y=\"0\"/>").unwrap_err();
        assert!(matches!(e, ArenaError::Xml { .. }), "{e}");
    }

    #[test]
    fn an_arena_without_walls_is_empty() {
        let e = parse("<elements></elements>").unwrap_err();
        assert!(matches!(e, ArenaError::Empty { elements: 0, .. }), "{e}");
        let e = parse(
            "<elements><element type=\"half_ramp\" rotation=\"0\" x=\"0\" y=\"0\"/></elements>",
        )
        .unwrap_err();
        assert!(e.to_string().contains("half_ramp x 1"), "{e}");
        let e = parse("").unwrap_err();
        assert!(matches!(e, ArenaError::Empty { .. }));
    }

    #[test]
    fn entities_are_decoded() {
        assert_eq!(
            decode_entities("a&amp;b&#65;&#x42;").as_deref(),
            Some("a&bAB")
        );
        assert_eq!(decode_entities("a&b"), None);
    }
}
