//! The runs of a statistics-type study (`statistics.csv`, `damping.csv`) and the definitions its
//! documents use, restated here from their prose so that a claim computes what the prose says:
//! two values *agree* within 2σ of their difference; the *error* of a run against a reference is
//! |v − v_ref|/|v_ref| with the uncertainty 2·√(σ² + σ_ref²)/|v_ref|. Where a quantity
//! *stays within its noise* in Δt on a mesh (every smaller Δt within 2σ of the smallest; no verdict
//! of convergence) is read from the `_within_noise.csv` the study's write step writes beside its
//! runs, never computed again here.

use super::data::table;

/// One row: a statistic of one run.
#[derive(Clone, Debug)]
pub struct Run {
    /// The scene, `scene/damping` in the damping study.
    pub scene: String,
    pub quantity: String,
    /// `element:NXxNY`, e.g. `argyris:10x7`.
    pub mesh: String,
    pub dt: f64,
    pub omega_max_dt: f64,
    pub value: f64,
    pub spread: f64,
    pub wall_s: f64,
}

/// Every row of a study's CSV, and where each (scene, quantity, mesh) stays within its noise when
/// the study writes that (`statistics_within_noise.csv`: the Δt, or empty).
pub struct Runs {
    pub rows: Vec<Run>,
    settling: Vec<(String, String, String, Option<f64>)>,
}

impl Runs {
    /// The rows of the CSV at `path`; with a `damping` column, the scene is `scene/damping`.
    pub fn load(path: &str) -> Runs {
        Runs::load_where(path, "")
    }

    /// The rows of the CSV at `path` that `selection` picks (`data::Table::select`).
    pub fn load_where(path: &str, selection: &str) -> Runs {
        let t = table(path);
        let with_damping = t.has_column("damping");
        let rows = t
            .select(selection)
            .iter()
            .map(|r| Run {
                scene: if with_damping {
                    format!("{}/{}", r.text("scene"), r.text("damping"))
                } else {
                    r.text("scene").to_string()
                },
                quantity: r.text("quantity").to_string(),
                mesh: format!("{}:{}x{}", r.text("element"), r.text("nx"), r.text("ny")),
                dt: r.number("dt"),
                omega_max_dt: r.number("omega_max_dt"),
                value: r.number("value"),
                spread: r.number("spread"),
                wall_s: r.number("wall_s"),
            })
            .collect();
        let beside = path.replace(".csv", "_within_noise.csv");
        let settling = if super::root().join(&beside).exists() {
            table(&beside)
                .select("")
                .iter()
                .map(|r| {
                    let dt = r.text("within_noise_dt");
                    (
                        r.text("scene").to_string(),
                        r.text("quantity").to_string(),
                        r.text("mesh").to_string(),
                        (!dt.is_empty()).then(|| r.number("within_noise_dt")),
                    )
                })
                .collect()
        } else {
            Vec::new()
        };
        Runs { rows, settling }
    }

    /// The runs of `scene` and `quantity` on `mesh`, by decreasing Δt (a failure when none).
    pub fn select(&self, scene: &str, quantity: &str, mesh: &str) -> Vec<&Run> {
        let mut runs: Vec<&Run> = self
            .rows
            .iter()
            .filter(|r| r.scene == scene && r.quantity == quantity && r.mesh == mesh)
            .collect();
        assert!(!runs.is_empty(), "no run of {scene} {quantity} on {mesh}");
        runs.sort_by(|a, b| b.dt.total_cmp(&a.dt));
        runs
    }

    /// The run at Δt = `dt`.
    pub fn at(&self, scene: &str, quantity: &str, mesh: &str, dt: f64) -> &Run {
        self.select(scene, quantity, mesh)
            .into_iter()
            .find(|r| (r.dt / dt - 1.0).abs() < 1e-9)
            .unwrap_or_else(|| panic!("no run of {scene} {quantity} on {mesh} at Δt = {dt}"))
    }

    /// The value at Δt = `dt`.
    pub fn value(&self, scene: &str, quantity: &str, mesh: &str, dt: f64) -> f64 {
        self.at(scene, quantity, mesh, dt).value
    }

    /// The run at the mesh's smallest Δt.
    pub fn smallest(&self, scene: &str, quantity: &str, mesh: &str) -> &Run {
        self.select(scene, quantity, mesh)
            .pop()
            .expect("select returns runs")
    }

    /// The run at the Δt from which the quantity stays within its noise on the mesh, as the
    /// study's write step found it (`*_within_noise.csv`), or None.
    pub fn within_noise(&self, scene: &str, quantity: &str, mesh: &str) -> Option<&Run> {
        let (_, _, _, dt) = self
            .settling
            .iter()
            .find(|(s, q, m, _)| s == scene && q == quantity && m == mesh)
            .unwrap_or_else(|| panic!("no noise check of {scene} {quantity} on {mesh}"));
        dt.map(|dt| self.at(scene, quantity, mesh, dt))
    }

    /// The runs of the forced scenes' `quantity` on `mesh` whose settling point exists, for
    /// every scene of `scenes` and mesh of `meshes`: (settled run, how many cases were tried).
    pub fn within_noise_cases<'a>(
        &'a self,
        scenes: &[&str],
        quantities: &[&str],
        meshes: &[&str],
    ) -> (Vec<&'a Run>, usize) {
        let mut found = Vec::new();
        let mut tried = 0;
        for s in scenes {
            for q in quantities {
                for m in meshes {
                    tried += 1;
                    found.extend(self.within_noise(s, q, m));
                }
            }
        }
        (found, tried)
    }
}

/// Whether `a` and `b` agree within 2σ of their difference.
pub fn agree(a: &Run, b: &Run) -> bool {
    (a.value - b.value).abs() <= 2.0 * a.spread.hypot(b.spread)
}

/// The error of `r` against `reference`, relative, and its 2σ uncertainty, both in percent.
pub fn error(r: &Run, reference: &Run) -> (f64, f64) {
    let scale = reference.value.abs();
    (
        100.0 * (r.value - reference.value).abs() / scale,
        100.0 * 2.0 * r.spread.hypot(reference.spread) / scale,
    )
}

/// The least-squares slope of log y against log x.
pub fn fit_slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let lx: Vec<f64> = points.iter().map(|p| p.0.ln()).collect();
    let ly: Vec<f64> = points.iter().map(|p| p.1.ln()).collect();
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let sxx: f64 = lx.iter().map(|x| (x - mx).powi(2)).sum();
    let sxy: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    sxy / sxx
}

/// The median of `xs`.
pub fn median(xs: &[f64]) -> f64 {
    let mut xs = xs.to_vec();
    xs.sort_by(f64::total_cmp);
    let n = xs.len();
    if n % 2 == 1 {
        xs[n / 2]
    } else {
        0.5 * (xs[n / 2 - 1] + xs[n / 2])
    }
}
