//! The claims of docs/accuracy/damping.md (the damping study, from damping.csv, damping_meshes.csv
//! and damping_meta.csv), and those of the damping study's summaries in docs/studies.md
//! ([`brief`]) and README.md ([`readme`]).

use super::claims::Claims;
use super::data::{pct, span, table, Table};
use super::study::{Run, Runs};

mod findings;
mod opening;
mod summaries;

use findings::{adds, contact_loss, criterion, finer_reference};
use opening::{answer, pair_beta, regenerate, table_rows, why_beta};
pub use summaries::{brief, limits_doc, readme};

const DIR: &str = "docs/accuracy/";

const REFERENCE: &str = "argyris:14x10";

const PAPER_MESHES: [&str; 2] = ["argyris:10x7", "fvs:14x10"];

const FOUR: [&str; 4] = [
    "mean_energy_J",
    "rms_corner_m",
    "mean_abs_base_force_N",
    "rms_base_force_N",
];

const SCENES: [&str; 2] = ["forced-35hz", "forced-60hz"];

/// The grid's meshes.
const GRID: [&str; 7] = [
    "argyris:2x1",
    "argyris:4x2",
    "argyris:6x4",
    "argyris:10x7",
    REFERENCE,
    "fvs:7x5",
    "fvs:14x10",
];

/// Every mesh of the grid from Argyris 6 × 4 on, and FVS 14 × 10.
const FINER: [&str; 4] = ["argyris:6x4", "argyris:10x7", REFERENCE, "fvs:14x10"];

/// The damping study's runs and the helpers its claims use: the runs its comparison reads, the
/// part `evidence` (runs that only close the rule's ladders, docs/accuracy/damping.md) left out,
/// as the write step leaves it out of its tables.
pub struct Study {
    pub runs: Runs,
    csv: Table,
}
impl Study {
    pub fn load() -> Study {
        Study {
            runs: Runs::load_where(&format!("{DIR}damping.csv"), "part!=evidence"),
            csv: table(&format!("{DIR}damping.csv")),
        }
    }

    /// The reference of (scene, model, q): Argyris 14 × 10 at its smallest Δt.
    pub fn reference(&self, scene: &str, model: &str, q: &str) -> &Run {
        self.runs
            .smallest(&format!("{scene}/{model}"), q, REFERENCE)
    }

    /// The value of (scene, model, q) on `mesh` at Δt = `dt`.
    pub fn value(&self, scene: &str, model: &str, q: &str, mesh: &str, dt: f64) -> f64 {
        self.runs.value(&format!("{scene}/{model}"), q, mesh, dt)
    }

    /// The signed error (%) of a run against its reference.
    pub fn error(&self, scene: &str, model: &str, q: &str, mesh: &str, dt: f64) -> f64 {
        pct(
            self.value(scene, model, q, mesh, dt),
            self.reference(scene, model, q).value,
        )
    }

    /// The wall time (s) of a run.
    pub fn wall(&self, scene: &str, model: &str, mesh: &str, dt: f64) -> f64 {
        self.runs
            .at(&format!("{scene}/{model}"), "mean_energy_J", mesh, dt)
            .wall_s
    }

    /// ζ_hf of a run.
    pub fn zeta_hf(&self, scene: &str, model: &str, mesh: &str, dt: f64) -> f64 {
        let (element, cells) = mesh.split_once(':').expect("mesh");
        let (nx, ny) = cells.split_once('x').expect("cells");
        self.csv
            .select(&format!(
                "quantity=mean_energy_J scene={scene} damping={model} element={element} nx={nx} ny={ny} dt={dt}"
            ))
            .first()
            .unwrap_or_else(|| panic!("no run {scene} {model} {mesh} {dt}"))
            .number("zeta_hf")
    }

    /// The largest |error| (%) of `quantities` over `scenes`, `meshes` and `steps`.
    pub fn worst(
        &self,
        model: &str,
        scenes: &[&str],
        quantities: &[&str],
        meshes: &[&str],
        steps: &[f64],
    ) -> f64 {
        let mut worst: f64 = 0.0;
        for s in scenes {
            for q in quantities {
                for m in meshes {
                    for &dt in steps {
                        worst = worst.max(self.error(s, model, q, m, dt).abs());
                    }
                }
            }
        }
        worst
    }
}

/// The β numbers both damping.md and the README state.
struct Headline {
    /// The largest |error| (%) of the four time averages at 1e-5 s, both scenes, on FVS 14 × 10
    /// and on Argyris 10 × 7.
    fvs_1e5: f64,
    argyris_1e5: f64,
    /// The wall times (s) of FVS 14 × 10 and Argyris 10 × 7 at 1e-5 s, 35 Hz then 60 Hz.
    walls_fvs: [f64; 2],
    walls_argyris: [f64; 2],
    /// The wall times (s) of both paper meshes at 1e-4 s, both scenes.
    walls_paper: Vec<f64>,
    /// The largest |error| (%) on the finer meshes of everything but the 35 Hz RMS base force,
    /// and the largest error of that.
    finer_steady: f64,
    finer_moving: f64,
}

impl Headline {
    fn of(d: &Study) -> Headline {
        let rms = "rms_base_force_N";
        let finer = finer_errors(d);
        let moving = |e: &&(&str, &str, f64)| e.0 == "forced-35hz" && e.1 == rms;
        let steady: Vec<f64> = finer
            .iter()
            .filter(|e| !moving(e))
            .map(|e| e.2.abs())
            .collect();
        let moved: Vec<f64> = finer.iter().filter(moving).map(|e| e.2).collect();
        Headline {
            fvs_1e5: d.worst("beta", &SCENES, &FOUR, &["fvs:14x10"], &[1e-5]),
            argyris_1e5: d.worst("beta", &SCENES, &FOUR, &["argyris:10x7"], &[1e-5]),
            walls_fvs: SCENES.map(|s| d.wall(s, "beta", "fvs:14x10", 1e-5)),
            walls_argyris: SCENES.map(|s| d.wall(s, "beta", "argyris:10x7", 1e-5)),
            walls_paper: SCENES
                .iter()
                .flat_map(|s| PAPER_MESHES.iter().map(move |m| d.wall(s, "beta", m, 1e-4)))
                .collect(),
            finer_steady: span(&steady).1,
            finer_moving: span(&moved).1,
        }
    }
}

/// The value under `key` (which may hold spaces, `damping beta`) in damping_meta.csv.
fn meta_of(key: &str) -> String {
    let meta = table(&format!("{DIR}damping_meta.csv"));
    let rows = meta.select("");
    let row = rows
        .iter()
        .find(|r| r.text("key") == key)
        .unwrap_or_else(|| panic!("damping_meta.csv has no {key}"));
    row.text("value").to_string()
}

/// A setting of a damping model in the meta file, e.g. `damping.frequency_high` of
/// `rayleigh-5k`.
fn setting(model: &str, name: &str) -> f64 {
    let settings = meta_of(&format!("damping {model}"));
    settings
        .split_whitespace()
        .find_map(|kv| kv.strip_prefix(&format!("{name}=")))
        .unwrap_or_else(|| panic!("{model} has no {name}"))
        .parse()
        .expect("a number")
}

pub fn claims() -> Claims {
    let mut c = Claims::new("docs/accuracy/damping.md");
    c.defines(&["plus its 2σ and the converged value's bound, is within 1 %"]);
    let d = Study::load();
    c.given(GIVEN);
    regenerate(&mut c, &d);
    answer(&mut c, &d);
    table_rows(&mut c, &d);
    why_beta(&mut c, &d);
    finer_reference(&mut c, &d);
    contact_loss(&mut c, &d);
    criterion(&mut c, &d);
    adds(&mut c, &d);
    c
}

const GIVEN: &[&str] = &[
    "§10",
    "§6",
    "7 models × 2 forced scenes × 7 meshes at Δt = 1e-4, 1e-5, 1e-6 s",
    "the 1e-6 s runs",
    "1e-7 s on Argyris 2 × 1 and 4 × 2",
    "2 windows instead of 8",
    "β at Δt = 1e-6 s",
    "2-core",
    "ζ₁ = 1 %",
    "Δt = 1e-5 s",
    "4 s simulated",
    "Δt = 1e-4 s",
    "(a lighter forcing)",
    "1 s transient + 8 windows",
    "1 % from",
    "within 1 %",
    "1 kHz",
    "5 kHz",
    "20 kHz",
    "Δt = 1e-4, 1e-5, 1e-6 s",
    "at 1e-4 s",
    "ζ_m = 1 %",
    "2 impacts per period",
    "at 1e-6, 5e-7 s",
    "at 1e-6, 5e-7, 1e-7 s",
    "at 1e-6 s",
    "from 1e-5 s",
    "at 1e-5, 1e-6 s",
    "ζ < 1 %",
    "the 1, 5 and 20 kHz anchors",
    "more than 1 %",
    "Δt = 1e-6 s",
    "(2 675 free",
    "above 2 000)",
    "at 1e-7 s",
    "at 5e-8 s",
    "from 1e-5 to 1e-7 s",
    "Δt = 1e-7 s",
    "e = 0",
    "ωΔt ≲ 1",
    "ζ(ω) = α/(2ω) + βω/2 + ζ_m",
    "1/Δt",
    "β/(2Δt)",
    "ζ_hf ≥ 0.25",
    "Δt ≤ β/(2·0.25) = 2β",
    "ζ_hf < 0.25",
    "fmi2ExitInitializationMode",
    "fmi3ExitInitializationMode",
    "at 5e-5 s",
    "9 mm",
    "±10 mm",
    "8 windows of 13 forcing periods",
    "√8",
    "β = 2.9565e-5 s is ζ₁ = 0.5 %",
    "ζ = 1 % at f₁ and 5 kHz",
    "(`forced-60hz`, 2 mm",
    "(1.8751/L)²",
    "D = Ee³/(12(1−ν²))",
    "35 Hz",
    "60 Hz",
    "1e-5 s",
    "1e-6 s",
    "1e-7 s",
    "5e-7",
    "f₁ and 1 kHz",
    "f₁ and 5 kHz",
    "f₁ and 20 kHz",
    "4 × 2 on",
    "6 × 4 on",
    "1 s of transient",
    "β = 2ζ₁/ω₁",
    "ζ_k = βω_k/2",
    "with β > 0",
    "cheapest 1 %",
    "ζ = 1 % at f₁",
    "at 2e-7 s",
    "ζ₁ = 0.5 %",
    "modal ratio of 1 %",
    "The threshold 0.25",
    "(± 2σ of the difference)",
    "1 % of it needs",
    "the rule, at 1 %,",
    "factor 2 or more",
    "1e-6, 1e-7 s",
    "5e-7 and 2e-7 s",
    "(2 mm)",
    "Δt ≤ 1e-6 s",
];

/// (scene, quantity, error % against the reference) of β at 1e-6 s on the meshes finer than
/// the reference's.
fn finer_errors(d: &Study) -> Vec<(&'static str, &'static str, f64)> {
    let mut out = Vec::new();
    for s in SCENES {
        for q in FOUR {
            for m in ["argyris:20x14", "fvs:20x14", "fvs:28x20"] {
                out.push((s, q, d.error(s, "beta", q, m, 1e-6)));
            }
        }
    }
    out
}

/// Every Δt the grid ran `model` at on the reference mesh's scene.
fn steps_of(d: &Study, scene: &str, model: &str) -> Vec<f64> {
    d.runs
        .select(&format!("{scene}/{model}"), "mean_energy_J", REFERENCE)
        .iter()
        .map(|r| r.dt)
        .filter(|&dt| dt >= 1e-6)
        .collect()
}

/// The largest |error| of the four time averages of `model` on both scenes of (the reference
/// mesh at the next larger Δt, FVS 14 × 10 at the reference's Δt).
fn reference_checks(d: &Study, model: &str) -> (f64, f64) {
    let (mut time, mut mesh): (f64, f64) = (0.0, 0.0);
    for s in SCENES {
        for q in FOUR {
            let key = format!("{s}/{model}");
            let runs = d.runs.select(&key, q, REFERENCE);
            let reference = runs[runs.len() - 1];
            let coarser = runs[runs.len() - 2];
            time = time.max(pct(coarser.value, reference.value).abs());
            let fvs = d.runs.at(&key, q, "fvs:14x10", reference.dt);
            mesh = mesh.max(pct(fvs.value, reference.value).abs());
        }
    }
    (time, mesh)
}

/// The values of `model`'s `q` at `scene` on `meshes`, every Δt of the grid and contact-loss
/// parts.
fn grid_values(d: &Study, scene: &str, model: &str, q: &str, meshes: &[&str]) -> Vec<f64> {
    meshes
        .iter()
        .flat_map(|m| {
            d.runs
                .select(&format!("{scene}/{model}"), q, m)
                .into_iter()
                .map(|r| r.value)
        })
        .collect()
}

/// v(h) = v∞ − C·h^p through three (h, v): the order p and the limit v∞.
fn extrapolate(points: [(f64, f64); 3]) -> (f64, f64) {
    let [(h0, v0), (h1, v1), (h2, v2)] = points;
    let ratio = (v1 - v0) / (v2 - v1);
    let f = |p: f64| (h0.powf(p) - h1.powf(p)) / (h1.powf(p) - h2.powf(p)) - ratio;
    let (mut lo, mut hi) = (0.01, 10.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(lo) * f(mid) <= 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let p = 0.5 * (lo + hi);
    let c = (v2 - v1) / (h1.powf(p) - h2.powf(p));
    (p, v2 + c * h2.powf(p))
}

/// The extrapolated mesh limits of the 35 Hz RMS base force with β, in % above the reference:
/// (Argyris from 10 × 7, 14 × 10, 20 × 14; FVS from 14 × 10, 20 × 14, 28 × 20), and the orders.
fn extrapolated(d: &Study) -> ((f64, f64), (f64, f64)) {
    let q = "rms_base_force_N";
    let h = |nx: f64| 0.4 / nx;
    let v = |mesh: &str| d.value("forced-35hz", "beta", q, mesh, 1e-6);
    let reference = v(REFERENCE);
    let (pa, la) = extrapolate([
        (h(10.0), v("argyris:10x7")),
        (h(14.0), v(REFERENCE)),
        (h(20.0), v("argyris:20x14")),
    ]);
    let (pf, lf) = extrapolate([
        (h(14.0), v("fvs:14x10")),
        (h(20.0), v("fvs:20x14")),
        (h(28.0), v("fvs:28x20")),
    ]);
    ((pa, pct(la, reference)), (pf, pct(lf, reference)))
}

/// The extrapolated limits of [`extrapolated`], Argyris and FVS (% above the reference).
fn limits(d: &Study) -> (f64, f64) {
    let ((_, a), (_, f)) = extrapolated(d);
    (a, f)
}
