//! The plate restricted to its free dofs (clamp dofs removed) for one time step Δt: the matrices
//! and vectors every linear backend and the clarabel reference path start from.
//!
//! With Rayleigh damping C = αM + βK on the relative motion w, the scheme gains the centred term
//! C(w_{n+1} − w_{n−1})/(2Δt): the QP's matrix becomes A = M + ½Δt²K + ½ΔtC (still symmetric
//! positive definite, one strictly convex box QP per step) and w_{n−1} enters the right-hand side
//! through A − ΔtC. The start step, from rest (v_0 = 0), has no damping term: its matrix stays
//! A₀ = M + ½Δt²K.

use super::vectors::dot;
use crate::assembly::dofs_per_vertex;
use crate::contact::{add_product, ContactRows};
use crate::modes::sparse_restriction;
use crate::scene::{DampingCoefficients, Scene};
use crate::system::{PlateSystem, OUTPUT_POINTS};
use faer::sparse::SparseColMat;
use std::sync::Arc;

/// Forcing of one step, as multipliers of the precomputed free-dof vectors f (unit load) and
/// m₁ = (M𝟙)_f (the mass matrix times the rigid translation).
#[derive(Clone, Copy, Debug)]
pub struct StepForcing {
    /// Multiplier of f: ½Δt²(p_{n+1} + p_{n−1}) (start: ½Δt²·(p_1 + p_0)/2).
    pub load: f64,
    /// Multiplier of m₁: −(z_{n+1} − 2z_n + z_{n−1}) (start: −(z_1 − z_0)).
    pub translation: f64,
    /// Whether this is the start step n = 0 → 1.
    pub start: bool,
}

/// The free-dof restriction of the plate for one time step Δt.
#[derive(Debug)]
pub struct FreeSystem {
    /// M_ff.
    pub mass: SparseColMat<usize, f64>,
    /// K_ff.
    pub stiffness: SparseColMat<usize, f64>,
    /// A = M_ff + ½Δt²K_ff + ½ΔtC_ff, C = αM + βK the Rayleigh damping (zero by default).
    pub system: Arc<SparseColMat<usize, f64>>,
    /// A − ΔtC, the matrix of w_{n−1} in the right-hand side; `None` without damping (then A).
    lagged_system: Option<SparseColMat<usize, f64>>,
    /// A₀ = M_ff + ½Δt²K_ff, the matrix of the start step, which has no damping term (v_0 = 0);
    /// `None` without damping (then A).
    start_system: Option<Arc<SparseColMat<usize, f64>>>,
    /// The scene's damping as the scheme applies it.
    pub damping: DampingCoefficients,
    /// f_f for a 1 Pa pressure.
    pub load: Vec<f64>,
    /// m₁ = (M𝟙)_f: the mass matrix times the rigid translation, on the free dofs.
    pub translation_mass: Vec<f64>,
    /// The constraint rows B of the contact points over the free dofs (none without obstacles):
    /// (Bw)_i is the deflection relative to the base at contact point i.
    pub contact: ContactRows,
    /// The obstacles' heights [h₁, h₂] over each contact point, relative to their levels (−∞ and
    /// +∞ where an obstacle is absent; 0 everywhere for flat obstacles): the bounds of a step are
    /// g1 − z + h₁_i ≤ (Bw)_i ≤ g2 − z + h₂_i.
    pub heights: [Vec<f64>; 2],
    /// Whether every height is 0 (flat obstacles): a step's bounds are then the levels.
    pub flat: bool,
    /// The stop each contact point belongs to on each side (lower, upper), numbered over both
    /// obstacles ([`crate::obstacles::Height::stop`]), for the per-stop outputs.
    pub point_stops: Vec<[Option<usize>; 2]>,
    /// The number of stops of the enabled obstacles.
    pub stop_count: usize,
    /// Per side, the height nearest to the plate at rest over the clamp (`None` where the
    /// obstacle lies over no clamped point): the base must stay strictly between the levels plus
    /// these ([`crate::scene::Scene::clamp_heights`]).
    pub clamp_heights: [Option<f64>; 2],
    /// The obstacles' heights [h₁, h₂] over the two corners (Lx, 0) and (Lx, Ly) where they are
    /// contact points, −∞ and +∞ where they are not: the check of the reported corner
    /// displacements against the obstacles.
    pub corner_heights: [Vec<f64>; 2],
    /// Per side, the height nearest to the plate at rest anywhere
    /// ([`crate::scene::Scene::nearest_heights`]), for the gap that scales the tolerances.
    pub nearest_heights: [f64; 2],
    /// Output functionals restricted to the free dofs: the three points of the paper's figures,
    /// then the probes ([`crate::system::output_points`]).
    pub outputs: [Vec<f64>; OUTPUT_POINTS],
    /// For each mesh vertex, in the mesh's order, the free-dof index of its value dof; `None` on
    /// the clamp, where the value is the base displacement.
    pub vertex_values: Vec<Option<usize>>,
    /// The node of each free dof (its vertex, or for Argyris the midpoint of its edge) as a point
    /// of the lattice of half cells, (round(2x/hx), round(2y/hy)) for cells of hx × hy: the input
    /// of the nested-dissection ordering ([`crate::contact::ordering`]).
    pub nodes: Vec<[i64; 2]>,
    /// 𝟙ᵀM𝟙: the plate's mass (kg).
    pub total_mass: f64,
    /// ∫ 1: the plate's area (m²).
    pub area: f64,
}

impl FreeSystem {
    /// Restricts the assembled plate of `scene` to its free dofs.
    pub fn new(scene: &Scene, plate: &PlateSystem) -> FreeSystem {
        let keep = &plate.free;
        let mass = sparse_restriction(plate.mass.as_ref(), keep);
        let stiffness = sparse_restriction(plate.stiffness.as_ref(), keep);
        let dt = scene.solver.time_step;
        let damping = scene.damping.coefficients();
        let (alpha, beta) = (damping.alpha, damping.beta);
        // a·M + b·K; for α = β = 0 the system is M·1 + K·½Δt², bit for bit M + ½Δt²K.
        let combine = |a: f64, b: f64| &(&mass * faer::Scale(a)) + &(&stiffness * faer::Scale(b));
        let half_dt2 = 0.5 * dt * dt;
        let system = combine(1.0 + 0.5 * dt * alpha, half_dt2 + 0.5 * dt * beta);
        let (lagged_system, start_system) = if damping.is_zero() {
            (None, None)
        } else {
            (
                Some(combine(1.0 - 0.5 * dt * alpha, half_dt2 - 0.5 * dt * beta)),
                Some(combine(1.0, half_dt2)),
            )
        };
        let mut m_translation = vec![0.0; plate.disc.dof_count];
        add_product(
            plate.mass.as_ref(),
            &plate.translation,
            1.0,
            &mut m_translation,
        );
        let layout = &plate.layout;
        let heights = layout.heights();
        FreeSystem {
            mass,
            stiffness,
            system: Arc::new(system),
            lagged_system,
            start_system: start_system.map(Arc::new),
            damping,
            load: keep.iter().map(|&d| plate.unit_load[d]).collect(),
            translation_mass: keep.iter().map(|&d| m_translation[d]).collect(),
            contact: ContactRows::new(
                plate
                    .contact_rows
                    .iter()
                    .map(|r| (&r.dofs[..], &r.weights[..])),
            ),
            flat: heights.iter().all(|h| h.iter().all(|&x| x == 0.0)),
            point_stops: layout
                .points
                .iter()
                .map(|p| [p.lower, p.upper].map(|h| h.and_then(|h| h.stop)))
                .collect(),
            stop_count: layout.stops.len(),
            clamp_heights: layout.clamp_heights,
            corner_heights: {
                let corners = &crate::system::output_points(scene)[..2];
                let point = |c: &[f64; 2]| layout.points.iter().position(|p| p.position == *c);
                [0, 1].map(|side| {
                    let absent = [f64::NEG_INFINITY, f64::INFINITY][side];
                    corners
                        .iter()
                        .map(|c| point(c).map_or(absent, |i| heights[side][i]))
                        .collect()
                })
            },
            nearest_heights: scene.nearest_heights(),
            heights,
            outputs: plate.outputs.each_ref().map(|f| {
                let mut row = vec![0.0; keep.len()];
                for (&d, &w) in f.dofs.iter().zip(&f.weights) {
                    if let Ok(k) = keep.binary_search(&d) {
                        row[k] += w;
                    }
                }
                row
            }),
            vertex_values: (0..plate.disc.mesh.vertices.len())
                .map(|v| keep.binary_search(&plate.disc.value_dof(v)).ok())
                .collect(),
            total_mass: dot(&m_translation, &plate.translation),
            area: dot(&plate.unit_load, &plate.translation),
            nodes: free_dof_nodes(scene, plate),
        }
    }

    /// The matrix of the step's QP: A, or A₀ for the start step.
    pub fn system_matrix(&self, start: bool) -> &SparseColMat<usize, f64> {
        match (&self.start_system, start) {
            (Some(start_system), true) => start_system,
            _ => &self.system,
        }
    }

    /// A₀, the start step's matrix, when damping makes it differ from A.
    pub fn start_system(&self) -> Option<&Arc<SparseColMat<usize, f64>>> {
        self.start_system.as_ref()
    }

    /// The right-hand side b of a step over the free dofs, from w_{n−1} and w_n:
    /// b = 2 M w_n − (A − ΔtC) w_{n−1} + r (start step: b = M w_0 + r), with
    /// r = load·f + translation·m₁ the forcing of [`StepForcing`]. With A = M + ½Δt²K + ½ΔtC this
    /// is the scheme M(w_{n+1} − 2w_n + w_{n−1})/Δt² + K(w_{n+1} + w_{n−1})/2
    /// + C(w_{n+1} − w_{n−1})/(2Δt) = r/Δt² (+ the contact term).
    pub fn right_hand_side(
        &self,
        forcing: &StepForcing,
        previous: &[f64],
        current: &[f64],
        b: &mut [f64],
    ) {
        for ((b, &f), &m) in b.iter_mut().zip(&self.load).zip(&self.translation_mass) {
            *b = forcing.load * f + forcing.translation * m;
        }
        if forcing.start {
            add_product(self.mass.as_ref(), current, 1.0, b);
        } else {
            add_product(self.mass.as_ref(), current, 2.0, b);
            let lagged = self.lagged_system.as_ref().unwrap_or(&self.system);
            add_product(lagged.as_ref(), previous, -1.0, b);
        }
    }
}

/// The lattice point of each free dof's node (see [`FreeSystem::nodes`]): vertex dofs come first,
/// `dofs_per_vertex` per vertex, then (Argyris) one per edge.
fn free_dof_nodes(scene: &Scene, plate: &PlateSystem) -> Vec<[i64; 2]> {
    let mesh = &plate.disc.mesh;
    let cell = [
        scene.plate.length / scene.mesh.nx as f64,
        scene.plate.width / scene.mesh.ny as f64,
    ];
    let lattice = |p: [f64; 2]| [0, 1].map(|a| (2.0 * p[a] / cell[a]).round() as i64);
    let per_vertex = dofs_per_vertex(scene.mesh.element);
    let vertex_dofs = per_vertex * mesh.vertices.len();
    plate
        .free
        .iter()
        .map(|&d| {
            if d < vertex_dofs {
                lattice(mesh.vertices[d / per_vertex])
            } else {
                let [p, q] = mesh.edges[d - vertex_dofs].map(|v| lattice(mesh.vertices[v]));
                [(p[0] + q[0]) / 2, (p[1] + q[1]) / 2]
            }
        })
        .collect()
}

/// xᵀ A x for a sparse A.
pub(crate) fn quadratic(a: &SparseColMat<usize, f64>, x: &[f64]) -> f64 {
    let mut ax = vec![0.0; x.len()];
    add_product(a.as_ref(), x, 1.0, &mut ax);
    dot(&ax, x)
}
