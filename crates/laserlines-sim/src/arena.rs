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

use laserlines::math::{Isometry2, Point2, Vector2};

use crate::index::WorldIndex;
use crate::world::{Target, World};

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

/// Side of the cells of [`interior_start`]'s search, m.
pub const START_SEARCH_CELL: f64 = 0.1;

/// A start pose inside the arena: the centre of the grid cell (a point `(1.2 i, 1.2 j)`)
/// nearest to the origin within the largest *enclosed* free region, facing +x (yaw 0).
///
/// Free means at least `clearance` m (e.g. a robot's circumradius) from every wall and
/// disc, on a [`START_SEARCH_CELL`] grid over the world's bounding box and 1 m around it;
/// regions are 4-connected; a region touching the grid's edge is outside the arena and
/// never chosen. Real arena files put their origin anywhere: inside the arena, in a small
/// pocket closed by barrels, or outside the outer wall. `None` when no enclosed region
/// holds a grid cell's centre with that clearance.
///
/// ```
/// use laserlines_sim::World;
/// use laserlines_sim::arena::interior_start;
/// use laserlines::math::Point2;
/// // A 6 m x 4 m room around (10, 10), and a 1 m pocket at the origin.
/// let mut world = World::new();
/// world.add_box(Point2::new(10.8, 10.8), 6.0, 4.0, 0.0);
/// world.add_box(Point2::new(0.0, 0.0), 1.0, 1.0, 0.0);
/// let start = interior_start(&world, 0.32).unwrap();
/// let p = start.translation.vector;
/// assert!((p.x - 8.4).abs() < 1e-9 && (p.y - 9.6).abs() < 1e-9, "{p:?}");
/// ```
#[must_use]
pub fn interior_start(world: &World, clearance: f64) -> Option<Isometry2> {
    let index = WorldIndex::new(world, 0.6);
    let mut lo = Point2::new(f64::INFINITY, f64::INFINITY);
    let mut hi = Point2::new(f64::NEG_INFINITY, f64::NEG_INFINITY);
    let mut grow = |p: Point2| {
        if p.x.is_finite() && p.y.is_finite() {
            lo = Point2::new(lo.x.min(p.x), lo.y.min(p.y));
            hi = Point2::new(hi.x.max(p.x), hi.y.max(p.y));
        }
    };
    for w in &world.walls {
        grow(w.a);
        grow(w.b);
    }
    for d in &world.discs {
        grow(d.centre);
    }
    if !(lo.x.is_finite() && hi.x.is_finite() && clearance.is_finite()) {
        return None;
    }
    let cell = START_SEARCH_CELL;
    let origin = Point2::new(lo.x - 1.0, lo.y - 1.0);
    let cols = (((hi.x - lo.x + 2.0) / cell).ceil() as usize).clamp(1, 4000);
    let rows = (((hi.y - lo.y + 2.0) / cell).ceil() as usize).clamp(1, 4000);
    let centre = |c: usize| {
        Point2::new(
            origin.x + ((c % cols) as f64 + 0.5) * cell,
            origin.y + ((c / cols) as f64 + 0.5) * cell,
        )
    };
    let clear_at = |p: Point2, need: f64| {
        let r = Vector2::new(need, need);
        let mut ok = true;
        index.near_box(p - r, p + r, |t| {
            let d = match t {
                Target::Wall(i) => {
                    let w = &world.walls[i];
                    laserlines::line::distance_to_segment(p, w.a, w.b)
                }
                Target::Disc(i) => {
                    let d = &world.discs[i];
                    (p - d.centre).norm() - d.radius
                }
            };
            if d < need {
                ok = false;
            }
        });
        ok
    };
    let free: Vec<bool> = (0..cols * rows)
        .map(|c| clear_at(centre(c), clearance))
        .collect();
    // Regions by flood fill: the size of each, and whether it touches the grid's edge.
    let mut region = vec![usize::MAX; cols * rows];
    let mut regions: Vec<(usize, bool)> = Vec::new();
    let mut stack = Vec::new();
    for seed in 0..cols * rows {
        if !free[seed] || region[seed] != usize::MAX {
            continue;
        }
        let id = regions.len();
        let (mut size, mut outside) = (0, false);
        region[seed] = id;
        stack.push(seed);
        while let Some(c) = stack.pop() {
            size += 1;
            let (x, y) = (c % cols, c / cols);
            outside |= x == 0 || y == 0 || x + 1 == cols || y + 1 == rows;
            let mut visit = |n: usize| {
                if free[n] && region[n] == usize::MAX {
                    region[n] = id;
                    stack.push(n);
                }
            };
            if x > 0 {
                visit(c - 1);
            }
            if x + 1 < cols {
                visit(c + 1);
            }
            if y > 0 {
                visit(c - cols);
            }
            if y + 1 < rows {
                visit(c + cols);
            }
        }
        regions.push((size, outside));
    }
    let (best, _) = regions
        .iter()
        .enumerate()
        .filter(|(_, (_, outside))| !outside)
        .max_by_key(|(id, (size, _))| (*size, std::cmp::Reverse(*id)))?;
    // The grid cell centre in that region nearest to the origin.
    let (i0, i1) = (
        (lo.x / ARENA_GRID).floor() as i64,
        (hi.x / ARENA_GRID).ceil() as i64,
    );
    let (j0, j1) = (
        (lo.y / ARENA_GRID).floor() as i64,
        (hi.y / ARENA_GRID).ceil() as i64,
    );
    let mut pick: Option<Point2> = None;
    for j in j0..=j1 {
        for i in i0..=i1 {
            let p = cell_centre(i, j);
            let fx = ((p.x - origin.x) / cell).floor();
            let fy = ((p.y - origin.y) / cell).floor();
            if !(fx >= 0.0 && fy >= 0.0 && (fx as usize) < cols && (fy as usize) < rows) {
                continue;
            }
            let c = fy as usize * cols + fx as usize;
            if region[c] == best
                && clear_at(p, clearance)
                && pick.is_none_or(|q| p.coords.norm() < q.coords.norm())
            {
                pick = Some(p);
            }
        }
    }
    pick.map(|p| Isometry2::new(p.coords, 0.0))
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

/// An opening or empty-element tag with its attributes.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Tag<'a> {
    name: &'a str,
    attributes: Vec<(&'a str, String)>,
    line: usize,
}

impl Tag<'_> {
    fn attribute(&self, name: &str) -> Option<String> {
        self.attributes
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, v)| v.clone())
    }
}

/// The opening tags of an XML text, in order; a small reader for the subset `.raf` files
/// use: declarations, comments, CDATA and closing tags are skipped, attribute values are
/// quoted with `"` or `'`, the five predefined entities and numeric references are decoded.
struct Tags<'a> {
    text: &'a str,
    pos: usize,
}

impl<'a> Tags<'a> {
    fn new(text: &'a str) -> Self {
        Self { text, pos: 0 }
    }

    fn line_at(&self, pos: usize) -> usize {
        1 + self.text.as_bytes()[..pos.min(self.text.len())]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
    }

    fn skip_past(&mut self, start: usize, end: &str, what: &str) -> Result<(), (usize, String)> {
        match self.text[start..].find(end) {
            Some(k) => {
                self.pos = start + k + end.len();
                Ok(())
            }
            None => {
                self.pos = self.text.len();
                Err((self.line_at(start), format!("unclosed {what}")))
            }
        }
    }
}

impl<'a> Iterator for Tags<'a> {
    type Item = Result<Tag<'a>, (usize, String)>;

    fn next(&mut self) -> Option<Self::Item> {
        loop {
            let start = self.pos + self.text.get(self.pos..)?.find('<')?;
            let rest = &self.text[start..];
            let skipped = if rest.starts_with("<!--") {
                Some(self.skip_past(start, "-->", "comment"))
            } else if rest.starts_with("<![CDATA[") {
                Some(self.skip_past(start, "]]>", "CDATA section"))
            } else if rest.starts_with("<?") {
                Some(self.skip_past(start, "?>", "declaration"))
            } else if rest.starts_with("<!") || rest.starts_with("</") {
                Some(self.skip_past(start, ">", "tag"))
            } else {
                None
            };
            match skipped {
                Some(Ok(())) => continue,
                Some(Err(e)) => return Some(Err(e)),
                None => {}
            }
            let line = self.line_at(start);
            let Some(len) = tag_end(rest) else {
                self.pos = self.text.len();
                return Some(Err((line, "unclosed tag".to_owned())));
            };
            self.pos = start + len + 1;
            let inner = rest[1..len].trim_end_matches('/');
            return Some(parse_tag(inner, line));
        }
    }
}

/// The offset of the `>` closing the tag at the start of `s`, outside quoted values.
fn tag_end(s: &str) -> Option<usize> {
    let mut quote: Option<char> = None;
    for (i, ch) in s.char_indices().skip(1) {
        match (quote, ch) {
            (Some(q), c) if c == q => quote = None,
            (Some(_), _) => {}
            (None, '"' | '\'') => quote = Some(ch),
            (None, '>') => return Some(i),
            (None, '<') => return None,
            _ => {}
        }
    }
    None
}

fn parse_tag(inner: &str, line: usize) -> Result<Tag<'_>, (usize, String)> {
    let inner = inner.trim();
    let name_end = inner
        .find(|c: char| c.is_whitespace())
        .unwrap_or(inner.len());
    let name = &inner[..name_end];
    if name.is_empty() {
        return Err((line, "a tag without a name".to_owned()));
    }
    let mut attributes = Vec::new();
    let mut rest = inner[name_end..].trim_start();
    while !rest.is_empty() {
        let Some(eq) = rest.find('=') else {
            return Err((line, format!("attribute {rest:?} has no value")));
        };
        let key = rest[..eq].trim();
        if key.is_empty() || key.contains(char::is_whitespace) {
            return Err((line, format!("bad attribute name {key:?}")));
        }
        let after = rest[eq + 1..].trim_start();
        let Some(q) = after.chars().next().filter(|c| *c == '"' || *c == '\'') else {
            return Err((line, format!("the value of {key:?} is not quoted")));
        };
        let Some(close) = after[1..].find(q) else {
            return Err((line, format!("the value of {key:?} is not closed")));
        };
        let raw = &after[1..1 + close];
        let value = decode_entities(raw)
            .ok_or_else(|| (line, format!("bad entity in the value of {key:?}")))?;
        attributes.push((key, value));
        rest = after[close + 2..].trim_start();
    }
    Ok(Tag {
        name,
        attributes,
        line,
    })
}

fn decode_entities(raw: &str) -> Option<String> {
    if !raw.contains('&') {
        return Some(raw.to_owned());
    }
    let mut out = String::with_capacity(raw.len());
    let mut rest = raw;
    while let Some(amp) = rest.find('&') {
        out.push_str(&rest[..amp]);
        let semi = rest[amp..].find(';')? + amp;
        let entity = &rest[amp + 1..semi];
        let ch = match entity {
            "lt" => '<',
            "gt" => '>',
            "amp" => '&',
            "quot" => '"',
            "apos" => '\'',
            e if e.starts_with("#x") => char::from_u32(u32::from_str_radix(&e[2..], 16).ok()?)?,
            e if e.starts_with('#') => char::from_u32(e[1..].parse().ok()?)?,
            _ => return None,
        };
        out.push(ch);
        rest = &rest[semi + 1..];
    }
    out.push_str(rest);
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

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
