//! The lowest natural frequencies of a plate whose full eigenbasis is not formed (the sparse
//! backend's meshes): subspace iteration with the sparse Cholesky factor of K_ff (Bathe and
//! Wilson, *Numerical Methods in Finite Element Analysis*, 1976, §12.3).
//!
//! With a block X of p M-independent vectors, each iteration solves K X̄ = M X (p solves with one
//! factor), projects the pencil onto X̄ (K_r = X̄ᵀ K X̄ = X̄ᵀ M X, M_r = X̄ᵀ M X̄), solves the p × p
//! problem K_r Q = M_r Q Λ and sets X = X̄ Q. The i-th Ritz value converges to ω_i² at the rate
//! (ω_i/ω_{p+1})⁴ per iteration; p = 2·count + 4 vectors make it fast for the lowest count
//! modes of a plate, whose ω² grow roughly with the square of the mode number. The iteration stops
//! when the count lowest Ritz values changed by less than 1e-13 of themselves over one iteration
//! (an error in ω² of the same order, far below the discretisation's), within 300 iterations.

use super::symmetric_eigen_qr;
use crate::contact::add_product;
use crate::error::Error;
use faer::linalg::solvers::Solve;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::sparse::SparseColMat;
use faer::{Mat, Par, Side};

/// Relative change of the Ritz values below which the iteration has converged (module docs).
const TOLERANCE: f64 = 1e-13;

/// Most iterations before the iteration is reported as not converged.
const MAX_ITERATIONS: usize = 300;

/// The `count` lowest ω² (rad²/s², ascending) of K φ = ω² M φ for sparse symmetric positive
/// definite K and M of order n (module docs); all n of them when n ≤ the block size. An error
/// when K is not positive definite (a plate clamped nowhere) or the iteration does not converge.
pub fn lowest_omega_squared(
    mass: &SparseColMat<usize, f64>,
    stiffness: &SparseColMat<usize, f64>,
    count: usize,
) -> Result<Vec<f64>, Error> {
    let n = mass.nrows();
    let p = (2 * count + 4).min(n);
    let factor = stiffness.sp_cholesky(Side::Lower).map_err(|e| {
        Error::Numerical(format!(
            "the clamped stiffness matrix is not positive definite ({e:?})"
        ))
    })?;
    // Start vectors from a fixed linear congruential sequence: the same on every platform.
    let mut seed = 0x2545_f491_4f6c_dd1d_u64;
    let mut x = Mat::from_fn(n, p, |_, _| {
        seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    });
    let mut previous = vec![f64::INFINITY; p];
    for _ in 0..MAX_ITERATIONS {
        // Y = M X, then X̄ = K⁻¹ Y.
        let mut y = Mat::<f64>::zeros(n, p);
        for k in 0..p {
            let column: Vec<f64> = x.col(k).iter().copied().collect();
            let mut product = vec![0.0; n];
            add_product(mass.as_ref(), &column, 1.0, &mut product);
            for (i, v) in product.into_iter().enumerate() {
                y[(i, k)] = v;
            }
        }
        let mut solved = y.clone();
        factor.solve_in_place(solved.as_mut());
        let stiffness_r = solved.transpose() * &y;
        let mut mass_solved = Mat::<f64>::zeros(n, p);
        for k in 0..p {
            let column: Vec<f64> = solved.col(k).iter().copied().collect();
            let mut product = vec![0.0; n];
            add_product(mass.as_ref(), &column, 1.0, &mut product);
            for (i, v) in product.into_iter().enumerate() {
                mass_solved[(i, k)] = v;
            }
        }
        let mass_r = solved.transpose() * &mass_solved;
        let (values, q) = reduced_pencil(&stiffness_r, &mass_r)?;
        x = &solved * &q;
        let converged = values[..count.min(p)]
            .iter()
            .zip(&previous)
            .all(|(v, old)| (v - old).abs() <= TOLERANCE * v.abs());
        previous = values;
        if converged {
            previous.truncate(count.min(p));
            return Ok(previous);
        }
    }
    Err(Error::Numerical(format!(
        "the subspace iteration for the {count} lowest natural frequencies did not converge in \
         {MAX_ITERATIONS} iterations"
    )))
}

/// The eigenpairs of the small pencil K_r q = λ M_r q, λ ascending, through the Cholesky factor of
/// M_r = R Rᵀ: C = R⁻¹ K_r R⁻ᵀ = U Λ Uᵀ and Q = R⁻ᵀ U.
fn reduced_pencil(stiffness: &Mat<f64>, mass: &Mat<f64>) -> Result<(Vec<f64>, Mat<f64>), Error> {
    let p = mass.nrows();
    let symmetric = |a: &Mat<f64>| Mat::from_fn(p, p, |i, j| 0.5 * (a[(i, j)] + a[(j, i)]));
    let llt = symmetric(mass).llt(Side::Lower).map_err(|e| {
        Error::Numerical(format!(
            "the subspace iteration's block lost its independence ({e:?})"
        ))
    })?;
    let r = llt.L();
    let mut c = symmetric(stiffness);
    solve_lower_triangular_in_place(r, c.as_mut(), Par::Seq);
    let mut c = c.transpose().to_owned();
    solve_lower_triangular_in_place(r, c.as_mut(), Par::Seq);
    let (values, mut u) = symmetric_eigen_qr(&symmetric(&c))?;
    solve_upper_triangular_in_place(r.transpose(), u.as_mut(), Par::Seq);
    Ok((values, u))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;
    use crate::system::PlateSystem;

    /// On a mesh small enough for the dense eigensolver, the lowest six ω² agree with it to
    /// 1e-10 (both are exact to round-off for these well-separated low modes; the dense method's
    /// low modes are accurate to a small multiple of ε‖C‖ relative, [`super::super`]), on a
    /// clamp other than x = 0 too.
    #[test]
    fn agrees_with_the_dense_eigensolver() {
        for clamp in ["xmin", "xmin, ymax", "all"] {
            let mut scene = Scene::default();
            scene.plate.clamp = clamp.to_string();
            (scene.mesh.nx, scene.mesh.ny) = (6, 4);
            let plate = PlateSystem::new(&scene).unwrap();
            let dense = plate.modes().unwrap().omega_squared;
            let mass = crate::modes::sparse_restriction(plate.mass.as_ref(), &plate.free);
            let stiffness = crate::modes::sparse_restriction(plate.stiffness.as_ref(), &plate.free);
            let lowest = lowest_omega_squared(&mass, &stiffness, 6).unwrap();
            for (k, (a, b)) in lowest.iter().zip(&dense).enumerate() {
                assert!((a / b - 1.0).abs() < 1e-10, "{clamp}: mode {k}: {a} vs {b}");
            }
        }
    }
}
