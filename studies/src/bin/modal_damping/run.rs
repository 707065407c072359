//! Running the modal damping study: the modes of a plate and mesh, one run recorded forcing period
//! by forcing period with the energy of each band of modes, a setting's runs (the main one and its
//! perturbed replicas) and what they cost, and the statistics of each quantity with its three
//! spreads (see the study's documentation in main.rs).

use super::plan::{scene_of, Plan, Setting};
use plate_impact::scene::Scene;
use plate_impact::scheme::Stepper;
use plate_impact::system::PlateSystem;
use plate_impact_studies::autocorrelation::correlation;
use plate_impact_studies::recorder::{stride, Recorder, Tally, Windows, SAMPLE_INTERVAL};
use plate_impact_studies::sample::mean_std;
use plate_impact_studies::windows::{window_spread, window_values, Quantity};
use std::time::Instant;

/// The modal energies are sampled at this interval, or every step when Δt is larger (s): 286
/// samples per period at 35 Hz, out of phase with the forcing.
pub const MODAL_SAMPLE_INTERVAL: f64 = 1e-4;

/// Lower edges of the bands of natural frequency (Hz) the modal energy is summed over; the last
/// band is open above.
pub const BAND_EDGES_HZ: [f64; 10] = [0.0, 1e2, 3e2, 1e3, 3e3, 1e4, 3e4, 1e5, 3e5, 1e6];

/// The replicas' perturbation of the first modal coordinate per replica (m·√kg): about 1e-11 m of
/// tip deflection on the paper's 6.2 kg plate, as the statistics study's preload perturbation.
pub const REPLICA_PERTURBATION: f64 = 2.5e-11;

/// Relative tolerance of Σ_k ¼ω_k²(q_k,n² + q_k,n−1²) against `energy.elastic`: the two sums of
/// the same quadratic form in two bases differ by round-off of the eigenbasis, about n·ε·κ with
/// the graded pencil's high modes carrying little of the energy.
pub const MODAL_ENERGY_TOLERANCE: f64 = 1e-6;

/// The natural frequencies of a plate and mesh, and the band of each mode.
pub struct MeshModes {
    pub omega_squared: Vec<f64>,
    pub band: Vec<usize>,
    pub free_dofs: usize,
    pub omega1: f64,
    pub omega_max: f64,
    /// CPU s of the assembly and the eigenbasis.
    pub set_up_cpu_s: f64,
}

impl MeshModes {
    pub fn of(scene: &Scene) -> Result<MeshModes, String> {
        let started = cpu_seconds();
        let plate = PlateSystem::new(scene).map_err(|e| e.to_string())?;
        let modes = plate.modes().map_err(|e| e.to_string())?;
        let band = modes
            .frequencies_hz()
            .iter()
            .map(|&f| {
                BAND_EDGES_HZ
                    .iter()
                    .rposition(|&edge| f >= edge)
                    .unwrap_or(0)
            })
            .collect();
        let w2 = modes.omega_squared;
        Ok(MeshModes {
            omega1: w2[0].sqrt(),
            omega_max: w2.last().expect("modes").sqrt(),
            free_dofs: plate.free.len(),
            band,
            omega_squared: w2,
            set_up_cpu_s: cpu_seconds() - started,
        })
    }
}

/// What one forcing period of a run accumulates: the recorder's tally, and the energy of each
/// band of modes summed over the modal samples.
#[derive(Clone, Debug)]
pub struct Period {
    pub tally: Tally,
    pub modal_samples: usize,
    pub bands: [f64; BAND_EDGES_HZ.len()],
}

impl Period {
    pub fn new() -> Period {
        Period {
            tally: Tally::spanning(1),
            modal_samples: 0,
            bands: [0.0; BAND_EDGES_HZ.len()],
        }
    }
}

impl AsRef<Tally> for Period {
    fn as_ref(&self) -> &Tally {
        &self.tally
    }
}

impl AsMut<Tally> for Period {
    fn as_mut(&mut self) -> &mut Tally {
        &mut self.tally
    }
}

/// One run: its periods from t = 0, its steps, wall and CPU time.
pub struct Run {
    pub periods: Vec<Period>,
    pub steps: usize,
    pub wall_s: f64,
    pub cpu_s: f64,
}

/// What a setting cost: its main run with the stepper's set-up (wall and CPU s), the set-up's CPU
/// s, and the CPU µs per step of the main run.
pub struct Cost {
    pub wall_s: f64,
    pub cpu_s: f64,
    pub set_up_cpu_s: f64,
    pub step_us: f64,
}

/// The CPU time of this process so far (s), from /proc/self/stat (user + system, in the kernel's
/// USER_HZ = 100 ticks per second): the costs the study reports, which a machine shared with other
/// jobs inflates less than wall times. NaN where /proc is missing.
pub fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let fields: Vec<&str> = stat
        .rsplit_once(')')
        .map_or(vec![], |(_, rest)| rest.split_whitespace().collect());
    let ticks = |i: usize| fields.get(i).and_then(|v| v.parse::<f64>().ok());
    match (ticks(11), ticks(12)) {
        (Some(user), Some(system)) => (user + system) / 100.0,
        _ => f64::NAN,
    }
}

/// Adds the energy of each mode between the state's two levels to its band.
pub fn add_modal_energy(
    modes: &MeshModes,
    previous: &[f64],
    current: &[f64],
    dt: f64,
    bands: &mut [f64],
) -> f64 {
    let mut elastic = 0.0;
    for (k, (&a, &b)) in previous.iter().zip(current).enumerate() {
        let velocity = (b - a) / dt;
        let potential = 0.25 * modes.omega_squared[k] * (a * a + b * b);
        bands[modes.band[k]] += 0.5 * velocity * velocity + potential;
        elastic += potential;
    }
    elastic
}

/// Runs `stepper` from its current state (the initial one) for `transient + duration` s of the
/// forcing, recording each period.
pub fn run(
    stepper: &mut Stepper,
    modes: &MeshModes,
    setting: &Setting,
    total_s: f64,
) -> Result<Run, String> {
    let dt = setting.dt;
    let f = setting.forcing.frequency;
    let periods = (total_s * f).round() as usize;
    let steps = (periods as f64 / f / dt).round() as usize;
    let recorder = Recorder {
        windows: Windows::Periods {
            dt,
            frequency: f,
            count: periods,
        },
        steps,
        stride: stride(SAMPLE_INTERVAL, dt),
    };
    let modal_sample = stride(MODAL_SAMPLE_INTERVAL, dt);
    let mut record = vec![Period::new(); periods];
    let started = Instant::now();
    let cpu_started = cpu_seconds();
    let mut checked = false;
    let label = setting.forcing.label;
    recorder.run(stepper, label, &mut record, |n, stepper, period| {
        if n % modal_sample != 0 {
            return Ok(());
        }
        let state = stepper.state();
        let elastic = add_modal_energy(
            modes,
            &state.previous,
            &state.current,
            dt,
            &mut period.bands,
        );
        period.modal_samples += 1;
        if !checked {
            // The state's levels are w_{n−1}, w_n; the outputs' elastic energy is that of the
            // same pair.
            let reported = stepper.outputs().energy_elastic;
            if (elastic - reported).abs() > MODAL_ENERGY_TOLERANCE * reported.abs().max(1e-12) {
                return Err(format!(
                    "modal elastic energy {elastic:e} J against energy.elastic {reported:e} J: \
                     the state's coordinates are not those of the eigenbasis"
                ));
            }
            checked = elastic > 0.0;
        }
        Ok(())
    })?;
    Ok(Run {
        periods: record,
        steps,
        wall_s: started.elapsed().as_secs_f64(),
        cpu_s: cpu_seconds() - cpu_started,
    })
}

/// Index of the first band at or above 1 kHz in [`BAND_EDGES_HZ`].
pub const BAND_1KHZ: usize = 3;

/// Index of the first band at or above 10 kHz in [`BAND_EDGES_HZ`].
pub const BAND_10KHZ: usize = 5;

/// The statistics of a run, with the damping study's names: the recorder's time averages, then
/// the share of the modal energy above 1 and 10 kHz.
pub const QUANTITIES: [Quantity<Period>; 8] = [
    Quantity::MEAN_ENERGY,
    Quantity::RMS_CORNER,
    Quantity::MEAN_ABS_BASE_FORCE,
    Quantity::RMS_BASE_FORCE,
    Quantity::IMPACTS_PER_PERIOD,
    Quantity::CONTACT_LOSS_PER_PERIOD,
    Quantity::new(
        "modal_share_above_1khz",
        |p| p.bands[BAND_1KHZ..].iter().sum(),
        |p| p.bands.iter().sum(),
        false,
    ),
    Quantity::new(
        "modal_share_above_10khz",
        |p| p.bands[BAND_10KHZ..].iter().sum(),
        |p| p.bands.iter().sum(),
        false,
    ),
];

/// The statistics of one quantity of a setting.
pub struct Estimate {
    pub value: f64,
    pub window_spread: f64,
    pub correlation_spread: f64,
    pub replica_spread: f64,
    pub tau_periods: f64,
    pub tau_resolved: bool,
    pub windows: usize,
}

impl Estimate {
    /// The spread the study reports: the largest of its estimates (the replicas' where they ran).
    pub fn spread(&self) -> f64 {
        let replica = if self.replica_spread.is_nan() {
            0.0
        } else {
            self.replica_spread
        };
        self.window_spread.max(self.correlation_spread).max(replica)
    }
}

/// The statistics of a quantity, `over` a set of periods, over the steady-state periods of a run
/// and its replicas.
pub fn estimate(
    over: &dyn Fn(&[Period]) -> f64,
    runs: &[&[Period]],
    window_periods: usize,
) -> Estimate {
    let steady = runs[0];
    let value = over(steady);
    let series: Vec<f64> = steady
        .iter()
        .map(|p| over(std::slice::from_ref(p)))
        .collect();
    let correlation = correlation(&series);
    let window_values = window_values(steady, window_periods, over);
    let replica_spread = if runs.len() >= 2 {
        let values: Vec<f64> = runs.iter().map(|r| over(r)).collect();
        mean_std(&values).1
    } else {
        f64::NAN
    };
    Estimate {
        value,
        window_spread: window_spread(&window_values),
        correlation_spread: correlation.spread,
        replica_spread,
        tau_periods: correlation.tau,
        tau_resolved: correlation.resolved,
        windows: window_values.len(),
    }
}

/// The time averages whose agreement at two successive Δt settles a line.
pub const SETTLING: [&str; 4] = [
    "mean_energy_J",
    "rms_corner_m",
    "mean_abs_base_force_N",
    "rms_base_force_N",
];

/// The statistics of a setting's runs, one per [`QUANTITIES`], over the steady state.
pub fn estimates(plan: &Plan, s: &Setting, runs: &[Run]) -> (Vec<Estimate>, usize) {
    let first = (plan.transient * s.forcing.frequency).round() as usize;
    let window = ((plan.window * s.forcing.frequency).round() as usize).max(1);
    let steady: Vec<&[Period]> = runs.iter().map(|r| &r.periods[first..]).collect();
    let all = QUANTITIES
        .iter()
        .map(|q| estimate(&|ps| q.over(ps), &steady, window))
        .collect();
    (all, window)
}

/// Whether the settling quantities of two runs of a line agree: within `tolerance` (relative) or
/// 2σ of their difference.
pub fn settled(a: &[Estimate], b: &[Estimate], tolerance: f64) -> bool {
    QUANTITIES
        .iter()
        .zip(a.iter().zip(b))
        .filter(|(q, _)| SETTLING.contains(&q.name))
        .all(|(_, (a, b))| {
            let difference = (a.value - b.value).abs();
            difference <= tolerance * b.value.abs()
                || difference <= 2.0 * a.spread().hypot(b.spread())
        })
}

/// Runs one setting: its main run and replicas on one stepper (the replicas restore the initial
/// state, perturbed on the first mode). Returns the runs and the main run's cost.
pub fn run_setting(
    plan: &Plan,
    replicas: usize,
    s: &Setting,
    modes: &MeshModes,
) -> Result<(Vec<Run>, Cost), String> {
    let scene = scene_of(s, &plan.overrides)?;
    let started = Instant::now();
    let cpu_started = cpu_seconds();
    let mut stepper = Stepper::new(&scene, 0.0).map_err(|e| e.to_string())?;
    let set_up_s = started.elapsed().as_secs_f64();
    let set_up_cpu_s = cpu_seconds() - cpu_started;
    let initial = stepper.state();
    if initial.current.len() != modes.omega_squared.len() {
        return Err(format!(
            "{}: the stepper's field has {} coordinates, the eigenbasis {} modes: not the modal \
             backend",
            s.mesh.name(),
            initial.current.len(),
            modes.omega_squared.len()
        ));
    }
    let total_s = plan.transient + plan.duration;
    let mut runs = vec![run(&mut stepper, modes, s, total_s)?];
    let cost = Cost {
        wall_s: set_up_s + runs[0].wall_s,
        cpu_s: set_up_cpu_s + runs[0].cpu_s,
        set_up_cpu_s,
        step_us: runs[0].cpu_s / runs[0].steps as f64 * 1e6,
    };
    for k in 1..=replicas {
        let mut perturbed = initial.clone();
        perturbed.previous[0] += k as f64 * REPLICA_PERTURBATION;
        perturbed.current[0] += k as f64 * REPLICA_PERTURBATION;
        stepper.restore(&perturbed).map_err(|e| e.to_string())?;
        runs.push(run(&mut stepper, modes, s, total_s)?);
    }
    Ok((runs, cost))
}
