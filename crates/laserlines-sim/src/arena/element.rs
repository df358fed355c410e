//! One `<element>` of a `.raf` file, read from its tag.

use laserlines::math::Vector2;

use super::ArenaError;
use super::tags::Tag;

/// One `<element>` of a `.raf` file.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Element {
    pub(crate) kind: String,
    pub(crate) rotation: u16,
    pub(crate) x: i64,
    pub(crate) y: i64,
    /// `offset-x`, `offset-y` (grid units; both or neither, as the designer reads them).
    pub(crate) offset: Vector2,
    /// `mount-point`.
    pub(crate) mount_point: Option<i64>,
}

impl Element {
    pub(crate) fn from_tag(tag: &Tag<'_>, name: &str) -> Result<Self, ArenaError> {
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
                .ok_or_else(|| {
                    bad(
                        attribute,
                        &v,
                        "an integer grid index from -1000000 to 1000000",
                    )
                })
        };
        let offset = |attribute: &'static str| -> Result<Option<f64>, ArenaError> {
            tag.attribute(attribute)
                .map(|v| {
                    v.trim()
                        .parse::<f64>()
                        .ok()
                        .filter(|o| o.is_finite() && o.abs() <= 1000.0)
                        .ok_or_else(|| {
                            bad(attribute, &v, "an offset in grid units from -1000 to 1000")
                        })
                })
                .transpose()
        };
        let offset = match (offset("offset-x")?, offset("offset-y")?) {
            (Some(ox), Some(oy)) => Vector2::new(ox, oy),
            _ => Vector2::zeros(),
        };
        let mount_point = tag
            .attribute("mount-point")
            .map(|v| {
                v.trim()
                    .parse::<i64>()
                    .ok()
                    .filter(|m| m.abs() <= 1000)
                    .ok_or_else(|| bad("mount-point", &v, "an integer mount point index"))
            })
            .transpose()?;
        Ok(Self {
            kind: kind.trim().to_owned(),
            rotation,
            x: coord("x")?,
            y: coord("y")?,
            offset,
            mount_point,
        })
    }
}
