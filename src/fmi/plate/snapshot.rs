//! The plate model's FMU state and its validation as untrusted input.

use super::{beyond_stop_time, check_experiment, values};
use crate::fmi::model::Phase;
use crate::fmi::status::Failure;
use crate::scene::Scene;
use crate::simulation::SimulationState;
use serde::{Deserialize, Serialize};

/// Everything a [`PlateModel`](super::PlateModel) needs to continue: the parameters as set, the
/// experiment, the input and its derivatives, and, once the simulation runs, its state.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlateSnapshot {
    /// The parameters (tunable ones at their current values).
    pub parameters: Scene,
    /// The experiment's start time (s).
    pub start_time: f64,
    /// The experiment's stop time, if set (s).
    pub stop_time: Option<f64>,
    /// The input `base.displacement` (m).
    pub input: f64,
    /// Input derivatives of orders 1 and 2 sent for the next step.
    pub input_derivatives: [Option<f64>; 2],
    /// The simulation's state, in the phases where it runs.
    pub simulation: Option<SimulationState>,
}

fn refused(message: String) -> Failure {
    Failure::refused(format!("the FMU state is refused: {message}"))
}

impl PlateSnapshot {
    /// Checks every field a host could have crafted, for a snapshot taken in `phase`: each
    /// parameter as fmi2SetXxx would (by name, with its limit), no scene field that is not an FMU
    /// variable, the parameters together where a simulation runs on them, finite times with a
    /// grid that resolves the internal steps, finite input and derivatives, a simulation exactly
    /// in the phases that have one, for the same parameters and start time, consistent
    /// ([`SimulationState::check`]) and within the stop time (the grid may run one step beyond
    /// it). The simulation's fields themselves (dimensions, finiteness, contact
    /// codes, vertices inside the obstacles) are checked when it is restored.
    pub fn validate(&self, phase: Phase) -> Result<(), Failure> {
        values::check_parameters(&self.parameters).map_err(|f| refused(f.message))?;
        // Together only where a simulation runs on them: an error before initialization ends FMI
        // 3.0 in Terminated with parameters not yet checked together (initialization does).
        if self.simulation.is_some() {
            self.parameters
                .validate()
                .map_err(|e| refused(e.to_string()))?;
        }
        check_experiment(&self.parameters, self.start_time, self.stop_time)
            .map_err(|f| refused(f.message))?;
        if !self.input.is_finite() {
            return Err(refused(format!(
                "base.displacement = {} is not finite",
                self.input
            )));
        }
        for (order, d) in self.input_derivatives.iter().enumerate() {
            if let Some(x) = d.filter(|x| !x.is_finite()) {
                return Err(refused(format!(
                    "the input derivative of order {} = {x} is not finite",
                    order + 1
                )));
            }
        }
        let state = match (&self.simulation, phase) {
            (None, Phase::Instantiated | Phase::Initialization | Phase::Failed) => return Ok(()),
            (Some(state), Phase::Stepping | Phase::Terminated | Phase::Failed) => state,
            (None, _) => {
                return Err(refused(format!(
                    "it was taken in the {phase:?} phase but holds no simulation"
                )))
            }
            (Some(_), _) => {
                return Err(refused(format!(
                    "it was taken in the {phase:?} phase but holds a running simulation"
                )))
            }
        };
        if state.stepper.scene != self.parameters {
            return Err(refused(
                "the simulation's scene differs from the parameters".into(),
            ));
        }
        if state.start_time.to_bits() != self.start_time.to_bits() {
            return Err(refused(format!(
                "the simulation starts at {} s, the experiment at {} s",
                state.start_time, self.start_time
            )));
        }
        // The number of constrained vertices is the plate's: checked again when the state is
        // restored.
        let grid = state
            .check(usize::MAX)
            .map_err(|e| refused(format!("its simulation {e}")))?;
        let n = state.stepper.step_index;
        let elapsed = state.point.elapsed(&grid, n);
        let now = grid.start + elapsed;
        if let Some(stop) = self.stop_time {
            if beyond_stop_time(now, grid.start, stop, grid.step) {
                return Err(refused(format!(
                    "its simulation is at t = {now} s (grid step {n}), beyond stopTime = {stop} s"
                )));
            }
        }
        Ok(())
    }
}
