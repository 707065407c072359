//! Writing the modal damping study's CSVs: `modal_damping.csv` (a row per setting and quantity),
//! `modal_damping_bands.csv` (the energy of each band of modes), `modal_damping_meshes.csv`,
//! `modal_damping_periods.csv` (the per-period series) and `modal_damping_meta.csv`.

use super::plan::{Line, Mesh, Plan, Plate, Setting};
use super::run::{
    cpu_seconds, estimate, estimates, Cost, MeshModes, Period, Run, BAND_EDGES_HZ,
    MODAL_SAMPLE_INTERVAL, QUANTITIES, REPLICA_PERTURBATION,
};
use plate_impact_studies::element::element_name;
use plate_impact_studies::output::StudyDir;
use plate_impact_studies::recorder::SAMPLE_INTERVAL;
use plate_impact_studies::revision::source_revision;
use std::fmt::Write as _;
use std::time::Instant;

/// The CSV text of a study, rewritten after every setting so that a study stopped early keeps
/// what ran.
pub struct Tables {
    pub statistics: String,
    pub bands: String,
    pub meshes: String,
    pub periods: String,
}

impl Tables {
    pub fn new() -> Tables {
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

    pub fn write(&self, dir: &StudyDir, series: bool) -> Result<(), String> {
        dir.write("modal_damping.csv", &self.statistics)?;
        dir.write("modal_damping_bands.csv", &self.bands)?;
        dir.write("modal_damping_meshes.csv", &self.meshes)?;
        if series {
            dir.write("modal_damping_periods.csv", &self.periods)?;
        }
        Ok(())
    }

    /// The rows of one setting: its statistics, its bands, and with `series` its periods.
    pub fn add(
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

/// The meta file: the commit that ran, the settings, the runs left out for their cost, and
/// whether the plan ran to its end.
pub fn meta(
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

impl Tables {
    /// The row of a plate and mesh in `modal_damping_meshes.csv`.
    pub fn add_mesh(&mut self, plate: Plate, mesh: Mesh, modes: &MeshModes) {
        writeln!(
            self.meshes,
            "{plate:?},{},{},{},{},{:.6},{:.6e},{:.2}",
            element_name(mesh.element),
            mesh.nx,
            mesh.ny,
            modes.free_dofs,
            modes.omega1,
            modes.omega_max,
            modes.set_up_cpu_s
        )
        .expect("write to string");
    }
}
