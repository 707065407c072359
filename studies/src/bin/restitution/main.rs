//! What the impact laws do in a scene: the measurements behind docs/restitution/ (the single runs
//! are plotted by `plateimpact_tools.studies.restitution`), and the per-step cost of the laws.
//!
//! `cargo run --release -p plate_impact_studies --bin restitution -- <scene> [key=value ...] [--csv FILE] [--every N]`
//!
//! runs the scene (`default` or a file stem of `scenes/`; overrides as for the `scene` example,
//! e.g. `solver.restitution=0.5 solver.time_step=1e-5 solver.impact_law=newton`) and prints one
//! JSON object on stdout ([`Watch::summary`]: energies, where contacts act, contact loss, QPs).
//! With `--csv FILE` the trajectory goes to FILE (`t,corner1,energy_total`, every N-th step with
//! `--every N`, n = 0 first).
//!
//! `cargo run --release -p plate_impact_studies --bin restitution -- --timing E1,E2,... <scene> [key=value ...]`
//!
//! instead times the scene's steps for each restitution E1, E2, … in one process (five runs each,
//! medians), split into steps proven contact-free by the screening, steps checked free in full,
//! and steps needing a QP; it prints one line per e.
//!
//! `cargo run --release -p plate_impact_studies --bin restitution -- --study [--quick] [--out DIR]`
//!
//! runs the study of docs/restitution/ and writes its CSVs there ([`study`]); `--quick` runs a
//! small subset into a temporary directory to check the pipeline.

use plate_impact::element::ElementKind;
use plate_impact::fmi::fmi2::instance::Fmi2;
use plate_impact::fmi::instance::{Instance, Version};
use plate_impact::fmi::model::StepOptions;
use plate_impact::fmi::plate::PlateModel;
use plate_impact::fmi::variables::{vr, Causality, Kind};
use plate_impact::scene::{ImpactLaw, Scene};
use plate_impact::scheme::{StepPath, StepReport, Stepper};
use plate_impact_studies::cli::{exit_code, positive_integer, set_override};
use plate_impact_studies::element::element_name;
use plate_impact_studies::order::observed_order;
use plate_impact_studies::output::StudyDir;
use plate_impact_studies::recorder::{stride, Recorder, Tally, Windows};
use plate_impact_studies::sample::mean_variance;
use plate_impact_studies::windows::{window_spread, Quantity};
use serde_json::json;
use std::fmt::Write as _;
use std::io::Write;
use std::process::ExitCode;
use std::time::Instant;

const USAGE: &str = "usage: restitution [--timing E1,E2,...] <scene> [key=value ...] [--csv FILE] \
                     [--every N] | restitution --study [--quick] [--out DIR]";

fn main() -> ExitCode {
    exit_code(run())
}

/// The command line of a single run or a timing.
struct Options {
    scene: Scene,
    timing: Option<Vec<f64>>,
    csv: Option<String>,
    every: u64,
}

fn parse(args: &[String]) -> Result<Options, String> {
    let mut args = args.iter().cloned().peekable();
    let timing = if args.peek().map(String::as_str) == Some("--timing") {
        args.next();
        let list = args.next().ok_or("--timing needs a list E1,E2,...")?;
        let values: Result<Vec<f64>, _> = list.split(',').map(str::parse).collect();
        Some(values.map_err(|e| format!("--timing {list}: {e}"))?)
    } else {
        None
    };
    let name = args.next().ok_or(USAGE)?;
    let mut options = Options {
        scene: Scene::named(&name).map_err(|e| e.to_string())?,
        timing,
        csv: None,
        every: 1,
    };
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--csv" => options.csv = Some(args.next().ok_or("--csv needs a file name")?),
            "--every" => options.every = positive_integer("--every", args.next())?,
            _ => set_override(&mut options.scene, &arg, USAGE)?,
        }
    }
    Ok(options)
}

fn run() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) == Some("--study") {
        return study(&StudyDir::from_args(&args, "restitution", "restitution")?);
    }
    let options = parse(&args)?;
    match &options.timing {
        Some(restitutions) => timing(&options.scene, restitutions),
        None => measure(&options),
    }
}

// ------------------------------------------------------------------ what a run observes

/// Round-off of a constrained value u = z + Cq relative to the gap: a vertex on its bound sits
/// on it to 1e-16 m (measured), so anything within 1e-12 of the gap is on it.
const ON_BOUND: f64 = 1e-12;

/// What a run observed, step by step after the start step.
struct Watch {
    lower: Option<f64>,
    upper: Option<f64>,
    /// Distance from an obstacle below which a vertex counts as on it (m).
    on: f64,
    /// u_{n−1} and u_n at the constrained vertices.
    older: Vec<f64>,
    previous: Vec<f64>,
    /// Per vertex: the consecutive steps, up to the last, after which a contact force held it
    /// above its obstacle.
    held_for: Vec<u32>,
    /// E_{n+½} after the first step, the last, the largest after the first, and the largest rise
    /// of one step (J).
    energy_first: f64,
    energy_last: f64,
    energy_max: f64,
    worst_rise: f64,
    /// How far any constrained vertex went past an obstacle (m; ≤ 0: none did, then minus the
    /// closest approach).
    penetration: f64,
    /// The largest height above its obstacle at which a force turned a vertex: the nearer of
    /// u_n and u_{n+1} to the obstacle (m); and the same over the contacts that were closing
    /// (the vertex approached the obstacle, u_n nearer to it than u_{n−1}) and the others.
    turn: f64,
    turn_closing: f64,
    turn_other: f64,
    /// The largest arriving speed |v_{n−½}| at a closing contact (m/s).
    fastest_arrival: f64,
    /// The largest height u_{n+1} above its obstacle at which a force held a vertex (m).
    held: f64,
    /// Vertex-steps held above the obstacle in the second or a later consecutive step (hovering),
    /// the largest height of those (m), and the longest run of consecutive held steps.
    hover_steps: u64,
    hover: f64,
    longest_hold: u32,
    /// Vertex-steps with a contact force, those whose vertex the force holds on the obstacle,
    /// steps with a QP, and the repeated contact solves of the persistent law (steps that had
    /// one, and in all).
    contact_vertex_steps: u64,
    on_obstacle_vertex_steps: u64,
    contact_steps: u64,
    resolved_steps: u64,
    resolves: u64,
    /// The largest |½ f_i (u_{n+1,i} − u_{n−1,i})| of one contact in one step (J), and the largest
    /// |f_i|·gap seen (J), its scale.
    largest_contact_work: f64,
    work_scale: f64,
}

impl Watch {
    fn new(scene: &Scene, stepper: &Stepper) -> Watch {
        let levels = stepper.constrained_displacements();
        Watch {
            lower: scene.lower_obstacle(),
            upper: scene.upper_obstacle(),
            on: ON_BOUND * scene.gap(),
            older: levels.clone(),
            held_for: vec![0; levels.len()],
            previous: levels,
            energy_first: 0.0,
            energy_last: 0.0,
            energy_max: f64::NEG_INFINITY,
            worst_rise: f64::NEG_INFINITY,
            penetration: f64::NEG_INFINITY,
            turn: 0.0,
            turn_closing: 0.0,
            turn_other: 0.0,
            fastest_arrival: 0.0,
            held: 0.0,
            hover_steps: 0,
            hover: 0.0,
            longest_hold: 0,
            contact_vertex_steps: 0,
            on_obstacle_vertex_steps: 0,
            contact_steps: 0,
            resolved_steps: 0,
            resolves: 0,
            largest_contact_work: 0.0,
            work_scale: 0.0,
        }
    }

    /// Signed distance of u past the obstacles (> 0 inside one).
    fn past(&self, u: f64) -> f64 {
        let below = self.lower.map_or(f64::NEG_INFINITY, |g| g - u);
        let above = self.upper.map_or(f64::NEG_INFINITY, |g| u - g);
        below.max(above)
    }

    /// Reads step n (n ≥ 1) that `stepper` just took.
    fn observe(&mut self, n: u64, stepper: &Stepper, report: &StepReport, gap: f64) {
        let dt = stepper.scene().solver.time_step;
        self.contact_steps += u64::from(report.path != StepPath::Unconstrained);
        self.resolved_steps += u64::from(report.resolves > 0);
        self.resolves += u64::from(report.resolves);
        let next = stepper.constrained_displacements();
        for (i, (&u, &f)) in next.iter().zip(stepper.contact_forces()).enumerate() {
            self.penetration = self.penetration.max(self.past(u));
            if f == 0.0 || n == 1 {
                self.held_for[i] = 0;
                continue;
            }
            let obstacle = if f > 0.0 { self.lower } else { self.upper };
            let height = |v: f64| obstacle.map_or(f64::INFINITY, |g| (v - g).abs());
            let turn = height(self.previous[i]).min(height(u));
            self.turn = self.turn.max(turn);
            let travel = (self.previous[i] - self.older[i]).abs();
            if height(self.previous[i]) < height(self.older[i]) {
                self.turn_closing = self.turn_closing.max(turn);
                self.fastest_arrival = self.fastest_arrival.max(travel / dt);
            } else {
                self.turn_other = self.turn_other.max(turn);
            }
            self.contact_vertex_steps += 1;
            let work = 0.5 * f * (u - self.older[i]);
            self.largest_contact_work = self.largest_contact_work.max(work.abs());
            self.work_scale = self.work_scale.max(f.abs() * gap);
            if height(u) <= self.on {
                self.on_obstacle_vertex_steps += 1;
                self.held_for[i] = 0;
                continue;
            }
            self.held = self.held.max(height(u));
            self.held_for[i] += 1;
            self.longest_hold = self.longest_hold.max(self.held_for[i]);
            if self.held_for[i] >= 2 {
                self.hover_steps += 1;
                self.hover = self.hover.max(height(u));
            }
        }
        self.older = std::mem::replace(&mut self.previous, next);
        let energy = stepper.outputs().energy_total;
        if n == 1 {
            self.energy_first = energy;
        } else {
            self.worst_rise = self.worst_rise.max(energy - self.energy_last);
        }
        self.energy_last = energy;
        self.energy_max = self.energy_max.max(energy);
    }

    /// The run's summary, with the `contact_loss` output at its end.
    fn summary(&self, scene: &Scene, steps: u64, contact_loss: f64) -> serde_json::Value {
        json!({
            "restitution": scene.solver.restitution,
            "impact_law": scene.solver.impact_law,
            "time_step": scene.solver.time_step,
            "steps": steps,
            "energy_first": self.energy_first,
            "energy_last": self.energy_last,
            "energy_max": self.energy_max,
            "worst_rise": self.worst_rise,
            "contact_loss": contact_loss,
            "penetration": self.penetration,
            "standoff": self.turn,
            "turn_closing": self.turn_closing,
            "turn_other": self.turn_other,
            "fastest_arrival": self.fastest_arrival,
            "held": self.held,
            "hover": self.hover,
            "hover_steps": self.hover_steps,
            "longest_hold": self.longest_hold,
            "contact_vertex_steps": self.contact_vertex_steps,
            "on_obstacle_vertex_steps": self.on_obstacle_vertex_steps,
            "contact_steps": self.contact_steps,
            "resolved_steps": self.resolved_steps,
            "resolves": self.resolves,
            "largest_contact_work": self.largest_contact_work,
            "work_scale": self.work_scale,
        })
    }
}

/// Runs `scene` to its stop time, calling `sample(n, stepper)` at every step n ≥ 0 (after it).
fn watch(
    scene: &Scene,
    mut sample: impl FnMut(u64, &Stepper) -> Result<(), String>,
) -> Result<(Watch, serde_json::Value), String> {
    let dt = scene.solver.time_step;
    let steps = (scene.stop_time / dt).round() as u64;
    let mut stepper = Stepper::new(scene, scene.builtin_base(0.0)).map_err(|e| e.to_string())?;
    let mut w = Watch::new(scene, &stepper);
    sample(0, &stepper)?;
    for n in 1..=steps {
        let report = stepper
            .step(scene.builtin_base(n as f64 * dt))
            .map_err(|e| e.to_string())?;
        w.observe(n, &stepper, &report, scene.gap());
        sample(n, &stepper)?;
    }
    let summary = w.summary(scene, steps, stepper.outputs().contact_loss);
    Ok((w, summary))
}

/// Runs the scene with every diagnostic and prints the JSON summary.
fn measure(options: &Options) -> Result<(), String> {
    let mut csv = match &options.csv {
        Some(path) => {
            let file = std::fs::File::create(path).map_err(|e| format!("{path}: {e}"))?;
            let mut out = std::io::BufWriter::new(file);
            writeln!(out, "t,corner1,energy_total").map_err(|e| e.to_string())?;
            Some(out)
        }
        None => None,
    };
    let (_, summary) = watch(&options.scene, |n, stepper| match csv.as_mut() {
        Some(out) if n % options.every == 0 => {
            let o = stepper.outputs();
            writeln!(
                out,
                "{},{:e},{:e}",
                stepper.time(),
                o.corner1,
                o.energy_total
            )
            .map_err(|e| e.to_string())
        }
        _ => Ok(()),
    })?;
    if let Some(mut out) = csv {
        out.flush().map_err(|e| e.to_string())?;
    }
    println!("{summary}");
    Ok(())
}

/// Times the scene's steps for each restitution, five runs each, and prints one line per e: the
/// median over the runs of the time per step, and of the mean time of each kind of step.
fn timing(scene: &Scene, restitutions: &[f64]) -> Result<(), String> {
    const RUNS: usize = 5;
    let dt = scene.solver.time_step;
    let steps = (scene.stop_time / dt).round() as u64;
    let median = |mut xs: Vec<f64>| {
        xs.sort_by(f64::total_cmp);
        xs[xs.len() / 2]
    };
    for &e in restitutions {
        let mut s = scene.clone();
        s.set("solver.restitution", &e.to_string())
            .map_err(|e| e.to_string())?;
        // Per run: the time per step, and the count and total time of the steps screened free,
        // checked free and needing a QP (the counts are the same in every run).
        let mut runs = Vec::new();
        for _ in 0..RUNS {
            let mut stepper = Stepper::new(&s, s.builtin_base(0.0)).map_err(|e| e.to_string())?;
            let mut kinds = [(0u64, 0.0f64); 3];
            let clock = Instant::now();
            for n in 1..=steps {
                let z = s.builtin_base(n as f64 * dt);
                let t = Instant::now();
                let report = stepper.step(z).map_err(|e| e.to_string())?;
                let kind = match (report.path, report.bounds_evaluated) {
                    (StepPath::Unconstrained, false) => 0,
                    (StepPath::Unconstrained, true) => 1,
                    _ => 2,
                };
                kinds[kind].0 += 1;
                kinds[kind].1 += t.elapsed().as_secs_f64();
            }
            runs.push((clock.elapsed().as_secs_f64() / steps as f64, kinds));
        }
        let per_step = median(runs.iter().map(|r| r.0).collect());
        let kind = |k: usize| {
            let count = runs[0].1[k].0;
            let mean = median(
                runs.iter()
                    .map(|r| 1e6 * r.1[k].1 / count.max(1) as f64)
                    .collect(),
            );
            (count, mean)
        };
        let [(screened, t0), (checked, t1), (qp, t2)] = [kind(0), kind(1), kind(2)];
        println!(
            "e = {e}: {:.2} µs/step over {steps} steps (median of {RUNS} runs); screened free \
             {screened} at {t0:.2} µs, checked free {checked} at {t1:.2} µs, QP {qp} at {t2:.2} µs",
            1e6 * per_step
        );
    }
    Ok(())
}

// ------------------------------------------------------------------ the study of docs/restitution

/// The study of docs/restitution/, into `dir`:
/// * `fmu_energy.csv`: the `energy` scene at e = 1 through the FMU at four Δt ([`fmu_energy`]);
/// * `runs.csv`: the `energy` scene under each law against e and Δt ([`energy_runs`]);
/// * `contact_loss.csv`: every shipped scene without damping at e = 1 ([`undamped_scenes`]);
/// * `forced.csv`: the forced scenes' statistics at e = 1 under both laws ([`forced_statistics`]);
/// * `convergence.csv`: the `energy` scene at e = 1 against Δt and mesh ([`convergence`]).
fn study(dir: &StudyDir) -> Result<(), String> {
    let files = [
        ("fmu_energy.csv", fmu_energy(dir.quick)?),
        ("runs.csv", energy_runs(dir.quick)?),
        ("contact_loss.csv", undamped_scenes(dir.quick)?),
        ("forced.csv", forced_statistics(dir.quick)?),
        ("convergence.csv", convergence(dir.quick)?),
    ];
    for (name, text) in &files {
        dir.write(name, text)?;
    }
    let names: Vec<&str> = files.iter().map(|(name, _)| *name).collect();
    println!("wrote {} into {}", names.join(", "), dir.path.display());
    dir.finish(dir.missing(&names))
}

/// The `energy` scene (10 × 7 Argyris, released onto g1 = −10 mm, fixed base) with restitution
/// e, law `law`, time step Δt and horizon `stop` (s).
fn energy_scene(e: f64, law: ImpactLaw, dt: f64, stop: f64) -> Scene {
    let mut s = Scene::named("energy").expect("a shipped scene");
    s.solver.restitution = e;
    s.solver.impact_law = law;
    s.solver.time_step = dt;
    s.stop_time = stop;
    s
}

/// The CSV name of a law.
fn law_name(law: ImpactLaw) -> &'static str {
    match law {
        ImpactLaw::Auto => "auto",
        ImpactLaw::Newton => "newton",
        ImpactLaw::Persistent => "persistent",
    }
}

/// Sets every FMU parameter of `scene` on `inst` (the variable names are the scene's paths).
fn set_parameters<V: Version>(
    inst: &mut Instance<V, PlateModel>,
    scene: &Scene,
) -> Result<(), String> {
    let tree = serde_json::to_value(scene).map_err(|e| e.to_string())?;
    for v in V::description::<PlateModel>()
        .variables
        .iter()
        .filter(|v| v.causality == Causality::Parameter)
    {
        let field = v.name.split('.').fold(&tree, |t, k| &t[k]);
        let done = match v.kind {
            Kind::Real => inst.set_real(&[v.vr], &[field.as_f64().unwrap_or(f64::NAN)]),
            Kind::Boolean => inst.set_boolean(&[v.vr], &[field.as_bool() == Some(true)]),
            Kind::Integer if v.vr == vr::MESH_ELEMENT => {
                let code = if field.as_str() == Some("argyris") {
                    1
                } else {
                    2
                };
                inst.set_integer(&[v.vr], &[code])
            }
            Kind::Integer => {
                let value = field.as_i64().and_then(|x| i32::try_from(x).ok());
                inst.set_integer(&[v.vr], &[value.unwrap_or(-1)])
            }
            _ => continue,
        };
        done.map_err(|f| format!("{}: {}", v.name, f.message))?;
    }
    Ok(())
}

/// The `energy` scene at e = 1 with time step Δt through the FMU's FMI 2.0 instance (the code
/// its exported functions run): E after a first communication step of Δt, E and the contact
/// loss after communication steps of 1 ms up to the scene's stop time (J).
fn through_the_fmu(scene: &Scene) -> Result<[f64; 3], String> {
    let failed = |f: plate_impact::fmi::status::Failure| f.message;
    let token = Fmi2::description::<PlateModel>().token;
    let mut inst = Instance::<Fmi2, PlateModel>::new("restitution", token, false, None)?;
    set_parameters(&mut inst, scene)?;
    inst.begin_initialization(Some((0.0, None)))
        .map_err(failed)?;
    inst.exit_initialization_mode().map_err(failed)?;
    let options = StepOptions {
        early_return: false,
    };
    let mut energy = [0.0];
    let dt = scene.solver.time_step;
    inst.step(0.0, dt, options).map_err(failed)?;
    inst.get_real(&[vr::ENERGY_TOTAL], &mut energy)
        .map_err(failed)?;
    let first = energy[0];
    let (mut t, points) = (dt, (scene.stop_time / 1e-3).round() as u32);
    for k in 1..=points {
        let next = f64::from(k) * 1e-3;
        inst.step(t, next - t, options).map_err(failed)?;
        t = next;
    }
    let mut last = [0.0; 2];
    inst.get_real(&[vr::ENERGY_TOTAL, vr::ENERGY_CONTACT_LOSS], &mut last)
        .map_err(failed)?;
    Ok([first, last[0], last[1]])
}

/// `fmu_energy.csv`: |E(1 s)/E(Δt) − 1| of the `energy` scene at e = 1 through the FMU at
/// Δt = 1e-4, 5e-5, 2.5e-5, 1e-5 and 1e-6 s, with the lower obstacle and, for the scheme's own
/// round-off, without it (quick: 1e-4 s over 0.1 s).
fn fmu_energy(quick: bool) -> Result<String, String> {
    let (steps, stop): (&[f64], f64) = if quick {
        (&[1e-4], 0.1)
    } else {
        (&[1e-4, 5e-5, 2.5e-5, 1e-5, 1e-6], 1.0)
    };
    let mut csv = String::from(
        "dt,obstacle,stop_s,energy_first_J,energy_last_J,relative_change,contact_loss_J\n",
    );
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
            let row = format!("{dt:e},{obstacle},{stop},{first:e},{last:e},{change:e},{loss:e}");
            writeln!(csv, "{row}").expect("a String");
        }
    }
    Ok(csv)
}

/// The header of a run's row, and its values from [`Watch::summary`].
const RUN_COLUMNS: &str = "energy_first_J,energy_last_J,relative_change,worst_rise_J,\
contact_loss_J,penetration_m,turn_m,turn_closing_m,turn_other_m,fastest_arrival_m_s,held_m,\
hover_m,hover_steps,longest_hold,contact_vertex_steps,on_obstacle_vertex_steps,contact_steps,\
resolved_steps,resolves,largest_contact_work_J,work_scale_J";

fn run_values(s: &serde_json::Value) -> String {
    let first = s["energy_first"].as_f64().unwrap_or(f64::NAN);
    let last = s["energy_last"].as_f64().unwrap_or(f64::NAN);
    let keys = [
        "worst_rise",
        "contact_loss",
        "penetration",
        "standoff",
        "turn_closing",
        "turn_other",
        "fastest_arrival",
        "held",
        "hover",
        "hover_steps",
        "longest_hold",
        "contact_vertex_steps",
        "on_obstacle_vertex_steps",
        "contact_steps",
        "resolved_steps",
        "resolves",
        "largest_contact_work",
        "work_scale",
    ];
    let rest: Vec<String> = keys.iter().map(|k| s[k].to_string()).collect();
    format!(
        "{first:e},{last:e},{:e},{}",
        (last / first - 1.0).abs(),
        rest.join(",")
    )
}

/// `runs.csv`: the `energy` scene over 1 s under the laws `auto` (the persistent law for e > 0,
/// the paper's at e = 0), `newton` and `persistent` at Δt = 1e-4 s for e ∈ {0, 0.25, 0.5, 0.75,
/// 0.9, 1}, under `auto` and `newton` for e ∈ {0.5, 0.9, 1} at Δt = 5e-5, 2.5e-5 and 1e-5 s, and
/// for e = 1 at 5e-6, 2.5e-6 and 1e-6 s (quick: e = 1 at 1e-4 s over 0.1 s).
fn energy_runs(quick: bool) -> Result<String, String> {
    let laws = [ImpactLaw::Auto, ImpactLaw::Newton, ImpactLaw::Persistent];
    let mut cases = Vec::new();
    if quick {
        cases.extend(laws[..2].iter().map(|&law| (law, 1.0, 1e-4)));
    } else {
        for e in [0.0, 0.25, 0.5, 0.75, 0.9, 1.0] {
            cases.extend(laws.iter().map(|&law| (law, e, 1e-4)));
        }
        for dt in [5e-5, 2.5e-5, 1e-5] {
            for e in [0.5, 0.9, 1.0] {
                cases.extend(laws[..2].iter().map(|&law| (law, e, dt)));
            }
        }
        for dt in [5e-6, 2.5e-6, 1e-6] {
            cases.extend(laws[..2].iter().map(|&law| (law, 1.0, dt)));
        }
    }
    let stop = if quick { 0.1 } else { 1.0 };
    let mut csv = format!("law,e,dt,{RUN_COLUMNS}\n");
    for (law, e, dt) in cases {
        let (_, summary) = watch(&energy_scene(e, law, dt, stop), |_, _| Ok(()))?;
        println!(
            "energy, {}, e = {e}, Δt = {dt:e} s: {summary}",
            law_name(law)
        );
        writeln!(csv, "{},{e},{dt:e},{}", law_name(law), run_values(&summary)).expect("a String");
    }
    Ok(csv)
}

/// `contact_loss.csv`: every shipped scene without damping (`energy`, `forced`, `forced-30hz`,
/// `forced-35hz`) at e = 1 over 1 s, Δt = 1e-4 s, under `auto` and `newton` (quick: 0.05 s).
fn undamped_scenes(quick: bool) -> Result<String, String> {
    let mut csv = format!("scene,law,{RUN_COLUMNS}\n");
    for name in ["energy", "forced", "forced-30hz", "forced-35hz"] {
        for law in [ImpactLaw::Auto, ImpactLaw::Newton] {
            let mut scene = Scene::named(name).map_err(|e| e.to_string())?;
            scene.solver.restitution = 1.0;
            scene.solver.impact_law = law;
            scene.stop_time = if quick { 0.05 } else { 1.0 };
            let (_, summary) = watch(&scene, |_, _| Ok(()))?;
            println!("{name}, {}, e = 1: {summary}", law_name(law));
            writeln!(csv, "{name},{},{}", law_name(law), run_values(&summary)).expect("a String");
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
fn windows(scene: &Scene, transient: f64, length: f64) -> Result<Vec<Tally>, String> {
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
fn forced_statistics(quick: bool) -> Result<String, String> {
    let (transient, length, count) = if quick { (0.1, 0.05, 2) } else { (1.0, 1.0, 4) };
    let mut csv = String::from("scene,law,quantity,mean,spread,first_window,last_window\n");
    for name in ["forced-35hz", "forced-30hz", "forced", "forced-35hz-damped"] {
        for law in [ImpactLaw::Auto, ImpactLaw::Newton] {
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
                writeln!(
                    csv,
                    "{name},{},{quantity},{mean:e},{spread:e},{:e},{:e}",
                    law_name(law),
                    xs[0],
                    xs[xs.len() - 1]
                )
                .expect("a String");
            }
        }
    }
    Ok(csv)
}

/// A run of the convergence study: E after the first step (J), the time of the first contact (s)
/// and the free corner u(Lx, 0) every 1e-4 s (m).
struct Trajectory {
    energy_first: f64,
    first_contact: f64,
    corner: Vec<f64>,
    /// The run's [`run_values`].
    summary: String,
}

/// The sampling interval of [`Trajectory::corner`] (s): every Δt of the study divides it.
const SAMPLE: f64 = 1e-4;

fn trajectory(scene: &Scene) -> Result<Trajectory, String> {
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

/// The ends of the windows [0, T] over which corner errors are taken: the reference's first
/// contact, then 0.05, 0.2 and 1 s.
const HORIZONS: [f64; 3] = [0.05, 0.2, 1.0];

/// The largest |corner − reference| over [0, T] for T = the reference's first contact and
/// [`HORIZONS`] (m).
fn corner_errors(run: &Trajectory, reference: &Trajectory) -> [f64; 4] {
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

/// One convergence run: its series, element, mesh and Δt.
type Setting = (&'static str, ElementKind, usize, usize, f64);

/// A run's errors against its series' reference: at `x` (Δt, or 1/nx), of E(Δt) (J) and of the
/// corner over the windows of [`corner_errors`] (m).
struct Errors {
    x: f64,
    energy: f64,
    corner: [f64; 4],
}

/// The meshes (nx, ny) of the mesh series of each element.
type Meshes = [&'static [(usize, usize)]; 2];

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
        let &(series, element, nx, ny, dt) = setting;
        let e = corner_errors(run, &reference);
        let energy_error = (run.energy_first - reference.energy_first).abs();
        errors.push(Errors {
            x: x(setting),
            energy: energy_error,
            corner: e,
        });
        writeln!(
            rows,
            "{series},{},{nx},{ny},{dt:e},{:e},{energy_error:e},{:e},{:e},{:e},{:e},{}",
            element_name(element),
            run.first_contact,
            e[0],
            e[1],
            e[2],
            e[3],
            run.summary
        )
        .expect("a String");
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
/// Δt = [`MESH_TIME_STEP`], four meshes of each element): E(Δt), E(1 s), the first contact, and
/// the largest distance of the free corner from the series' last (finest) run over [0, T]; the
/// finest meshes of the two elements are also compared with each other (series `elements`).
/// Quick: Argyris 2 × 1 and FVS 4 × 3 over 0.02 s.
fn convergence(quick: bool) -> Result<String, String> {
    use ElementKind::{Argyris, Fvs};
    let (stop, steps, meshes): (f64, &[f64], Meshes) = if quick {
        (
            0.02,
            &[1e-4, 5e-5, 2.5e-5],
            [&[(1, 1), (2, 1)], &[(2, 2), (4, 3)]],
        )
    } else {
        (
            1.0,
            &[1e-4, 5e-5, 2.5e-5, 1e-5, 5e-6, 2.5e-6, 1e-6],
            [
                &[(2, 1), (4, 2), (6, 4), (10, 7)],
                &[(4, 3), (7, 5), (10, 7), (14, 10)],
            ],
        )
    };
    let mut csv = format!(
        "series,element,nx,ny,dt,first_contact_s,energy_first_error_J,\
         corner_error_to_first_contact_m,corner_error_to_0.05s_m,corner_error_to_0.2s_m,\
         corner_error_to_1s_m,{RUN_COLUMNS}\n",
    );
    for (element, paper) in [(Argyris, (10, 7)), (Fvs, (14, 10))] {
        let (nx, ny) = if quick { (2, 1) } else { paper };
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
    writeln!(
        csv,
        "elements,fvs-argyris,,,{MESH_TIME_STEP:e},{:e},{gap:e},{:e},{:e},{:e},{:e},{}",
        finest[1].first_contact, e[0], e[1], e[2], e[3], finest[1].summary
    )
    .expect("a String");
    Ok(csv)
}

/// The time step of the mesh series of [`convergence`] (s).
const MESH_TIME_STEP: f64 = 1e-5;
