//! The model behind the FMU: a [`Stepper`] whose base displacement is the built-in sine
//! c sin(2π f t) plus an external signal (the FMU input `base.displacement`).

use crate::error::Error;
use crate::scene::Scene;
use crate::scheme::Stepper;
pub use crate::scheme::{Outputs, State, StepPath, StepReport};

/// One simulation of a scene, driven step by step.
pub struct Simulation {
    stepper: Stepper,
}

impl Simulation {
    /// Sets the scene up (assembly, backend, static preload); `initial_external_base` is the
    /// external base displacement at t = 0 (m).
    pub fn new(scene: &Scene, initial_external_base: f64) -> Result<Simulation, Error> {
        let z0 = scene.builtin_base(0.0) + initial_external_base;
        Ok(Simulation {
            stepper: Stepper::new(scene, z0)?,
        })
    }

    /// The scene, tunable parameters at their current values.
    pub fn scene(&self) -> &Scene {
        self.stepper.scene()
    }

    /// t_n (s).
    pub fn time(&self) -> f64 {
        self.stepper.time()
    }

    /// n.
    pub fn step_index(&self) -> u64 {
        self.stepper.step_index()
    }

    /// One step to t_{n+1} with base displacement builtin(t_{n+1}) + `external_base` (m).
    pub fn step(&mut self, external_base: f64) -> Result<StepReport, Error> {
        let t_next = (self.stepper.step_index() + 1) as f64 * self.stepper.scene().solver.time_step;
        let z = self.stepper.scene().builtin_base(t_next) + external_base;
        self.stepper.step(z)
    }

    /// Outputs after the last step (evaluated on demand).
    pub fn outputs(&self) -> Outputs {
        self.stepper.outputs()
    }

    /// Tunable obstacle levels.
    pub fn set_obstacles(&mut self, lower: f64, upper: f64) -> Result<(), Error> {
        self.stepper.set_obstacles(lower, upper)
    }

    /// Tunable pressure.
    pub fn set_pressure(&mut self, pressure: f64) -> Result<(), Error> {
        self.stepper.set_pressure(pressure)
    }

    /// The dynamic state.
    pub fn state(&self) -> State {
        self.stepper.state()
    }

    /// Restores a state of a simulation with the same fixed parameters.
    pub fn restore(&mut self, state: &State) -> Result<(), Error> {
        self.stepper.restore(state)
    }
}
