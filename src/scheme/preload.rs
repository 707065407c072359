//! The initial state: static equilibrium under the preload pressure, with contact when it pushes
//! the plate into an obstacle.

use super::FreeSystem;
use crate::contact::{self, BoxQp};
use crate::error::Error;
use crate::scene::Scene;

/// u₀ − z₀𝟙 over the free dofs: the static equilibrium K_ff w = p₀ f under the preload p₀, with the
/// obstacle bounds g − z₀ when the unconstrained equilibrium violates them (a static contact QP,
/// solved by clarabel).
pub fn static_preload(
    scene: &Scene,
    free: &FreeSystem,
    initial_base: f64,
) -> Result<Vec<f64>, Error> {
    let p = scene.initial.preload_pressure;
    let n = free.load.len();
    if p == 0.0 {
        return Ok(vec![0.0; n]);
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
    let lower = scene
        .lower_obstacle()
        .map_or(f64::NEG_INFINITY, |g| g - initial_base);
    let upper = scene
        .upper_obstacle()
        .map_or(f64::INFINITY, |g| g - initial_base);
    let feasible = free
        .constrained
        .iter()
        .all(|&i| w[i] >= lower && w[i] <= upper);
    if feasible {
        return Ok(w);
    }
    let m = free.constrained.len();
    let (lower, upper) = (vec![lower; m], vec![upper; m]);
    let solution = contact::clarabel::solve_box_qp(&BoxQp {
        a: free.stiffness.as_ref(),
        b: &b,
        constrained: &free.constrained,
        lower: &lower,
        upper: &upper,
    })?;
    Ok(solution.x)
}
