//! The choice of the linear backend for a scene, and its construction.

use super::backend::LinearBackend;
use super::modal::{FreeDofData, ModalBackend, ModalData};
use super::sparse::SparseBackend;
use super::FreeSystem;
use crate::error::Error;
use crate::scene::{LinearChoice, Scene};
use crate::system::PlateSystem;
use std::sync::Arc;

/// Largest number of free dofs for which `auto` picks the dense modal backend: its set-up is a dense
/// O(n³) eigen-decomposition (measured on this 2-core machine: 1 s at 1369 free dofs, 12 s at
/// 2675) and O(n²) memory; at 2000 dofs it stays near 5 s, which a host initialising an FMU still
/// tolerates, and beyond it the sparse backend's cheaper set-up wins for runs of ordinary length.
pub const MODAL_AUTO_LIMIT: usize = 2000;

/// The backend `choice` names, `auto` resolved by the number of free dofs.
pub fn resolve(choice: LinearChoice, free_dofs: usize) -> LinearChoice {
    match choice {
        LinearChoice::Auto if free_dofs <= MODAL_AUTO_LIMIT => LinearChoice::Modal,
        LinearChoice::Auto => LinearChoice::Sparse,
        choice => choice,
    }
}

/// Builds the backend `linear` (resolved, not `Auto`) of the plate of `scene`.
pub fn build(
    linear: LinearChoice,
    scene: &Scene,
    plate: &PlateSystem,
    free: &Arc<FreeSystem>,
) -> Result<Box<dyn LinearBackend>, Error> {
    Ok(match linear {
        LinearChoice::Modal => {
            let data = ModalData::new(
                plate.modes()?,
                scene.solver.time_step,
                FreeDofData {
                    constrained: &free.constrained,
                    load: &free.load,
                    translation_mass: &free.translation_mass,
                    outputs: &free.outputs,
                    mass: free.mass.to_dense(),
                    damping: &free.damping,
                },
            );
            Box::new(ModalBackend::new(Arc::new(data)))
        }
        _ => Box::new(SparseBackend::new(Arc::clone(free))?),
    })
}
