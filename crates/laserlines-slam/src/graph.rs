//! A pose graph over SE(2): nodes are poses, edges measured relative poses with their
//! information matrices, solved by Levenberg-Marquardt on the sparse normal equations
//! (`faer`'s sparse Cholesky), with robust kernels so that a wrong edge (a false loop
//! closure) is down-weighted instead of bending the whole graph.
//!
//! An edge `from -> to` measuring `z = from_T_to` has the error
//! `e = t2v(z^-1 * (x_from^-1 * x_to))` (translation and wrapped heading), and costs
//! `rho(e^T Omega e)`; the first node is held in place.

use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, Side};
use laserlines::math::wrap_angle;
use nalgebra::{Matrix3, Vector3};

use crate::se2::Se2;

/// How an edge's squared error `s = e^T Omega e` is weighed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RobustKernel {
    /// Plain least squares, `rho(s) = s`.
    None,
    /// Huber: quadratic up to `k` standard deviations, linear beyond.
    Huber(f64),
    /// Cauchy: `c^2 ln(1 + s / c^2)`; an edge `c` standard deviations off counts half.
    Cauchy(f64),
}

impl RobustKernel {
    /// `(rho(s), rho'(s))`.
    fn eval(self, s: f64) -> (f64, f64) {
        match self {
            Self::None => (s, 1.0),
            Self::Huber(k) => {
                let r = s.sqrt();
                if r <= k {
                    (s, 1.0)
                } else {
                    (2.0 * k * r - k * k, k / r)
                }
            }
            Self::Cauchy(c) => {
                let c2 = c * c;
                (c2 * (s / c2).ln_1p(), 1.0 / (1.0 + s / c2))
            }
        }
    }
}

/// A measured relative pose between two nodes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Edge {
    /// The node the measurement is taken from.
    pub from: usize,
    /// The node measured.
    pub to: usize,
    /// `from_T_to`, the pose of `to` in the frame of `from`.
    pub measurement: Se2,
    /// Information (inverse covariance) of the measurement's `(x, y, theta)`.
    pub information: Matrix3<f64>,
    /// The kernel applied to this edge.
    pub kernel: RobustKernel,
}

/// Errors of the pose graph.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GraphError {
    /// An edge names a node that does not exist, or joins a node to itself.
    #[error("edge {from} -> {to} is not between two nodes of the {nodes} in the graph")]
    BadEdge {
        /// from
        from: usize,
        /// to
        to: usize,
        /// nodes in the graph
        nodes: usize,
    },
    /// A measurement or information matrix is not finite.
    #[error("edge {from} -> {to} has a non-finite measurement or information")]
    NotFinite {
        /// from
        from: usize,
        /// to
        to: usize,
    },
    /// The normal equations could not be factored (the graph is not connected to the first
    /// node, or an information matrix is not positive).
    #[error("the pose graph's normal equations are singular: {0}")]
    Singular(String),
}

/// Settings of [`PoseGraph::optimize`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OptimizeParams {
    /// Most Levenberg-Marquardt rounds (default 30).
    pub max_iterations: usize,
    /// Stop when a round lowers the cost by less than this fraction (default 1e-7).
    pub min_relative_decrease: f64,
}

impl Default for OptimizeParams {
    fn default() -> Self {
        Self {
            max_iterations: 30,
            min_relative_decrease: 1e-7,
        }
    }
}

/// What [`PoseGraph::optimize`] did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OptimizeReport {
    /// Rounds taken.
    pub iterations: usize,
    /// Total robust cost before.
    pub initial_cost: f64,
    /// Total robust cost after.
    pub final_cost: f64,
}

/// Nodes (poses in one world frame) and edges between them.
#[derive(Debug, Clone, Default)]
pub struct PoseGraph {
    nodes: Vec<Se2>,
    edges: Vec<Edge>,
}

impl PoseGraph {
    /// An empty graph.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a node at `pose` (`world_from_node`); returns its index.
    pub fn add_node(&mut self, pose: Se2) -> usize {
        self.nodes.push(pose);
        self.nodes.len() - 1
    }

    /// Adds an edge; returns its index.
    ///
    /// # Errors
    /// [`GraphError::BadEdge`] or [`GraphError::NotFinite`].
    pub fn add_edge(&mut self, edge: Edge) -> Result<usize, GraphError> {
        if edge.from >= self.nodes.len() || edge.to >= self.nodes.len() || edge.from == edge.to {
            return Err(GraphError::BadEdge {
                from: edge.from,
                to: edge.to,
                nodes: self.nodes.len(),
            });
        }
        if !edge.measurement.is_finite() || !edge.information.iter().all(|v| v.is_finite()) {
            return Err(GraphError::NotFinite {
                from: edge.from,
                to: edge.to,
            });
        }
        self.edges.push(edge);
        Ok(self.edges.len() - 1)
    }

    /// The nodes' poses.
    #[must_use]
    pub fn nodes(&self) -> &[Se2] {
        &self.nodes
    }

    /// Moves a node (e.g. to seed it before optimising).
    pub fn set_node(&mut self, index: usize, pose: Se2) {
        if let Some(n) = self.nodes.get_mut(index) {
            *n = pose;
        }
    }

    /// The edges.
    #[must_use]
    pub fn edges(&self) -> &[Edge] {
        &self.edges
    }

    /// The squared Mahalanobis error `e^T Omega e` of an edge at the current poses.
    #[must_use]
    pub fn edge_chi2(&self, index: usize) -> f64 {
        self.edges.get(index).map_or(f64::NAN, |e| {
            let (r, _, _) = linearise(e, &self.nodes[e.from], &self.nodes[e.to]);
            (r.transpose() * e.information * r)[0]
        })
    }

    /// The total robust cost at the current poses.
    #[must_use]
    pub fn cost(&self) -> f64 {
        cost_of(&self.edges, &self.nodes)
    }

    /// Minimises the total robust cost by Levenberg-Marquardt, holding the first node.
    ///
    /// # Errors
    /// [`GraphError::Singular`] when the normal equations cannot be factored.
    pub fn optimize(&mut self, params: &OptimizeParams) -> Result<OptimizeReport, GraphError> {
        let initial_cost = self.cost();
        let mut cost = initial_cost;
        let mut lambda = 1e-6;
        let mut iterations = 0;
        if self.nodes.len() < 2 || self.edges.is_empty() {
            return Ok(OptimizeReport {
                iterations,
                initial_cost,
                final_cost: cost,
            });
        }
        // The sparsity pattern is the same in every round: analysed once.
        let mut symbolic = None;
        while iterations < params.max_iterations {
            iterations += 1;
            let (h, g) = self.normal_equations();
            let mut improved = false;
            for _ in 0..10 {
                let step = solve(&h, &g, lambda, self.nodes.len(), &mut symbolic)?;
                let moved: Vec<Se2> = self
                    .nodes
                    .iter()
                    .enumerate()
                    .map(|(i, n)| {
                        Se2::new(
                            n.x + step[3 * i],
                            n.y + step[3 * i + 1],
                            n.theta + step[3 * i + 2],
                        )
                    })
                    .collect();
                let new_cost = cost_of(&self.edges, &moved);
                if new_cost.is_finite() && new_cost <= cost {
                    self.nodes = moved;
                    let decrease = (cost - new_cost) / cost.max(1e-300);
                    cost = new_cost;
                    lambda = (lambda / 10.0).max(1e-12);
                    improved = decrease >= params.min_relative_decrease;
                    break;
                }
                lambda *= 10.0;
            }
            if !improved {
                break;
            }
        }
        Ok(OptimizeReport {
            iterations,
            initial_cost,
            final_cost: cost,
        })
    }

    /// `H` as triplets and `g`, with the robust weights at the current poses and the first
    /// node held by a stiff prior.
    fn normal_equations(&self) -> (Vec<Triplet<usize, usize, f64>>, Vec<f64>) {
        let n = self.nodes.len();
        let mut trip = Vec::with_capacity(self.edges.len() * 36 + 3);
        let mut g = vec![0.0; 3 * n];
        for e in &self.edges {
            let (r, a, b) = linearise(e, &self.nodes[e.from], &self.nodes[e.to]);
            let s = (r.transpose() * e.information * r)[0];
            let (_, w) = e.kernel.eval(s);
            let om = e.information * w;
            let blocks = [(e.from, a), (e.to, b)];
            for &(i, ji) in &blocks {
                let gi = ji.transpose() * om * r;
                for k in 0..3 {
                    g[3 * i + k] += gi[k];
                }
                for &(j, jj) in &blocks {
                    let hij = ji.transpose() * om * jj;
                    for (row, col) in (0..3).flat_map(|r| (0..3).map(move |c| (r, c))) {
                        trip.push(Triplet::new(3 * i + row, 3 * j + col, hij[(row, col)]));
                    }
                }
            }
        }
        for k in 0..3 {
            trip.push(Triplet::new(k, k, 1e12));
        }
        (trip, g)
    }
}

/// The rotation by `theta` of the translation part of `(x, y, theta)`.
fn rotation(theta: f64) -> Matrix3<f64> {
    let (s, c) = theta.sin_cos();
    Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

/// A covariance of `(x, y, theta)` given in a frame turned by `theta` from its parent,
/// expressed in the parent: `R cov R^T`.
#[must_use]
pub fn covariance_in_parent(cov: &Matrix3<f64>, theta: f64) -> Matrix3<f64> {
    let r = rotation(theta);
    r * cov * r.transpose()
}

/// An information matrix of `(x, y, theta)` given in a parent frame, expressed in a frame
/// turned by `theta` from it (as an edge's error is, in its measurement's frame):
/// `R^T info R`.
#[must_use]
pub fn information_in_frame(info: &Matrix3<f64>, theta: f64) -> Matrix3<f64> {
    let r = rotation(theta);
    r.transpose() * info * r
}

/// Solves `(H + lambda diag(H)) dx = -g`, analysing the pattern on the first call.
fn solve(
    h: &[Triplet<usize, usize, f64>],
    g: &[f64],
    lambda: f64,
    nodes: usize,
    symbolic: &mut Option<SymbolicLlt<usize>>,
) -> Result<Vec<f64>, GraphError> {
    let dim = 3 * nodes;
    let mut diag = vec![0.0; dim];
    for t in h {
        if t.row == t.col {
            diag[t.row] += t.val;
        }
    }
    let mut all = h.to_vec();
    for (i, d) in diag.iter().enumerate() {
        // A floor keeps nodes with nothing but a heading constraint solvable.
        all.push(Triplet::new(i, i, lambda * d.max(1e-9) + 1e-9));
    }
    let m = SparseColMat::<usize, f64>::try_new_from_triplets(dim, dim, &all)
        .map_err(|e| GraphError::Singular(format!("{e:?}")))?;
    let singular = |e: &dyn std::fmt::Debug| GraphError::Singular(format!("{e:?}"));
    let sym = match symbolic {
        Some(s) => s.clone(),
        None => {
            let s = SymbolicLlt::try_new(m.symbolic(), Side::Lower).map_err(|e| singular(&e))?;
            *symbolic = Some(s.clone());
            s
        }
    };
    let llt = Llt::try_new_with_symbolic(sym, m.as_ref(), Side::Lower).map_err(|e| singular(&e))?;
    let rhs = Mat::from_fn(dim, 1, |i, _| -g[i]);
    let x = llt.solve(&rhs);
    Ok((0..dim).map(|i| x[(i, 0)]).collect())
}

/// Total robust cost of `edges` at `nodes`.
fn cost_of(edges: &[Edge], nodes: &[Se2]) -> f64 {
    edges
        .iter()
        .map(|e| {
            let (r, _, _) = linearise(e, &nodes[e.from], &nodes[e.to]);
            e.kernel.eval((r.transpose() * e.information * r)[0]).0
        })
        .sum()
}

/// The error of `edge` at poses `xi`, `xj` and its Jacobians with respect to both.
fn linearise(edge: &Edge, xi: &Se2, xj: &Se2) -> (Vector3<f64>, Matrix3<f64>, Matrix3<f64>) {
    let z = &edge.measurement;
    let (si, ci) = xi.theta.sin_cos();
    let (sz, cz) = z.theta.sin_cos();
    let dx = xj.x - xi.x;
    let dy = xj.y - xi.y;
    // Ri^T (tj - ti)
    let lx = ci * dx + si * dy;
    let ly = -si * dx + ci * dy;
    let ex = lx - z.x;
    let ey = ly - z.y;
    let r = Vector3::new(
        cz * ex + sz * ey,
        -sz * ex + cz * ey,
        wrap_angle(xj.theta - xi.theta - z.theta),
    );
    // d(Ri^T d)/d theta_i = (ly, -lx); then rotated by Rz^T.
    let rz_t = nalgebra::Matrix2::new(cz, sz, -sz, cz);
    let ri_t = nalgebra::Matrix2::new(ci, si, -si, ci);
    let m = rz_t * ri_t;
    let dtheta = rz_t * nalgebra::Vector2::new(ly, -lx);
    let a = Matrix3::new(
        -m[(0, 0)],
        -m[(0, 1)],
        dtheta.x,
        -m[(1, 0)],
        -m[(1, 1)],
        dtheta.y,
        0.0,
        0.0,
        -1.0,
    );
    let b = Matrix3::new(
        m[(0, 0)],
        m[(0, 1)],
        0.0,
        m[(1, 0)],
        m[(1, 1)],
        0.0,
        0.0,
        0.0,
        1.0,
    );
    (r, a, b)
}
