//! The assembled plate of a scene: M, K, the unit load, the split of the dofs into clamp dofs
//! (prescribed by the base) and free dofs, and the contact points of the obstacles with their
//! constraint rows.

use crate::assembly::{Discretization, PointFunctional};
use crate::element::Jet;
use crate::error::Error;
use crate::modes::{generalized_eigen, sparse_restriction, Modes};
use crate::obstacles::ObstacleLayout;
use crate::scene::{ClampedEdges, Scene, PROBES};
use faer::sparse::SparseColMat;

/// The number of natural frequencies the FMU reports (`mode1.frequency` … `mode6.frequency`).
pub const FREQUENCIES: usize = 6;

/// The number of points whose displacement the FMU reports: the three of the paper's figures and
/// the probes.
pub const OUTPUT_POINTS: usize = 3 + PROBES;

/// The points whose displacement the FMU reports (`docs/model.md` §7): the corners (Lx, 0) and
/// (Lx, Ly) and the edge midpoint (Lx, Ly/2) (the free corners and free-edge midpoint of the
/// paper's plate), then the probes.
pub fn output_points(scene: &Scene) -> [[f64; 2]; OUTPUT_POINTS] {
    let (lx, ly) = (scene.plate.length, scene.plate.width);
    let probes = scene.probes();
    let mut points = [[0.0; 2]; OUTPUT_POINTS];
    points[..3].copy_from_slice(&[[lx, 0.0], [lx, ly], [lx, 0.5 * ly]]);
    for (point, probe) in points[3..].iter_mut().zip(probes) {
        *point = [probe.x, probe.y];
    }
    points
}

/// A plate discretised and assembled in physical units.
#[derive(Clone, Debug)]
pub struct PlateSystem {
    /// The finite element space.
    pub disc: Discretization,
    /// Mass matrix M (kg, with the dof scaling of [`crate::element`]).
    pub mass: SparseColMat<usize, f64>,
    /// Stiffness matrix K.
    pub stiffness: SparseColMat<usize, f64>,
    /// Load vector of a 1 Pa pressure.
    pub unit_load: Vec<f64>,
    /// Clamp dofs, sorted (`docs/elements.md` §5).
    pub clamp: Vec<usize>,
    /// Free dofs, sorted: every dof not in `clamp`.
    pub free: Vec<usize>,
    /// The clamp on the mesh.
    pub clamped: ClampedEdges,
    /// The contact points and the obstacles' heights over them.
    pub layout: ObstacleLayout,
    /// The constraint row of each contact point, over the free dofs (indices into `free`): the
    /// deflection relative to the base there, u(p_i) − z. A mesh vertex's row is its value dof
    /// with weight 1; another point's is Σ φ_k(p_i) over the free dofs k of its cell (its clamp
    /// dofs contribute z times the rows' sum over the clamp's value dofs, which with the free
    /// part's sum is 1: the elements reproduce constants).
    pub contact_rows: Vec<PointFunctional>,
    /// Dof vector of the rigid translation u ≡ 1 (value dofs 1, derivative dofs 0).
    pub translation: Vec<f64>,
    /// Functionals u ↦ u(p) at the [`output_points`].
    pub outputs: [PointFunctional; OUTPUT_POINTS],
}

impl PlateSystem {
    /// Discretises and assembles the plate of `scene` (validated first).
    pub fn new(scene: &Scene) -> Result<PlateSystem, Error> {
        scene.validate()?;
        let disc = Discretization::rectangle(
            scene.mesh.element,
            scene.plate.length,
            scene.plate.width,
            scene.mesh.nx,
            scene.mesh.ny,
        );
        let (mass, stiffness) = disc.assemble(
            scene.areal_mass(),
            scene.bending_stiffness(),
            scene.material.poisson_ratio,
        );
        let unit_load = disc.unit_load();
        let clamped = scene.clamped_edges()?;
        let clamp = disc.clamp_dofs(&clamped);
        let free: Vec<usize> = (0..disc.dof_count)
            .filter(|d| clamp.binary_search(d).is_err())
            .collect();
        let layout = ObstacleLayout::new(scene, &disc.mesh.vertices, &clamped)?;
        let contact_rows = layout
            .points
            .iter()
            .map(|point| {
                let row = match point.vertex {
                    Some(v) => PointFunctional {
                        dofs: vec![disc.value_dof(v)],
                        weights: vec![1.0],
                    },
                    None => disc
                        .point_functional(point.position)
                        .expect("contact points lie on the plate"),
                };
                free_row(&row, &free)
            })
            .collect();
        let translation = disc.interpolate(&|_| Jet {
            value: 1.0,
            ..Jet::default()
        });
        let outputs = output_points(scene).map(|p| {
            disc.point_functional(p)
                .expect("output points lie on the plate")
        });
        Ok(PlateSystem {
            disc,
            mass,
            stiffness,
            unit_load,
            clamp,
            free,
            clamped,
            layout,
            contact_rows,
            translation,
            outputs,
        })
    }

    /// Eigenpairs of the plate clamped at rest (O(n³) in the free dofs, [`crate::modes`]).
    pub fn modes(&self) -> Result<Modes, Error> {
        generalized_eigen(
            &sparse_restriction(self.mass.as_ref(), &self.free),
            &sparse_restriction(self.stiffness.as_ref(), &self.free),
        )
    }
}

/// The part of a functional over the free dofs, as indices into `free` (sorted): the clamp
/// dofs' entries dropped, entries of one free dof summed.
fn free_row(row: &PointFunctional, free: &[usize]) -> PointFunctional {
    let mut out = PointFunctional {
        dofs: Vec::with_capacity(row.dofs.len()),
        weights: Vec::with_capacity(row.dofs.len()),
    };
    for (&d, &w) in row.dofs.iter().zip(&row.weights) {
        if let Ok(k) = free.binary_search(&d) {
            match out.dofs.iter().position(|&j| j == k) {
                Some(at) => out.weights[at] += w,
                None => {
                    out.dofs.push(k);
                    out.weights.push(w);
                }
            }
        }
    }
    out
}
