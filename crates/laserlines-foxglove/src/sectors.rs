//! The paper's three sectors as a Foxglove scene (`/sectors`, `foxglove.SceneUpdate`): one
//! entity `sectors` holding the sector bounds (1.5 m rays from the origin the bearings are
//! measured from), the robot's footprint when known, and the selected object of each sector
//! (left blue, front red, right green) as a thick line, a sphere at its nearest point and a
//! label with its distance, width and angle, also as metadata (`left`, `front`, `right`).
//!
//! `laserlines simulate --mcap` writes it in frame `base_link` with the footprint and the
//! explorer's mode and side (through [`crate::NavRecorder`]); `laserlines live --sectors`
//! in frame `laser`, the sensor standing for the robot.

use foxglove::messages::{
    Color, KeyValuePair, LinePrimitive, SceneEntity, SceneUpdate, SpherePrimitive, TextPrimitive,
    Vector3,
};
use laserlines::math::{Point2, Vector2};
use laserlines::robot::Footprint;
use laserlines_nav::{Sector, SectorObject, SectorObjects};

use crate::proto::timestamp;
use crate::shapes::{color, line_list, point3, pose_at};

/// Topic of the sector scene.
pub const SECTORS_TOPIC: &str = "/sectors";

/// Id of the scene entity holding the sectors.
pub const SECTORS_ENTITY: &str = "sectors";

/// Length of the rays drawn along the sector bounds, m.
const BOUND_RAY_M: f64 = 1.5;

/// The sector scene of one scan: `objects` (as `laserlines_nav::select_objects` gives them)
/// in frame `frame_id` at `time_s` (s), with `footprint`'s outline when given.
#[must_use]
pub fn sectors_update(
    objects: &SectorObjects,
    frame_id: &str,
    footprint: Option<&Footprint>,
    time_s: f64,
) -> SceneUpdate {
    let mut lines = Vec::with_capacity(2);
    if let Some(f) = footprint {
        lines.push(outline(f));
    }
    lines.push(bounds());
    let mut entity = SceneEntity {
        timestamp: Some(timestamp(time_s)),
        frame_id: frame_id.to_owned(),
        id: SECTORS_ENTITY.to_owned(),
        lines,
        ..SceneEntity::default()
    };
    for s in Sector::ALL {
        if let Some(o) = objects.get(s) {
            add_object(&mut entity, s, o);
        }
    }
    SceneUpdate {
        deletions: Vec::new(),
        entities: vec![entity],
    }
}

/// The footprint's outline, a rectangle centred on the origin.
fn outline(footprint: &Footprint) -> LinePrimitive {
    let (hl, hw) = (footprint.length / 2.0, footprint.width / 2.0);
    let corners = [(hl, hw), (-hl, hw), (-hl, -hw), (hl, -hw)].map(|(x, y)| Point2::new(x, y));
    let mut points = Vec::with_capacity(8);
    for k in 0..4 {
        points.push(point3(corners[k]));
        points.push(point3(corners[(k + 1) % 4]));
    }
    line_list(points, color(0.0, 0.0, 0.0, 1.0), 2.0)
}

/// The sector bounds: a ray from the origin along each bound.
fn bounds() -> LinePrimitive {
    let origin = Point2::origin();
    let mut points = Vec::with_capacity(12);
    for s in Sector::ALL {
        let (from, to) = s.bounds_rad();
        for a in [from, to] {
            points.push(point3(origin));
            points.push(point3(
                origin + BOUND_RAY_M * Vector2::new(a.cos(), a.sin()),
            ));
        }
    }
    line_list(points, color(0.5, 0.5, 0.5, 0.6), 1.0)
}

/// The colour of a sector's object, as in the sector picture.
fn sector_color(s: Sector) -> Color {
    match s {
        Sector::Left => color(0.12, 0.47, 0.71, 1.0),
        Sector::Front => color(0.84, 0.15, 0.16, 1.0),
        Sector::Right => color(0.17, 0.63, 0.17, 1.0),
    }
}

/// A sector's object in the entity: the piece as a thick line, its nearest point as a sphere,
/// its distance, width and angle as a label and as metadata.
fn add_object(entity: &mut SceneEntity, s: Sector, o: &SectorObject) {
    let c = sector_color(s);
    entity
        .lines
        .push(line_list(vec![point3(o.start), point3(o.end)], c, 6.0));
    entity.spheres.push(SpherePrimitive {
        pose: Some(pose_at(o.nearest.x, o.nearest.y, 0.0)),
        size: Some(Vector3 {
            x: 0.08,
            y: 0.08,
            z: 0.08,
        }),
        color: Some(c),
    });
    let label = format!(
        "{}: {:.2} m, width {:.2} m, {:.0} deg",
        s.name(),
        o.distance_m,
        o.width_m,
        o.angle_rad.to_degrees()
    );
    entity.texts.push(TextPrimitive {
        pose: Some(pose_at(o.nearest.x, o.nearest.y, 0.0)),
        billboard: true,
        font_size: 12.0,
        scale_invariant: true,
        color: Some(c),
        text: label.clone(),
    });
    entity.metadata.push(KeyValuePair {
        key: s.name().to_owned(),
        value: label,
    });
}
