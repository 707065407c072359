//! The β = ½ Newmark–Dumont–Paoli scheme with obstacles, base motion, load and preload (SPEC §3).
//!
//! Unknowns are split as u = z(t)·𝟙 + w, with 𝟙 the rigid translation (value dofs 1) and w the
//! displacement relative to the base, whose clamp dofs are all zero. Because K𝟙 = 0, the scheme for
//! the free dofs of w reads, with A = M_ff + ½Δt²K_ff and m₁ = (M𝟙)_f,
//!
//!   A w_{n+1} = 2 M w_n − A w_{n−1} + ½Δt²(p_{n+1} + p_{n−1}) f − m₁ (z_{n+1} − 2z_n + z_{n−1}) + Bᵀμ,
//!
//! which is the scheme of SPEC §3 for u exactly (up to the round-off of K𝟙), and the start step
//! A w_1 = M w_0 + ¼Δt²(p_1 + p_0) f − m₁ (z_1 − z_0) + Bᵀμ (v_0 = 0, F̄_0 read as (F_1 + F_0)/2). The obstacle bounds
//! on u become g − z_{n+1} on w; with restitution e they are imposed on (u_{n+1} + e u_{n−1})/(1 + e),
//! i.e. on u_{n+1} ∈ [(1+e)g1 − e u_{n−1}, (1+e)g2 − e u_{n−1}] (Paoli–Schatzman), still a box.
//! μ is the QP multiplier: the contact force at a vertex is μ/Δt² (N).
//!
//! The linear part runs in one of two [`Propagator`]s: [`modal`] (dense eigenbasis, O(n) per
//! contact-free step) or [`sparse`] (sparse Cholesky), chosen by [`crate::scene::LinearChoice`].

pub mod modal;
pub mod sparse;

use crate::contact::{self, ActiveSetSolver, BoundState, BoxQp, Delassus, PdasSettings};
use crate::error::Error;
use crate::modes::dense_restriction;
use crate::scene::{LinearChoice, QpChoice, Scene};
use crate::system::PlateSystem;
use faer::sparse::SparseColMat;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// Largest number of free dofs for which `auto` picks the dense modal backend: its set-up is a dense
/// O(n³) eigen-decomposition (measured on this 2-core machine: 1 s at 1369 free dofs, 12 s at
/// 2675) and O(n²) memory; at 2000 dofs it stays near 5 s, which a host initialising an FMU still
/// tolerates, and beyond it the sparse backend's cheaper set-up wins for runs of ordinary length.
pub const MODAL_AUTO_LIMIT: usize = 2000;

/// y ← y + alpha·A x for a sparse A.
pub(crate) fn multiply(a: &SparseColMat<usize, f64>, x: &[f64], alpha: f64, out: &mut [f64]) {
    let a = a.as_ref();
    for (j, &xj) in x.iter().enumerate().take(a.ncols()) {
        let xj = alpha * xj;
        for (i, &v) in a.row_idx_of_col(j).zip(a.val_of_col(j)) {
            out[i] += v * xj;
        }
    }
}

/// xᵀ A x for a sparse A.
pub(crate) fn quadratic(a: &SparseColMat<usize, f64>, x: &[f64]) -> f64 {
    let mut ax = vec![0.0; x.len()];
    multiply(a, x, 1.0, &mut ax);
    dot(&ax, x)
}

pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The free-dof restriction of the plate for one time step Δt.
#[derive(Debug)]
pub struct FreeSystem {
    /// M_ff.
    pub mass: SparseColMat<usize, f64>,
    /// K_ff.
    pub stiffness: SparseColMat<usize, f64>,
    /// A = M_ff + ½Δt²K_ff.
    pub system: SparseColMat<usize, f64>,
    /// f_f for a 1 Pa pressure.
    pub load: Vec<f64>,
    /// m₁ = (M𝟙)_f.
    pub base: Vec<f64>,
    /// Free-dof indices of the obstacle-constrained vertex values (empty without obstacles).
    pub constrained: Vec<usize>,
    /// Output functionals restricted to the free dofs.
    pub outputs: [Vec<f64>; 3],
    /// 𝟙ᵀM𝟙: the plate's mass (kg).
    pub total_mass: f64,
    /// ∫ 1: the plate's area (m²).
    pub area: f64,
}

/// Forcing of one step, as multipliers of the precomputed vectors f (load) and m₁ (base).
#[derive(Clone, Copy, Debug)]
pub struct StepForcing {
    /// Multiplier of f: ½Δt²(p_{n+1} + p_{n−1}) (start: ½Δt²·(p_1 + p_0)/2).
    pub load: f64,
    /// Multiplier of m₁: −(z_{n+1} − 2z_n + z_{n−1}) (start: −(z_1 − z_0)).
    pub base: f64,
    /// Whether this is the start step n = 0 → 1.
    pub start: bool,
}

/// Which stored field a propagator returns.
#[derive(Clone, Copy, Debug)]
pub enum Level {
    /// w_{n−1}
    Previous,
    /// w_n
    Current,
    /// the prediction w_{n+1}
    Next,
}

/// The quadratic and linear forms of the last two fields that the discrete energy needs.
#[derive(Clone, Copy, Debug, Default)]
pub struct EnergyPieces {
    /// ẇᵀMẇ with ẇ = (w_n − w_{n−1})/Δt.
    pub velocity_mass_velocity: f64,
    /// m₁ᵀẇ.
    pub translation_mass_velocity: f64,
    /// w_nᵀ K w_n.
    pub stiffness_current: f64,
    /// w_{n−1}ᵀ K w_{n−1}.
    pub stiffness_previous: f64,
    /// fᵀ w_n.
    pub load_current: f64,
    /// fᵀ w_{n−1}.
    pub load_previous: f64,
}

/// The linear part of a step: a backend that owns w_{n−1}, w_n and the prediction w_{n+1}.
pub trait Propagator: Send {
    /// Computes the unconstrained prediction w_{n+1}.
    fn predict(&mut self, forcing: &StepForcing);
    /// Whether the prediction provably satisfies lower ≤ w_{n+1} ≤ upper at every constrained
    /// vertex, without computing those values exactly (a cheap screening test). `false` means
    /// "not proven", not "violated": the caller then evaluates the values.
    fn prediction_proven_within(&mut self, lower: f64, upper: f64) -> bool;
    /// Column j of the Delassus operator W = B A⁻¹ Bᵀ.
    fn delassus_column(&mut self, j: usize) -> &[f64];
    /// Replaces the prediction by A⁻¹(b + Bᵀμ), μ nonzero only at `active`.
    fn correct(&mut self, active: &[usize], multipliers: &[f64]);
    /// Constrained values of a stored field.
    fn constrained_values(&self, which: Level, out: &mut [f64]);
    /// A stored field over the free dofs.
    fn free_field(&self, which: Level) -> Vec<f64>;
    /// Replaces the prediction by a free-dof field (from the clarabel path).
    fn set_next(&mut self, w: &[f64]);
    /// Shifts n−1 ← n ← n+1.
    fn accept(&mut self);
    /// Energy pieces of the two current fields.
    fn energy(&self, time_step: f64) -> EnergyPieces;
    /// w_n at the three output points.
    fn output_values(&self) -> [f64; 3];
    /// The backend's own coordinates of (w_{n−1}, w_n), for bit-exact state restore.
    fn state(&self) -> (Vec<f64>, Vec<f64>);
    /// Restores what [`Propagator::state`] returned.
    fn set_state(&mut self, previous: Vec<f64>, current: Vec<f64>);
    /// Length of the state vectors.
    fn dimension(&self) -> usize;
}

/// What the FMU and the examples report after each step (SPEC §5).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Outputs {
    /// u(Lx, 0) (m).
    pub corner1: f64,
    /// u(Lx, Ly) (m).
    pub corner2: f64,
    /// u(Lx, Ly/2) (m).
    pub edge_mid: f64,
    /// ½ v_{n+½}ᵀ M v_{n+½} (J).
    pub energy_kinetic: f64,
    /// ¼ (u_{n+1}ᵀKu_{n+1} + u_nᵀKu_n) (J).
    pub energy_elastic: f64,
    /// Kinetic + elastic − ½ Fᵀ(u_{n+1} + u_n) (J).
    pub energy_total: f64,
    /// Vertices in contact after the last step.
    pub active_nodes: usize,
    /// Sum of the contact forces (N), positive upwards.
    pub contact_force: f64,
}

/// Which method produced a step's u_{n+1}.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum StepPath {
    /// The unconstrained step satisfied every bound: it is the QP's exact solution.
    Unconstrained,
    /// The primal–dual active-set method on the Delassus operator.
    ActiveSet,
    /// clarabel, because `solver.qp = clarabel`.
    Clarabel,
    /// clarabel, after the active-set method did not converge.
    ClarabelFallback,
}

/// What one step did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepReport {
    /// Vertices in contact after the step.
    pub active: usize,
    /// The solver path.
    pub path: StepPath,
    /// Whether the constrained values had to be evaluated in full: false when the backend's cheap
    /// test proved the step contact-free (the modal low-mode screening; for the sparse backend that
    /// test is itself exact), or when there is no constraint.
    pub bounds_evaluated: bool,
}

/// The serializable dynamic state of a [`Stepper`]: the scene (fixed parameters, and tunable ones
/// at their current values), the linear backend whose coordinates it holds, and the fields.
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

/// The time stepper of one scene.
pub struct Stepper {
    scene: Scene,
    free: Arc<FreeSystem>,
    propagator: Box<dyn Propagator>,
    linear: LinearChoice,
    step_index: u64,
    base: [f64; 2],
    pressure: [f64; 2],
    /// Constrained values of w_{n−1}, kept only when restitution e > 0 needs them for the bounds.
    restitution_previous: Vec<f64>,
    /// Constrained values of w_n, likewise.
    restitution_current: Vec<f64>,
    /// The contact state of each constrained vertex: the active-set warm start.
    states: Vec<BoundState>,
    active_set: ActiveSetSolver,
    /// Contact force at each constrained vertex after the last step (N).
    forces: Vec<f64>,
    // Workspaces for the hot path.
    prediction: Vec<f64>,
    lower: Vec<f64>,
    upper: Vec<f64>,
}

impl Stepper {
    /// Assembles the plate, chooses and builds the linear backend, computes the initial state
    /// (static equilibrium under the preload, with contact if it pushes into an obstacle, about
    /// the base position `initial_base` (m)), released at rest.
    pub fn new(scene: &Scene, initial_base: f64) -> Result<Stepper, Error> {
        let plate = PlateSystem::new(scene)?;
        Stepper::from_system(scene, &plate, initial_base)
    }

    /// As [`Stepper::new`], reusing an assembled plate of the same scene.
    pub fn from_system(
        scene: &Scene,
        plate: &PlateSystem,
        initial_base: f64,
    ) -> Result<Stepper, Error> {
        scene.validate()?;
        check_base(scene, 0.0, initial_base)?;
        let dt = scene.solver.time_step;
        let free = Arc::new(free_system(scene, plate));
        let n = plate.free.len();
        let linear = match scene.solver.linear {
            LinearChoice::Auto if n <= MODAL_AUTO_LIMIT => LinearChoice::Modal,
            LinearChoice::Auto => LinearChoice::Sparse,
            choice => choice,
        };
        let w0 = static_preload(scene, &free, initial_base)?;
        let propagator: Box<dyn Propagator> = match linear {
            LinearChoice::Modal => {
                let modes = plate.modes()?;
                let data = modal::ModalData::new(
                    modes,
                    dt,
                    &free.constrained,
                    &free.load,
                    &free.base,
                    free.outputs.clone(),
                    dense_restriction(&plate.mass, &plate.free),
                );
                Box::new(modal::ModalPropagator::new(Arc::new(data), &w0))
            }
            _ => Box::new(sparse::SparsePropagator::new(
                Arc::new(sparse::SparseData::new(free.clone())?),
                &w0,
            )),
        };
        let m = free.constrained.len();
        // The constrained values of w_0 as the backend evaluates them, so that a state restored
        // at n = 0 or 1 continues bit-identically (restore evaluates them the same way).
        let mut constrained_w0 = vec![0.0; m];
        propagator.constrained_values(Level::Current, &mut constrained_w0);
        Ok(Stepper {
            scene: scene.clone(),
            propagator,
            linear,
            step_index: 0,
            base: [initial_base; 2],
            pressure: [scene.load.pressure; 2],
            restitution_previous: constrained_w0.clone(),
            restitution_current: constrained_w0,
            states: vec![BoundState::Free; m],
            active_set: ActiveSetSolver::new(),
            forces: vec![0.0; m],
            prediction: vec![0.0; m],
            lower: vec![0.0; m],
            upper: vec![0.0; m],
            free,
        })
    }

    /// The scene, with tunable parameters at their current values.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The linear backend that runs (`Modal` or `Sparse`, never `Auto`).
    pub fn linear_backend(&self) -> LinearChoice {
        self.linear
    }

    /// n.
    pub fn step_index(&self) -> u64 {
        self.step_index
    }

    /// t_n = n Δt (s).
    pub fn time(&self) -> f64 {
        self.step_index as f64 * self.scene.solver.time_step
    }

    /// Outputs after the last step, evaluated on demand (O(n): a host that reads them at its
    /// communication points only does not pay for them at every internal step).
    pub fn outputs(&self) -> Outputs {
        self.compute_outputs()
    }

    /// Number of free dofs.
    pub fn free_dof_count(&self) -> usize {
        self.propagator.dimension()
    }

    /// Number of obstacle-constrained vertices (0 without obstacles).
    pub fn constrained_count(&self) -> usize {
        self.free.constrained.len()
    }

    /// Displacements u_n at the obstacle-constrained vertices (m).
    pub fn constrained_displacements(&self) -> Vec<f64> {
        let mut w = vec![0.0; self.free.constrained.len()];
        self.propagator.constrained_values(Level::Current, &mut w);
        w.iter().map(|w| self.base[1] + w).collect()
    }

    /// Contact forces f_i = μ_i/Δt² at the constrained vertices after the last step (N): ≥ 0 on the
    /// lower obstacle, ≤ 0 on the upper one, 0 where the vertex is free.
    pub fn contact_forces(&self) -> &[f64] {
        &self.forces
    }

    /// Changes the obstacle levels (tunable). The base and every constrained vertex must lie
    /// within the new levels (to 1e-12 of the gap): moving an obstacle into the plate would make
    /// the next step push it out within one Δt, an arbitrary impulse, so that is refused.
    pub fn set_obstacles(&mut self, lower: f64, upper: f64) -> Result<(), Error> {
        let mut scene = self.scene.clone();
        scene.obstacle.lower = lower;
        scene.obstacle.upper = upper;
        scene.validate()?;
        check_base(&scene, self.time(), self.base[1])?;
        let tolerance = 1e-12 * (upper - lower).abs().min(1.0);
        let u = self.constrained_displacements();
        if let Some(g) = scene.lower_obstacle() {
            if let Some(v) = u.iter().find(|&&v| v < g - tolerance) {
                return Err(Error::invalid(
                    "obstacle.lower",
                    lower,
                    &format!("must not be above the plate: a vertex is at u = {v} m"),
                ));
            }
        }
        if let Some(g) = scene.upper_obstacle() {
            if let Some(v) = u.iter().find(|&&v| v > g + tolerance) {
                return Err(Error::invalid(
                    "obstacle.upper",
                    upper,
                    &format!("must not be below the plate: a vertex is at u = {v} m"),
                ));
            }
        }
        self.scene = scene;
        Ok(())
    }

    /// Changes the pressure during the motion (tunable), applied from the next step on.
    pub fn set_pressure(&mut self, pressure: f64) -> Result<(), Error> {
        if !pressure.is_finite() {
            return Err(Error::invalid("load.pressure", pressure, "must be finite"));
        }
        self.scene.load.pressure = pressure;
        Ok(())
    }

    /// Advances one step to t_{n+1}; the base displacement there is `base_next` (m), absolute.
    pub fn step(&mut self, base_next: f64) -> Result<StepReport, Error> {
        let dt = self.scene.solver.time_step;
        let t_next = (self.step_index + 1) as f64 * dt;
        check_base(&self.scene, t_next, base_next)?;
        let start = self.step_index == 0;
        let [z_prev, z_curr] = self.base;
        let p_next = self.scene.load.pressure;
        let forcing = if start {
            StepForcing {
                load: 0.25 * dt * dt * (p_next + self.pressure[1]),
                base: -(base_next - z_curr),
                start,
            }
        } else {
            StepForcing {
                load: 0.5 * dt * dt * (p_next + self.pressure[0]),
                base: -(base_next - 2.0 * z_curr + z_prev),
                start,
            }
        };
        self.propagator.predict(&forcing);
        let m = self.prediction.len();
        let e = self.scene.solver.restitution;
        let auto = self.scene.solver.qp == QpChoice::Auto;
        let lower = self
            .scene
            .lower_obstacle()
            .map_or(f64::NEG_INFINITY, |g| g - base_next);
        let upper = self
            .scene
            .upper_obstacle()
            .map_or(f64::INFINITY, |g| g - base_next);
        let proven =
            m == 0 || (auto && e == 0.0 && self.propagator.prediction_proven_within(lower, upper));
        let (path, multipliers) = if proven {
            (StepPath::Unconstrained, None)
        } else {
            self.propagator
                .constrained_values(Level::Next, &mut self.prediction);
            self.fill_bounds(base_next, if start { z_curr } else { z_prev });
            let feasible = (0..m).all(|i| {
                self.prediction[i] >= self.lower[i] && self.prediction[i] <= self.upper[i]
            });
            if feasible && auto {
                (StepPath::Unconstrained, None)
            } else if !auto {
                (
                    StepPath::Clarabel,
                    Some(self.solve_with_clarabel(&forcing)?),
                )
            } else {
                match self.solve_with_active_set() {
                    Some(mu) => (StepPath::ActiveSet, Some(mu)),
                    None => (
                        StepPath::ClarabelFallback,
                        Some(self.solve_with_clarabel(&forcing)?),
                    ),
                }
            }
        };
        let active = match &multipliers {
            Some(mu) => {
                for (f, &x) in self.forces.iter_mut().zip(mu) {
                    *f = x / (dt * dt);
                }
                self.states.iter().filter(|s| s.is_active()).count()
            }
            None => {
                self.states.fill(BoundState::Free);
                self.forces.fill(0.0);
                0
            }
        };
        if e != 0.0 {
            std::mem::swap(
                &mut self.restitution_previous,
                &mut self.restitution_current,
            );
            self.propagator
                .constrained_values(Level::Next, &mut self.restitution_current);
        }
        self.propagator.accept();
        self.base = [z_curr, base_next];
        self.pressure = [self.pressure[1], p_next];
        self.step_index += 1;
        Ok(StepReport {
            active,
            path,
            bounds_evaluated: !proven,
        })
    }

    /// Bounds on w_{n+1} at the constrained vertices: [(1+e)g1 − e u_{n−1} − z_{n+1}, …] with
    /// u_{n−1} = z_{n−1} + w_{n−1} (e = 0: exactly g − z_{n+1}). At the start step
    /// u_{−1} := u_1 − 2Δt v_0 = u_1 (SPEC §3, v_0 = 0), so the constraint is on u_1 itself: e = 0.
    fn fill_bounds(&mut self, base_next: f64, base_previous: f64) {
        let e = if self.step_index == 0 {
            0.0
        } else {
            self.scene.solver.restitution
        };
        let lower = self.scene.lower_obstacle();
        let upper = self.scene.upper_obstacle();
        for i in 0..self.prediction.len() {
            let u_prev = base_previous + self.restitution_previous[i];
            let shift = |g: f64| {
                if e == 0.0 {
                    g - base_next
                } else {
                    (1.0 + e) * g - e * u_prev - base_next
                }
            };
            self.lower[i] = lower.map_or(f64::NEG_INFINITY, shift);
            self.upper[i] = upper.map_or(f64::INFINITY, shift);
        }
    }

    /// The exact active-set method on the Delassus operator, warm-started from the last step's
    /// contact states; `None` when it does not converge (the caller falls back to clarabel).
    fn solve_with_active_set(&mut self) -> Option<Vec<f64>> {
        let mut delassus = PropagatorDelassus {
            propagator: &mut *self.propagator,
            dim: self.prediction.len(),
        };
        let report = self.active_set.solve(
            &mut delassus,
            &self.prediction,
            &self.lower,
            &self.upper,
            &mut self.states,
            &PdasSettings::default(),
        );
        if !report.status.is_solved() {
            self.states.fill(BoundState::Free);
            return None;
        }
        let mu = self.active_set.lambda().to_vec();
        let active: Vec<usize> = (0..mu.len())
            .filter(|&i| self.states[i].is_active())
            .collect();
        self.propagator.correct(&active, &mu);
        Some(mu)
    }

    /// clarabel on the full primal QP min ½wᵀAw − bᵀw over the box; returns the multipliers.
    fn solve_with_clarabel(&mut self, forcing: &StepForcing) -> Result<Vec<f64>, Error> {
        let free = &*self.free;
        let mut b: Vec<f64> = (0..free.load.len())
            .map(|i| forcing.load * free.load[i] + forcing.base * free.base[i])
            .collect();
        let current = self.propagator.free_field(Level::Current);
        if forcing.start {
            multiply(&free.mass, &current, 1.0, &mut b);
        } else {
            multiply(&free.mass, &current, 2.0, &mut b);
            multiply(
                &free.system,
                &self.propagator.free_field(Level::Previous),
                -1.0,
                &mut b,
            );
        }
        let solution = contact::clarabel::solve_box_qp(&BoxQp {
            a: free.system.as_ref(),
            b: &b,
            constrained: &free.constrained,
            lower: &self.lower,
            upper: &self.upper,
        })?;
        self.propagator.set_next(&solution.x);
        self.states = solution.states;
        Ok(solution.lambda)
    }

    fn compute_outputs(&self) -> Outputs {
        let active_nodes = self.states.iter().filter(|s| s.is_active()).count();
        let contact_force = self.forces.iter().sum();
        let dt = self.scene.solver.time_step;
        let [z0, z1] = self.base;
        let pieces = if self.step_index == 0 {
            // Before the first step the plate is at rest: E_0 = ½ u₀ᵀKu₀ − Fᵀu₀.
            let mut p = self.propagator.energy(dt);
            p.velocity_mass_velocity = 0.0;
            p.translation_mass_velocity = 0.0;
            p
        } else {
            self.propagator.energy(dt)
        };
        let base_velocity = if self.step_index == 0 {
            0.0
        } else {
            (z1 - z0) / dt
        };
        let free = &*self.free;
        let kinetic = 0.5
            * (base_velocity * base_velocity * free.total_mass
                + 2.0 * base_velocity * pieces.translation_mass_velocity
                + pieces.velocity_mass_velocity);
        let elastic = 0.25 * (pieces.stiffness_current + pieces.stiffness_previous);
        // The pressure that acted on the last step, not one set since for the next.
        let p = self.pressure[1];
        let work = 0.5 * p * (free.area * (z0 + z1) + pieces.load_current + pieces.load_previous);
        let [a, b, c] = self.propagator.output_values();
        Outputs {
            corner1: z1 + a,
            corner2: z1 + b,
            edge_mid: z1 + c,
            energy_kinetic: kinetic,
            energy_elastic: elastic,
            energy_total: kinetic + elastic - work,
            active_nodes,
            contact_force,
        }
    }

    /// The dynamic state, for FMU get/set/serialize.
    pub fn state(&self) -> State {
        let (previous, current) = self.propagator.state();
        State {
            scene: self.scene.clone(),
            backend: self.linear,
            step_index: self.step_index,
            base: self.base,
            pressure: self.pressure,
            previous,
            current,
            active_set: self.states.iter().map(|s| state_code(*s)).collect(),
            forces: self.forces.clone(),
        }
    }

    /// Restores a state taken from a stepper of a scene with the same fixed parameters.
    pub fn restore(&mut self, state: &State) -> Result<(), Error> {
        let mut fixed = state.scene.clone();
        fixed.obstacle.lower = self.scene.obstacle.lower;
        fixed.obstacle.upper = self.scene.obstacle.upper;
        fixed.load.pressure = self.scene.load.pressure;
        fixed.stop_time = self.scene.stop_time;
        // The QP choice changes how a step is solved, not what it computes: a state moves freely
        // between the fast path and the clarabel reference.
        fixed.solver.qp = self.scene.solver.qp;
        let m = self.free.constrained.len();
        if fixed != self.scene
            || state.backend != self.linear
            || state.previous.len() != self.propagator.dimension()
            || state.current.len() != self.propagator.dimension()
            || state.forces.len() != m
            || state.active_set.len() != m
        {
            return Err(Error::invalid(
                "FMU state",
                "<state>",
                "was taken from a model with other fixed parameters",
            ));
        }
        let states = state
            .active_set
            .iter()
            .map(|&c| state_from_code(c))
            .collect::<Option<Vec<_>>>()
            .ok_or_else(|| Error::invalid("FMU state", "<state>", "holds an invalid active set"))?;
        self.propagator
            .set_state(state.previous.clone(), state.current.clone());
        let qp = self.scene.solver.qp;
        self.scene = state.scene.clone();
        self.scene.solver.qp = qp;
        self.step_index = state.step_index;
        self.base = state.base;
        self.pressure = state.pressure;
        self.propagator
            .constrained_values(Level::Previous, &mut self.restitution_previous);
        self.propagator
            .constrained_values(Level::Current, &mut self.restitution_current);
        self.states = states;
        self.forces = state.forces.clone();
        Ok(())
    }
}

/// The Delassus operator of a propagator, column by column.
struct PropagatorDelassus<'a> {
    propagator: &'a mut dyn Propagator,
    dim: usize,
}

impl Delassus for PropagatorDelassus<'_> {
    fn dim(&self) -> usize {
        self.dim
    }

    fn column(&mut self, j: usize) -> &[f64] {
        self.propagator.delassus_column(j)
    }
}

fn state_code(state: BoundState) -> i8 {
    match state {
        BoundState::AtLower => -1,
        BoundState::Free => 0,
        BoundState::AtUpper => 1,
    }
}

fn state_from_code(code: i8) -> Option<BoundState> {
    match code {
        -1 => Some(BoundState::AtLower),
        0 => Some(BoundState::Free),
        1 => Some(BoundState::AtUpper),
        _ => None,
    }
}

/// SPEC §1: the base must stay strictly inside the gap.
fn check_base(scene: &Scene, time: f64, base: f64) -> Result<(), Error> {
    let (lower, upper) = (scene.lower_obstacle(), scene.upper_obstacle());
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

fn free_system(scene: &Scene, plate: &PlateSystem) -> FreeSystem {
    let keep = &plate.free;
    let restrict = |a: &SparseColMat<usize, f64>| -> SparseColMat<usize, f64> {
        let mut position = vec![usize::MAX; a.nrows()];
        for (k, &d) in keep.iter().enumerate() {
            position[d] = k;
        }
        let a = a.as_ref();
        let mut triplets = Vec::new();
        for (jk, &j) in keep.iter().enumerate() {
            for (i, &v) in a.row_idx_of_col(j).zip(a.val_of_col(j)) {
                if position[i] != usize::MAX {
                    triplets.push(faer::sparse::Triplet::new(position[i], jk, v));
                }
            }
        }
        SparseColMat::try_new_from_triplets(keep.len(), keep.len(), &triplets)
            .expect("indices in range")
    };
    let mass = restrict(&plate.mass);
    let stiffness = restrict(&plate.stiffness);
    let half_dt2 = 0.5 * scene.solver.time_step * scene.solver.time_step;
    let system = &mass + &(&stiffness * faer::Scale(half_dt2));
    let mut m_translation = vec![0.0; plate.disc.dof_count];
    multiply(&plate.mass, &plate.translation, 1.0, &mut m_translation);
    let has_obstacle = scene.obstacle.lower_enabled || scene.obstacle.upper_enabled;
    FreeSystem {
        mass,
        stiffness,
        system,
        load: keep.iter().map(|&d| plate.unit_load[d]).collect(),
        base: keep.iter().map(|&d| m_translation[d]).collect(),
        constrained: if has_obstacle {
            plate.constrained.clone()
        } else {
            Vec::new()
        },
        outputs: plate.outputs.each_ref().map(|f| {
            let mut row = vec![0.0; keep.len()];
            for (&d, &w) in f.dofs.iter().zip(&f.weights) {
                if let Ok(k) = keep.binary_search(&d) {
                    row[k] += w;
                }
            }
            row
        }),
        total_mass: dot(&m_translation, &plate.translation),
        area: dot(&plate.unit_load, &plate.translation),
    }
}

/// u₀ − z₀𝟙: the static equilibrium K_ff w = p₀ f under the preload, with the obstacle bounds
/// g − z₀ when the unconstrained equilibrium violates them (a static contact QP, solved by clarabel).
fn static_preload(scene: &Scene, free: &FreeSystem, initial_base: f64) -> Result<Vec<f64>, Error> {
    let p = scene.initial.preload_pressure;
    let n = free.load.len();
    if p == 0.0 {
        return Ok(vec![0.0; n]);
    }
    let b: Vec<f64> = free.load.iter().map(|f| p * f).collect();
    let factor = free.stiffness.sp_cholesky(faer::Side::Lower).map_err(|e| {
        Error::Numerical(format!(
            "the clamped stiffness matrix is not numerically positive definite ({e:?})"
        ))
    })?;
    let mut w = b.clone();
    {
        use faer::linalg::solvers::Solve;
        factor.solve_in_place(faer::ColMut::from_slice_mut(&mut w).as_mat_mut());
    }
    let lower = scene
        .lower_obstacle()
        .map_or(f64::NEG_INFINITY, |g| g - initial_base);
    let upper = scene
        .upper_obstacle()
        .map_or(f64::INFINITY, |g| g - initial_base);
    let feasible = free
        .constrained
        .iter()
        .all(|&i| w[i] >= lower && w[i] <= upper);
    if feasible {
        return Ok(w);
    }
    let m = free.constrained.len();
    let (lower, upper) = (vec![lower; m], vec![upper; m]);
    let solution = contact::clarabel::solve_box_qp(&BoxQp {
        a: free.stiffness.as_ref(),
        b: &b,
        constrained: &free.constrained,
        lower: &lower,
        upper: &upper,
    })?;
    Ok(solution.x)
}
