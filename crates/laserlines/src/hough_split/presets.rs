//! The named presets of [`HoughSplitParams`]: the paper alone, and the defaults as a robot
//! driving, a user who wants every line, scan matching and a map of walls read them.

use super::params::HoughSplitParams;
use crate::noise::{NoiseModel, RangeNoise};
use crate::scan::RangeWindow;

impl HoughSplitParams {
    /// The paper's pipeline alone: its grid and criterion, its range limits (0.03..3.00 m),
    /// grid connectivity only, Linseg with a fixed distance criterion (1 cm, growing by 2 %
    /// of the range beyond 0.5 m: four standard deviations of the URG-04LX read as in its
    /// data sheet) with `sigma(r)` across every line, no merge, no shared fits, no end
    /// refinement, no significance test, no minimum length, no RMS limit, no advance test
    /// of glancing lines and no test of round obstacles; data segments and lines need three
    /// points.
    #[must_use]
    pub fn paper() -> Self {
        Self {
            noise: NoiseModel::Fixed(RangeNoise::new(0.0025, 0.005)),
            noise_floor: 0.0,
            bridge_beams: false,
            local_bridge: false,
            min_segment_points: 3,
            split_sigmas: 4.0,
            split_significance: 0.0,
            min_bend: 0.0,
            split_steps: false,
            noise_along_beams: false,
            merge_collinear: false,
            cut_excursions: false,
            keep_split_bounds: false,
            share_fits: false,
            refine_ends: false,
            min_line_points: 3,
            min_line_length: 0.0,
            max_rms_sigmas: f64::INFINITY,
            min_advance_t: 0.0,
            arc_significance: 0.0,
            max_alpha_sd: f64::INFINITY,
            max_r_sd: f64::INFINITY,
            own_scatter: false,
            remove_mixed_pixels: false,
            range_limits: Some(RangeWindow::PAPER),
            ..Self::default()
        }
    }

    /// The defaults for a robot driving among obstacles rather than for a map of walls: every
    /// surface of 5 cm or more gives a line (`min_line_length = 0.05`), so that posts and
    /// legs near the robot are objects of its sectors, and the line gates of
    /// [`complete`](Self::complete) (an obstacle need not be placed within 5 cm to be avoided),
    /// without shared fits (`share_fits = false`): each line lies on its own points, where the
    /// robot meets them, with `sigma(r)` across every line (`noise_along_beams = false`),
    /// and lines on streaks of points along the beams too (`min_advance_t = 0`): a leg seen
    /// through noise larger than the beam spacing is still in the robot's way; so are the
    /// chords of a barrel (`arc_significance = 0`). Every split stands as it did (`min_bend
    /// = 0`, `split_steps = false`, `keep_split_bounds = false`): the simulator's noise has
    /// no bows, and each change of a line moves the explorer's runs (with `min_bend` and
    /// `keep_split_bounds`, maze 17 of the acceptance runs covered 0.777 of its floor against
    /// 1.000).
    /// The explorer of `laserlines simulate` uses it; with shared fits it covered less of the
    /// bundled big arena (8 seeds of the fence test: mean 0.897, worst 0.639, against 0.970
    /// and 0.919), and with the noise taken along the beams too (mean 0.913, worst 0.655).
    #[must_use]
    pub fn navigation() -> Self {
        Self {
            min_line_length: 0.05,
            share_fits: false,
            noise_along_beams: false,
            min_advance_t: 0.0,
            arc_significance: 0.0,
            min_bend: 0.0,
            split_steps: false,
            keep_split_bounds: false,
            ..Self::complete()
        }
    }

    /// Every line the noise lets through, not only those placed within a user's tolerances:
    /// the defaults with the gate on `alpha` widened to 5 deg and none on `r`. It finds more
    /// of the short and far pieces (under the field criteria, 0.4-1.2 points more of the TP
    /// rate, at about twice the false lines); see the README's goals for `hough-split`.
    #[must_use]
    pub fn complete() -> Self {
        Self {
            max_alpha_sd: 5f64.to_radians(),
            max_r_sd: f64::INFINITY,
            ..Self::default()
        }
    }

    /// The defaults as scan matching reads them (`laserlines map`, `laserlines-slam`'s tests):
    /// without shared fits (`share_fits = false`), each line on its own points, and with
    /// `sigma(r)` across every line (`noise_along_beams = false`). With shared fits, a
    /// simulated ring lap's loop closure lost to scan matching alone (worst pose error 0.067 m
    /// against 0.038 m; without, 0.050 m against 0.052 m); with the noise taken along the
    /// beams it lost too (0.136 m against 0.070 m), and under 2 % noise the line normals'
    /// worst pose error rose from 0.235 m to 0.399 m (`laserlines-slam`'s `mapping.rs`). Lines
    /// whose `r` is known worse than 5 cm are left out (`max_r_sd` at most
    /// [`MAPPING_MAX_R_SD`](Self::MAPPING_MAX_R_SD)), as when the figures were measured.
    /// Lines at a glancing angle need not show that their points advance along them
    /// (`min_advance_t = 0`): scan matching takes normals from short glancing pieces under
    /// heavy noise that the test leaves out; with it, the line normals' worst pose error under
    /// 2 % noise rose from 0.235 m to 0.375 m, and the MIT CSAIL log with 2 % noise added
    /// (`laserlines-cli`'s `map_noise.rs`) lost its way (mean translational error 1.49 m
    /// against 0.074 m). Round obstacles' chords are kept too (`arc_significance = 0`), as
    /// when those figures were measured, and excursions stay in their pieces
    /// (`cut_excursions = false`): with the cut, one of nine draws of the MIT CSAIL log with
    /// 1 % noise added was bent by wrong loop closures (1.58 m; without it 0.039 m), the
    /// other eight within 0.004 m of their figures without it.
    #[must_use]
    pub fn mapping() -> Self {
        Self::default().for_mapping()
    }

    /// The largest `max_r_sd` scan matching takes, m: a line it matches must be placed well.
    pub const MAPPING_MAX_R_SD: f64 = 0.05;

    /// These parameters as scan matching reads them ([`mapping`](Self::mapping)): without
    /// shared fits, with `sigma(r)` across every line and without `cut_excursions`,
    /// `min_advance_t`, `arc_significance`, `own_scatter`, `local_bridge`, `min_bend`,
    /// `split_steps` and `keep_split_bounds`, whatever they said of those (the mapping
    /// figures were measured without the last two), and `max_r_sd` at most
    /// [`MAPPING_MAX_R_SD`](Self::MAPPING_MAX_R_SD). (With the local bridge, loop closure on
    /// the simulated loop of the mapping tests gave 0.091 m where scan matching alone gave
    /// 0.049 m; with `min_bend`, scan matching alone mapped the MIT CSAIL log to 0.118 m
    /// against 0.092 m: a line drawn across a bow lies off each side of it by more than its
    /// covariance says; with `keep_split_bounds`, MIT CSAIL with 1 % noise added mapped to
    /// 1.60 m on one draw.)
    #[must_use]
    pub fn for_mapping(self) -> Self {
        Self {
            share_fits: false,
            noise_along_beams: false,
            cut_excursions: false,
            min_advance_t: 0.0,
            arc_significance: 0.0,
            own_scatter: false,
            local_bridge: false,
            min_bend: 0.0,
            split_steps: false,
            keep_split_bounds: false,
            // A NaN stays, for `validate` to refuse.
            max_r_sd: if self.max_r_sd.is_nan() {
                self.max_r_sd
            } else {
                self.max_r_sd.min(Self::MAPPING_MAX_R_SD)
            },
            ..self
        }
    }

    /// The defaults, by name: a map of walls, where a line must be right rather than there.
    /// Only lines whose standard errors lie about within the tolerances of a user who wants
    /// walls (a line within 5 cm and 3 deg of its wall) are kept (`max_r_sd = 0.06`,
    /// `max_alpha_sd = 3 deg`).
    #[must_use]
    pub fn walls() -> Self {
        Self::default()
    }
}
