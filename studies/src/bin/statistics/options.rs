//! the command line of the statistics study and the plan it asks for.

use super::plan::{
    damping_grid, damping_models, damping_plan, parse_mesh, quick_grid, statistics_grid,
    statistics_plan, Grid, MeshPlan, Part, Plan, SceneKind, FORCINGS,
};
use plate_impact_studies::cli::{flag_value, positive_integer};

/// Which study runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Study {
    /// The statistics study, with `reduced` the committed grid.
    Statistics { reduced: bool },
    /// The damping study.
    Damping,
}

/// The options of a run of the study (see its documentation).
pub struct Options {
    pub study: Study,
    pub quick: bool,
    forcings: Option<String>,
    meshes: Option<String>,
    windows: Option<usize>,
    steps: Option<Vec<f64>>,
    skip: Vec<String>,
    dampings: Option<Vec<String>>,
    parts: Option<Vec<Part>>,
    /// Trailing `name=value` scene parameters, applied to every run after its own.
    pub overrides: Vec<String>,
}

/// The value after `flag` in `args`, if the flag is there.
fn value_of(args: &[String], flag: &str) -> Result<Option<String>, String> {
    flag_value(args, flag)
}

fn list(value: Option<String>) -> Option<Vec<String>> {
    value.map(|v| v.split(',').map(str::to_string).collect())
}

impl Options {
    /// Reads the options from `args`; `quick` is `--quick` (read by the output directory).
    pub fn parse(args: &[String], quick: bool) -> Result<Options, String> {
        let study = match value_of(args, "--study")?.as_deref() {
            None | Some("statistics") => Study::Statistics {
                reduced: args.iter().any(|a| a == "--reduced"),
            },
            Some("damping") => Study::Damping,
            Some(other) => return Err(format!("--study {other}: use statistics or damping")),
        };
        let windows = match value_of(args, "--windows")? {
            None => None,
            given => Some(positive_integer::<usize>("--windows", given)?),
        };
        if windows.is_some_and(|k| k < 2) {
            return Err("--windows needs at least 2 windows (the spread)".into());
        }
        let steps = list(value_of(args, "--dt")?)
            .map(|steps| {
                steps
                    .iter()
                    .map(|dt| {
                        dt.parse::<f64>()
                            .ok()
                            .filter(|dt| dt.is_finite() && *dt > 0.0)
                            .ok_or(format!("--dt {dt}: use time steps > 0 (s), e.g. 1e-4,1e-5"))
                    })
                    .collect::<Result<Vec<f64>, _>>()
            })
            .transpose()?;
        let skip = list(value_of(args, "--skip")?).unwrap_or_default();
        if let Some(bad) = skip
            .iter()
            .find(|s| !["energy", "forced", "replicas"].contains(&s.as_str()))
        {
            return Err(format!("--skip {bad}: use energy, forced and/or replicas"));
        }
        let dampings = list(value_of(args, "--damping")?);
        let parts = list(value_of(args, "--part")?)
            .map(|labels| labels.iter().map(|l| part(l)).collect())
            .transpose()?;
        if study != Study::Damping && (dampings.is_some() || parts.is_some()) {
            return Err("--damping and --part need --study damping".into());
        }
        Ok(Options {
            study,
            quick,
            forcings: value_of(args, "--forcings")?,
            meshes: value_of(args, "--mesh")?,
            windows,
            steps,
            skip,
            dampings,
            parts,
            overrides: args.iter().filter(|a| a.contains('=')).cloned().collect(),
        })
    }

    /// Whether the options run a part of the study (which then writes its CSVs but neither
    /// plots nor checks).
    pub fn partial(&self) -> bool {
        self.forcings.is_some()
            || self.meshes.is_some()
            || self.windows.is_some()
            || self.steps.is_some()
            || !self.skip.is_empty()
            || self.dampings.is_some()
            || self.parts.is_some()
            || !self.overrides.is_empty()
    }

    fn skips(&self, part: &str) -> bool {
        self.skip.iter().any(|s| s == part)
    }

    /// The plan the options ask for; ω₁ (rad/s) of the paper's mesh sets the damping models.
    pub fn plan(&self, omega1: f64) -> Result<Plan, String> {
        let mut grid = match (self.study, self.quick) {
            (Study::Statistics { .. }, true) => quick_grid(),
            (Study::Statistics { reduced }, false) => statistics_grid(reduced),
            (Study::Damping, quick) => {
                let mut grid = damping_grid();
                if quick {
                    // The pipeline only: every model on the coarsest mesh, two Δt, one forcing.
                    grid.scenes.truncate(1);
                    grid.meshes.truncate(1);
                    grid.ladder = vec![1e-4, 1e-5];
                }
                grid
            }
        };
        self.restrict(&mut grid)?;
        let mut plan = match self.study {
            Study::Statistics { reduced } => {
                let name = match (self.quick, reduced) {
                    (true, _) => "quick",
                    (false, true) => "reduced",
                    (false, false) => "full",
                };
                statistics_plan(name, &grid, self.quick)
            }
            Study::Damping => {
                let mut dampings = damping_models(omega1);
                if let Some(labels) = &self.dampings {
                    if let Some(bad) = labels
                        .iter()
                        .find(|l| !dampings.iter().any(|d| d.label == *l))
                    {
                        let known: Vec<&str> = dampings.iter().map(|d| d.label).collect();
                        return Err(format!("--damping {bad}: use labels among {known:?}"));
                    }
                    dampings.retain(|d| labels.iter().any(|l| l == d.label));
                }
                let default = if self.quick {
                    &[Part::Grid][..]
                } else {
                    &Part::ALL[..]
                };
                let parts = self.parts.as_deref().unwrap_or(default);
                let mut plan = damping_plan(&grid, dampings, parts);
                if self.quick {
                    plan.name = "damping-quick";
                }
                plan
            }
        };
        self.select(&mut plan, &grid);
        Ok(plan)
    }

    /// Narrows the grid to the options' forcings, meshes and Δt.
    fn restrict(&self, grid: &mut Grid) -> Result<(), String> {
        if let Some(kind) = &self.forcings {
            let keep: Box<dyn Fn(&SceneKind) -> bool> = match kind.as_str() {
                "damped" => Box::new(|s| matches!(s, SceneKind::Forced(f) if f.damped)),
                "undamped" => Box::new(|s| matches!(s, SceneKind::Forced(f) if !f.damped)),
                labels => {
                    let labels: Vec<String> = labels.split(',').map(str::to_string).collect();
                    if let Some(bad) = labels
                        .iter()
                        .find(|l| !FORCINGS.iter().any(|f| f.label == *l))
                    {
                        return Err(format!(
                            "--forcings {bad}: use damped, undamped or labels among {:?}",
                            FORCINGS.map(|f| f.label)
                        ));
                    }
                    Box::new(move |s| labels.iter().any(|l| l == s.label()))
                }
            };
            grid.scenes.retain(|s| *s == SceneKind::Energy || keep(s));
        }
        if let Some(list) = &self.meshes {
            grid.meshes = list
                .split(',')
                .map(|item| parse_mesh(item).map(|mesh| MeshPlan { mesh, dt_min: 0.0 }))
                .collect::<Result<_, _>>()?;
        }
        if let Some(steps) = &self.steps {
            grid.ladder = steps.clone();
            grid.ladder_given = true;
        }
        if let Some(k) = self.windows {
            grid.windows = k;
        }
        Ok(())
    }

    /// Keeps the runs of `plan` that the options select: those of the grid's scenes, and with
    /// `--mesh` or `--dt` those meshes and Δt only; `--skip` and `--windows` apply to all.
    fn select(&self, plan: &mut Plan, grid: &Grid) {
        let meshes: Vec<_> = grid.meshes.iter().map(|m| m.mesh).collect();
        plan.runs.retain(|r| {
            let skipped = match r.scene {
                SceneKind::Energy => self.skips("energy"),
                SceneKind::Forced(_) => self.skips("forced"),
            };
            !skipped
                && grid.scenes.contains(&r.scene)
                && (self.meshes.is_none() || meshes.contains(&r.mesh))
                && (self.steps.is_none() || grid.ladder.contains(&r.dt))
        });
        if let Some(k) = self.windows {
            for r in &mut plan.runs {
                r.windows = k;
            }
        }
        if self.skips("replicas") {
            plan.replica_check.clear();
        }
        let forced = |f| grid.scenes.contains(&SceneKind::Forced(f));
        plan.replica_check.retain(|(f, _, _)| forced(*f));
    }
}

/// A part of the damping study by its label.
fn part(label: &str) -> Result<Part, String> {
    Part::ALL
        .into_iter()
        .find(|p| p.label() == label)
        .ok_or_else(|| {
            let known: Vec<&str> = Part::ALL.iter().map(|p| p.label()).collect();
            format!("--part {label}: use labels among {known:?}")
        })
}
