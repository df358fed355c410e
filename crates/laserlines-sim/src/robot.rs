//! A differential-drive robot like NAJI V with a URG-04LX on board, stepped at a fixed time
//! step.
//!
//! - **Footprint**: a rectangle [`Footprint::naji_v`] of 0.50 m (length, along x) by
//!   0.40 m (width), centred on the point midway between the wheels (the robot frame's
//!   origin), about the size of the NAJI V rescue robot.
//! - **Drive**: commands are a forward speed and a turn rate; the robot follows them within
//!   [`DriveLimits`] (speed, turn rate and their accelerations), integrated exactly as an
//!   arc over each physics step.
//! - **Collisions**: after every step the footprint is checked exactly against every wall
//!   (segment-rectangle) and disc (circle-rectangle) near it. A step that would make the
//!   footprint touch an obstacle is not taken: the robot stops where it was and the contact
//!   is counted ([`RobotSim::collisions`]).
//! - **Odometry**: the wheels' travel is measured with gaussian noise whose variance grows
//!   with the distance each wheel rolled ([`OdometryNoise`]), and integrated into the pose
//!   estimate [`RobotSim::odom_from_robot`], as wheel encoders do.
//! - **Laser**: the [`LaserModel`] (URG-04LX by default) at `robot_from_laser`, one scan
//!   every [`RobotParams::scan_period_s`] (10 Hz), taken at the pose of that instant.
//!
//! Everything random draws from generators seeded by [`RobotSim::new`]'s seed: the same
//! world, start, parameters, seed and commands give the same run, bit for bit.
//!
//! ```
//! use laserlines_sim::robot::{RobotParams, RobotSim, VelocityCommand};
//! use laserlines_sim::World;
//! use laserlines::math::{Isometry2, Point2, Vector2};
//! let mut world = World::new();
//! world.add_box(Point2::new(0.0, 0.0), 4.0, 4.0, 0.0);
//! let mut robot = RobotSim::new(&world, Isometry2::identity(), RobotParams::default(), 7).unwrap();
//! for _ in 0..50 {
//!     robot.step(VelocityCommand::new(0.3, 0.0));
//! }
//! // One second at up to 0.3 m/s, accelerating at 1 m/s^2.
//! let x = robot.world_from_robot().translation.vector.x;
//! assert!(x > 0.2 && x < 0.3);
//! assert_eq!(robot.collisions(), 0);
//! // A start pose inside a wall is an error.
//! let bad = Isometry2::new(Vector2::new(1.9, 0.0), 0.0);
//! assert!(RobotSim::new(&world, bad, RobotParams::default(), 7).is_err());
//! ```

use laserlines::Scan;
use laserlines::geometry::distance_to_segment;
use laserlines::math::{Isometry2, Point2, Vector2};
use laserlines::params::{self, ParamsError};
pub use laserlines::robot::{DriveLimits, Footprint, RobotDescription, VelocityCommand, arc};

use crate::index::WorldIndex;
use crate::laser::LaserModel;
use crate::rng::{Rng, mix_seed};
use crate::world::{Target, World};

/// How far around the footprint obstacles are searched for the clearance, m: clearances
/// beyond this are reported as this value.
pub const CLEARANCE_SEARCH: f64 = 0.5;

/// Clearance (m) the footprint must regain after a contact before another contact counts
/// as a new collision.
pub const CONTACT_RELEASE: f64 = 0.01;

/// Noise of the wheel odometry.
///
/// Each wheel's measured travel over a step is its true travel `d` plus gaussian noise of
/// standard deviation `wheel_sigma * sqrt(|d|)`: the variance grows linearly with the
/// distance rolled, whatever the step size.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct OdometryNoise {
    /// Noise of one wheel, m per square root of metre rolled. Default 0.01 (1 cm after 1 m
    /// of travel); 0 gives perfect odometry.
    pub wheel_sigma: f64,
}

impl Default for OdometryNoise {
    fn default() -> Self {
        Self { wheel_sigma: 0.01 }
    }
}

/// Everything about the simulated robot. [`RobotParams::default`] is NAJI V with a
/// URG-04LX at 10 Hz, physics at 50 Hz.
///
/// With the `serde` feature, the simulator's own settings (odometry noise, rates) are the
/// `[simulator]` table of a params file; the robot's description ([`RobotDescription`]) is
/// read apart, as `[robot]`, and the laser model is always the URG-04LX.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct RobotParams {
    /// The robot: footprint, drive limits, wheel base, the laser's mount.
    #[cfg_attr(feature = "serde", serde(skip))]
    pub robot: RobotDescription,
    /// Odometry noise.
    pub odometry: OdometryNoise,
    /// The laser (default [`LaserModel::urg04lx`]).
    #[cfg_attr(feature = "serde", serde(skip))]
    pub laser_model: LaserModel,
    /// Time between scans, s. Default 0.1 (the URG-04LX's 10 Hz).
    pub scan_period_s: f64,
    /// The physics time step, s. Default 0.02 (50 Hz).
    pub physics_dt_s: f64,
    /// Height of the laser's scan plane above the floor, m: arenas are what that plane
    /// cuts ([`crate::arena`]). Default [`crate::arena::DEFAULT_LASER_HEIGHT`] (0.45).
    pub laser_height_m: f64,
}

impl Default for RobotParams {
    fn default() -> Self {
        Self {
            robot: RobotDescription::default(),
            odometry: OdometryNoise::default(),
            laser_model: LaserModel::urg04lx(),
            scan_period_s: 0.1,
            physics_dt_s: 0.02,
            laser_height_m: crate::arena::DEFAULT_LASER_HEIGHT,
        }
    }
}

/// Errors of [`RobotSim::new`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RobotError {
    /// The start pose puts the footprint on a wall or a disc.
    #[error(
        "the start pose (x {x:.3} m, y {y:.3} m, yaw {yaw_deg:.1} deg) puts the robot's footprint on {what}"
    )]
    StartInCollision {
        /// start x, m
        x: f64,
        /// start y, m
        y: f64,
        /// start yaw, deg
        yaw_deg: f64,
        /// what it overlaps, e.g. `wall 3 from (0.6, 0.6) to (1.8, 0.6)`
        what: String,
    },
    /// A parameter is out of its domain.
    #[error("robot parameters: {0}")]
    Params(#[from] ParamsError),
    /// The start pose is not finite.
    #[error("the start pose is not finite")]
    BadStart,
}

/// What one physics step did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepOutcome {
    /// The step was refused because the footprint would have touched an obstacle.
    pub blocked: bool,
    /// Distance travelled by the origin during the step, m.
    pub travelled_m: f64,
}

/// The simulated robot in its world, see the [module docs](self).
#[derive(Debug, Clone)]
pub struct RobotSim {
    index: WorldIndex,
    params: RobotParams,
    world_from_robot: Isometry2,
    odom_from_robot: Isometry2,
    linear: f64,
    angular: f64,
    steps: u64,
    steps_per_scan: u64,
    odom_rng: Rng,
    laser_rng: Rng,
    collisions: u64,
    in_contact: bool,
    min_clearance: f64,
    path_length: f64,
}

impl RobotSim {
    /// A robot at `world_from_robot` in `world`; `seed` seeds the odometry and laser noise.
    /// The odometry frame starts at the start pose (`odom_from_robot` = identity).
    ///
    /// # Errors
    /// [`RobotError::StartInCollision`] when the footprint at the start touches a wall or a
    /// disc, [`RobotError::BadStart`] for a non-finite pose, [`RobotError::BadParameter`]
    /// for a non-positive time step, scan period, footprint, wheel base or limit.
    pub fn new(
        world: &World,
        world_from_robot: Isometry2,
        params: RobotParams,
        seed: u64,
    ) -> Result<Self, RobotError> {
        params.validate()?;
        let t = world_from_robot.translation.vector;
        let yaw = world_from_robot.rotation.angle();
        if !(t.x.is_finite() && t.y.is_finite() && yaw.is_finite()) {
            return Err(RobotError::BadStart);
        }
        let index = WorldIndex::new(world, 0.6);
        let steps_per_scan = (params.scan_period_s / params.physics_dt_s)
            .round()
            .max(1.0) as u64;
        let mut sim = Self {
            index,
            params,
            world_from_robot,
            odom_from_robot: Isometry2::identity(),
            linear: 0.0,
            angular: 0.0,
            steps: 0,
            steps_per_scan,
            odom_rng: Rng::new(mix_seed(seed, 1)),
            laser_rng: Rng::new(mix_seed(seed, 2)),
            collisions: 0,
            in_contact: false,
            min_clearance: CLEARANCE_SEARCH,
            path_length: 0.0,
        };
        let (clearance, nearest) = sim.clearance_at(&world_from_robot);
        if clearance <= 0.0 {
            let what = match nearest {
                Some(Target::Wall(i)) => {
                    let w = world.walls[i];
                    format!(
                        "wall {i} from ({:.2}, {:.2}) to ({:.2}, {:.2})",
                        w.a.x, w.a.y, w.b.x, w.b.y
                    )
                }
                Some(Target::Disc(i)) => {
                    let d = world.discs[i];
                    format!(
                        "disc {i} at ({:.2}, {:.2}) of radius {:.2} m",
                        d.centre.x, d.centre.y, d.radius
                    )
                }
                None => "an obstacle".to_owned(),
            };
            return Err(RobotError::StartInCollision {
                x: t.x,
                y: t.y,
                yaw_deg: yaw.to_degrees(),
                what,
            });
        }
        sim.min_clearance = clearance;
        Ok(sim)
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &RobotParams {
        &self.params
    }

    /// The world's index (walls and discs), for ground truth.
    #[must_use]
    pub fn index(&self) -> &WorldIndex {
        &self.index
    }

    /// The true pose (ground truth, not known to the robot).
    #[must_use]
    pub fn world_from_robot(&self) -> Isometry2 {
        self.world_from_robot
    }

    /// The true pose of the laser.
    #[must_use]
    pub fn world_from_laser(&self) -> Isometry2 {
        self.world_from_robot * self.params.robot.laser.robot_from_laser()
    }

    /// The pose estimated by the wheel odometry, in the odometry frame (the start pose).
    #[must_use]
    pub fn odom_from_robot(&self) -> Isometry2 {
        self.odom_from_robot
    }

    /// The present forward speed (m/s) and turn rate (rad/s).
    #[must_use]
    pub fn velocity(&self) -> VelocityCommand {
        VelocityCommand::new(self.linear, self.angular)
    }

    /// Simulated time, s.
    #[must_use]
    pub fn time_s(&self) -> f64 {
        self.steps as f64 * self.params.physics_dt_s
    }

    /// Physics steps taken.
    #[must_use]
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Collisions so far: steps refused because the footprint would have touched an
    /// obstacle, counting once every contact until the robot is [`CONTACT_RELEASE`] clear
    /// of everything again.
    #[must_use]
    pub fn collisions(&self) -> u64 {
        self.collisions
    }

    /// The least distance between the footprint and any obstacle so far, m (at most
    /// [`CLEARANCE_SEARCH`]).
    #[must_use]
    pub fn min_clearance(&self) -> f64 {
        self.min_clearance
    }

    /// Distance travelled by the robot's origin, m.
    #[must_use]
    pub fn path_length(&self) -> f64 {
        self.path_length
    }

    /// True when a scan is due at the present step (every [`RobotParams::scan_period_s`],
    /// starting at time 0).
    #[must_use]
    pub fn scan_due(&self) -> bool {
        self.steps.is_multiple_of(self.steps_per_scan)
    }

    /// Takes a scan at the present true pose into reused buffers: the scan as the laser
    /// reports it (stamped with the simulated time) and the noise-free range of every beam
    /// (NaN where it hit nothing in range), see [`WorldIndex::scan_into`].
    pub fn scan_into(&mut self, scan: &mut Scan, true_ranges: &mut Vec<f64>) {
        let world_from_laser = self.world_from_laser();
        self.index.scan_into(
            &world_from_laser,
            &self.params.laser_model,
            &mut self.laser_rng,
            scan,
            true_ranges,
        );
        scan.stamp = Some(self.time_s());
    }

    /// The clearance of the footprint at `world_from_robot` (m, capped at
    /// [`CLEARANCE_SEARCH`]; 0 when touching) and the nearest obstacle within that range.
    #[must_use]
    pub fn clearance_at(&self, world_from_robot: &Isometry2) -> (f64, Option<Target>) {
        let fp = &self.params.robot.footprint;
        let c = Point2::from(world_from_robot.translation.vector);
        let reach = fp.circumradius() + CLEARANCE_SEARCH;
        let lo = c - Vector2::new(reach, reach);
        let hi = c + Vector2::new(reach, reach);
        let robot_from_world = world_from_robot.inverse();
        let world = self.index.world();
        let mut best = CLEARANCE_SEARCH;
        let mut nearest = None;
        let circumradius = fp.circumradius();
        // An obstacle is filed under every grid cell it crosses: the last few seen are
        // skipped when they come again.
        let mut recent = [None::<Target>; 8];
        let mut next = 0;
        self.index.near_box(lo, hi, |t| {
            if recent.contains(&Some(t)) {
                return;
            }
            recent[next] = Some(t);
            next = (next + 1) % recent.len();
            let d = match t {
                Target::Wall(i) => {
                    let w = &world.walls[i];
                    // The footprint is no nearer than its centre less its circumradius:
                    // walls that cannot beat the best so far skip the exact distance.
                    let bound = distance_to_segment(c, w.a, w.b) - circumradius;
                    if bound > best {
                        return;
                    }
                    fp.distance_to_segment_local(robot_from_world * w.a, robot_from_world * w.b)
                }
                Target::Disc(i) => {
                    let disc = &world.discs[i];
                    fp.distance_to_point_local(robot_from_world * disc.centre)
                        - disc.radius.max(0.0)
                }
            };
            if d < best || (d <= 0.0 && nearest.is_none()) {
                best = d.max(0.0);
                nearest = Some(t);
            }
        });
        (best, nearest)
    }

    /// Advances the simulation by one physics step under `command`.
    ///
    /// The speed and turn rate move toward the command within the drive's limits; the pose
    /// follows the arc they describe. If the footprint at the new pose would touch an
    /// obstacle the step is refused: the robot stays, stops, and the contact is counted.
    /// Non-finite commands count as stop.
    pub fn step(&mut self, command: VelocityCommand) -> StepOutcome {
        let dt = self.params.physics_dt_s;
        let lim = &self.params.robot.limits;
        let finite_or_zero = |v: f64| if v.is_finite() { v } else { 0.0 };
        let v_cmd = finite_or_zero(command.linear_m_s).clamp(-lim.max_reverse, lim.max_speed);
        let w_cmd =
            finite_or_zero(command.angular_rad_s).clamp(-lim.max_turn_rate, lim.max_turn_rate);
        let dv = lim.max_accel * dt;
        let dw = lim.max_angular_accel * dt;
        let v = self.linear + (v_cmd - self.linear).clamp(-dv, dv);
        let w = self.angular + (w_cmd - self.angular).clamp(-dw, dw);
        self.steps += 1;

        let ds = v * dt;
        let dtheta = w * dt;
        let next = self.world_from_robot * arc(ds, dtheta);
        let (clearance, _) = self.clearance_at(&next);
        if clearance <= 0.0 {
            if !self.in_contact {
                self.collisions += 1;
            }
            // One contact lasts until the footprint is clear of everything by
            // `CONTACT_RELEASE` again.
            self.in_contact = true;
            self.linear = 0.0;
            self.angular = 0.0;
            self.min_clearance = 0.0;
            return StepOutcome {
                blocked: true,
                travelled_m: 0.0,
            };
        }
        if clearance > CONTACT_RELEASE {
            self.in_contact = false;
        }
        self.min_clearance = self.min_clearance.min(clearance);
        self.world_from_robot = next;
        self.linear = v;
        self.angular = w;
        self.path_length += ds.abs();

        // Odometry: noisy wheel travel, integrated as an arc.
        let half_base = 0.5 * self.params.robot.wheel_base;
        let left = ds - dtheta * half_base;
        let right = ds + dtheta * half_base;
        let sigma = self.params.odometry.wheel_sigma.max(0.0);
        let (left_m, right_m) = if sigma > 0.0 {
            (
                left + sigma * left.abs().sqrt() * self.odom_rng.gaussian(),
                right + sigma * right.abs().sqrt() * self.odom_rng.gaussian(),
            )
        } else {
            (left, right)
        };
        let ds_m = 0.5 * (left_m + right_m);
        let dtheta_m = (right_m - left_m) / self.params.robot.wheel_base;
        self.odom_from_robot *= arc(ds_m, dtheta_m);
        StepOutcome {
            blocked: false,
            travelled_m: ds.abs(),
        }
    }
}

/// The longest scan period the simulator takes, s: a scanner of at least 1 Hz.
pub const MAX_SCAN_PERIOD_S: f64 = 1.0;

/// The farthest the robot moves in one physics step, m.
pub const MAX_STEP_M: f64 = 0.05;

impl RobotParams {
    /// Checks the robot's description ([`RobotDescription::validate`]), that the rates are
    /// positive and finite with the physics step no longer than the scan period and the scan
    /// period at most [`MAX_SCAN_PERIOD_S`], that the robot's top speed moves it at most
    /// [`MAX_STEP_M`] per physics step, and that the odometry noise is finite and not
    /// negative.
    ///
    /// # Errors
    /// [`RobotError::Params`] naming the first field out of range.
    pub fn validate(&self) -> Result<(), RobotError> {
        self.robot.validate()?;
        self.validate_simulation()?;
        Ok(self.validate_motion()?)
    }

    /// The checks of [`RobotParams::validate`] of the `[simulator]` table's fields alone:
    /// the rates and the odometry noise.
    ///
    /// # Errors
    /// A [`ParamsError`] naming the first field out of range.
    pub fn validate_simulation(&self) -> Result<(), ParamsError> {
        params::non_negative("odometry.wheel_sigma", self.odometry.wheel_sigma)?;
        params::positive("scan_period_s", self.scan_period_s)?;
        params::positive("physics_dt_s", self.physics_dt_s)?;
        params::positive("laser_height_m", self.laser_height_m)?;
        if self.physics_dt_s > self.scan_period_s {
            return Err(ParamsError::AboveField {
                field: "physics_dt_s",
                value: self.physics_dt_s,
                limit_field: "scan_period_s",
                limit: self.scan_period_s,
            });
        }
        if self.scan_period_s > MAX_SCAN_PERIOD_S {
            return Err(ParamsError::AboveField {
                field: "scan_period_s",
                value: self.scan_period_s,
                limit_field: "a scan a second at least",
                limit: MAX_SCAN_PERIOD_S,
            });
        }
        Ok(())
    }

    /// Checks that the robot's top speeds, forward and in reverse, move it at most
    /// [`MAX_STEP_M`] per physics step, so that it meets a wall rather than jumps it (the
    /// description's limits against the simulator's step).
    ///
    /// # Errors
    /// A [`ParamsError`] naming the speed.
    pub fn validate_motion(&self) -> Result<(), ParamsError> {
        let fastest = MAX_STEP_M / self.physics_dt_s;
        let limits = &self.robot.limits;
        for (field, value) in [
            ("limits.max_speed", limits.max_speed),
            ("limits.max_reverse", limits.max_reverse),
        ] {
            if value > fastest {
                return Err(ParamsError::AboveField {
                    field,
                    value,
                    limit_field: "5 cm per physics step of physics_dt_s",
                    limit: fastest,
                });
            }
        }
        Ok(())
    }
}

#[cfg(test)]
#[path = "robot_tests.rs"]
mod tests;
