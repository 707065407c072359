//! The serializable dynamic state of a stepper, for FMU get/set/serialize.

use super::energy::EnergyFlows;
use crate::contact::BoundState;
use crate::error::Error;
use crate::scene::{LinearChoice, Scene};
use serde::{Deserialize, Serialize};

/// The serializable dynamic state of a [`Stepper`](super::Stepper): the scene (fixed parameters,
/// and tunable ones at their current values), the linear backend whose coordinates it holds, and
/// the fields. Every field is required when it is deserialized: a payload that lacks one is
/// refused, not completed with a default.
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
    /// −G of the last step (N): the force on the base, see [`Outputs`](super::Outputs).
    pub base_force: f64,
    /// J_n, the impulse of the force on the base since t_0 (N·s), see
    /// [`Outputs::base_impulse`](super::Outputs::base_impulse).
    pub base_impulse: f64,
    /// Energy flows summed since t_1 (J).
    pub flows: EnergyFlows,
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

/// Largest step index a state may hold: t_n = n·Δt is computed from n as an f64, exact up to 2⁵³.
pub const MAX_STEP_INDEX: u64 = 1 << 53;

impl State {
    /// Checks the fields that need no model: every number finite, the step index at most
    /// [`MAX_STEP_INDEX`], a state at n = 0 at rest (both levels and both base values equal),
    /// contact codes in range and contact forces of the sign their codes imply (≥ 0 at the lower
    /// obstacle, ≤ 0 at the upper, 0 at a free vertex) up to `force_tolerance` (N). Returns the
    /// contact states. Dimensions are the caller's to check first.
    pub(crate) fn check_fields(&self, force_tolerance: f64) -> Result<Vec<BoundState>, Error> {
        let finite = |field: &str, values: &[f64]| -> Result<(), Error> {
            match values.iter().position(|v| !v.is_finite()) {
                Some(i) => Err(Error::invalid_state(
                    &format!("{field}[{i}]"),
                    values[i],
                    "must be finite",
                )),
                None => Ok(()),
            }
        };
        finite("base", &self.base)?;
        finite("pressure", &self.pressure)?;
        finite("previous", &self.previous)?;
        finite("current", &self.current)?;
        finite("forces", &self.forces)?;
        finite("base_force", &[self.base_force])?;
        finite("base_impulse", &[self.base_impulse])?;
        if !self.flows.is_finite() {
            let flows = format!("{:?}", self.flows);
            return Err(Error::invalid_state("flows", flows, "must be finite"));
        }
        if self.step_index > MAX_STEP_INDEX {
            return Err(Error::invalid_state(
                "step_index",
                self.step_index,
                &format!("must be at most 2^53 = {MAX_STEP_INDEX}"),
            ));
        }
        if self.step_index == 0 && (self.previous != self.current || self.base[0] != self.base[1]) {
            return Err(Error::invalid_state(
                "step_index",
                0,
                "must belong to a plate at rest: at n = 0 previous must equal current and \
                 base[0] must equal base[1]",
            ));
        }
        let mut states = Vec::with_capacity(self.active_set.len());
        for (i, (&code, &force)) in self.active_set.iter().zip(&self.forces).enumerate() {
            let state = state_from_code(code).ok_or_else(|| {
                Error::invalid_state(
                    &format!("active_set[{i}]"),
                    code,
                    "must be -1 (at the lower obstacle), 0 (free) or 1 (at the upper obstacle)",
                )
            })?;
            let (consistent, rule) = match state {
                BoundState::Free => (force.abs() <= force_tolerance, "0 N at a free vertex"),
                BoundState::AtLower => (force >= -force_tolerance, ">= 0 at the lower obstacle"),
                BoundState::AtUpper => (force <= force_tolerance, "<= 0 at the upper obstacle"),
            };
            if !consistent {
                return Err(Error::invalid_state(
                    &format!("forces[{i}]"),
                    force,
                    &format!("must be {rule} (active_set[{i}] = {code}), to {force_tolerance:e} N"),
                ));
            }
            states.push(state);
        }
        Ok(states)
    }
}

#[cfg(test)]
mod tests {
    use crate::scene::Scene;
    use crate::scheme::Stepper;

    /// A payload without the force on the base, its impulse or the energy flows is refused by
    /// name.
    #[test]
    fn every_field_is_required() {
        let mut scene = Scene::default();
        (scene.mesh.nx, scene.mesh.ny) = (1, 1);
        let state = Stepper::new(&scene, 0.0).unwrap().state();
        let full = serde_json::to_value(&state).unwrap();
        assert_eq!(
            serde_json::from_value::<super::State>(full.clone()).unwrap(),
            state
        );
        for field in ["base_force", "base_impulse", "flows"] {
            let mut partial = full.clone();
            partial.as_object_mut().unwrap().remove(field);
            let err = serde_json::from_value::<super::State>(partial).unwrap_err();
            assert!(
                err.to_string()
                    .contains(&format!("missing field `{field}`")),
                "{err}"
            );
        }
    }

    /// A non-finite energy flow is refused, naming the flows and their values.
    #[test]
    fn a_non_finite_flow_is_refused() {
        let mut scene = Scene::default();
        (scene.mesh.nx, scene.mesh.ny) = (1, 1);
        let mut state = Stepper::new(&scene, 0.0).unwrap().state();
        assert!(state.check_fields(0.0).is_ok());
        state.flows.load_work = f64::NAN;
        let err = state.check_fields(0.0).unwrap_err().to_string();
        assert!(
            err.contains("flows") && err.contains("load_work: NaN"),
            "{err}"
        );
    }
}
