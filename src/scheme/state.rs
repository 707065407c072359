//! The serializable dynamic state of a stepper, for FMU get/set/serialize.

use crate::contact::BoundState;
use crate::scene::{LinearChoice, Scene};
use serde::{Deserialize, Serialize};

/// The serializable dynamic state of a [`Stepper`](super::Stepper): the scene (fixed parameters,
/// and tunable ones at their current values), the linear backend whose coordinates it holds, and
/// the fields.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct State {
    /// Parameters, tunable ones at their current values.
    pub scene: Scene,
    /// The backend that ran (`Modal` or `Sparse`): `previous` and `current` are in its coordinates.
    pub backend: LinearChoice,
    /// n.
    pub step_index: u64,
    /// (z_{n−1}, z_n) (m).
    pub base: [f64; 2],
    /// (p_{n−1}, p_n) (Pa).
    pub pressure: [f64; 2],
    /// Backend coordinates of w_{n−1} and w_n.
    pub previous: Vec<f64>,
    /// See `previous`.
    pub current: Vec<f64>,
    /// Warm-start active set: −1 at the lower bound, 1 at the upper, 0 free.
    pub active_set: Vec<i8>,
    /// Contact forces of the last step (N).
    pub forces: Vec<f64>,
}

/// The code of a contact state in [`State::active_set`].
pub(crate) fn state_code(state: BoundState) -> i8 {
    match state {
        BoundState::AtLower => -1,
        BoundState::Free => 0,
        BoundState::AtUpper => 1,
    }
}

/// The contact state of a code of [`State::active_set`], if it is one.
pub(crate) fn state_from_code(code: i8) -> Option<BoundState> {
    match code {
        -1 => Some(BoundState::AtLower),
        0 => Some(BoundState::Free),
        1 => Some(BoundState::AtUpper),
        _ => None,
    }
}
