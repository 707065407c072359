//! The choice of the linear backend for a scene, and its construction.

use super::backend::Backend;
use super::free_system::FreeSystem;
use super::modal::{FreeDofData, ModalBackend, ModalData};
use super::sparse::SparseBackend;
use crate::error::Error;
use crate::modes::generalized_eigen;
use crate::scene::{LinearChoice, Scene};
use std::sync::Arc;

/// Builds the backend `linear` (resolved, not `Auto`) of the free system `free` of `scene`.
pub fn build(
    linear: LinearChoice,
    scene: &Scene,
    free: &Arc<FreeSystem>,
) -> Result<Backend, Error> {
    Ok(match linear {
        LinearChoice::Modal => {
            let modes = generalized_eigen(&free.mass, &free.stiffness)?;
            let data = ModalData::new(
                modes,
                scene.solver.time_step,
                FreeDofData {
                    contact: &free.contact,
                    load: &free.load,
                    translation_mass: &free.translation_mass,
                    outputs: &free.outputs,
                    damping: &free.damping,
                },
            );
            Backend::Modal(ModalBackend::new(Arc::new(data)))
        }
        _ => Backend::Sparse(SparseBackend::new(Arc::clone(free))?),
    })
}
