//! Modal damping study: the statistics of a plate damped mode by mode (`damping.modal_ratio` ζ,
//! the same ratio on every mode of the clamped plate), per ratio, scene, element, mesh and Δt,
//! with their spreads from windows and from perturbed replicas, the correlation time that sets the
//! windows, and where the energy sits among the modes (docs/accuracy/modal_damping.md).
//!
//! `cargo run --release -p plate_impact_studies --bin modal_damping [-- --quick | --plan] [--out DIR] [selection]`
//!
//! Without a selection the committed plan runs ([`committed_plan`], `--plan` lists its lines), then
//! `python -m plateimpact_tools.studies.modal_damping_plots` writes the plots and the generated
//! part of the page.
//! A selection runs a part of it, to share the study between processes (its CSVs are then
//! concatenated and the plotting script run on the result): `--part middle,third,ratios,fine,finedt`,
//! `--scenes LABEL,…` among [`SCENES`], `--zeta 0.005,0.01`, `--keep-mesh argyris:28x20,…` keep
//! those lines of the plan; `--mesh argyris:10x7,fvs:14x10` runs those meshes instead of the
//! plan's, `--dt 1e-5,1e-6` that ladder, `--duration S`, `--transient S`, `--window S`,
//! `--replicas R`, `--max-run-cpu S`, `--no-settle` (every Δt of the ladder), `--series` (every
//! run's per-period series in `modal_damping_periods.csv`) change its settings, and trailing
//! `name=value` arguments set scene parameters of every run (the FMU variable names).
//!
//! Per run (one [`Stepper`], modal backend): the scene forced from rest for `transient` s, then
//! `duration` s of steady state, recorded forcing period by forcing period: the mean of
//! `energy.total`, the mean square and peak of the free corner u(Lx, 0), the mean of |base.force|
//! and of its square, the impacts (`StepReport::impact`) and the energy removed at the obstacles,
//! and the energy of each band of natural frequencies ([`BAND_EDGES_HZ`]), averaged over the period.
//! The energy of mode k between levels n−1 and n is that of the scheme's discrete energy,
//! E_k = ½((q_k,n − q_k,n−1)/Δt)² + ¼ω_k²(q_k,n² + q_k,n−1²), from the modal coordinates q of the
//! stepper's state (the modal backend's field, w = Φq with Φ M-orthonormal) and ω_k² from the
//! library's eigenbasis of the same plate (`PlateSystem::modes`); Σ_k of the elastic part equals
//! `energy.elastic`, which every run checks at its first sample.
//!
//! Statistics over the steady state's P periods: the value of a time average is the mean over all
//! of them; its spread, the standard deviation of what one run would report had its chaotic
//! response taken another course, is estimated three ways:
//! - windows: the periods cut into K windows of the whole periods nearest `window` s (chosen
//!   from the correlation times), the standard deviation of the K window values / √K;
//! - correlation: √(τ σ² / P), σ² the variance of the per-period values and τ their integrated
//!   autocorrelation time in periods (`plate_impact_studies::autocorrelation`);
//! - replicas: R more runs of the same setting from initial states perturbed by
//!   k·[`REPLICA_PERTURBATION`] on the first modal coordinate (k = 1 … R), restored into the same
//!   stepper, the standard deviation of the R + 1 run values;
//!
//! and the largest is the reported spread. A line of the plan runs its Δt ladder until the time
//! averages of [`SETTLING`] agree at two successive Δt, or until the next run's estimated CPU time
//! exceeds the line's cap (listed in the meta file as left out). Costs are CPU times of this
//! process (`/proc/self/stat`), which a machine shared with other jobs inflates less than wall
//! times.
//!
//! `--quick`: Argyris 4 × 2 at Δt = 1e-4 and 1e-5 s, 35 Hz, ζ = 1 %, 2 s, two replicas, into a
//! temporary directory; it checks the pipeline and the modal energy against `energy.elastic`.

use plate_impact::element::ElementKind;
use plate_impact::scene::Scene;
use plate_impact::scheme::Stepper;
use plate_impact::system::PlateSystem;
use plate_impact_studies::autocorrelation::correlation;
use plate_impact_studies::cli::{exit_code, flag_value};
use plate_impact_studies::element::{element_name, parse_mesh_cells};
use plate_impact_studies::output::StudyDir;
use plate_impact_studies::recorder::{stride, Recorder, Tally, Windows, SAMPLE_INTERVAL};
use plate_impact_studies::revision::source_revision;
use plate_impact_studies::sample::mean_std;
use plate_impact_studies::windows::{window_spread, window_values, Quantity};
use std::fmt::Write as _;
use std::process::ExitCode;
use std::time::Instant;

/// The modal energies are sampled at this interval, or every step when Δt is larger (s): 286
/// samples per period at 35 Hz, out of phase with the forcing.
const MODAL_SAMPLE_INTERVAL: f64 = 1e-4;

/// Lower edges of the bands of natural frequency (Hz) the modal energy is summed over; the last
/// band is open above.
const BAND_EDGES_HZ: [f64; 10] = [0.0, 1e2, 3e2, 1e3, 3e3, 1e4, 3e4, 1e5, 3e5, 1e6];

/// The replicas' perturbation of the first modal coordinate per replica (m·√kg): about 1e-11 m of
/// tip deflection on the paper's 6.2 kg plate, as the statistics study's preload perturbation.
const REPLICA_PERTURBATION: f64 = 2.5e-11;

/// Relative tolerance of Σ_k ¼ω_k²(q_k,n² + q_k,n−1²) against `energy.elastic`: the two sums of
/// the same quadratic form in two bases differ by round-off of the eigenbasis, about n·ε·κ with
/// the graded pencil's high modes carrying little of the energy.
const MODAL_ENERGY_TOLERANCE: f64 = 1e-6;

/// A plate of the study.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Plate {
    /// The paper's steel plate, 0.4 × 0.2 × 0.01 m, obstacles at ±10 mm.
    Paper,
    /// The third plate: aluminium, 0.3 × 0.3 × 0.005 m, obstacles at ±5 mm (see the study's page).
    Aluminium,
}

/// A forced scene: a plate, its base sine.
#[derive(Clone, Copy, Debug)]
struct Forcing {
    label: &'static str,
    plate: Plate,
    frequency: f64,
    amplitude: f64,
}

/// The scenes of the study.
const SCENES: [Forcing; 3] = [
    Forcing {
        label: "forced-35hz",
        plate: Plate::Paper,
        frequency: 35.0,
        amplitude: 0.009,
    },
    Forcing {
        label: "forced-60hz",
        plate: Plate::Paper,
        frequency: 60.0,
        amplitude: 0.002,
    },
    Forcing {
        label: "aluminium-square",
        plate: Plate::Aluminium,
        frequency: 40.0,
        amplitude: 0.004,
    },
];

/// A mesh of the study.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Mesh {
    element: ElementKind,
    nx: usize,
    ny: usize,
}

impl Mesh {
    fn name(&self) -> String {
        format!("{} {}x{}", element_name(self.element), self.nx, self.ny)
    }
}

/// One setting of the study: scene, ratio, mesh and Δt.
#[derive(Clone, Copy, Debug)]
struct Setting {
    forcing: Forcing,
    zeta: f64,
    mesh: Mesh,
    dt: f64,
}

/// A scene, ratio and mesh, run down a ladder of Δt until the time averages settle.
#[derive(Clone, Debug)]
struct Line {
    /// The part of the committed plan it belongs to (`--part`).
    part: &'static str,
    forcing: Forcing,
    zeta: f64,
    mesh: Mesh,
    /// Δt (s), decreasing.
    ladder: Vec<f64>,
    /// A run whose estimated CPU time exceeds this (s) is left out, with the smaller Δt of its
    /// line.
    max_run_cpu: f64,
    /// Perturbed replicas of each run.
    replicas: usize,
    /// Whether the per-period series of its runs are written (`modal_damping_periods.csv`).
    series: bool,
}

/// What the study runs.
struct Plan {
    name: &'static str,
    lines: Vec<Line>,
    /// Simulated time before the statistics (s).
    transient: f64,
    /// Simulated time of the statistics (s).
    duration: f64,
    /// Window length (s), for the window spread: the whole periods nearest to it.
    window: f64,
    /// A line stops refining Δt once the time averages of [`SETTLING`] at two successive Δt
    /// agree: differ by at most this relative tolerance or 2σ of their difference.
    settle_tolerance: f64,
    /// `name=value` scene parameters of every run.
    overrides: Vec<String>,
}

/// The scene of a setting: the plate's parameters, the forcing, the ratio, the mesh and Δt, then
/// the command line's `name=value` parameters (the FMU variable names, [`Scene::set_all`]).
fn scene_of(setting: &Setting, overrides: &[String]) -> Result<Scene, String> {
    let mut s = Scene::named("forced-35hz").map_err(|e| e.to_string())?;
    if setting.forcing.plate == Plate::Aluminium {
        s.plate.length = 0.3;
        s.plate.width = 0.3;
        s.plate.thickness = 0.005;
        s.material.young_modulus = 7e10;
        s.material.poisson_ratio = 0.33;
        s.material.density = 2700.0;
        s.obstacle.lower = -0.005;
        s.obstacle.upper = 0.005;
    }
    s.base.frequency = setting.forcing.frequency;
    s.base.amplitude = setting.forcing.amplitude;
    s.damping.modal_ratio = setting.zeta;
    s.mesh.element = setting.mesh.element;
    (s.mesh.nx, s.mesh.ny) = (setting.mesh.nx, setting.mesh.ny);
    s.solver.time_step = setting.dt;
    let pairs: Vec<(&str, &str)> = overrides.iter().filter_map(|o| o.split_once('=')).collect();
    s.set_all(&pairs).map_err(|e| e.to_string())?;
    Ok(s)
}

/// The natural frequencies of a plate and mesh, and the band of each mode.
struct MeshModes {
    omega_squared: Vec<f64>,
    band: Vec<usize>,
    free_dofs: usize,
    omega1: f64,
    omega_max: f64,
    /// CPU s of the assembly and the eigenbasis.
    set_up_cpu_s: f64,
}

impl MeshModes {
    fn of(scene: &Scene) -> Result<MeshModes, String> {
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
struct Period {
    tally: Tally,
    modal_samples: usize,
    bands: [f64; BAND_EDGES_HZ.len()],
}

impl Period {
    fn new() -> Period {
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
struct Run {
    periods: Vec<Period>,
    steps: usize,
    wall_s: f64,
    cpu_s: f64,
}

/// What a setting cost: its main run with the stepper's set-up (wall and CPU s), the set-up's CPU
/// s, and the CPU µs per step of the main run.
struct Cost {
    wall_s: f64,
    cpu_s: f64,
    set_up_cpu_s: f64,
    step_us: f64,
}

/// The CPU time of this process so far (s), from /proc/self/stat (user + system, in the kernel's
/// USER_HZ = 100 ticks per second): the costs the study reports, which a machine shared with other
/// jobs inflates less than wall times. NaN where /proc is missing.
fn cpu_seconds() -> f64 {
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
fn add_modal_energy(
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
fn run(
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
const BAND_1KHZ: usize = 3;

/// Index of the first band at or above 10 kHz in [`BAND_EDGES_HZ`].
const BAND_10KHZ: usize = 5;

/// The statistics of a run, with the damping study's names: the recorder's time averages, then
/// the share of the modal energy above 1 and 10 kHz.
const QUANTITIES: [Quantity<Period>; 8] = [
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
struct Estimate {
    value: f64,
    window_spread: f64,
    correlation_spread: f64,
    replica_spread: f64,
    tau_periods: f64,
    tau_resolved: bool,
    windows: usize,
}

impl Estimate {
    /// The spread the study reports: the largest of its estimates (the replicas' where they ran).
    fn spread(&self) -> f64 {
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
fn estimate(
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

/// The committed study (docs/accuracy/modal_damping.md says why each part), in parts that
/// `--part` runs alone:
/// - `middle`: ζ = 1 % on both forced scenes of the paper's plate, the coarse and middle meshes
///   of both elements, Δt from 1e-4 s down to 1e-6 s until the time averages settle or a run
///   would cost more than its line's cap, two perturbed replicas on Argyris 10 × 7;
/// - `third`: the aluminium plate at ζ = 1 %, two Argyris meshes and one FVS mesh;
/// - `ratios`: ζ = 0.5 % and 2 % on both forced scenes, Argyris 10 × 7, 14 × 10 and FVS 14 × 10,
///   then at 35 Hz FVS 28 × 20 and Argyris 28 × 20, Δt = 1e-5 and 1e-6 s;
/// - `fine`: ζ = 1 % on both forced scenes, Argyris 20 × 14 at Δt = 1e-5 and 1e-6 s, then
///   Argyris 28 × 20 (5 257 free dofs) from Δt = 1e-4 s;
/// - `finedt`: Argyris 10 × 7 at ζ = 1 % and Δt = 1e-7 s, 60 Hz then 35 Hz; then FVS 28 × 20 at
///   35 Hz.
fn committed_plan() -> Plan {
    use ElementKind::{Argyris, Fvs};
    let mesh = |element, nx, ny| Mesh { element, nx, ny };
    let line = |part, forcing: Forcing, zeta, mesh, ladder: &[f64], max_run_cpu, replicas| Line {
        part,
        forcing,
        zeta,
        mesh,
        ladder: ladder.to_vec(),
        max_run_cpu,
        replicas,
        series: replicas > 0,
    };
    let mut lines = Vec::new();
    // Sized for about 15 CPU minutes on one core (the budget this machine had), in the order of
    // what the findings need, so that a run cut short keeps the first parts whole.
    // Part `middle`: ζ = 1 % on the paper's plate, both elements, coarse to middle meshes, Δt
    // down to 1e-6 s (a run at 1e-7 s costs 25–90 CPU s here); Argyris 10 × 7 with two replicas
    // (the replica spread).
    for forcing in [SCENES[0], SCENES[1]] {
        for (m, replicas) in [
            (mesh(Argyris, 4, 2), 0),
            (mesh(Argyris, 6, 4), 0),
            (mesh(Argyris, 10, 7), 2),
            (mesh(Argyris, 14, 10), 0),
            (mesh(Fvs, 7, 5), 0),
            (mesh(Fvs, 14, 10), 0),
            (mesh(Fvs, 28, 20), 0),
        ] {
            // The 1e-5 s run's CPU per step overestimates the 1e-6 s run's (more of its steps
            // solve a QP): FVS 28 × 20 at 1e-6 s is estimated at 130 CPU s and takes about 60.
            let cap = if m == mesh(Fvs, 28, 20) { 200.0 } else { 120.0 };
            lines.push(line(
                "middle",
                forcing,
                0.01,
                m,
                &LADDER[..3],
                cap,
                replicas,
            ));
        }
    }
    // Part `third`: the aluminium plate at ζ = 1 %, two meshes of each element, then at 0.5 % and
    // 2 % on the same meshes (each run under 20 CPU s at ζ = 1 %).
    for zeta in [0.01, 0.005, 0.02] {
        for m in [
            mesh(Argyris, 7, 7),
            mesh(Argyris, 10, 10),
            mesh(Fvs, 14, 14),
        ] {
            lines.push(line("third", SCENES[2], zeta, m, &LADDER[..3], 60.0, 0));
        }
    }
    // Part `ratios`: ζ = 0.5 % and 2 % on the paper's plate, one middle mesh of each element.
    for forcing in [SCENES[0], SCENES[1]] {
        for zeta in [0.005, 0.02] {
            for m in [
                mesh(Argyris, 10, 7),
                mesh(Argyris, 14, 10),
                mesh(Fvs, 14, 10),
            ] {
                lines.push(line("ratios", forcing, zeta, m, &LADDER[1..3], 60.0, 0));
            }
        }
    }
    // Then, at 35 Hz, each element's finest mesh at both ratios, FVS 28 × 20 (the cheaper) first:
    // whether the elements meet there as they do at ζ = 1 %. The cap lets Argyris 28 × 20's
    // 1e-6 s run happen (265 CPU s at ζ = 1 %).
    for m in [mesh(Fvs, 28, 20), mesh(Argyris, 28, 20)] {
        for zeta in [0.005, 0.02] {
            lines.push(line("ratios", SCENES[0], zeta, m, &LADDER[1..3], 600.0, 0));
        }
    }
    // And the same finest meshes at 60 Hz (ζ = 1 %: 47 and 120 CPU s at 1e-6 s).
    for m in [mesh(Fvs, 28, 20), mesh(Argyris, 28, 20)] {
        for zeta in [0.005, 0.02] {
            lines.push(line("ratios", SCENES[1], zeta, m, &LADDER[1..3], 600.0, 0));
        }
    }
    // Part `fine`: Argyris 20 × 14 at ζ = 1 % (its set-up, two dense eigendecompositions, about
    // 40 CPU s) from Δt = 1e-5 s; then Argyris 28 × 20 (5 257 free dofs, set-up by the band and
    // divide-and-conquer eigensolver, about 20 CPU s twice) on the whole ladder, 35 Hz first.
    for (m, ladder, cap) in [
        (mesh(Argyris, 20, 14), &LADDER[1..3], 250.0),
        (mesh(Argyris, 28, 20), &LADDER[..3], 600.0),
    ] {
        for forcing in [SCENES[0], SCENES[1]] {
            lines.push(line("fine", forcing, 0.01, m, ladder, cap, 0));
        }
    }
    // Part `finedt`: Δt = 1e-7 s on Argyris 10 × 7 at ζ = 1 %, 60 Hz then 35 Hz, without replicas
    // (about 1.3 µs per step at 1e-6 s, so 7e7 steps cost 70–100 CPU s): whether the RMS base
    // force and the 35 Hz corner, still moving at 1e-6 s, settle one decade further.
    for forcing in [SCENES[1], SCENES[0]] {
        lines.push(line(
            "finedt",
            forcing,
            0.01,
            mesh(Argyris, 10, 7),
            &LADDER[3..],
            200.0,
            0,
        ));
    }
    // Then FVS 28 × 20 at 35 Hz, the finest mesh whose 1e-7 s run fits (7.9 µs per step at
    // 1e-6 s, so about 9 CPU minutes): whether the 35 Hz corner and base force, which Argyris
    // 10 × 7 found settled at 1e-6 s, have settled on a fine mesh too.
    lines.push(line(
        "finedt",
        SCENES[0],
        0.01,
        mesh(Fvs, 28, 20),
        &LADDER[3..],
        900.0,
        0,
    ));
    Plan {
        name: "committed",
        lines,
        transient: 1.0,
        duration: 6.0,
        window: 1.0,
        settle_tolerance: 0.01,
        overrides: Vec::new(),
    }
}

/// The Δt ladder (s).
const LADDER: [f64; 4] = [1e-4, 1e-5, 1e-6, 1e-7];

fn quick_plan() -> Plan {
    Plan {
        name: "quick",
        lines: vec![Line {
            forcing: SCENES[0],
            zeta: 0.01,
            mesh: Mesh {
                element: ElementKind::Argyris,
                nx: 4,
                ny: 2,
            },
            ladder: vec![1e-4, 1e-5],
            part: "quick",
            max_run_cpu: 60.0,
            replicas: 2,
            series: true,
        }],
        transient: 0.5,
        duration: 1.5,
        window: 0.25,
        settle_tolerance: 0.01,
        overrides: Vec::new(),
    }
}

/// The meshes of `--mesh argyris:10x7,fvs:14x10`.
fn parse_meshes(list: &str) -> Result<Vec<Mesh>, String> {
    list.split(',')
        .map(|item| {
            let (element, nx, ny) = parse_mesh_cells(item)?;
            Ok(Mesh { element, nx, ny })
        })
        .collect()
}

/// A comma-separated list of positive numbers, for `flag`.
fn parse_numbers(flag: &str, list: &str) -> Result<Vec<f64>, String> {
    list.split(',')
        .map(|v| {
            v.parse::<f64>()
                .ok()
                .filter(|x| x.is_finite() && *x > 0.0)
                .ok_or(format!("{flag} {v}: use numbers > 0"))
        })
        .collect()
}

/// The plan of the command line: `--quick`, the committed plan, or a part of it; and whether it
/// is a part.
fn plan_of(args: &[String], quick: bool) -> Result<(Plan, bool), String> {
    let value_of = |flag: &str| flag_value(args, flag);
    let number = |flag: &str| -> Result<Option<f64>, String> {
        value_of(flag)?
            .map(|v| parse_numbers(flag, &v).map(|x| x[0]))
            .transpose()
    };
    let mut plan = if quick {
        quick_plan()
    } else {
        committed_plan()
    };
    let mut partial = false;
    if let Some(list) = value_of("--part")? {
        let parts: Vec<&str> = list.split(',').collect();
        if let Some(bad) = parts
            .iter()
            .find(|p| !plan.lines.iter().any(|l| l.part == **p))
        {
            return Err(format!(
                "--part {bad}: use middle, third, ratios, fine or finedt"
            ));
        }
        plan.lines.retain(|l| parts.contains(&l.part));
        partial = true;
    }
    if let Some(list) = value_of("--scenes")? {
        let labels: Vec<&str> = list.split(',').collect();
        if let Some(bad) = labels
            .iter()
            .find(|l| !SCENES.iter().any(|s| s.label == **l))
        {
            return Err(format!(
                "--scenes {bad}: use labels among {:?}",
                SCENES.map(|s| s.label)
            ));
        }
        plan.lines.retain(|l| labels.contains(&l.forcing.label));
        partial = true;
    }
    if let Some(list) = value_of("--zeta")? {
        let zetas = parse_numbers("--zeta", &list)?;
        plan.lines.retain(|l| zetas.contains(&l.zeta));
        partial = true;
    }
    if let Some(list) = value_of("--keep-mesh")? {
        // The plan's lines on the named meshes only.
        let meshes = parse_meshes(&list)?;
        plan.lines.retain(|l| meshes.contains(&l.mesh));
        partial = true;
    }
    if let Some(list) = value_of("--mesh")? {
        // The named meshes replace the plan's, for every scene and ratio kept.
        let meshes = parse_meshes(&list)?;
        let mut kept: Vec<Line> = Vec::new();
        for line in &plan.lines {
            if !kept
                .iter()
                .any(|k| k.forcing.label == line.forcing.label && k.zeta == line.zeta)
            {
                kept.extend(meshes.iter().map(|&mesh| Line {
                    mesh,
                    ..line.clone()
                }));
            }
        }
        plan.lines = kept;
        partial = true;
    }
    if let Some(list) = value_of("--dt")? {
        let ladder = parse_numbers("--dt", &list)?;
        plan.lines
            .iter_mut()
            .for_each(|l| l.ladder = ladder.clone());
        partial = true;
    }
    if let Some(d) = number("--duration")? {
        plan.duration = d;
        partial = true;
    }
    if let Some(w) = number("--window")? {
        plan.window = w;
        partial = true;
    }
    if let Some(c) = number("--max-run-cpu")? {
        plan.lines.iter_mut().for_each(|l| l.max_run_cpu = c);
        partial = true;
    }
    if let Some(t) = value_of("--transient")? {
        plan.transient = t
            .parse()
            .map_err(|_| format!("--transient {t}: use seconds ≥ 0"))?;
        partial = true;
    }
    if let Some(r) = value_of("--replicas")? {
        let r = r
            .parse()
            .map_err(|_| format!("--replicas {r}: use a count ≥ 0"))?;
        plan.lines.iter_mut().for_each(|l| l.replicas = r);
        partial = true;
    }
    if args.iter().any(|a| a == "--no-settle") {
        plan.settle_tolerance = 0.0;
        partial = true;
    }
    if args.iter().any(|a| a == "--series") {
        plan.lines.iter_mut().for_each(|l| l.series = true);
    }
    plan.overrides = args.iter().filter(|a| a.contains('=')).cloned().collect();
    let partial = !quick && (partial || !plan.overrides.is_empty());
    Ok((plan, partial))
}

fn main() -> ExitCode {
    exit_code(study())
}

/// The CSV text of a study, rewritten after every setting so that a study stopped early keeps
/// what ran.
struct Tables {
    statistics: String,
    bands: String,
    meshes: String,
    periods: String,
}

/// The time averages whose agreement at two successive Δt settles a line.
const SETTLING: [&str; 4] = [
    "mean_energy_J",
    "rms_corner_m",
    "mean_abs_base_force_N",
    "rms_base_force_N",
];

/// The statistics of a setting's runs, one per [`QUANTITIES`], over the steady state.
fn estimates(plan: &Plan, s: &Setting, runs: &[Run]) -> (Vec<Estimate>, usize) {
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
fn settled(a: &[Estimate], b: &[Estimate], tolerance: f64) -> bool {
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

impl Tables {
    fn new() -> Tables {
        Tables {
            statistics:
                "quantity,scene,damping,modal_ratio,element,nx,ny,free_dofs,dt,omega_max_dt,\
                         value,spread,wall_s,cpu_s,set_up_cpu_s,step_us,window_spread,\
                         correlation_spread,replica_spread,tau_periods,tau_resolved,periods,\
                         window_periods,windows,replicas\n"
                    .into(),
            bands: "scene,modal_ratio,element,nx,ny,dt,band_low_hz,band_high_hz,modes,energy_J,\
                    spread_J,share\n"
                .into(),
            meshes: "plate,element,nx,ny,free_dofs,omega1_rad_s,omega_max_rad_s,modes_cpu_s\n"
                .into(),
            periods: "scene,modal_ratio,element,nx,ny,dt,replica,period,mean_energy_J,\
                      rms_corner_m,mean_abs_base_force_N,impacts,contact_loss_J,share_above_1khz\n"
                .into(),
        }
    }

    fn write(&self, dir: &StudyDir, series: bool) -> Result<(), String> {
        dir.write("modal_damping.csv", &self.statistics)?;
        dir.write("modal_damping_bands.csv", &self.bands)?;
        dir.write("modal_damping_meshes.csv", &self.meshes)?;
        if series {
            dir.write("modal_damping_periods.csv", &self.periods)?;
        }
        Ok(())
    }

    /// The rows of one setting: its statistics, its bands, and with `series` its periods.
    fn add(
        &mut self,
        plan: &Plan,
        line: &Line,
        s: &Setting,
        modes: &MeshModes,
        runs: &[Run],
        cost: &Cost,
    ) {
        let series = line.series;
        let (all, window) = estimates(plan, s, runs);
        let first = (plan.transient * s.forcing.frequency).round() as usize;
        let steady = &runs[0].periods[first..];
        let key = format!(
            "{},{},{},{},{}",
            s.forcing.label,
            s.zeta,
            element_name(s.mesh.element),
            s.mesh.nx,
            s.mesh.ny
        );
        for (q, e) in QUANTITIES.iter().zip(&all) {
            writeln!(
                self.statistics,
                "{},{},modal,{},{},{},{},{},{:e},{:.6e},{:.10e},{:.4e},{:.3},{:.2},{:.2},{:.3},\
                 {:.4e},{:.4e},{:.4e},{:.3},{},{},{window},{},{}",
                q.name,
                s.forcing.label,
                s.zeta,
                element_name(s.mesh.element),
                s.mesh.nx,
                s.mesh.ny,
                modes.free_dofs,
                s.dt,
                modes.omega_max * s.dt,
                e.value,
                e.spread(),
                cost.wall_s,
                cost.cpu_s,
                cost.set_up_cpu_s,
                cost.step_us,
                e.window_spread,
                e.correlation_spread,
                e.replica_spread,
                e.tau_periods,
                e.tau_resolved,
                steady.len(),
                e.windows,
                runs.len() - 1,
            )
            .expect("write to string");
        }
        let total: f64 = steady.iter().map(|p| p.bands.iter().sum::<f64>()).sum();
        for (b, &low) in BAND_EDGES_HZ.iter().enumerate() {
            let band = |ps: &[Period]| {
                ps.iter().map(|p| p.bands[b]).sum::<f64>()
                    / ps.iter().map(|p| p.modal_samples as f64).sum::<f64>()
            };
            let e = estimate(&band, &[steady], window);
            let share = steady.iter().map(|p| p.bands[b]).sum::<f64>() / total;
            let high = BAND_EDGES_HZ
                .get(b + 1)
                .map_or("inf".to_string(), |h| h.to_string());
            let count = modes.band.iter().filter(|&&k| k == b).count();
            writeln!(
                self.bands,
                "{key},{:e},{},{high},{count},{:.6e},{:.3e},{share:.6e}",
                s.dt,
                low,
                e.value,
                e.spread(),
            )
            .expect("write to string");
        }
        if series {
            for (r, run) in runs.iter().enumerate() {
                for (j, p) in run.periods.iter().enumerate() {
                    let one = std::slice::from_ref(p);
                    let v = |i: usize| QUANTITIES[i].over(one);
                    writeln!(
                        self.periods,
                        "{key},{:e},{r},{j},{:.8e},{:.8e},{:.8e},{},{:.6e},{:.6e}",
                        s.dt,
                        v(0),
                        v(1),
                        v(2),
                        p.tally.impacts,
                        p.tally.contact_loss,
                        v(6),
                    )
                    .expect("write to string");
                }
            }
        }
    }
}

/// Runs one setting: its main run and replicas on one stepper (the replicas restore the initial
/// state, perturbed on the first mode). Returns the runs and the main run's cost.
fn run_setting(
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

/// The meta file: the commit that ran, the settings, the runs left out for their cost, and
/// whether the plan ran to its end.
fn meta(
    plan: &Plan,
    args: &[String],
    started: Instant,
    left_out: &[String],
    complete: bool,
) -> String {
    let mut parts: Vec<&str> = plan.lines.iter().map(|l| l.part).collect();
    parts.dedup();
    let mut meta = String::from("key,value\n");
    for (k, v) in [
        ("commit", source_revision()),
        ("plan", plan.name.to_string()),
        ("arguments", args.join(" ")),
        ("complete", complete.to_string()),
        ("total_s", format!("{:.1}", started.elapsed().as_secs_f64())),
        ("cpu_s", format!("{:.1}", cpu_seconds())),
        ("transient_s", plan.transient.to_string()),
        ("duration_s", plan.duration.to_string()),
        ("window_s", plan.window.to_string()),
        ("parts", parts.join(" ")),
        ("settle_tolerance", plan.settle_tolerance.to_string()),
        ("overrides", plan.overrides.join(" ")),
        ("replica_perturbation", REPLICA_PERTURBATION.to_string()),
        ("sample_interval_s", SAMPLE_INTERVAL.to_string()),
        ("modal_sample_interval_s", MODAL_SAMPLE_INTERVAL.to_string()),
        ("left_out", left_out.join("; ")),
    ] {
        writeln!(meta, "{k},{v}").expect("write to string");
    }
    meta
}

fn study() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dir = StudyDir::from_args(&args, "modal_damping", "accuracy")?;
    let (plan, partial) = plan_of(&args, dir.quick)?;
    if args.iter().any(|a| a == "--plan") {
        for line in &plan.lines {
            println!(
                "{:<9} {:<17} ζ={:<6} {:<14} Δt {:?} s, runs ≤ {} CPU s, {} replicas{}",
                line.part,
                line.forcing.label,
                line.zeta,
                line.mesh.name(),
                line.ladder,
                line.max_run_cpu,
                line.replicas,
                if line.series { ", series" } else { "" }
            );
        }
        return Ok(());
    }
    let started = Instant::now();
    let mut tables = Tables::new();
    let mut left_out = Vec::new();
    let mut cache: Vec<(Plate, Mesh, MeshModes)> = Vec::new();
    for (i, line) in plan.lines.iter().enumerate() {
        let plate = line.forcing.plate;
        let first = Setting {
            forcing: line.forcing,
            zeta: line.zeta,
            mesh: line.mesh,
            dt: line.ladder[0],
        };
        if !cache.iter().any(|(p, m, _)| *p == plate && *m == line.mesh) {
            let modes = MeshModes::of(&scene_of(&first, &plan.overrides)?)?;
            writeln!(
                tables.meshes,
                "{plate:?},{},{},{},{},{:.6},{:.6e},{:.2}",
                element_name(line.mesh.element),
                line.mesh.nx,
                line.mesh.ny,
                modes.free_dofs,
                modes.omega1,
                modes.omega_max,
                modes.set_up_cpu_s
            )
            .expect("write to string");
            cache.push((plate, line.mesh, modes));
        }
        let (_, _, modes) = cache
            .iter()
            .find(|(p, m, _)| *p == plate && *m == line.mesh)
            .expect("cached above");
        let mut previous: Option<(Vec<Estimate>, Cost)> = None;
        for &dt in &line.ladder {
            let s = Setting { dt, ..first };
            let steps = (plan.transient + plan.duration) / dt;
            // The CPU time per step falls as Δt falls (fewer bound checks per step), so the last
            // run's is an upper estimate.
            let estimate = previous
                .as_ref()
                .map_or(0.0, |(_, c)| c.set_up_cpu_s + steps * c.step_us * 1e-6);
            if estimate > line.max_run_cpu {
                let what = format!(
                    "{} ζ={} {} Δt ≤ {dt:e} s (estimated {estimate:.0} CPU s)",
                    s.forcing.label,
                    s.zeta,
                    s.mesh.name()
                );
                eprintln!("left out: {what}");
                left_out.push(what);
                break;
            }
            let (runs, cost) = run_setting(&plan, line.replicas, &s, modes)?;
            tables.add(&plan, line, &s, modes, &runs, &cost);
            tables.write(&dir, plan.lines.iter().any(|l| l.series))?;
            // Written after every run too, so that a study cut short records what it ran.
            let unfinished = meta(&plan, &args, started, &left_out, false);
            dir.write("modal_damping_meta.csv", &unfinished)?;
            eprintln!(
                "[{:>3}/{}] {:<17} ζ={:<6} {:<14} Δt={:<6e} ω_max·Δt={:<9.3} {:>7.1} s, {:>6.1} CPU s, \
                 {:.2} µs/step (study {:.0} s)",
                i + 1,
                plan.lines.len(),
                s.forcing.label,
                s.zeta,
                s.mesh.name(),
                s.dt,
                modes.omega_max * s.dt,
                cost.wall_s,
                cost.cpu_s,
                cost.step_us,
                started.elapsed().as_secs_f64()
            );
            let (now, _) = estimates(&plan, &s, &runs);
            let done = previous
                .as_ref()
                .is_some_and(|(before, _)| settled(before, &now, plan.settle_tolerance));
            previous = Some((now, cost));
            if done {
                break;
            }
        }
    }
    dir.write(
        "modal_damping_meta.csv",
        &meta(&plan, &args, started, &left_out, true),
    )?;
    if partial {
        eprintln!(
            "partial study done: concatenate its CSVs with the other parts', then run \
             `python -m plateimpact_tools.studies.modal_damping_plots DIR` on them"
        );
        return Ok(());
    }
    dir.plot("modal_damping_plots")?;
    dir.finish(dir.missing(&[
        "modal_damping.csv",
        "modal_damping_bands.csv",
        "modal_damping.md",
        "modal_damping_bands.png",
    ]))
}
