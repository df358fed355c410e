//! The paper's three sector objects (`laserlines_nav::sectors`) as RViz markers, one
//! `MarkerArray` per scan (`--sectors`), in the lines' frame with the laser at the robot's
//! origin facing forward.
//!
//! | ns | id | type | content |
//! |---|---|---|---|
//! | `sector_objects` | 0 left, 1 front, 2 right | `LINE_LIST` | the selected object of the sector: the clipped piece of its line (two points); `DELETE` when the sector holds none |
//! | `sector_labels` | 0, 1, 2 | `TEXT_VIEW_FACING` | at the object's nearest point: `left: 1.23 m, 0.80 m wide, 90 deg` (distance, width, line direction); `DELETE` when none |
//! | `sector_bounds` | 0 | `LINE_LIST` | the sectors' bounds, 1.5 m rays at -120, -50, +50 and +120 deg |
//!
//! The numbers are the selection's ([`SectorObject`]): distance from the origin to the
//! nearest point of the piece, its visible length, and the line's direction in
//! `(-90, 90]` deg.

use laserlines::Line;
use laserlines::math::Isometry2;
use laserlines_nav::sectors::{Sector, SectorObject, SectorParams, select_objects};

use crate::convert::point;
use crate::msg::{ColorRgba, Header, Marker, MarkerArray};

/// Namespace of the object markers (id = sector index: left 0, front 1, right 2).
pub const OBJECTS_NS: &str = "sector_objects";
/// Namespace of the text markers.
pub const LABELS_NS: &str = "sector_labels";
/// Namespace of the bounds marker.
pub const BOUNDS_NS: &str = "sector_bounds";

/// Length of the rays drawn at the sectors' bounds, m.
const BOUND_RAY_M: f64 = 1.5;

/// Colour of a sector's markers: left blue, front red, right green.
fn color(sector: Sector) -> ColorRgba {
    let (r, g, b) = match sector {
        Sector::Left => (0.2, 0.4, 1.0),
        Sector::Front => (1.0, 0.2, 0.2),
        Sector::Right => (0.2, 0.8, 0.2),
    };
    ColorRgba { r, g, b, a: 1.0 }
}

/// The selected objects of `lines` (laser frame = robot frame) with the default
/// [`SectorParams`].
#[must_use]
pub fn objects(lines: &[Line]) -> [Option<SectorObject>; 3] {
    select_objects(lines, &Isometry2::identity(), &SectorParams::default()).objects
}

/// The text of a sector's label.
#[must_use]
pub fn label(object: &SectorObject) -> String {
    format!(
        "{}: {:.2} m, {:.2} m wide, {:.0} deg",
        object.sector.name(),
        object.distance_m,
        object.width_m,
        object.angle_rad.to_degrees()
    )
}

fn marker(header: &Header, ns: &str, id: i32, kind: i32) -> Marker {
    Marker {
        header: header.clone(),
        ns: ns.to_owned(),
        id,
        r#type: kind,
        action: Marker::ADD,
        ..Marker::default()
    }
}

/// The markers of one scan's sector objects (see the module docs).
#[must_use]
pub fn sector_markers(header: &Header, lines: &[Line]) -> MarkerArray {
    let objects = objects(lines);
    let mut markers = Vec::with_capacity(7);
    for sector in Sector::ALL {
        let id = i32::from(u8::try_from(sector.index()).unwrap_or(0));
        let mut piece = marker(header, OBJECTS_NS, id, Marker::LINE_LIST);
        let mut text = marker(header, LABELS_NS, id, Marker::TEXT_VIEW_FACING);
        match &objects[sector.index()] {
            Some(o) => {
                piece.scale.x = 0.06;
                piece.color = color(sector);
                piece.points = vec![point(o.start.x, o.start.y), point(o.end.x, o.end.y)];
                text.scale.z = 0.12;
                text.color = color(sector);
                text.pose.position = point(o.nearest.x, o.nearest.y);
                text.text = label(o);
            }
            None => {
                piece.action = Marker::DELETE;
                text.action = Marker::DELETE;
            }
        }
        markers.push(piece);
        markers.push(text);
    }
    let mut bounds = marker(header, BOUNDS_NS, 0, Marker::LINE_LIST);
    bounds.scale.x = 0.01;
    bounds.color = ColorRgba {
        r: 0.5,
        g: 0.5,
        b: 0.5,
        a: 0.8,
    };
    for deg in [-120.0_f64, -50.0, 50.0, 120.0] {
        let (s, c) = deg.to_radians().sin_cos();
        bounds.points.push(point(0.0, 0.0));
        bounds.points.push(point(BOUND_RAY_M * c, BOUND_RAY_M * s));
    }
    markers.push(bounds);
    MarkerArray { markers }
}

#[cfg(test)]
mod tests {
    use super::*;
    use laserlines::math::{Matrix2, Point2};

    fn wall(a: (f64, f64), b: (f64, f64)) -> Line {
        Line {
            start: Point2::new(a.0, a.1),
            end: Point2::new(b.0, b.1),
            r: 1.0,
            alpha: 0.0,
            first: 0,
            last: 10,
            points: 11,
            rms: 0.0,
            covariance: Matrix2::zeros(),
        }
    }

    #[test]
    fn a_wall_ahead_is_the_front_object_and_the_sides_are_deleted() {
        // A wall 1 m ahead from 1 m right to 1 m left: ends at -45 and +45 deg, all front.
        let header = Header {
            frame_id: "laser".to_owned(),
            ..Header::default()
        };
        let m = sector_markers(&header, &[wall((1.0, -1.0), (1.0, 1.0))]);
        assert_eq!(m.markers.len(), 7);
        let front = &m.markers[2];
        assert_eq!((front.ns.as_str(), front.id), (OBJECTS_NS, 1));
        assert_eq!(front.action, Marker::ADD);
        assert_eq!(front.points.len(), 2);
        let xs: Vec<f64> = front.points.iter().map(|p| p.x).collect();
        assert!(xs.iter().all(|x| (x - 1.0).abs() < 1e-12));
        let label = &m.markers[3];
        assert_eq!(label.text, "front: 1.00 m, 2.00 m wide, 90 deg");
        assert!((label.pose.position.x - 1.0).abs() < 1e-12);
        for k in [0, 1, 4, 5] {
            assert_eq!(m.markers[k].action, Marker::DELETE, "marker {k}");
        }
        assert_eq!(m.markers[6].points.len(), 8);
        assert!(m.markers.iter().all(|x| x.header.frame_id == "laser"));
    }
}
