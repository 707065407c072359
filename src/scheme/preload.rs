//! The initial state: static equilibrium under the preload pressure, with contact when it pushes
//! the plate into an obstacle.

use super::bounds::ObstacleBounds;
use super::free_system::FreeSystem;
use super::reference::solve_reference;
use crate::contact::{BoundState, BoxQp};
use crate::error::Error;
use crate::scene::Scene;

/// The static equilibrium of the preload and its contact.
#[derive(Clone, Debug)]
pub struct StaticPreload {
    /// u₀ − z₀𝟙 over the free dofs.
    pub displacement: Vec<f64>,
    /// The contact state of each constrained vertex.
    pub states: Vec<BoundState>,
    /// The static contact force λ_i at each constrained vertex (N): K w = p₀ f + Bᵀλ.
    pub forces: Vec<f64>,
    /// Set when the contact problem's answer is only clarabel's rough interior-point one.
    pub warning: Option<String>,
}

/// The static equilibrium K_ff w = p₀ f + Bᵀλ under the preload p₀ less the weight
/// ([`Scene::acting_preload_pressure`]), with the obstacle bounds g − z₀ + h_i when the
/// unconstrained equilibrium violates them (a static contact QP solved by clarabel; its
/// multipliers λ are the static contact forces, in newtons).
pub fn static_preload(
    scene: &Scene,
    free: &FreeSystem,
    initial_base: f64,
) -> Result<StaticPreload, Error> {
    let p = scene.acting_preload_pressure();
    let (n, m) = (free.load.len(), free.contact.len());
    let without_contact = |displacement| StaticPreload {
        displacement,
        states: vec![BoundState::Free; m],
        forces: vec![0.0; m],
        warning: None,
    };
    if p == 0.0 {
        return Ok(without_contact(vec![0.0; n]));
    }
    let b: Vec<f64> = free.load.iter().map(|f| p * f).collect();
    let factor = free.stiffness.sp_cholesky(faer::Side::Lower).map_err(|e| {
        Error::Numerical(format!(
            "the clamped stiffness matrix is not numerically positive definite ({e:?})"
        ))
    })?;
    let mut w = b.clone();
    {
        use faer::linalg::solvers::Solve;
        factor.solve_in_place(faer::ColMut::from_slice_mut(&mut w).as_mat_mut());
    }
    let bounds = ObstacleBounds::new(
        [
            scene
                .lower_obstacle()
                .map_or(f64::NEG_INFINITY, |g| g - initial_base),
            scene
                .upper_obstacle()
                .map_or(f64::INFINITY, |g| g - initial_base),
        ],
        &free.heights,
    );
    let rows = &free.contact;
    let feasible = (0..m).all(|i| bounds.admits(i, rows.value(i, &w)));
    if feasible {
        return Ok(without_contact(w));
    }
    let lower: Vec<f64> = (0..m).map(|i| bounds.lower(i)).collect();
    let upper: Vec<f64> = (0..m).map(|i| bounds.upper(i)).collect();
    let (solution, warning) = solve_reference(&BoxQp {
        a: free.stiffness.as_ref(),
        b: &b,
        rows,
        lower: &lower,
        upper: &upper,
    })?;
    Ok(StaticPreload {
        displacement: solution.x,
        states: solution.states,
        forces: solution.lambda,
        warning,
    })
}
