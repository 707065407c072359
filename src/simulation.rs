//! **TEMPORARY STAND-IN — replaced by the real time stepper at merge.**
//!
//! This file exists only on the `fmi` branch so that the FMU layer (`src/fmi/`) and its tests can
//! run while the numerical library is written in parallel. It has exactly the public API the real
//! `Simulation` will have, but its physics is a single-mode, undamped oscillator driven by the
//! base: the relative tip deflection r = u − z of the first cantilever mode,
//! ω = 1.875² √(D / (ρ e Lx⁴)), advanced with the same β = ½ scheme as SPEC §3,
//!
//!   (r_{n+1} − 2r_n + r_{n−1}) / Δt² + ω² (r_{n+1} + r_{n−1}) / 2 = p/(ρe) − (z_{n+1} − 2z_n + z_{n−1}) / Δt²,
//!
//! with the absolute displacement u = z + r projected onto the obstacles (Paoli–Schatzman form with
//! restitution e). All three output points report u. None of these numbers are the plate's.

use crate::error::Error;
use crate::scene::Scene;
use serde::{Deserialize, Serialize};

/// Outputs after the last step (SPEC §5 variables).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Outputs {
    /// u at (Lx, 0) (m).
    pub corner1: f64,
    /// u at (Lx, Ly) (m).
    pub corner2: f64,
    /// u at (Lx, Ly/2) (m).
    pub edge_mid: f64,
    /// Kinetic energy (J).
    pub energy_kinetic: f64,
    /// Elastic energy (J).
    pub energy_elastic: f64,
    /// Total discrete energy (J).
    pub energy_total: f64,
    /// Vertices in contact after the last step.
    pub active_nodes: usize,
    /// Sum of contact forces (N).
    pub contact_force: f64,
}

/// The dynamic state (stand-in: scene, step index and the modal recurrence).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct State {
    scene: Scene,
    n: u64,
    r: f64,
    r_prev: f64,
    z: f64,
    z_prev: f64,
    u_prev: f64,
    outputs: Outputs,
}

/// Which path a step took (stand-in).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StepPath {
    /// The unconstrained step was feasible.
    Free,
    /// The step was projected onto an obstacle.
    Projected,
}

/// What one step did.
#[derive(Clone, Debug)]
pub struct StepReport {
    /// Constrained vertices in contact.
    pub active: usize,
    /// The solver path taken.
    pub path: StepPath,
}

/// One running simulation (stand-in; see the module docs).
pub struct Simulation {
    omega: f64,
    mass: f64,
    state: State,
}

/// The scene with its tunable parameters (obstacle levels, pressure) neutralised, to compare the
/// fixed parameters of two scenes.
fn fixed_part(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    s.obstacle.lower = 0.0;
    s.obstacle.upper = 0.0;
    s.load.pressure = 0.0;
    s
}

impl Simulation {
    /// Expensive set-up (assembly, eigenbasis, static preload). z0 = external base displacement at
    /// t = 0 (m).
    pub fn new(scene: &Scene, initial_external_base: f64) -> Result<Simulation, Error> {
        scene.validate()?;
        if !initial_external_base.is_finite() {
            return Err(Error::invalid(
                "base.displacement",
                initial_external_base,
                "must be finite",
            ));
        }
        let z0 = scene.builtin_base(0.0) + initial_external_base;
        check_gap(scene, 0.0, z0)?;
        let l = scene.plate.length;
        let omega = 1.875f64.powi(2)
            * (scene.bending_stiffness() / (scene.areal_mass() * l.powi(4))).sqrt();
        let mass = scene.areal_mass() * scene.plate.length * scene.plate.width / 4.0;
        let mut u0 = z0 + scene.initial.preload_pressure / scene.areal_mass() / (omega * omega);
        if let Some(g) = scene.lower_obstacle() {
            u0 = u0.max(g);
        }
        if let Some(g) = scene.upper_obstacle() {
            u0 = u0.min(g);
        }
        let r0 = u0 - z0;
        let mut sim = Simulation {
            omega,
            mass,
            state: State {
                scene: scene.clone(),
                n: 0,
                r: r0,
                r_prev: r0,
                z: z0,
                z_prev: z0,
                u_prev: u0,
                outputs: Outputs::default(),
            },
        };
        sim.state.outputs = sim.make_outputs(u0, u0, r0, r0, 0, 0.0);
        Ok(sim)
    }

    /// The scene this simulation runs (with the current tunable values).
    pub fn scene(&self) -> &Scene {
        &self.state.scene
    }

    /// t_n = n Δt.
    pub fn time(&self) -> f64 {
        self.state.n as f64 * self.state.scene.solver.time_step
    }

    /// n.
    pub fn step_index(&self) -> u64 {
        self.state.n
    }

    /// One internal step to t_{n+1} = (n+1)Δt; the base displacement there is
    /// scene.builtin_base(t_{n+1}) + external_base.
    pub fn step(&mut self, external_base: f64) -> Result<StepReport, Error> {
        let s = &self.state;
        let dt = s.scene.solver.time_step;
        let t1 = (s.n + 1) as f64 * dt;
        let z1 = s.scene.builtin_base(t1) + external_base;
        if !z1.is_finite() {
            return Err(Error::Numerical(format!(
                "non-finite base displacement {z1} at t = {t1} s"
            )));
        }
        check_gap(&s.scene, t1, z1)?;
        let c = 1.0 + 0.5 * dt * dt * self.omega * self.omega;
        let a = s.scene.load.pressure / s.scene.areal_mass();
        let r_free = if s.n == 0 {
            // Start at rest: r_{-1} := r_1 and z_{-1} := z_1.
            (2.0 * s.r + dt * dt * a - 2.0 * (z1 - s.z)) / (2.0 * c)
        } else {
            (2.0 * s.r - c * s.r_prev + dt * dt * a - (z1 - 2.0 * s.z + s.z_prev)) / c
        };
        let u_free = z1 + r_free;
        let e = s.scene.solver.restitution;
        let mut u = u_free;
        let mut active = 0;
        if let Some(g) = s.scene.lower_obstacle() {
            let bound = (1.0 + e) * g - e * s.u_prev;
            if u < bound {
                u = bound;
                active = 1;
            }
        }
        if let Some(g) = s.scene.upper_obstacle() {
            let bound = (1.0 + e) * g - e * s.u_prev;
            if u > bound {
                u = bound;
                active = 1;
            }
        }
        let r1 = u - z1;
        let force = self.mass * c * (r1 - r_free) / (dt * dt);
        let u_n = s.z + s.r;
        let outputs = self.make_outputs(u, u_n, r1, s.r, active, force);
        let s = &mut self.state;
        s.u_prev = u_n;
        s.r_prev = s.r;
        s.r = r1;
        s.z_prev = s.z;
        s.z = z1;
        s.n += 1;
        s.outputs = outputs;
        Ok(StepReport {
            active,
            path: if active > 0 {
                StepPath::Projected
            } else {
                StepPath::Free
            },
        })
    }

    fn make_outputs(
        &self,
        u1: f64,
        u0: f64,
        r1: f64,
        r0: f64,
        active: usize,
        force: f64,
    ) -> Outputs {
        let dt = self.state.scene.solver.time_step;
        let v = (u1 - u0) / dt;
        let k = self.mass * self.omega * self.omega;
        let kinetic = 0.5 * self.mass * v * v;
        let elastic = 0.25 * k * (r1 * r1 + r0 * r0);
        Outputs {
            corner1: u1,
            corner2: u1,
            edge_mid: u1,
            energy_kinetic: kinetic,
            energy_elastic: elastic,
            energy_total: kinetic + elastic,
            active_nodes: active,
            contact_force: force,
        }
    }

    /// Outputs after the last step (or of the initial state).
    pub fn outputs(&self) -> &Outputs {
        &self.state.outputs
    }

    /// Sets the tunable obstacle levels (used only where the obstacle is enabled).
    pub fn set_obstacles(&mut self, lower: f64, upper: f64) -> Result<(), Error> {
        let mut s = self.state.scene.clone();
        s.obstacle.lower = lower;
        s.obstacle.upper = upper;
        s.validate()?;
        self.state.scene = s;
        Ok(())
    }

    /// Sets the tunable pressure.
    pub fn set_pressure(&mut self, pressure: f64) -> Result<(), Error> {
        let mut s = self.state.scene.clone();
        s.load.pressure = pressure;
        s.validate()?;
        self.state.scene = s;
        Ok(())
    }

    /// A copy of the dynamic state.
    pub fn state(&self) -> State {
        self.state.clone()
    }

    /// Restores a state; fails if the state's fixed parameters differ from this simulation's.
    pub fn restore(&mut self, state: &State) -> Result<(), Error> {
        if fixed_part(&state.scene) != fixed_part(&self.state.scene) {
            return Err(Error::invalid(
                "state",
                "<FMU state>",
                "was taken with different fixed parameters",
            ));
        }
        self.state = state.clone();
        Ok(())
    }
}

fn check_gap(scene: &Scene, time: f64, base: f64) -> Result<(), Error> {
    let lower = scene.lower_obstacle();
    let upper = scene.upper_obstacle();
    if lower.is_some_and(|g| base <= g) || upper.is_some_and(|g| base >= g) {
        return Err(Error::BaseOutsideGap {
            time,
            base,
            lower,
            upper,
        });
    }
    Ok(())
}
