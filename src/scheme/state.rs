//! The serializable dynamic state of a stepper, for FMU get/set/serialize, and its checks (among
//! them [`check_base`], which every step applies to its new base value too): a state is untrusted
//! input, and [`Stepper::restore`](super::Stepper::restore) adopts only a
//! [`CheckedState`], which [`Model::check`] alone makes.

use super::backend::FieldMaps;
use super::energy::{DiscreteEnergy, EnergyFlows};
use super::free_system::FreeSystem;
use crate::contact::BoundState;
use crate::error::Error;
use crate::scene::{LinearChoice, Outside, Scene};
use crate::system::OUTPUT_POINTS;
use serde::{Deserialize, Serialize};

/// Relative tolerance of the obstacle bounds when a state is restored: 1e-6 of the gap
/// ([`Scene::gap`]). A step satisfies its bounds to round-off
/// (the stability matrix asserts 1e-9 of the gap on extreme scenes, 1000 times inside this), and a
/// vertex 1e-6 of the gap inside an obstacle would be pushed out with a speed of 1e-6·gap/Δt, far
/// below anything physical; a crafted state with a vertex deep in an obstacle would instead be
/// pushed out within one step, an arbitrary impulse.
pub const RESTORE_BOUND_TOLERANCE: f64 = 1e-6;

/// Relative tolerance of the sign of a restored contact force, as a fraction of the force that
/// moves the hardest-to-move constrained vertex across the gap in one step, max_i A_ii·gap/Δt².
/// The active-set method accepts a wrong-signed multiplier μ_i while W_ii·|μ_i| ≤ 1e-11 of the gap
/// scale, with W_ii ≥ 1/A_ii, so its forces have the wrong sign by less than 1e-11·A_ii·gap/Δt²
/// (twice that after the start step) when the gap sets the scale: 1e-9 leaves a factor 50 for
/// predictions far beyond the gap.
pub const RESTORE_FORCE_TOLERANCE: f64 = 1e-9;

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

/// A [`State`] that passed every check of [`Model::check`] against a running stepper, with its
/// contact states decoded: the only input [`Stepper::adopt`](super::Stepper::adopt) takes.
pub(crate) struct CheckedState<'a> {
    pub(super) state: &'a State,
    pub(super) states: Vec<BoundState>,
}

/// What stored levels and states are checked against: a running stepper's scene, backend (its
/// field maps) and free system ([`Stepper::model`](super::Stepper::model)).
pub(super) struct Model<'a> {
    pub(super) scene: &'a Scene,
    pub(super) linear: LinearChoice,
    pub(super) maps: FieldMaps<'a>,
    pub(super) free: &'a FreeSystem,
}

/// The two stored levels of a stepper or of a state to restore: n, (z_{n−1}, z_n) (m) and the
/// fields w_{n−1}, w_n in the backend's coordinates.
pub(super) struct StoredLevels<'a> {
    pub(super) step_index: u64,
    pub(super) base: [f64; 2],
    pub(super) previous: &'a [f64],
    pub(super) current: &'a [f64],
}

/// Where stored levels leave the obstacles ([`Model::first_level_outside`]); `level` is 0 for
/// n − 1 and 1 for n.
pub(super) enum LevelOutside {
    /// The base value of that level is not strictly inside the gap: the error saying so.
    Base { level: usize, error: Error },
    /// A constrained vertex of that level lies past an obstacle.
    Vertex { level: usize, outside: Outside },
}

impl Model<'_> {
    /// Checks a state taken from a stepper of a scene with the same fixed parameters.
    ///
    /// The state is untrusted input: it is refused, with an error naming the field, unless its
    /// fixed parameters and backend match this model's and its tunable ones are valid, its
    /// dimensions match, every number is finite, its contact codes are in range and its contact
    /// forces have their signs ([`State::check_fields`] and [`RESTORE_FORCE_TOLERANCE`]), both
    /// base values lie strictly inside the gap, every constrained vertex of both levels lies
    /// within the obstacles to [`RESTORE_BOUND_TOLERANCE`] of the gap (every impact law keeps
    /// every level within them), and its energies and outputs are finite.
    pub(super) fn check<'s>(&self, state: &'s State) -> Result<CheckedState<'s>, Error> {
        // A state moves freely between the fast path and the clarabel reference.
        let (theirs, ours) = (
            state.scene.fixed_part_ignoring_qp(),
            self.scene.fixed_part_ignoring_qp(),
        );
        if let Some((name, state_value, model_value)) = theirs.first_difference(&ours) {
            return Err(Error::invalid_state(
                &format!("scene.{name}"),
                state_value,
                &format!(
                    "must have the fixed parameters of the running model, whose {name} is \
                     {model_value}: a state is restored only into an instance set up with the \
                     same fixed parameters"
                ),
            ));
        }
        state.scene.validate()?;
        if state.backend != self.linear {
            return Err(Error::invalid_state(
                "backend",
                format!("{:?}", state.backend),
                &format!("must be the running backend {:?}", self.linear),
            ));
        }
        self.check_dimensions(state)?;
        let states = state.check_fields(self.force_tolerance(&state.scene))?;
        self.check_levels(state)?;
        let (energy, values) = self.energy_and_values(
            &state.previous,
            &state.current,
            state.base,
            state.pressure[1],
            state.step_index == 0,
        );
        let force: f64 = state.forces.iter().sum();
        let reported = [energy.kinetic, energy.elastic, energy.total, force];
        if let Some(v) = values.iter().chain(&reported).find(|v| !v.is_finite()) {
            return Err(Error::invalid_state(
                "current",
                format!("<an energy or output of {v}>"),
                "must give finite energies and outputs",
            ));
        }
        Ok(CheckedState { state, states })
    }

    /// The lengths of the state's fields against the backend's dimension and the constrained
    /// vertices.
    fn check_dimensions(&self, state: &State) -> Result<(), Error> {
        let (n, m) = (self.maps.dimension(), self.free.contact.len());
        for (field, length, expected) in [
            ("previous", state.previous.len(), n),
            ("current", state.current.len(), n),
            ("forces", state.forces.len(), m),
            ("active_set", state.active_set.len(), m),
        ] {
            if length != expected {
                return Err(Error::invalid_state(
                    field,
                    format!("<{length} values>"),
                    &format!("must hold {expected} values"),
                ));
            }
        }
        Ok(())
    }

    /// Both base values strictly inside the gap and both levels within the obstacles of the
    /// state's scene to [`RESTORE_BOUND_TOLERANCE`] of the gap.
    fn check_levels(&self, state: &State) -> Result<(), Error> {
        let levels = StoredLevels {
            step_index: state.step_index,
            base: state.base,
            previous: &state.previous,
            current: &state.current,
        };
        let tolerance = RESTORE_BOUND_TOLERANCE * state.scene.gap_from(self.free.nearest_heights);
        match self.first_level_outside(&state.scene, &levels, tolerance) {
            None => Ok(()),
            Some(LevelOutside::Base { level, error }) => Err(Error::invalid_state(
                &format!("base[{level}]"),
                state.base[level],
                &format!("must be inside the gap ({error})"),
            )),
            Some(LevelOutside::Vertex { level, outside }) => Err(Error::invalid_state(
                &format!(
                    "{}[contact point {}]",
                    ["previous", "current"][level],
                    outside.index
                ),
                format!("<u = {:?} m>", outside.value),
                &format!(
                    "must put every contact point within the obstacles (there at {} m), to \
                     {tolerance:e} m",
                    outside.level
                ),
            )),
        }
    }

    /// Where two stored levels leave the obstacles of `scene`, if they do: a base value z_{n−1}
    /// or z_n not strictly inside the gap (the base first), or a constrained vertex of
    /// u = z + w past an obstacle by more than `tolerance` (m) ([`Scene::first_outside`]). The one
    /// test of stored levels against the obstacles, for
    /// [`Stepper::set_obstacles`](super::Stepper::set_obstacles) and [`Model::check`].
    pub(super) fn first_level_outside(
        &self,
        scene: &Scene,
        levels: &StoredLevels,
        tolerance: f64,
    ) -> Option<LevelOutside> {
        let dt = scene.solver.time_step;
        let times = [levels.step_index.saturating_sub(1), levels.step_index].map(|n| n as f64 * dt);
        for (level, (&z, time)) in levels.base.iter().zip(times).enumerate() {
            if let Err(error) = check_base(scene, self.free.clamp_heights, time, z) {
                return Some(LevelOutside::Base { level, error });
            }
        }
        let mut u = vec![0.0; self.free.contact.len()];
        let [lower, upper] = &self.free.heights;
        for (level, (field, z)) in [levels.previous, levels.current]
            .into_iter()
            .zip(levels.base)
            .enumerate()
        {
            self.maps.constrained_values(field, &mut u);
            for u in u.iter_mut() {
                *u += z;
            }
            if let Some(outside) = scene.first_outside(&u, [lower, upper], tolerance) {
                return Some(LevelOutside::Vertex { level, outside });
            }
        }
        None
    }

    /// The energy between two levels (`previous`, `current`) at base positions `base` under
    /// `pressure`, and the relative displacement w of `current` at the output points.
    pub(super) fn energy_and_values(
        &self,
        previous: &[f64],
        current: &[f64],
        base: [f64; 2],
        pressure: f64,
        at_rest: bool,
    ) -> (DiscreteEnergy, [f64; OUTPUT_POINTS]) {
        let dt = self.scene.solver.time_step;
        let pieces = self.maps.energy(previous, current, dt);
        let energy = DiscreteEnergy::new(self.free, pieces, base, pressure, dt, at_rest);
        (energy, self.maps.output_values(current))
    }

    /// [`RESTORE_FORCE_TOLERANCE`] in newtons for the obstacles of `scene`.
    fn force_tolerance(&self, scene: &Scene) -> f64 {
        let a = self.free.system.as_ref();
        let rows = &self.free.contact;
        let largest_diagonal = (0..rows.len())
            .flat_map(|i| rows.row(i).0.iter().copied())
            .map(|d| {
                a.row_idx_of_col(d)
                    .zip(a.val_of_col(d))
                    .find(|&(i, _)| i == d)
                    .map_or(0.0, |(_, &v)| v)
            })
            .fold(0.0, f64::max);
        let dt = scene.solver.time_step;
        RESTORE_FORCE_TOLERANCE * largest_diagonal * scene.gap() / (dt * dt)
    }
}

/// The base must stay strictly inside the gap over the clamp (docs/model.md §5): z strictly
/// between g1 + h₁ and g2 + h₂, with `clamp_heights` = [h₁, h₂] the profiles' heights nearest to
/// the plate at rest over the clamp (`None` where that obstacle lies over no clamped point; 0 for
/// flat obstacles, whose limits are then the levels bit for bit).
pub(super) fn check_base(
    scene: &Scene,
    [lower_height, upper_height]: [Option<f64>; 2],
    time: f64,
    base: f64,
) -> Result<(), Error> {
    let lower = scene.lower_obstacle().zip(lower_height).map(|(g, h)| g + h);
    let upper = scene.upper_obstacle().zip(upper_height).map(|(g, h)| g + h);
    let inside =
        base.is_finite() && lower.is_none_or(|g| base > g) && upper.is_none_or(|g| base < g);
    if inside {
        Ok(())
    } else {
        Err(Error::BaseOutsideGap {
            time,
            base,
            lower,
            upper,
        })
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

    /// A state of a plate with another profile (a fixed parameter) is refused, naming the profile
    /// and both texts; the stepper keeps its own state.
    #[test]
    fn a_state_of_another_profile_is_refused_by_name() {
        let mut scene = Scene::default();
        (scene.mesh.nx, scene.mesh.ny) = (3, 2);
        let mut stud = scene.clone();
        stud.obstacle.lower_profile = "point(x = 0.35, y = 0.1)".to_string();
        let mut stepper = Stepper::new(&scene, 0.0).unwrap();
        let mut other = Stepper::new(&stud, 0.0).unwrap();
        other.step(1e-4).unwrap();
        let err = stepper.restore(&other.state()).unwrap_err().to_string();
        assert!(
            err.contains("scene.obstacle.lower_profile")
                && err.contains("point(x = 0.35, y = 0.1)")
                && err.contains("\"flat\""),
            "{err}"
        );
        assert_eq!(stepper.step_index(), 0, "nothing was applied");
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
