//! Running the restitution study: the simulations behind each CSV of docs/restitution/ (the
//! `energy` scene through the FMU, the `energy` scene and the undamped scenes watched run by run,
//! the forced scenes' window statistics, the convergence series in Δt and mesh), each CSV's rows
//! written by write.rs as its runs end, and what they print on the way.

use super::fmu::through_the_fmu;
use super::plan::{
    convergence_plan, dt_series_mesh, energy_run_cases, energy_scene, fmu_energy_cases,
    forced_windows, undamped_stop, Setting, FORCED_SCENES, HORIZONS, LAWS, MESH_TIME_STEP, SAMPLE,
    UNDAMPED_SCENES,
};
use super::watch::watch;
use super::write::{
    contact_loss_header, contact_loss_row, convergence_header, convergence_row, elements_row,
    energy_run_row, energy_runs_header, fmu_energy_row, forced_row, law_name, run_values,
    FMU_ENERGY_HEADER, FORCED_HEADER,
};
use plate_impact::element::ElementKind;
use plate_impact::scene::{ImpactLaw, Scene};
use plate_impact::scheme::Stepper;
use plate_impact_studies::order::observed_order;
use plate_impact_studies::recorder::{stride, Recorder, Tally, Windows};
use plate_impact_studies::sample::mean_variance;
use plate_impact_studies::windows::{window_spread, Quantity};

/// `fmu_energy.csv`: |E(1 s)/E(Δt) − 1| of the `energy` scene at e = 1 through the FMU at
/// Δt = 1e-4, 5e-5, 2.5e-5, 1e-5 and 1e-6 s, with the lower obstacle and, for the scheme's own
/// round-off, without it (quick: 1e-4 s over 0.1 s).
pub fn fmu_energy(quick: bool) -> Result<String, String> {
    let (steps, stop) = fmu_energy_cases(quick);
    let mut csv = String::from(FMU_ENERGY_HEADER);
    for &dt in steps {
        for obstacle in [true, false] {
            let mut scene = energy_scene(1.0, ImpactLaw::Auto, dt, stop);
            scene.obstacle.lower_enabled = obstacle;
            let [first, last, loss] = through_the_fmu(&scene)?;
            let change = (last / first - 1.0).abs();
            println!(
                "FMU, e = 1, Δt = {dt:e} s, obstacle {obstacle}: E {first} → {last} J, \
                 |E(1 s)/E(Δt) − 1| = {change:.1e}, contact loss {loss:.1e} J"
            );
            fmu_energy_row(&mut csv, dt, obstacle, stop, [first, last, change, loss]);
        }
    }
    Ok(csv)
}

/// `runs.csv`: the `energy` scene over 1 s under the laws `auto` (the persistent law for e > 0,
/// the paper's at e = 0), `newton` and `persistent` at Δt = 1e-4 s for e ∈ {0, 0.25, 0.5, 0.75,
/// 0.9, 1}, under `auto` and `newton` for e ∈ {0.5, 0.9, 1} at Δt = 5e-5, 2.5e-5 and 1e-5 s, and
/// for e = 1 at 5e-6, 2.5e-6 and 1e-6 s (quick: e = 1 at 1e-4 s over 0.1 s).
pub fn energy_runs(quick: bool) -> Result<String, String> {
    let (cases, stop) = energy_run_cases(quick);
    let mut csv = energy_runs_header();
    for (law, e, dt) in cases {
        let (_, summary) = watch(&energy_scene(e, law, dt, stop), |_, _| Ok(()))?;
        println!(
            "energy, {}, e = {e}, Δt = {dt:e} s: {summary}",
            law_name(law)
        );
        energy_run_row(&mut csv, law, e, dt, &summary);
    }
    Ok(csv)
}

/// `contact_loss.csv`: every shipped scene without damping (`energy`, `forced`, `forced-30hz`,
/// `forced-35hz`) at e = 1 over 1 s, Δt = 1e-4 s, under `auto` and `newton` (quick: 0.05 s).
pub fn undamped_scenes(quick: bool) -> Result<String, String> {
    let mut csv = contact_loss_header();
    for name in UNDAMPED_SCENES {
        for law in LAWS {
            let mut scene = Scene::named(name).map_err(|e| e.to_string())?;
            scene.solver.restitution = 1.0;
            scene.solver.impact_law = law;
            scene.stop_time = undamped_stop(quick);
            let (_, summary) = watch(&scene, |_, _| Ok(()))?;
            println!("{name}, {}, e = 1: {summary}", law_name(law));
            contact_loss_row(&mut csv, name, law, &summary);
        }
    }
    Ok(csv)
}

/// The statistics of a forced run read from each window, in the order of [`WINDOW_QUANTITIES`]:
/// RMS and peak |u| of the free corner (m), impacts, energy removed at the obstacles (J), mean
/// `energy.total` (J) and mean |`base.force`| (N). Every step of a window is sampled.
fn window_values(w: &Tally) -> [f64; 6] {
    let one = std::slice::from_ref(w);
    [
        Quantity::RMS_CORNER.over(one),
        w.corner_peak,
        IMPACTS.over(one),
        CONTACT_LOSS.over(one),
        Quantity::MEAN_ENERGY.over(one),
        Quantity::MEAN_ABS_BASE_FORCE.over(one),
    ]
}

/// The impacts of a window.
const IMPACTS: Quantity<Tally> = Quantity::new("impacts", |t| t.impacts as f64, |_| 1.0, false);

/// The energy removed at the obstacles in a window (J).
const CONTACT_LOSS: Quantity<Tally> =
    Quantity::new("contact_loss_J", |t| t.contact_loss, |_| 1.0, false);

const WINDOW_QUANTITIES: [&str; 6] = [
    "rms_corner_m",
    "peak_corner_m",
    "impacts",
    "contact_loss_J",
    "mean_energy_J",
    "mean_abs_base_force_N",
];

/// The windows of `scene` after a transient of `transient` s: consecutive windows of `length` s
/// up to the stop time.
pub fn windows(scene: &Scene, transient: f64, length: f64) -> Result<Vec<Tally>, String> {
    let dt = scene.solver.time_step;
    let per_window = (length / dt).round() as usize;
    let skip = (transient / dt).round() as usize;
    let steps = (scene.stop_time / dt).round() as usize;
    let count = (steps - skip) / per_window;
    let recorder = Recorder {
        windows: Windows::Bounds((0..=count).map(|j| skip + j * per_window).collect()),
        steps,
        stride: 1,
    };
    let mut stepper = Stepper::new(scene, scene.builtin_base(0.0)).map_err(|e| e.to_string())?;
    let mut out = vec![Tally::default(); count];
    recorder.run(&mut stepper, "forced", &mut out, |_, _, _| Ok(()))?;
    Ok(out)
}

/// `forced.csv`: the forced scenes (`forced-35hz`, `forced-30hz`, `forced`, and the damped
/// `forced-35hz-damped`) at e = 1 under `auto` and `newton`, Δt = 1e-4 s, 10 × 7 Argyris: 1 s of
/// transient, then four windows of 1 s; per quantity the mean over the windows, its spread (the
/// windows' standard deviation / √4) and the first and last window's value (quick: windows of
/// 0.05 s after 0.1 s).
pub fn forced_statistics(quick: bool) -> Result<String, String> {
    let (transient, length, count) = forced_windows(quick);
    let mut csv = String::from(FORCED_HEADER);
    for name in FORCED_SCENES {
        for law in LAWS {
            let mut scene = Scene::named(name).map_err(|e| e.to_string())?;
            scene.solver.restitution = 1.0;
            scene.solver.impact_law = law;
            scene.stop_time = transient + length * f64::from(count);
            let values: Vec<[f64; 6]> = windows(&scene, transient, length)?
                .iter()
                .map(window_values)
                .collect();
            for (q, quantity) in WINDOW_QUANTITIES.iter().enumerate() {
                let xs: Vec<f64> = values.iter().map(|v| v[q]).collect();
                let (mean, _) = mean_variance(&xs);
                let spread = window_spread(&xs);
                println!(
                    "{name}, {}, e = 1: {quantity} {mean:.4e} ± {spread:.1e}",
                    law_name(law)
                );
                forced_row(&mut csv, (name, law, quantity), mean, spread, &xs);
            }
        }
    }
    Ok(csv)
}

/// A run of the convergence study: E after the first step (J), the time of the first contact (s)
/// and the free corner u(Lx, 0) every 1e-4 s (m).
pub struct Trajectory {
    energy_first: f64,
    first_contact: f64,
    corner: Vec<f64>,
    /// The run's [`run_values`].
    summary: String,
}

pub fn trajectory(scene: &Scene) -> Result<Trajectory, String> {
    let every = stride(SAMPLE, scene.solver.time_step) as u64;
    let (mut corner, mut first_contact) = (Vec::new(), f64::INFINITY);
    let (w, summary) = watch(scene, |n, stepper| {
        if stepper.active_count() > 0 {
            first_contact = first_contact.min(stepper.time());
        }
        if n % every == 0 {
            corner.push(stepper.outputs().corner1);
        }
        Ok(())
    })?;
    Ok(Trajectory {
        energy_first: w.energy_first,
        first_contact,
        corner,
        summary: run_values(&summary),
    })
}

/// The largest |corner − reference| over [0, T] for T = the reference's first contact and
/// [`HORIZONS`] (m).
pub fn corner_errors(run: &Trajectory, reference: &Trajectory) -> [f64; 4] {
    let until = |t: f64| {
        let samples = ((t / SAMPLE).round() as usize + 1).min(run.corner.len());
        run.corner[..samples]
            .iter()
            .zip(&reference.corner)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
    };
    let first = reference.first_contact;
    [
        until(first),
        until(HORIZONS[0]),
        until(HORIZONS[1]),
        until(HORIZONS[2]),
    ]
}

/// A run's errors against its series' reference: at `x` (Δt, or 1/nx), of E(Δt) (J) and of the
/// corner over the windows of [`corner_errors`] (m).
struct Errors {
    x: f64,
    energy: f64,
    corner: [f64; 4],
}

/// The rows of one series, errors against its last setting (the reference), and the fitted orders
/// printed against `x` of each setting.
fn series_rows(
    settings: &[Setting],
    stop: f64,
    x: impl Fn(&Setting) -> f64,
) -> Result<(String, Trajectory), String> {
    let mut runs = Vec::new();
    for setting in settings {
        let &(_, element, nx, ny, dt) = setting;
        let mut scene = energy_scene(1.0, ImpactLaw::Auto, dt, stop);
        scene.mesh.element = element;
        (scene.mesh.nx, scene.mesh.ny) = (nx, ny);
        runs.push(trajectory(&scene)?);
    }
    let reference = runs.pop().ok_or("an empty series")?;
    let mut rows = String::new();
    let mut errors = Vec::new();
    for (setting, run) in settings.iter().zip(runs.iter().chain([&reference])) {
        let e = corner_errors(run, &reference);
        let energy_error = (run.energy_first - reference.energy_first).abs();
        errors.push(Errors {
            x: x(setting),
            energy: energy_error,
            corner: e,
        });
        convergence_row(
            &mut rows,
            setting,
            run.first_contact,
            energy_error,
            e,
            &run.summary,
        );
    }
    errors.pop();
    let xs: Vec<f64> = errors.iter().map(|e| e.x).collect();
    let order =
        |f: fn(&Errors) -> f64| observed_order(&xs, &errors.iter().map(f).collect::<Vec<_>>());
    println!(
        "{} {:?}: observed orders: E(Δt) {:.2}, corner to the first contact {:.2}, \
         to 0.05 s {:.2}, to 0.2 s {:.2}, to 1 s {:.2}",
        settings[0].0,
        settings[0].1,
        order(|e| e.energy),
        order(|e| e.corner[0]),
        order(|e| e.corner[1]),
        order(|e| e.corner[2]),
        order(|e| e.corner[3])
    );
    Ok((rows, reference))
}

/// `convergence.csv`: the `energy` scene at e = 1 (law `auto`) over 1 s against Δt (1e-4 down to
/// 1e-6 s, on the paper's meshes: Argyris 10 × 7 and FVS 14 × 10) and against the mesh (at
/// Δt = `MESH_TIME_STEP` (plan.rs), four meshes of each element): E(Δt), E(1 s), the first contact, and
/// the largest distance of the free corner from the series' last (finest) run over [0, T]; the
/// finest meshes of the two elements are also compared with each other (series `elements`).
/// Quick: Argyris 2 × 1 and FVS 4 × 3 over 0.02 s.
pub fn convergence(quick: bool) -> Result<String, String> {
    use ElementKind::{Argyris, Fvs};
    let (stop, steps, meshes) = convergence_plan(quick);
    let mut csv = convergence_header();
    for element in [Argyris, Fvs] {
        let (nx, ny) = dt_series_mesh(quick, element);
        let settings: Vec<Setting> = steps
            .iter()
            .map(|&dt| ("dt", element, nx, ny, dt))
            .collect();
        csv += &series_rows(&settings, stop, |s| s.4)?.0;
    }
    let mut finest = Vec::new();
    for (element, list) in [(Argyris, meshes[0]), (Fvs, meshes[1])] {
        let settings: Vec<Setting> = list
            .iter()
            .map(|&(nx, ny)| ("mesh", element, nx, ny, MESH_TIME_STEP))
            .collect();
        let (rows, reference) = series_rows(&settings, stop, |s| 1.0 / s.2 as f64)?;
        csv += &rows;
        finest.push(reference);
    }
    let e = corner_errors(&finest[1], &finest[0]);
    let gap = (finest[1].energy_first - finest[0].energy_first).abs();
    println!(
        "finest FVS against finest Argyris: E(Δt) differs by {gap:.2e} J; corner by {:.2e}, \
         {:.2e}, {:.2e}, {:.2e} m to the first contact, 0.05, 0.2 and 1 s",
        e[0], e[1], e[2], e[3]
    );
    elements_row(
        &mut csv,
        MESH_TIME_STEP,
        finest[1].first_contact,
        gap,
        e,
        &finest[1].summary,
    );
    Ok(csv)
}
