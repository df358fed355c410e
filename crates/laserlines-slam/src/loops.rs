//! Loop closure: a scan searched in an earlier, finished submap by branch-and-bound
//! correlative matching around its estimated pose, then verified and refined by
//! point-to-line ICP. A closure that passes becomes a pose-graph edge with a Cauchy kernel.

use laserlines::math::Point2;
use nalgebra::Matrix3;

use crate::cloud::SurfacePoint;
use crate::correlative::SearchWindow;
use crate::graph::{Edge, RobustKernel, information_in_frame};
use crate::icp::match_points;
use crate::params::MapperParams;
use crate::se2::Se2;
use crate::submap::Submap;

/// What a search in one submap gave.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LoopOutcome {
    /// A verified closure: the edge from the submap's anchor to the scan (its `from` and
    /// `to` are left for the caller to set).
    Accepted(Edge),
    /// The search found a pose, ICP did not confirm it.
    Rejected,
    /// Nothing scored high enough.
    NotFound,
}

/// Searches `submap` (anchored at `anchor`, `map_from_anchor`) for the scan whose estimated
/// pose is `pose` (`map_from_scan`); `search` are the scan points for the correlative
/// search, `surface` its points with normals for verification.
#[must_use]
pub fn try_closure(
    submap: &Submap,
    anchor: &Se2,
    pose: &Se2,
    search: &[Point2],
    surface: &[SurfacePoint],
    params: &MapperParams,
) -> LoopOutcome {
    let Some(grid) = &submap.grid else {
        return LoopOutcome::NotFound;
    };
    let l = &params.loops;
    let guess = anchor.between(pose);
    let window = SearchWindow {
        linear_m: l.linear_window_m,
        angular_rad: l.angular_window_rad,
    };
    let Some(found) = grid.search(search, guess, window, l.min_score) else {
        return LoopOutcome::NotFound;
    };
    let mut icp = params.icp;
    icp.min_inlier_fraction = l.min_inlier_fraction;
    icp.basin_translation_m = 2.0 * grid.resolution();
    icp.basin_rotation_rad = 0.05;
    let Ok(refined) = match_points(&submap.cloud, surface, found.pose, None, &icp) else {
        return LoopOutcome::Rejected;
    };
    let cov = refined.covariance * params.match_covariance_scale;
    let information = cov.try_inverse().unwrap_or_else(Matrix3::identity);
    // The measurement is in the anchor's frame, as the edge's error is.
    LoopOutcome::Accepted(Edge {
        from: submap.anchor,
        to: submap.anchor,
        measurement: refined.pose,
        information: information_in_frame(&information, refined.pose.theta),
        kernel: RobustKernel::Cauchy(l.cauchy_scale),
    })
}
