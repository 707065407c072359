//! The buffers a step works in, one entry per constrained vertex, kept from step to step so that
//! a step allocates nothing.

use crate::contact::BoundState;

/// A step's workspace.
pub(super) struct StepWorkspace {
    /// The prediction's values at the constrained vertices (stand-ins where the backend proved
    /// them inside), which the backend's stages hold while the step runs.
    pub(super) values: Vec<f64>,
    /// The step's bounds and its trial answer.
    pub(super) trial: Trial,
}

/// The bounds of a step and its answer on trial: adopted (states and forces) when the step is
/// accepted.
pub(super) struct Trial {
    /// The bounds on w_{n+1} at the constrained vertices: the obstacles relative to the base, or
    /// the impact law's bounds.
    pub(super) lower: Vec<f64>,
    pub(super) upper: Vec<f64>,
    /// The contact states of the answer.
    pub(super) states: Vec<BoundState>,
    /// The contact forces of the answer (N).
    pub(super) forces: Vec<f64>,
    /// w_{n+1} at the constrained vertices after the contact solve, for its bound check.
    pub(super) solved: Vec<f64>,
}

impl StepWorkspace {
    /// The workspace of `m` constrained vertices.
    pub(super) fn new(m: usize) -> StepWorkspace {
        StepWorkspace {
            values: vec![0.0; m],
            trial: Trial {
                lower: vec![0.0; m],
                upper: vec![0.0; m],
                states: vec![BoundState::Free; m],
                forces: vec![0.0; m],
                solved: vec![0.0; m],
            },
        }
    }
}
