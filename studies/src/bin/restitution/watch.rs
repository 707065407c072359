//! What a run of a scene observes step by step: energies, where contacts act and turn, contact
//! loss, QPs ([`Watch`]), and the loop that runs a scene under watch.

use plate_impact::scene::Scene;
use plate_impact::scheme::{StepPath, StepReport, Stepper};
use serde_json::json;

/// Round-off of a constrained value u = z + Cq relative to the gap: a vertex on its bound sits
/// on it to 1e-16 m (measured), so anything within 1e-12 of the gap is on it.
const ON_BOUND: f64 = 1e-12;

/// What a run observed, step by step after the start step.
pub struct Watch {
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
    pub energy_first: f64,
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
pub fn watch(
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
