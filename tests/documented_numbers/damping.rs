//! The claims of docs/accuracy/damping.md (the damping study, from damping.csv, damping_meshes.csv
//! and damping_meta.csv), and those of the damping study's summaries in docs/studies.md
//! ([`brief`]) and README.md ([`readme`]).

use super::claims::Claims;
use super::data::{pct, span, table, Table};
use super::study::{Run, Runs};

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

/// The damping study's runs and the helpers its claims use.
pub struct Study {
    pub runs: Runs,
    csv: Table,
}

impl Study {
    pub fn load() -> Study {
        Study {
            runs: Runs::load(&format!("{DIR}damping.csv")),
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
    "2σ uncertainty",
    "1 % for them",
    "factor 2 or more",
    "1e-6, 1e-7 s",
    "5e-7 and 2e-7 s",
    "(2 mm)",
    "Δt ≤ 1e-6 s",
];

fn regenerate(c: &mut Claims, d: &Study) {
    let count = |part: &str| {
        d.csv
            .select(&format!("quantity=mean_energy_J part={part}"))
            .len() as f64
    };
    c.value(
        "and 4 × 2 for β and the 5 kHz pair ({294} runs)",
        count("grid"),
    );
    c.value("on the fine meshes ({15} runs", count("contact-loss"));
    c.value("and 28 × 20 ({6} runs", count("finer-reference"));
    c.value("({11} runs beyond", count("threshold"));
    let runs = d.csv.select("quantity=mean_energy_J");
    let wall: f64 = runs.iter().map(|r| r.number("wall_s")).sum();
    c.value("The committed run: {326} runs", runs.len() as f64);
    c.value("{5 013} s of run wall time", wall);
    c.value("in all ({84} min;", wall / 60.0);
    c.value(
        "{85} min with the meshes'",
        meta_of("total_s").parse::<f64>().expect("total_s") / 60.0,
    );
    assert!(
        !meta_of("commit").contains("modified") && meta_of("commit").len() == 40,
        "the page says the run is from a committed state"
    );
}

/// Every mesh of the grid from Argyris 6 × 4 on, and FVS 14 × 10.
const FINER: [&str; 4] = ["argyris:6x4", "argyris:10x7", REFERENCE, "fvs:14x10"];

fn answer(c: &mut Claims, d: &Study) {
    c.value(
        "β = 2ζ₁/ω₁ = {5.913e-5} s, the preset",
        setting("beta", "damping.stiffness_proportional"),
    );
    c.upper(
        "within {0.3} % of the reference (Argyris 14 × 10 at 1e-6 s) on",
        d.worst("beta", &SCENES, &FOUR, &["fvs:14x10"], &[1e-5]),
    );
    c.value(
        "in {4.5} s per run",
        d.wall("forced-35hz", "beta", "fvs:14x10", 1e-5),
    );
    let worst_10x7 = d.worst("beta", &SCENES, &FOUR, &["argyris:10x7"], &[1e-5]);
    c.value("Argyris 10 × 7 within {1.04} % (the 35 Hz RMS", worst_10x7);
    let rms = "rms_base_force_N";
    assert_eq!(
        worst_10x7,
        d.error("forced-35hz", "beta", rms, "argyris:10x7", 1e-5)
            .abs(),
        "the page names the 35 Hz RMS base force as the largest"
    );
    c.value(
        "base force) in {5.3} s.",
        d.wall("forced-35hz", "beta", "argyris:10x7", 1e-5),
    );
    let at_paper = |scenes: &[&str], quantities: &[&str]| {
        d.worst("beta", scenes, quantities, &PAPER_MESHES, &[1e-4])
    };
    c.value(
        "the mean energy is within {0.11} % (35 Hz)",
        at_paper(&SCENES[..1], &FOUR[..1]),
    );
    c.value(
        "and {1.35} % (60 Hz), the RMS corner",
        at_paper(&SCENES[1..], &FOUR[..1]),
    );
    c.value(
        "the RMS corner within {1.82} %,",
        at_paper(&SCENES, &FOUR[1..2]),
    );
    c.value(
        "the base force within {1.84} % at",
        at_paper(&SCENES[1..], &FOUR[2..]),
    );
    let low = |q: &str| PAPER_MESHES.map(|m| -d.error("forced-35hz", "beta", q, m, 1e-4));
    c.range(
        "60 Hz but {5.5}–{5.6} % (mean |·|)",
        &low("mean_abs_base_force_N"),
    );
    c.range("and {9.4}–{9.5} % (RMS) low at 35 Hz", &low(rms));
    let walls: Vec<f64> = SCENES
        .iter()
        .flat_map(|s| PAPER_MESHES.iter().map(move |m| d.wall(s, "beta", m, 1e-4)))
        .collect();
    c.range("in {0.7}–{1.3} s.", &walls);
    let others = ["rayleigh-1k", "rayleigh-5k", "rayleigh-20k", "modal"];
    let worst60 = others
        .iter()
        .map(|m| {
            d.worst(
                m,
                &SCENES[1..],
                &FOUR[..2],
                &FINER,
                &steps_of(d, "forced-60hz", m),
            )
        })
        .fold(0.0, f64::max);
    c.upper("RMS corner within {2.1} % at every setting", worst60);
    let (time, mesh) = reference_checks(d, "beta");
    c.upper("agree within {0.42} % (Δt)", time);
    c.upper("and {0.16} % (mesh) for the four", mesh);
    let finer = finer_errors(d);
    let steady: Vec<f64> = finer
        .iter()
        .filter(|(s, q, _)| !(*s == "forced-35hz" && *q == rms))
        .map(|e| e.2.abs())
        .collect();
    c.upper(
        "and mean base force by at most {0.09} %, but",
        span(&steady).1,
    );
    let moving: Vec<f64> = finer
        .iter()
        .filter(|(s, q, _)| *s == "forced-35hz" && *q == rms)
        .map(|e| e.2)
        .collect();
    c.value("RMS base force by up to {1.05} %.", span(&moving).1);
}

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

fn table_rows(c: &mut Claims, d: &Study) {
    let three = |model: &str, q: &str, scale: f64| {
        [1e-4, 1e-5, 1e-6].map(|dt| scale * d.value("forced-35hz", model, q, "argyris:10x7", dt))
    };
    c.values(
        "(10 × 7: {9.6}, {37.6}, {66.2} J at",
        &three("none", "mean_energy_J", 1.0),
    );
    c.upper(
        "RMS corner within {1} % at 1e-4 s on the paper's meshes",
        d.worst("none", &SCENES[..1], &FOUR[1..2], &PAPER_MESHES, &[1e-4]),
    );
    c.values(
        "(10 × 7 mean: {2.2}, {13.7}, {36.9} kN)",
        &three("none", "mean_abs_base_force_N", 1e-3),
    );
    c.values(
        "no ({2.1}, {17.2}, {67.9})",
        &three("none", "impacts_per_period", 1.0),
    );
    c.values(
        "(35 Hz 10 × 7: {9.5}, {32.0}, {49.4} J)",
        &three("alpha", "mean_energy_J", 1.0),
    );
    c.value(
        "35 Hz RMS corner +{2.03} % on 6 × 4",
        d.error("forced-35hz", "beta", "rms_corner_m", "argyris:6x4", 1e-4),
    );
    let beta_fine = [
        "argyris:6x4",
        "argyris:10x7",
        REFERENCE,
        "fvs:7x5",
        "fvs:14x10",
    ];
    c.value(
        "60 Hz mean energy +{1.35} % at 1e-4 s",
        d.worst("beta", &SCENES[1..], &FOUR[..1], &beta_fine, &[1e-4]),
    );
    c.value(
        "FVS 7 × 5 at 1e-4 s ({0.18} s)",
        d.wall("forced-35hz", "beta", "fvs:7x5", 1e-4),
    );
    let both = ["mean_abs_base_force_N", "rms_base_force_N"];
    c.values(
        "(Argyris 10 × 7: −{0.31} / −{1.04} %;",
        &both.map(|q| -d.error("forced-35hz", "beta", q, "argyris:10x7", 1e-5)),
    );
    c.values(
        "at 1e-4 s −{5.6} / −{9.5} %)",
        &both.map(|q| -d.error("forced-35hz", "beta", q, "argyris:10x7", 1e-4)),
    );
    c.values(
        "(+{1.8} / +{1.0} % on 10 × 7 at 1e-4 s)",
        &both.map(|q| d.error("forced-60hz", "beta", q, "argyris:10x7", 1e-4)),
    );
    c.value(
        "60 Hz yes ({2});",
        d.reference("forced-60hz", "beta", "impacts_per_period")
            .value,
    );
    let grid_meshes = [
        "argyris:4x2",
        "argyris:6x4",
        "argyris:10x7",
        REFERENCE,
        "fvs:7x5",
        "fvs:14x10",
    ];
    let impacts: Vec<f64> = grid_meshes
        .iter()
        .flat_map(|m| d.runs.select("forced-35hz/beta", "impacts_per_period", m))
        .filter(|r| r.dt <= 1e-6)
        .map(|r| r.value)
        .collect();
    c.range("mesh ({2}–{6} per period at", &impacts);
    rayleigh_rows(c, d);
}

fn rayleigh_rows(c: &mut Claims, d: &Study) {
    let energy = |model: &str, scene: &str, mesh: &str, dt: f64| {
        d.value(scene, model, "mean_energy_J", mesh, dt)
    };
    let s35 = "forced-35hz";
    let s60 = "forced-60hz";
    c.range(
        "on Argyris ≥ 6 × 4 and FVS 14 × 10 ({13.57}–{13.72} J)",
        &grid_values(d, s60, "rayleigh-1k", "mean_energy_J", &FINER),
    );
    let (a14, f14) = (
        energy("rayleigh-1k", s35, REFERENCE, 1e-6),
        energy("rayleigh-1k", s35, "fvs:14x10", 1e-6),
    );
    c.value(
        "the 14 × 10 meshes agree within {1.1} %",
        pct(f14, a14).abs(),
    );
    c.values("({9.41}, {9.52} J)", &[f14, a14]);
    c.values(
        "Argyris 10 × 7 gives {10.05} J (+{5.5} %)",
        &[
            energy("rayleigh-1k", s35, "argyris:10x7", 1e-6),
            d.error(s35, "rayleigh-1k", "mean_energy_J", "argyris:10x7", 1e-6),
        ],
    );
    c.value(
        "({3.0} % at 1e-4 s)",
        d.worst("rayleigh-1k", &[s60], &FOUR[2..], &FINER, &[1e-4]),
    );
    c.upper(
        "60 Hz within {1} % from 1e-5 s on Argyris ≥ 6 × 4 and FVS 14 × 10 (3.0",
        d.worst("rayleigh-1k", &[s60], &FOUR[2..], &FINER, &[1e-5, 1e-6]),
    );
    c.value(
        "35 Hz within {4.8} % at 1e-6 s on 10 × 7 and the 14 × 10 meshes",
        d.worst(
            "rayleigh-1k",
            &[s35],
            &FOUR[2..],
            &["argyris:10x7", REFERENCE, "fvs:14x10"],
            &[1e-6],
        ),
    );
    c.upper(
        "60 Hz within {5} % from 1e-5 s; 35 Hz no",
        d.worst(
            "rayleigh-1k",
            &[s60],
            &["impacts_per_period"],
            &FINER,
            &[1e-5, 1e-6],
        ),
    );
    // Rayleigh 5 kHz.
    let all_grid = [
        "argyris:2x1",
        "argyris:4x2",
        "argyris:6x4",
        "argyris:10x7",
        REFERENCE,
        "fvs:7x5",
        "fvs:14x10",
    ];
    let mut every: f64 = 0.0;
    for q in &FOUR[..2] {
        let reference = d.reference(s60, "rayleigh-5k", q).value;
        for v in grid_values(d, s60, "rayleigh-5k", q, &all_grid) {
            every = every.max(pct(v, reference).abs());
        }
    }
    c.upper("60 Hz within {2} % at every setting; 35 Hz no", every);
    let r5 = |mesh: &str, dt: f64| energy("rayleigh-5k", s35, mesh, dt);
    c.values(
        "(Argyris {11.16}, {11.21} J at",
        &[r5(REFERENCE, 1e-6), r5(REFERENCE, 5e-7)],
    );
    c.values(
        "FVS {10.52}, {10.56}, {10.62} J at",
        &[
            r5("fvs:14x10", 1e-6),
            r5("fvs:14x10", 5e-7),
            r5("fvs:14x10", 1e-7),
        ],
    );
    c.value(
        "the two disagree by {6} %",
        pct(r5(REFERENCE, 5e-7), r5("fvs:14x10", 5e-7)),
    );
    c.value(
        "and Argyris 10 × 7 gives {11.8} J",
        r5("argyris:10x7", 1e-6),
    );
    c.values(
        "FVS 14 × 10 lies {5.5} % (mean) and {6.3} % (RMS) above Argyris at 1e-6 s",
        &["mean_abs_base_force_N", "rms_base_force_N"]
            .map(|q| d.error(s60, "rayleigh-5k", q, "fvs:14x10", 1e-6)),
    );
    // Rayleigh 20 kHz.
    let steps20 = steps_of(d, s60, "rayleigh-20k");
    c.upper(
        "60 Hz within {2.5} % (14.00",
        d.worst("rayleigh-20k", &[s60], &FOUR[..2], &FINER, &steps20),
    );
    c.range(
        "({14.00}–{14.32} J on Argyris",
        &grid_values(d, s60, "rayleigh-20k", "mean_energy_J", &FINER),
    );
    c.values(
        "no (10 × 7: {8.8}, {12.0}, {13.9} J)",
        &[1e-4, 1e-5, 1e-6].map(|dt| energy("rayleigh-20k", s35, "argyris:10x7", dt)),
    );
    let below = |model: &str| {
        let mut worst: f64 = 0.0;
        for m in FINER {
            for q in &FOUR[2..] {
                for r in d.runs.select(&format!("{s60}/{model}"), q, m) {
                    if r.dt <= 1e-5 {
                        worst = worst.max(d.error(s60, model, q, m, r.dt).abs());
                    }
                }
            }
        }
        worst
    };
    c.upper(
        "60 Hz within {3.7} % from 1e-5 s on Argyris",
        below("rayleigh-20k"),
    );
    // Modal.
    c.range(
        "FVS 14 × 10 ({13.46}–{13.57} J)",
        &grid_values(d, s60, "modal", "mean_energy_J", &FINER),
    );
    c.upper(
        "60 Hz within {1} % at every Δt on Argyris ≥ 6 × 4 and FVS 14 × 10 (13.46",
        d.worst(
            "modal",
            &[s60],
            &FOUR[..1],
            &FINER,
            &steps_of(d, s60, "modal"),
        ),
    );
    c.values(
        "({9.63}, {9.72} J at 1e-5, 1e-6 s)",
        &[1e-5, 1e-6].map(|dt| energy("modal", s35, "fvs:14x10", dt)),
    );
    c.values(
        "does not ({10.1}, {11.2} J)",
        &[1e-5, 1e-6].map(|dt| energy("modal", s35, "argyris:10x7", dt)),
    );
    c.upper(
        "60 Hz within {6.1} % from 1e-5 s on Argyris",
        below("modal"),
    );
    c.values(
        "(FVS 14 × 10: {3.7}, {4.5} kN)",
        &[1e-5, 1e-6]
            .map(|dt| 1e-3 * d.value(s35, "modal", "mean_abs_base_force_N", "fvs:14x10", dt)),
    );
}

/// √(αβ) of a Rayleigh pair ζ at f₁ and f₂, at its lightest frequency √(f₁f₂) (Hz).
fn pair_dip(model: &str) -> (f64, f64) {
    let zeta = setting(model, "damping.ratio");
    let (f1, f2) = (
        setting(model, "damping.frequency_low"),
        setting(model, "damping.frequency_high"),
    );
    // α = 2ζω₁ω₂/(ω₁ + ω₂), β = 2ζ/(ω₁ + ω₂): √(αβ) = 2ζ√(ω₁ω₂)/(ω₁ + ω₂).
    (2.0 * zeta * (f1 * f2).sqrt() / (f1 + f2), (f1 * f2).sqrt())
}

/// β (s) of a Rayleigh pair ζ at f₁ and f₂: 2ζ/(ω₁ + ω₂).
fn pair_beta(model: &str) -> f64 {
    let zeta = setting(model, "damping.ratio");
    let (f1, f2) = (
        setting(model, "damping.frequency_low"),
        setting(model, "damping.frequency_high"),
    );
    2.0 * zeta / (2.0 * std::f64::consts::PI * (f1 + f2))
}

fn why_beta(c: &mut Claims, d: &Study) {
    let relative: Vec<f64> = d
        .runs
        .rows
        .iter()
        .filter(|r| r.scene.ends_with("/beta") && FOUR.contains(&r.quantity.as_str()))
        .filter(|r| r.mesh == REFERENCE)
        .map(|r| r.spread / r.value.abs())
        .collect();
    c.upper(
        "four time averages below {4e-5} relative",
        span(&relative).1,
    );
    let dips = ["rayleigh-1k", "rayleigh-5k", "rayleigh-20k"].map(pair_dip);
    c.values(
        "√(αβ) = {0.44} %, {0.21} %, {0.10} % at {232} Hz, {519} Hz and {1038} Hz",
        &[
            100.0 * dips[0].0,
            100.0 * dips[1].0,
            100.0 * dips[2].0,
            dips[0].1,
            dips[1].1,
            dips[2].1,
        ],
    );
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

fn finer_reference(c: &mut Claims, d: &Study) {
    let (s35, q) = ("forced-35hz", "rms_base_force_N");
    c.value(
        "RMS base force still rises by {0.68} %",
        -d.error(s35, "beta", q, "argyris:10x7", 1e-6),
    );
    c.value(
        "FVS 14 × 10 lies {0.14} % above it",
        d.error(s35, "beta", q, "fvs:14x10", 1e-6),
    );
    let finer = finer_errors(d);
    let steady: Vec<f64> = finer
        .iter()
        .filter(|(s, qq, _)| !(*s == s35 && *qq == q))
        .map(|e| e.2.abs())
        .collect();
    c.upper(
        "move by at most {0.09} % from the reference on the finer meshes",
        span(&steady).1,
    );
    c.values(
        "it lies {0.55} % above the reference on Argyris 20 × 14 and {1.05} % above on FVS 28 × 20",
        &["argyris:20x14", "fvs:28x20"].map(|m| d.error(s35, "beta", q, m, 1e-6)),
    );
    let ((pa, la), (pf, lf)) = extrapolated(d);
    c.values("has p = {0.74} (Argyris) and p = {0.42} (FVS)", &[pa, pf]);
    c.values(
        "v∞ lie {2.4} % (Argyris) and {3.7} % (FVS) above the reference",
        &[la, lf],
    );
    c.value(
        "Δt = 1e-7 s adds {0.09} % to the RMS base force",
        pct(
            d.value(s35, "beta", q, "fvs:14x10", 1e-7),
            d.value(s35, "beta", q, "fvs:14x10", 1e-6),
        ),
    );
    let largest = d
        .runs
        .rows
        .iter()
        .filter(|r| r.scene == "forced-35hz/beta" && r.dt == 1e-6)
        .map(|r| r.omega_max_dt)
        .fold(0.0, f64::max);
    c.value("with ω_max·Δt up to {30}, may", largest);
}

fn contact_loss(c: &mut Claims, d: &Study) {
    let q = "contact_loss_per_period_J";
    let loss = |scene: &str, mesh: &str, dt: f64| d.value(scene, "beta", q, mesh, dt);
    let on = |scene: &str, meshes: &[&str], dt: f64| {
        meshes
            .iter()
            .map(|m| loss(scene, m, dt))
            .collect::<Vec<f64>>()
    };
    let from_4x2 = [
        "argyris:4x2",
        "argyris:6x4",
        "argyris:10x7",
        REFERENCE,
        "fvs:7x5",
        "fvs:14x10",
    ];
    let fine = [
        "argyris:6x4",
        "argyris:10x7",
        REFERENCE,
        "fvs:7x5",
        "fvs:14x10",
    ];
    let s35 = "forced-35hz";
    c.range(
        "it is {15.8}–{16.6} J per forcing period",
        &on(s35, &from_4x2, 1e-4),
    );
    c.range(
        "{5.7}–{7.1} J at 1e-5 s on those from 6 × 4 on",
        &on(s35, &fine, 1e-5),
    );
    c.value("({4.7} J on 4 × 2)", loss(s35, "argyris:4x2", 1e-5));
    c.range("{2.6}–{3.9} J at 1e-6 s", &on(s35, &fine, 1e-6));
    let at_1e7 = [
        "argyris:4x2",
        "argyris:6x4",
        "argyris:10x7",
        "fvs:7x5",
        "fvs:14x10",
    ];
    c.range("{1.1}–{2.4} J at 1e-7 s", &on(s35, &at_1e7, 1e-7));
    let omega_dt: Vec<f64> = at_1e7
        .iter()
        .map(|m| d.runs.at("forced-35hz/beta", q, m, 1e-7).omega_max_dt)
        .collect();
    c.range("(ω_max·Δt = {0.06}–{0.76})", &omega_dt);
    let finest = d.runs.at("forced-35hz/beta", q, "fvs:14x10", 5e-8);
    c.value("still {1.27} J at 5e-8 s", finest.value);
    c.value("(ω_max·Δt = {0.12}); at 60 Hz", finest.omega_max_dt);
    let s60 = "forced-60hz";
    c.value("from {2.9} J at 1e-4 s", loss(s60, "argyris:10x7", 1e-4));
    let fine_1e7 = ["argyris:6x4", "argyris:10x7", "fvs:7x5", "fvs:14x10"];
    c.range("to {0.21}–{0.36} J at 1e-7 s", &on(s60, &fine_1e7, 1e-7));
    c.range(
        "({0.12}–{0.14} J on the two coarsest)",
        &on(s60, &["argyris:2x1", "argyris:4x2"], 1e-7),
    );
    let agree: Vec<f64> = SCENES
        .iter()
        .flat_map(|s| fine.iter().map(move |m| (s, m)))
        .map(|(s, m)| pct(loss(s, m, 1e-4), loss(s, REFERENCE, 1e-4)).abs())
        .collect();
    c.upper("meshes from 6 × 4 on agree within {2.1} %", span(&agree).1);
    c.values(
        "(Argyris 4 × 2 is {4.8} % low at 35 Hz and {9.6} % at 60 Hz)",
        &SCENES.map(|s| -pct(loss(s, "argyris:4x2", 1e-4), loss(s, REFERENCE, 1e-4))),
    );
    let spread_of = |s: &str| {
        let (lo, hi) = span(&on(
            s,
            &["argyris:4x2", "argyris:6x4", "argyris:10x7"],
            1e-7,
        ));
        100.0 * (hi - lo) / hi
    };
    c.values(
        "span {7.2} % at 35 Hz but {39} % at 60 Hz",
        &SCENES.map(spread_of),
    );
    c.value(
        "FVS 14 × 10 lies {35} % above Argyris 10 × 7",
        pct(
            loss(s35, "fvs:14x10", 1e-7),
            loss(s35, "argyris:10x7", 1e-7),
        ),
    );
    c.value(
        "(FVS 7 × 5 {100} %)",
        pct(loss(s35, "fvs:7x5", 1e-7), loss(s35, "argyris:10x7", 1e-7)),
    );
    let mut factors = Vec::new();
    for s in SCENES {
        for m in FINER {
            let runs = d.runs.select(&format!("{s}/beta"), q, m);
            for pair in runs.windows(2) {
                if (pair[0].dt / pair[1].dt - 10.0).abs() < 1e-6 {
                    factors.push(pair[0].value / pair[1].value);
                }
            }
        }
    }
    c.range("a factor {1.9}–{2.9} per decade", &factors);
    c.values(
        "(Argyris 2 × 1: {0.71}, {0.57} J at",
        &[1e-6, 1e-7].map(|dt| loss(s35, "argyris:2x1", dt)),
    );
    let smallest = span(&grid_values(d, s35, "beta", q, &fine)).0;
    c.value("6 × 4 and finer, {1.1} J per period", smallest);
    c.value(
        "{14} times less than",
        loss(s35, "argyris:6x4", 1e-4) / smallest,
    );
    let energies =
        [1e-5, 1e-6, 1e-7].map(|dt| d.value(s35, "beta", "mean_energy_J", "argyris:10x7", dt));
    c.value("mean energy is {8.607} J at 35 Hz", energies[0]);
    let (lo, hi) = span(&energies);
    c.upper("(within {0.002} %)", 100.0 * (hi - lo) / lo);
    c.value(
        "contact loss falls {5.1}-fold",
        loss(s35, "argyris:10x7", 1e-5) / loss(s35, "argyris:10x7", 1e-7),
    );
    let two = |loss_too: bool| {
        let rows = d.csv.select("damping=beta windows=2");
        let values: Vec<f64> = rows
            .iter()
            .filter(|r| {
                let q = r.text("quantity");
                if loss_too {
                    q == "contact_loss_per_period_J"
                } else {
                    FOUR.contains(&q)
                }
            })
            .map(|r| r.number("spread") / r.number("value").abs())
            .collect();
        span(&values).1
    };
    c.upper(
        "window spread is below {1e-5} relative for the four",
        two(false),
    );
    c.value("time averages, {1.3e-3} for the contact loss", two(true));
}

fn criterion(c: &mut Claims, d: &Study) {
    let meshes = table(&format!("{DIR}damping_meshes.csv"));
    let paper = meshes.one("element=argyris nx=10 ny=7");
    let omega_max = paper.number("omega_max_rad_s");
    c.value("ω_max = {7.6e6} rad/s", omega_max);
    c.value("{761}/Δt at", omega_max * 1e-4);
    c.value(
        "(β = 2ζ₁/ω₁ = {5.913e-5} s, ζ₁ = 1 % on",
        setting("beta", "damping.stiffness_proportional"),
    );
    c.value(
        "ω₁ = {338.23} rad/s",
        meta_of("omega1_reference").parse().expect("ω₁"),
    );
    c.value(
        "ζ_hf = {0.296} at its Δt",
        d.zeta_hf("forced-35hz", "beta", "argyris:10x7", 1e-4),
    );
    let corner = |dt: f64| d.value("forced-35hz", "beta", "rms_corner_m", "argyris:10x7", dt);
    c.values(
        "is {1.7} % above its value at 1e-6 s at Δt = 1e-4 s, {0.8} % at",
        &[
            pct(corner(1e-4), corner(1e-6)),
            pct(corner(5e-5), corner(1e-6)),
        ],
    );
    let scene = plate_impact::scene::Scene::named("forced-35hz").expect("scene");
    let beam = plate_impact::advice::first_frequency_estimate(&scene);
    let plate = paper.number("omega1_rad_s");
    c.value("({345.7} rad/s on the paper's plate", beam);
    c.value("against {338.2} rad/s on Argyris", plate);
    c.value("the plate is {2.2} % softer", -pct(plate, beam));
    threshold(c, d);
}

/// The reading of the threshold table.
fn threshold(c: &mut Claims, d: &Study) {
    let s35 = "forced-35hz";
    let series = |model: &str| {
        let mut runs = d
            .runs
            .select(&format!("{s35}/{model}"), "mean_energy_J", "argyris:10x7");
        runs.sort_by(|a, b| b.dt.total_cmp(&a.dt));
        runs
    };
    // The change (%) of the mean energy from the series' smallest Δt, and ζ_hf, per Δt.
    let changes = |model: &str| {
        let runs = series(model);
        let last = runs[runs.len() - 1].value;
        runs.iter()
            .map(|r| {
                (
                    r.dt,
                    d.zeta_hf(s35, model, "argyris:10x7", r.dt),
                    pct(r.value, last),
                )
            })
            .collect::<Vec<_>>()
    };
    let (full, half) = (changes("beta"), changes("beta-half"));
    let converged = |c: &[(f64, f64, f64)]| {
        span(
            &c.iter()
                .filter(|x| x.1 >= 0.25)
                .map(|x| x.2.abs())
                .collect::<Vec<_>>(),
        )
        .1
    };
    c.values(
        "within {0.09} % (ζ₁ = 1 %) and {0.37} % (ζ₁ = 0.5 %)",
        &[converged(&full), converged(&half)],
    );
    let at = |c: &[(f64, f64, f64)], zeta: f64| {
        c.iter()
            .find(|x| (x.1 / zeta - 1.0).abs() < 0.01)
            .unwrap_or_else(|| panic!("no run at ζ_hf = {zeta}"))
            .2
            .abs()
    };
    c.value(
        "Δt from ζ_hf = {0.296} on",
        full.iter().find(|x| x.0 == 1e-4).expect("1e-4").1,
    );
    c.range(
        "{1.38}–{1.75} % off at ζ_hf = 0.148",
        &[at(&full, 0.148), at(&half, 0.148)],
    );
    c.value(
        "off at ζ_hf = {0.148} and",
        half.iter().find(|x| x.0 == 1e-4).expect("1e-4").1,
    );
    let below: Vec<f64> = full
        .iter()
        .chain(&half)
        .filter(|x| x.1 < 0.14)
        .map(|x| x.2.abs())
        .collect();
    c.range("{1.94}–{7.49} % below that", &below);
    c.value(
        "(whose β is {94} times smaller)",
        setting("beta", "damping.stiffness_proportional") / pair_beta("rayleigh-5k"),
    );
    let pair = changes("rayleigh-5k");
    c.values("is {26} % and then {9.7} % low", &[-pair[0].2, -pair[1].2]);
    c.upper("while ζ_hf ≤ {0.032}, and", pair[1].1);
    c.value("from ζ_hf = {0.315} (Δt = 1e-6 s)", pair[2].1);
    let r = |dt: f64| {
        d.runs.at(
            &format!("{s35}/rayleigh-5k"),
            "mean_energy_J",
            "argyris:10x7",
            dt,
        )
    };
    let (a, b) = (r(1e-6), r(2e-7));
    c.values(
        "({11.82} ± {0.22} against {11.62} ± {0.18} J",
        &[a.value, a.spread, b.value, b.spread],
    );
    c.value(
        "at 2e-7 s, {0.7}σ)",
        (a.value - b.value).abs() / a.spread.hypot(b.spread),
    );
    let modal = |q: &str, dt: f64| d.value(s35, "modal", q, "argyris:10x7", dt);
    c.value(
        "(ζ_hf = {0.01} at every Δt)",
        d.zeta_hf(s35, "modal", "argyris:10x7", 1e-6),
    );
    c.values(
        "(mean energy +{11} %, impacts per period +{34} % from 1e-5 s)",
        &[
            pct(modal("mean_energy_J", 1e-6), modal("mean_energy_J", 1e-5)),
            pct(
                modal("impacts_per_period", 1e-6),
                modal("impacts_per_period", 1e-5),
            ),
        ],
    );
    c.values(
        "unconverged ({0.148}) and the first converged ({0.296})",
        &[
            full.iter().find(|x| x.0 == 2e-4).expect("2e-4").1,
            full.iter().find(|x| x.0 == 1e-4).expect("1e-4").1,
        ],
    );
    let s60 = "forced-60hz";
    let steps = [1e-4, 1e-5, 1e-6];
    let pair60 = steps.map(|dt| d.value(s60, "rayleigh-5k", "mean_energy_J", "argyris:10x7", dt));
    let (lo, hi) = span(&pair60);
    c.upper("keeps its mean energy within {2} %", 100.0 * (hi - lo) / lo);
    c.values("({14.02}, {13.79}, {13.76} J at", &pair60);
    c.values(
        "ζ_hf = {0.0035}, {0.032}, {0.31})",
        &steps.map(|dt| d.zeta_hf(s60, "rayleigh-5k", "argyris:10x7", dt)),
    );
    c.values(
        "impacts per period ({2.6}, {5.2}, {6.3})",
        &steps.map(|dt| d.value(s60, "rayleigh-5k", "impacts_per_period", "argyris:10x7", dt)),
    );
    let e = |mesh: &str, dt: f64| d.value(s35, "beta", "mean_energy_J", mesh, dt);
    c.value(
        "with β = {5.913e-5} s: mean energy",
        setting("beta", "damping.stiffness_proportional"),
    );
    c.values(
        "mean energy {8.6067} J (Argyris 10 × 7), {8.6081} J (FVS 14 × 10) and {8.6227} J (Argyris 6 × 4)",
        &[e("argyris:10x7", 1e-5), e("fvs:14x10", 1e-5), e("argyris:6x4", 1e-5)],
    );
    c.values(
        "{8.614}, {8.616} and {8.627} J at 1e-4 s",
        &[
            e("argyris:10x7", 1e-4),
            e("fvs:14x10", 1e-4),
            e("argyris:6x4", 1e-4),
        ],
    );
}

fn adds(c: &mut Claims, d: &Study) {
    let s35 = "forced-35hz";
    c.value(
        "β only at ζ_hf = {0.296} (the preset",
        d.zeta_hf(s35, "beta", "argyris:10x7", 1e-4),
    );
    c.values(
        "the mean energy is within {0.09} % (35 Hz) and {1.35} % (60 Hz), but",
        &SCENES.map(|s| {
            d.error(s, "beta", "mean_energy_J", "argyris:10x7", 1e-4)
                .abs()
        }),
    );
    c.values(
        "base force are {5.6} % and {9.5} % below",
        &["mean_abs_base_force_N", "rms_base_force_N"]
            .map(|q| -d.error(s35, "beta", q, "argyris:10x7", 1e-4)),
    );
    c.value(
        "(ζ_hf = {3.0}).",
        d.zeta_hf(s35, "beta", "argyris:10x7", 1e-5),
    );
    c.value(
        "1e-6 s (ζ_hf = {0.31}) has",
        d.zeta_hf(s35, "rayleigh-5k", "argyris:10x7", 1e-6),
    );
    let e = |mesh: &str| d.value(s35, "rayleigh-5k", "mean_energy_J", mesh, 1e-6);
    c.values(
        "give {11.8}, {11.2} and {10.5} J",
        &[e("argyris:10x7"), e(REFERENCE), e("fvs:14x10")],
    );
    c.value(
        "from Δt = 1e-4 s (ζ_hf = {0.015})",
        d.zeta_hf("forced-60hz", "rayleigh-1k", "argyris:10x7", 1e-4),
    );
    c.value(
        "from 1e-5 s (ζ_hf = {0.15}); the",
        d.zeta_hf("forced-60hz", "rayleigh-1k", "argyris:10x7", 1e-5),
    );
    c.value(
        "the modal ratio (ζ_hf = {0.01})",
        d.zeta_hf("forced-60hz", "modal", "argyris:10x7", 1e-5),
    );
}

/// The damping study's paragraph of docs/studies.md.
pub fn brief(c: &mut Claims) {
    let study = Study::load();
    let d = &study;
    let runs = d.csv.select("quantity=mean_energy_J");
    let wall: f64 = runs.iter().map(|r| r.number("wall_s")).sum();
    c.value("The committed run: {326} runs", runs.len() as f64);
    c.value("{84} min of run wall time here", wall / 60.0);
    let (_, mesh) = reference_checks(d, "beta");
    c.upper("agree within {0.16} %; finer meshes", mesh);
    c.upper(
        "mean energy within {1.4} %",
        d.worst("beta", &SCENES, &FOUR[..1], &PAPER_MESHES, &[1e-4]),
    );
    let finer = finer_errors(d);
    let rms = "rms_base_force_N";
    let moving = finer
        .iter()
        .filter(|(s, q, _)| *s == "forced-35hz" && *q == rms)
        .map(|e| e.2)
        .fold(0.0, f64::max);
    c.value("move the 35 Hz RMS base force by up to {1.05} %", moving);
    let steady: Vec<f64> = finer
        .iter()
        .filter(|(s, q, _)| !(*s == "forced-35hz" && *q == rms))
        .map(|e| e.2.abs())
        .collect();
    c.upper("the rest by at most {0.09} %)", span(&steady).1);
    c.upper(
        "gives {0.3} % on FVS 14 × 10",
        d.worst("beta", &SCENES, &FOUR, &["fvs:14x10"], &[1e-5]),
    );
    c.value(
        "({1.04} % on Argyris 10 × 7)",
        d.worst("beta", &SCENES, &FOUR, &["argyris:10x7"], &[1e-5]),
    );
    let low = |q: &str| d.worst("beta", &["forced-35hz"], &[q], &PAPER_MESHES, &[1e-4]);
    c.upper("only within {5.6} % (mean)", low("mean_abs_base_force_N"));
    c.upper("and {9.5} % (RMS)", low("rms_base_force_N"));
    let q = "contact_loss_per_period_J";
    c.value(
        "falls about {14}-fold at 35 Hz",
        d.value("forced-35hz", "beta", q, "argyris:10x7", 1e-4)
            / d.value("forced-35hz", "beta", q, "argyris:10x7", 1e-7),
    );
}

/// The damping study's bullets of README.md.
pub fn readme(c: &mut Claims) {
    let study = Study::load();
    let d = &study;
    c.given(&[
        "ζ₁ = 1 %",
        "Δt = 1e-5 s",
        "4 s simulated",
        "Δt = 1e-4 s",
        "60 Hz",
        "35 Hz",
        "1e-6 s",
        "5 or 20 kHz",
        "1 kHz",
    ]);
    c.value(
        "`damping.stiffness_proportional` = {5.913e-5} s",
        setting("beta", "damping.stiffness_proportional"),
    );
    c.upper(
        "`base.force` within {0.3} % of the reference",
        d.worst("beta", &SCENES, &FOUR, &["fvs:14x10"], &[1e-5]),
    );
    c.value(
        "at {4.5} s per",
        d.wall("forced-35hz", "beta", "fvs:14x10", 1e-5),
    );
    c.value(
        "(Argyris 10 × 7: within {1.04} %",
        d.worst("beta", &SCENES, &FOUR, &["argyris:10x7"], &[1e-5]),
    );
    c.value(
        "1.04 %, {5.3} s)",
        d.wall("forced-35hz", "beta", "argyris:10x7", 1e-5),
    );
    let walls: Vec<f64> = SCENES
        .iter()
        .flat_map(|s| PAPER_MESHES.iter().map(move |m| d.wall(s, "beta", m, 1e-4)))
        .collect();
    c.range("Δt = 1e-4 s ({0.7}–{1.3} s)", &walls);
    let at_paper = |scenes: &[&str], quantities: &[&str]| {
        d.worst("beta", scenes, quantities, &PAPER_MESHES, &[1e-4])
    };
    c.upper(
        "the mean energy is within {1.35} %",
        at_paper(&SCENES, &FOUR[..1]),
    );
    c.value("the RMS corner {1.82} %", at_paper(&SCENES, &FOUR[1..2]));
    c.value(
        "force {1.84} % at 60 Hz",
        at_paper(&SCENES[1..], &FOUR[2..]),
    );
    c.values(
        "it is {5.5} % (mean) and {9.4} % (RMS) low at 35 Hz",
        &["mean_abs_base_force_N", "rms_base_force_N"]
            .map(|q| -d.error("forced-35hz", "beta", q, "fvs:14x10", 1e-4)),
    );
    let (_, mesh) = reference_checks(d, "beta");
    c.upper("FVS 14 × 10 within {0.16} %", mesh);
    let finer = finer_errors(d);
    let rms = "rms_base_force_N";
    let steady: Vec<f64> = finer
        .iter()
        .filter(|(s, q, _)| !(*s == "forced-35hz" && *q == rms))
        .map(|e| e.2.abs())
        .collect();
    c.upper("confirm it within {0.09} % except", span(&steady).1);
    let (argyris, fvs) = limits(d);
    c.range("limit {2.4}–{3.7} % higher", &[argyris, fvs]);
    c.upper(
        "converges within {1} % at 60 Hz",
        d.worst(
            "rayleigh-1k",
            &["forced-60hz"],
            &FOUR,
            &FINER,
            &[1e-5, 1e-6],
        ),
    );
    c.value(
        "Argyris 10 × 7 stays {5.5} % above",
        d.error(
            "forced-35hz",
            "rayleigh-1k",
            "mean_energy_J",
            "argyris:10x7",
            1e-6,
        ),
    );
}
