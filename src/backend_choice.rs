//! Which linear backend runs a scene: `solver.linear`, with `auto` resolved by the plate's size.
//! Its own module because both the scheme (which builds the backend) and the memory budget (which
//! prices it before anything is assembled) need the choice, and neither should import the other.

use crate::scene::{LinearChoice, Scene};

/// Largest number of free dofs for which `auto` picks the dense modal backend. Its set-up is a
/// dense O(n³) eigen-decomposition with O(n²) memory, the sparse backend's a sparse Cholesky
/// factorisation, but a modal step costs 20–60 µs where a sparse one costs 0.4–0.6 ms at these
/// sizes (`cargo bench --bench solver -- --crossover`, `forced-35hz`, a 2-core development
/// machine): at 1951 free dofs (Argyris 20 × 10) modal sets up in 3.0 s against 0.01 s and wins
/// after 6 000 steps, at 2773 (24 × 12) in 8.9 s and wins after 15 000; FVS 36 × 18 (2052) and
/// 40 × 20 (2520) break even after 6 400 and 11 000 steps. Up to this limit the modal backend
/// pays for its set-up (at most about 3 s and 270 MiB) within 0.65 s of simulated time at
/// Δt = 1e-4 s; a run of the default 1 s breaks even near 2 300 (Argyris) to 2 400 (FVS) free dofs.
pub const MODAL_AUTO_LIMIT: usize = 2000;

/// The backend the `solver.linear` of `scene` names, `auto` resolved by the number of free dofs,
/// except that a modal damping ratio (`damping.modal_ratio` > 0) needs the eigenbasis and makes
/// `auto` modal at every size: the memory budget then refuses a mesh whose dense eigenbasis does
/// not fit, naming the modal backend ([`crate::budget`]). An explicit `sparse` with a modal ratio
/// is refused by [`Scene::validate`].
pub fn resolve(scene: &Scene, free_dofs: usize) -> LinearChoice {
    match scene.solver.linear {
        LinearChoice::Auto if free_dofs <= MODAL_AUTO_LIMIT || scene.damping.is_modal() => {
            LinearChoice::Modal
        }
        LinearChoice::Auto => LinearChoice::Sparse,
        choice => choice,
    }
}
