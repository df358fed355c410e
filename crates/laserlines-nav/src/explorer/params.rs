//! The explorer's parameters, in groups: following a wall, the safety layer, loops, the map,
//! and travel to frontiers. Distances in metres, angles in radians, times in seconds.
//!
//! With the `serde` feature they are the `[explorer]` table of a params file, groups as
//! dotted keys or sub-tables (`follow.distance = 0.6`, `[explorer.travel]`).

use laserlines::math::Isometry2;
use laserlines::params::{self, ParamsError};
use laserlines_slam::{Se2, TrackerParams};

use crate::fence::Fence;
use crate::planner::PlannerParams;
use crate::sectors::{Sector, SectorParams};

/// Which side the followed wall is on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "lowercase")
)]
pub enum WallSide {
    /// Left-hand rule: the wall on the left.
    Left,
    /// Right-hand rule: the wall on the right.
    Right,
}

impl WallSide {
    /// +1 for left, -1 for right (the sign of a turn toward the wall).
    #[must_use]
    pub fn sign(self) -> f64 {
        match self {
            Self::Left => 1.0,
            Self::Right => -1.0,
        }
    }

    /// The sector on this side.
    #[must_use]
    pub fn sector(self) -> Sector {
        match self {
            Self::Left => Sector::Left,
            Self::Right => Sector::Right,
        }
    }

    /// The other side.
    #[must_use]
    pub fn other(self) -> Self {
        match self {
            Self::Left => Self::Right,
            Self::Right => Self::Left,
        }
    }
}

/// Following a wall, arcing around its end, turning away from what blocks the way.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct FollowParams {
    /// Distance kept from the followed wall, from the robot's origin, m. Default 0.6 (the
    /// middle of a 1.2 m arena corridor).
    pub distance: f64,
    /// A wall on the followed side nearer than this is followed, m. Default 1.0.
    pub range: f64,
    /// Speed along straight walls, m/s. Default 0.55.
    pub cruise_speed: f64,
    /// Speed around wall ends, m/s. Default 0.35.
    pub corner_speed: f64,
    /// Turn rate when turning on the spot, rad/s (also the most the wall and path followers
    /// ask for). Default 1.2.
    pub turn_rate: f64,
    /// Gain of the heading term, 1/s. Default 1.8.
    pub k_heading: f64,
    /// Gain of the distance term, rad/(s m). Default 2.0.
    pub k_distance: f64,
    /// Free distance ahead of the robot's front below which it turns away, m. Default 0.45.
    pub front_turn: f64,
    /// The same while arcing around a wall end or curving toward the followed side, m.
    /// Default 0.15.
    pub front_turn_corner: f64,
    /// Extra half-width of the band ahead checked for the free distance, m. Default 0.1.
    pub front_band_margin: f64,
}

impl Default for FollowParams {
    fn default() -> Self {
        Self {
            distance: 0.6,
            range: 1.0,
            cruise_speed: 0.55,
            corner_speed: 0.35,
            turn_rate: 1.2,
            k_heading: 1.8,
            k_distance: 2.0,
            front_turn: 0.45,
            front_turn_corner: 0.15,
            front_band_margin: 0.1,
        }
    }
}

/// The safety layer.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct SafetyParams {
    /// Margin the safety layer keeps around the footprint, m. Default 0.08.
    pub margin: f64,
    /// Margin kept while turning on the spot (a command of zero linear speed), m, at most
    /// `margin`. The footprint's corners then sweep a circle about its centre, with nothing
    /// carried ahead, so that with a smaller margin a robot beside a wall or a post (its
    /// centre less than its circumradius and `margin` away) can still turn where it stands.
    /// Default none: `margin`. See the README for 0.05.
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "Option::is_none"))]
    pub turn_margin: Option<f64>,
    /// Scan points within this of the robot are remembered for the safety layer, m.
    /// Default 1.5.
    pub memory_range_m: f64,
}

impl Default for SafetyParams {
    fn default() -> Self {
        Self {
            margin: 0.08,
            turn_margin: None,
            memory_range_m: 1.5,
        }
    }
}

/// Loop detection: a wall followed all the way round.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct LoopParams {
    /// Breadcrumb match radius, m. Default 0.5.
    pub match_radius_m: f64,
    /// Breadcrumb heading tolerance, rad. Default 0.6.
    pub heading_rad: f64,
    /// Least travel between a breadcrumb and its revisit for a loop, m. Default 8.0.
    pub min_path_m: f64,
}

impl Default for LoopParams {
    fn default() -> Self {
        Self {
            match_radius_m: 0.5,
            heading_rad: 0.6,
            min_path_m: 8.0,
        }
    }
}

/// What goes into the robot's own map.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct MapParams {
    /// Every this many scans one is added to the map (each is matched against it).
    /// Default 2: at the robot's speed (6 cm a scan), consecutive scans see nearly the
    /// same. With 3 the map of a post in a narrow corridor can come out thick enough to
    /// close the corridor to the planner (island maze 6, seed 1: the run ends "explored"
    /// after 4 m). At least 1.
    pub every: usize,
    /// A scan that makes fewer cells of the map known than this shows nothing new.
    /// Default 4 (0.04 m^2).
    pub new_cells: usize,
}

impl Default for MapParams {
    fn default() -> Self {
        Self {
            every: 2,
            new_cells: 4,
        }
    }
}

/// Leaving the wall for the nearest frontier, and the way there.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct TravelParams {
    /// Wall following that has made no cell of the map known for this long leaves the
    /// wall for the nearest frontier, s. Default 8.
    pub stale_s: f64,
    /// Seeking a wall (none in reach) for longer than this leaves for the nearest frontier,
    /// s. Default 6.
    pub seek_s: f64,
    /// Time between plans on the way to a frontier, s. Default 2.
    pub replan_s: f64,
    /// Distance from the robot to the path point the path follower steers to (the first
    /// one this far), m; nearer at a bend with little room (see the module docs). Default
    /// 0.5.
    pub lookahead_m: f64,
    /// Speed on the way to a frontier, m/s. Default 0.5.
    pub speed: f64,
    /// A frontier whose path the robot has not shortened by 0.2 m for this long is given up, s.
    /// Default 30: at a post in a corridor the robot may need a few escapes and a turn before
    /// its path gets shorter.
    pub give_up_s: f64,
    /// A re-plan keeps its frontier while its path is at most this much longer than the
    /// path to the nearest one, m. Default 1.
    pub hysteresis_m: f64,
    /// Frontiers within this of one given up are not chosen again, m. Default 0.6.
    pub avoid_radius_m: f64,
    /// When no frontier is left but some were given up, they are all tried again, at most
    /// this many times in a run. Default 2.
    pub retries: usize,
    /// A frontier given up while the robot stood within 0.5 m of where it last made
    /// progress closes the spot its path led to next (0.4 m ahead) to the planner for
    /// `blocked_s`, within this radius, m: a gap that the map shows open but that the
    /// safety layer does not let the robot through. Default 0.3.
    pub blocked_radius_m: f64,
    /// How long a blocked spot stays closed, s. Default 90.
    pub blocked_s: f64,
    /// Once this many different frontiers (farther than `avoid_radius_m` apart) have been
    /// given up while the map grew by less than [`TravelParams::fruitless_gain_m2`], the
    /// exploration is complete: what is left lies beyond gaps the robot sees through but
    /// cannot pass, and the few cells each scan through them adds would keep it trying for
    /// ever. Default 3 (about 90 s of fruitless trying with the default `give_up_s`); 0 never.
    pub fruitless_give_ups: usize,
    /// Growth of the map's known area that starts the count of fruitless give-ups afresh,
    /// m^2. Default 1.
    pub fruitless_gain_m2: f64,
    /// When no frontier can be reached with the planner's clearance, the planner tries
    /// again with this one, m, before the exploration is called complete: a gap that the
    /// 0.4 m wide robot passes driving straight but where it cannot turn (a post beside a
    /// corridor wall). Default 0.2 (the robot's half width; on the map, whose occupied
    /// cells reach up to half a cell into a gap, that is about 0.25 m of true clearance).
    pub tight_clearance_m: f64,
}

impl Default for TravelParams {
    fn default() -> Self {
        Self {
            stale_s: 8.0,
            seek_s: 6.0,
            replan_s: 2.0,
            lookahead_m: 0.5,
            speed: 0.5,
            give_up_s: 30.0,
            hysteresis_m: 1.0,
            avoid_radius_m: 0.6,
            retries: 2,
            blocked_radius_m: 0.3,
            blocked_s: 90.0,
            fruitless_give_ups: 3,
            fruitless_gain_m2: 1.0,
            tight_clearance_m: 0.2,
        }
    }
}

/// The scan matching that places each scan on the robot's map (`laserlines-slam`'s
/// [`Tracker`](laserlines_slam::Tracker): point-to-line ICP onto everything mapped so far,
/// held toward the odometry's prediction).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct MatchParams {
    /// Every this many beams give a point to the matching. Default 4 (about 170 points of
    /// a URG-04LX scan).
    pub beam_stride: usize,
    /// Most rounds of pairing and Gauss-Newton step per scan. Default 5.
    pub iterations: usize,
    /// A point pairs only with a mapped surface point within this distance, m. Default 0.1.
    pub gate_m: f64,
    /// Standard deviation of the odometry's translation over one scan, m: the weight of the
    /// prior toward the odometry's prediction. Default 0.003.
    pub odometry_sigma_m: f64,
    /// The same for the heading, rad. Default 0.009.
    pub odometry_sigma_rad: f64,
    /// A match that moves the pose farther than this from the prediction is refused, m.
    /// Default 0.1 (the odometry errs by millimetres over one scan).
    pub max_shift_m: f64,
    /// The same for the heading, rad. Default 0.1.
    pub max_turn_rad: f64,
    /// Fewer points within 5 cm of mapped surfaces than this and the match is refused.
    /// Default 20.
    pub min_support: usize,
}

impl Default for MatchParams {
    fn default() -> Self {
        let t = TrackerParams::default();
        Self {
            beam_stride: t.beam_stride,
            iterations: t.icp.max_iterations,
            gate_m: t.icp.max_correspondence_m,
            odometry_sigma_m: t.odometry_sigma_m,
            odometry_sigma_rad: t.odometry_sigma_rad,
            max_shift_m: t.icp.basin_translation_m,
            max_turn_rad: t.icp.basin_rotation_rad,
            min_support: t.icp.min_inliers,
        }
    }
}

impl MatchParams {
    /// The tracker's settings for a laser at `robot_from_laser`, a scan in every `every`
    /// entering the map.
    #[must_use]
    pub fn tracker(&self, robot_from_laser: &Isometry2, every: usize) -> TrackerParams {
        let t = TrackerParams::default();
        TrackerParams {
            robot_from_sensor: Se2::from_isometry(robot_from_laser),
            beam_stride: self.beam_stride,
            insert_every: every,
            odometry_sigma_m: self.odometry_sigma_m,
            odometry_sigma_rad: self.odometry_sigma_rad,
            icp: laserlines_slam::IcpParams {
                max_iterations: self.iterations,
                max_correspondence_m: self.gate_m,
                basin_translation_m: self.max_shift_m,
                basin_rotation_rad: self.max_turn_rad,
                min_inliers: self.min_support,
                ..t.icp
            },
            ..t
        }
    }
}

/// Parameters of the explorer, in groups (see the [module docs](self)).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct ExplorerParams {
    /// The side of the first followed wall. Default left.
    pub side: WallSide,
    /// Following a wall.
    pub follow: FollowParams,
    /// The safety layer.
    pub safety: SafetyParams,
    /// Loop detection.
    pub loops: LoopParams,
    /// The robot's own map.
    pub map: MapParams,
    /// Travel to frontiers.
    pub travel: TravelParams,
    /// Done when the map has gained nothing for this long, s. Default 120.
    pub idle_timeout_s: f64,
    /// The sector selection.
    pub sectors: SectorParams,
    /// The scan matching.
    pub matching: MatchParams,
    /// The planner.
    pub planner: PlannerParams,
    /// A rectangle in the map frame that the robot keeps inside (see [`crate::fence`]).
    /// Default none.
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "Option::is_none"))]
    pub fence: Option<Fence>,
}

impl Default for ExplorerParams {
    fn default() -> Self {
        Self {
            side: WallSide::Left,
            follow: FollowParams::default(),
            safety: SafetyParams::default(),
            loops: LoopParams::default(),
            map: MapParams::default(),
            travel: TravelParams::default(),
            idle_timeout_s: 120.0,
            sectors: SectorParams::default(),
            matching: MatchParams::default(),
            planner: PlannerParams::default(),
            fence: None,
        }
    }
}

impl ExplorerParams {
    /// Checks every group: lengths, speeds, rates, gains and times positive and finite,
    /// margins and tolerances finite and not negative, at least one scan in `map.every`.
    ///
    /// # Errors
    /// A [`ParamsError`] naming the first field out of range by its path
    /// (`follow.distance`, `travel.speed`, `planner.clearance_m`, ...).
    pub fn validate(&self) -> Result<(), ParamsError> {
        let f = &self.follow;
        for (field, v) in [
            ("follow.distance", f.distance),
            ("follow.range", f.range),
            ("follow.cruise_speed", f.cruise_speed),
            ("follow.corner_speed", f.corner_speed),
            ("follow.turn_rate", f.turn_rate),
            ("follow.k_heading", f.k_heading),
            ("follow.k_distance", f.k_distance),
            ("follow.front_turn", f.front_turn),
            ("safety.memory_range_m", self.safety.memory_range_m),
            ("loops.match_radius_m", self.loops.match_radius_m),
            ("loops.heading_rad", self.loops.heading_rad),
            ("idle_timeout_s", self.idle_timeout_s),
        ] {
            params::positive(field, v)?;
        }
        for (field, v) in [
            ("follow.front_turn_corner", f.front_turn_corner),
            ("travel.fruitless_gain_m2", self.travel.fruitless_gain_m2),
            ("follow.front_band_margin", f.front_band_margin),
            ("safety.margin", self.safety.margin),
            ("loops.min_path_m", self.loops.min_path_m),
        ] {
            params::non_negative(field, v)?;
        }
        if let Some(m) = self.safety.turn_margin {
            params::non_negative("safety.turn_margin", m)?;
        }
        params::at_least("map.every", self.map.every, 1)?;
        if let Some(fence) = &self.fence {
            fence.validate()?;
        }
        self.validate_travel()?;
        self.validate_parts()
    }

    fn validate_travel(&self) -> Result<(), ParamsError> {
        let t = &self.travel;
        for (field, v) in [
            ("travel.stale_s", t.stale_s),
            ("travel.seek_s", t.seek_s),
            ("travel.replan_s", t.replan_s),
            ("travel.lookahead_m", t.lookahead_m),
            ("travel.speed", t.speed),
            ("travel.give_up_s", t.give_up_s),
            ("travel.tight_clearance_m", t.tight_clearance_m),
        ] {
            params::positive(field, v)?;
        }
        for (field, v) in [
            ("travel.hysteresis_m", t.hysteresis_m),
            ("travel.avoid_radius_m", t.avoid_radius_m),
            ("travel.blocked_radius_m", t.blocked_radius_m),
            ("travel.blocked_s", t.blocked_s),
        ] {
            params::non_negative(field, v)?;
        }
        Ok(())
    }

    /// The sector selection, the scan matching and the planner.
    fn validate_parts(&self) -> Result<(), ParamsError> {
        let (m, pl) = (&self.matching, &self.planner);
        params::non_negative("sectors.min_width", self.sectors.min_width)?;
        params::positive("sectors.distance_floor", self.sectors.distance_floor)?;
        params::at_least("matching.iterations", m.iterations, 1)?;
        params::at_least("matching.beam_stride", m.beam_stride, 1)?;
        for (field, v) in [
            ("matching.gate_m", m.gate_m),
            ("matching.max_shift_m", m.max_shift_m),
            ("matching.max_turn_rad", m.max_turn_rad),
            ("matching.odometry_sigma_m", m.odometry_sigma_m),
            ("matching.odometry_sigma_rad", m.odometry_sigma_rad),
            ("planner.clearance_m", pl.clearance_m),
            ("planner.max_range_m", pl.max_range_m),
        ] {
            params::positive(field, v)?;
        }
        for (field, v) in [
            ("planner.escape_clearance_m", pl.escape_clearance_m),
            ("planner.escape_radius_m", pl.escape_radius_m),
            ("planner.preferred_clearance_m", pl.preferred_clearance_m),
            ("planner.clearance_cost", pl.clearance_cost),
        ] {
            params::non_negative(field, v)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_defaults_are_valid_and_bad_values_are_named_by_path() {
        assert!(ExplorerParams::default().validate().is_ok());
        let mut p = ExplorerParams::default();
        p.follow.distance = -0.6;
        assert!(matches!(
            p.validate(),
            Err(ParamsError::NotPositive {
                field: "follow.distance",
                ..
            })
        ));
        let mut p = ExplorerParams::default();
        p.travel.speed = f64::NAN;
        assert!(
            p.validate()
                .unwrap_err()
                .to_string()
                .starts_with("travel.speed")
        );
        let mut p = ExplorerParams::default();
        p.map.every = 0;
        assert!(
            p.validate()
                .unwrap_err()
                .to_string()
                .starts_with("map.every")
        );
        let mut p = ExplorerParams::default();
        p.planner.clearance_cost = -1.0;
        assert!(
            p.validate()
                .unwrap_err()
                .to_string()
                .starts_with("planner.clearance_cost")
        );
        let mut p = ExplorerParams::default();
        p.safety.margin = 0.0;
        assert!(p.validate().is_ok(), "no margin is allowed");
        for bad in [f64::NAN, -0.01] {
            let mut p = ExplorerParams::default();
            p.safety.turn_margin = Some(bad);
            assert!(
                p.validate()
                    .unwrap_err()
                    .to_string()
                    .starts_with("safety.turn_margin")
            );
        }
    }
}
