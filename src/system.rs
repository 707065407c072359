//! The assembled plate of a scene: M, K, the unit load, and the split of the dofs into clamp dofs
//! (prescribed by the base) and free dofs, with the obstacle-constrained vertices among the latter.

use crate::assembly::{Discretization, PointFunctional};
use crate::element::Jet;
use crate::error::Error;
use crate::modes::{generalized_eigen, sparse_restriction, Modes};
use crate::scene::Scene;
use faer::sparse::SparseColMat;

/// The points whose displacement the FMU reports (`docs/model.md` §7): free corners (Lx, 0),
/// (Lx, Ly) and the free-edge midpoint (Lx, Ly/2).
pub fn output_points(scene: &Scene) -> [[f64; 2]; 3] {
    let (lx, ly) = (scene.plate.length, scene.plate.width);
    [[lx, 0.0], [lx, ly], [lx, 0.5 * ly]]
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
    /// Obstacle-constrained value dofs, as indices into `free`.
    pub constrained: Vec<usize>,
    /// Dof vector of the rigid translation u ≡ 1 (value dofs 1, derivative dofs 0).
    pub translation: Vec<f64>,
    /// Functionals u ↦ u(p) at the three [`output_points`].
    pub outputs: [PointFunctional; 3],
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
        let clamp = disc.clamp_dofs();
        let free: Vec<usize> = (0..disc.dof_count)
            .filter(|d| clamp.binary_search(d).is_err())
            .collect();
        let constrained = disc
            .constrained_value_dofs()
            .iter()
            .map(|d| free.binary_search(d).expect("constrained dofs are free"))
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
            constrained,
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
