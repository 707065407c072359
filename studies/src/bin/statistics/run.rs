//! Running a plan: one simulation per [`Run`], its statistics and spreads (see the study's
//! documentation in main.rs), and the rows of the study's CSVs.

use super::plan::{Forcing, Mesh, Plan, Run, SceneKind, ZETA1};
use plate_impact::element::ElementKind;
use plate_impact::scene::Scene;
use plate_impact::scheme::Stepper;
use plate_impact::system::PlateSystem;
use plate_impact_studies::recorder::{stride, Recorder, Tally, Windows, SAMPLE_INTERVAL};
use plate_impact_studies::sample::mean_std;
use plate_impact_studies::windows::{window_spread, window_values, Quantity};
use std::time::Instant;

/// Relative perturbation step of the preload between replicas of the `energy` scene.
pub const ENERGY_PERTURBATION: f64 = 1e-9;

/// Preload pressure step between replicas of a forced scene (Pa): 1e-4 Pa deflects the plate by
/// about 1e-11 m, as 1e-9 of the `energy` scene's preload does.
pub const FORCED_PERTURBATION_PA: f64 = 1e-4;

/// Times at which the `energy` scene's energy is read (s); the last is its horizon.
const ENERGY_TIMES: [f64; 2] = [0.1, 0.3];

/// A statistic of one run: its value and spread (see the study's documentation (main.rs)).
#[derive(Clone, Copy, Debug)]
pub struct Stat {
    pub quantity: &'static str,
    pub value: f64,
    pub spread: f64,
}

/// What a run reports: its statistics, the wall time of one simulation and ζ_hf, the lightest
/// damping ratio of the modes with ω ≥ 1/Δt (the quantity of the start-up warning's threshold,
/// `DampingCoefficients::lightest_ratio_above`).
pub struct Outcome {
    pub stats: Vec<Stat>,
    pub wall_s: f64,
    pub zeta_hf: f64,
}

/// The statistics over all windows of a forced run (each of the same whole forcing periods),
/// with their spreads: each time average over the whole of the windows, its spread the standard
/// error of its K window values ([`window_spread`]); the peak |u| of the corner, a maximum, over
/// all windows, its spread the standard deviation of the window peaks.
fn window_stats(windows: &[Tally]) -> Vec<Stat> {
    let averaged = |q: Quantity<Tally>| Stat {
        quantity: q.name,
        value: q.over(windows),
        spread: window_spread(&window_values(windows, 1, |w| q.over(w))),
    };
    let peaks: Vec<f64> = windows.iter().map(|w| w.corner_peak).collect();
    vec![
        averaged(Quantity::RMS_CORNER),
        Stat {
            quantity: "peak_corner_m",
            value: peaks.iter().fold(0.0, |a: f64, &b| a.max(b)),
            spread: mean_std(&peaks).1,
        },
        averaged(Quantity::IMPACTS_PER_PERIOD),
        averaged(Quantity::CONTACT_LOSS_PER_PERIOD),
        averaged(Quantity::MEAN_ENERGY),
        averaged(Quantity::MEAN_ABS_BASE_FORCE),
        averaged(Quantity::RMS_BASE_FORCE),
    ]
}

fn base_scene(mesh: Mesh, dt: f64) -> Scene {
    let mut s = Scene::named("forced-35hz").expect("named scene");
    s.mesh.element = mesh.element;
    (s.mesh.nx, s.mesh.ny) = (mesh.nx, mesh.ny);
    s.solver.time_step = dt;
    s
}

/// Sets `name=value` scene parameters on `scene`, validated together ([`Scene::set_all`]).
fn apply(scene: &mut Scene, settings: &[String]) -> Result<(), String> {
    let pairs: Vec<(&str, &str)> = settings.iter().filter_map(|o| o.split_once('=')).collect();
    scene.set_all(&pairs).map_err(|e| e.to_string())
}

/// What every run of `plan` shares: the `-damped` forcings' α and the command line's settings.
pub struct Context<'a> {
    pub plan: &'a Plan,
    /// α of the `-damped` forcings (1/s).
    pub alpha: f64,
    /// The command line's `name=value` settings, applied after the run's own.
    pub overrides: &'a [String],
}

impl Context<'_> {
    /// The settings of `run` in the order they apply: the damping model's, the run's own, then
    /// the command line's.
    fn settings(&self, run: &Run) -> Vec<String> {
        let model = self.plan.damping_of(run).map(|d| d.arguments());
        model
            .into_iter()
            .flatten()
            .chain(run.settings.iter().cloned())
            .chain(self.overrides.iter().cloned())
            .collect()
    }

    /// Runs `run` (with R perturbed replicas for the `energy` scene).
    pub fn run(&self, run: &Run) -> Result<Outcome, String> {
        let settings = self.settings(run);
        match run.scene {
            SceneKind::Forced(forcing) => self.forced(run, forcing, 0.0, &settings),
            SceneKind::Energy => {
                let replicas = (0..self.plan.replicas)
                    .map(|k| {
                        let perturbation = k as f64 * ENERGY_PERTURBATION;
                        run_energy(run.mesh, run.dt, perturbation, &settings)
                    })
                    .collect::<Result<Vec<_>, _>>()?;
                Ok(energy_stats(&replicas, run.dt))
            }
        }
    }

    /// The statistics of R forced runs of `run`, the k-th with a preload of k·1e-4 Pa.
    pub fn replicas(&self, run: &Run) -> Result<Vec<Vec<Stat>>, String> {
        let SceneKind::Forced(forcing) = run.scene else {
            return Err("replicas of a forced scene only".into());
        };
        let settings = self.settings(run);
        (0..self.plan.replicas)
            .map(|k| {
                let preload = k as f64 * FORCED_PERTURBATION_PA;
                self.forced(run, forcing, preload, &settings)
                    .map(|o| o.stats)
            })
            .collect()
    }

    /// Runs a forced scene: transient, then `run.windows` windows of whole periods.
    fn forced(
        &self,
        run: &Run,
        forcing: Forcing,
        preload: f64,
        settings: &[String],
    ) -> Result<Outcome, String> {
        let (plan, dt) = (self.plan, run.dt);
        let mut s = base_scene(run.mesh, dt);
        s.base.frequency = forcing.frequency;
        s.base.amplitude = forcing.amplitude;
        s.damping.mass_proportional = if forcing.damped { self.alpha } else { 0.0 };
        s.initial.preload_pressure = preload;
        apply(&mut s, settings)?;
        let periods = (forcing.frequency * plan.window_target).round() as usize;
        let window_s = periods as f64 / forcing.frequency;
        // Last step of window j: bounds[j + 1]; the windows are (bounds[j], bounds[j + 1]].
        let bounds: Vec<usize> = (0..=run.windows)
            .map(|j| ((plan.transient + j as f64 * window_s) / dt).round() as usize)
            .collect();
        let recorder = Recorder {
            steps: *bounds.last().expect("windows"),
            windows: Windows::Bounds(bounds),
            stride: stride(SAMPLE_INTERVAL, dt),
        };
        let mut windows = vec![Tally::spanning(periods); run.windows];
        let started = Instant::now();
        let mut stepper = Stepper::new(&s, 0.0).map_err(|e| e.to_string())?;
        recorder.run(&mut stepper, forcing.label, &mut windows, |_, _, _| Ok(()))?;
        Ok(Outcome {
            stats: window_stats(&windows),
            wall_s: started.elapsed().as_secs_f64(),
            zeta_hf: zeta_hf(&s),
        })
    }
}

/// ζ_hf of `scene`: the lightest damping ratio of the modes with ω ≥ 1/Δt.
fn zeta_hf(scene: &Scene) -> f64 {
    let dt = scene.solver.time_step;
    scene.damping.coefficients().lightest_ratio_above(1.0 / dt)
}

/// What one run of the `energy` scene reports.
struct EnergyRun {
    first_impact_s: f64,
    energy_j: [f64; 2],
    impacts: usize,
    wall_s: f64,
    zeta_hf: f64,
}

fn run_energy(
    mesh: Mesh,
    dt: f64,
    perturbation: f64,
    settings: &[String],
) -> Result<EnergyRun, String> {
    let mut s = Scene::named("energy").expect("named scene");
    s.mesh.element = mesh.element;
    (s.mesh.nx, s.mesh.ny) = (mesh.nx, mesh.ny);
    s.solver.time_step = dt;
    s.initial.preload_pressure *= 1.0 + perturbation;
    apply(&mut s, settings)?;
    let marks = ENERGY_TIMES.map(|t| (t / dt).round() as usize);
    let started = Instant::now();
    let mut stepper = Stepper::new(&s, 0.0).map_err(|e| e.to_string())?;
    let (mut first, mut impacts, mut energy_j) = (f64::NAN, 0, [f64::NAN; 2]);
    for n in 1..=marks[1] {
        let report = stepper
            .step(0.0)
            .map_err(|e| format!("energy step {n}: {e}"))?;
        if report.impact {
            impacts += 1;
            if first.is_nan() {
                first = n as f64 * dt;
            }
        }
        for (k, &mark) in marks.iter().enumerate() {
            if n == mark {
                energy_j[k] = stepper.outputs().energy_total;
            }
        }
    }
    Ok(EnergyRun {
        first_impact_s: first,
        energy_j,
        impacts,
        wall_s: started.elapsed().as_secs_f64(),
        zeta_hf: zeta_hf(&s),
    })
}

/// The `energy` statistics of R replicas at time step `dt`: the unperturbed run's value, the
/// replicas' standard deviation, the unperturbed run's wall time. The first impact is read on the
/// step grid (the end of the step in which it happens), so its spread also holds the step's:
/// √(σ² + Δt²/12), the standard deviation of a time uniform within the step.
fn energy_stats(replicas: &[EnergyRun], dt: f64) -> Outcome {
    let stat = |quantity, f: &dyn Fn(&EnergyRun) -> f64| {
        let values: Vec<f64> = replicas.iter().map(f).collect();
        Stat {
            quantity,
            value: values[0],
            spread: mean_std(&values).1,
        }
    };
    let first = stat("first_impact_s", &|r| r.first_impact_s);
    Outcome {
        stats: vec![
            Stat {
                spread: first.spread.hypot(dt / 12f64.sqrt()),
                ..first
            },
            stat("energy_0.1s_J", &|r| r.energy_j[0]),
            stat("energy_0.3s_J", &|r| r.energy_j[1]),
            stat("impacts_to_0.3s", &|r| r.impacts as f64),
        ],
        wall_s: replicas[0].wall_s,
        zeta_hf: replicas[0].zeta_hf,
    }
}

/// ω₁ and ω_max of a mesh (rad/s) and its free dofs, from the library's eigenbasis.
pub fn mesh_modes(mesh: Mesh) -> Result<(f64, f64, usize), String> {
    let plate = PlateSystem::new(&base_scene(mesh, 1e-4)).map_err(|e| e.to_string())?;
    let modes = plate.modes().map_err(|e| e.to_string())?;
    let w2 = &modes.omega_squared;
    Ok((
        w2[0].sqrt(),
        w2.last().expect("modes").sqrt(),
        plate.free.len(),
    ))
}

/// α = 2ζ₁ω₁ of the `-damped` forcings (1/s) and ω₁ (rad/s) of the paper's Argyris 10 × 7 mesh.
pub fn reference_damping() -> Result<(f64, f64), String> {
    let (omega1, _, _) = mesh_modes(Mesh::new(ElementKind::Argyris, 10, 7))?;
    Ok((2.0 * ZETA1 * omega1, omega1))
}
