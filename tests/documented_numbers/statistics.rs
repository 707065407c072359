//! The claims of docs/accuracy/statistics.md, from statistics.csv, meshes.csv,
//! replica_check.csv and statistics_meta.csv.

use super::claims::Claims;
use super::data::{meta, span, table};
use super::study::{error, fit_slope, median, Runs};

pub const DIR: &str = "docs/accuracy/";
pub const FORCED: [&str; 4] = [
    "forced-35hz-damped",
    "forced-35hz",
    "forced-60hz-damped",
    "forced-60hz",
];
/// The time averages whose settling the study tests.
pub const AVERAGES: [&str; 3] = [
    "contact_loss_per_period_J",
    "mean_energy_J",
    "mean_abs_base_force_N",
];
pub const MESHES: [&str; 7] = [
    "argyris:2x1",
    "argyris:4x2",
    "argyris:6x4",
    "argyris:10x7",
    "fvs:4x3",
    "fvs:7x5",
    "fvs:14x10",
];
pub const PAPER: &str = "argyris:10x7";
pub const DAMPED: &str = "forced-35hz-damped";

pub fn claims() -> Claims {
    let mut c = Claims::new("docs/accuracy/statistics.md");
    let runs = Runs::load(&format!("{DIR}statistics.csv"));
    set_up(&mut c, &runs);
    spread(&mut c, &runs);
    time_step(&mut c, &runs);
    mesh_and_cost(&mut c, &runs);
    energy_scene(&mut c, &runs);
    c
}

fn meta_of(key: &str) -> f64 {
    meta(&format!("{DIR}statistics_meta.csv"), key)
}

/// The reference of a scene and quantity: the paper's (finest Argyris) mesh at its smallest Δt.
pub fn reference<'a>(runs: &'a Runs, scene: &str, q: &str) -> &'a super::study::Run {
    runs.smallest(scene, q, PAPER)
}

/// ω_max (rad/s) of `mesh` (`argyris:10x7`), from meshes.csv.
pub fn omega_max(mesh: &str) -> f64 {
    let (element, cells) = mesh.split_once(':').expect("mesh");
    let (nx, ny) = cells.split_once('x').expect("cells");
    table(&format!("{DIR}meshes.csv"))
        .one(&format!("element={element} nx={nx} ny={ny}"))
        .number("omega_max_rad_s")
}

/// The number of settings (scene, mesh, Δt) the study ran.
pub fn settings() -> usize {
    let runs = table(&format!("{DIR}statistics.csv"));
    let mut distinct: Vec<String> = runs
        .select("")
        .iter()
        .map(|r| {
            ["scene", "element", "nx", "ny", "dt"]
                .map(|k| r.text(k))
                .join(" ")
        })
        .collect();
    distinct.sort();
    distinct.dedup();
    distinct.len()
}

fn set_up(c: &mut Claims, runs: &Runs) {
    c.given(&[
        "2-core",
        "x86_64",
        "±10 mm",
        "35 Hz",
        "60 Hz",
        "c = 9 mm",
        "c = 2 mm",
        "ζ₁ = 1 %",
        "β = 0",
        "1 s of transient",
        "8 windows",
        "0.375 s",
        "13 periods",
        "22 at 60 Hz",
        "107.5 kPa",
        "(−10 mm)",
        "0.3 s",
        "1e-5 s",
        "0.1 s",
        "1 + k·1e-9",
        "(k = 0 … 5",
        "k = 0's",
        "√8",
        "Δt/√12",
        "6 runs",
        "2σ",
        "Δt = 1e-7 s",
        "5e-7 s",
        "c = 2 mm",
        "ω_max·Δt = 1",
        "ω_max·Δt = 30",
        "ω_max·Δt ≤ 10",
        "10 mm",
        "1 %",
        "5 %",
        "3 s window",
        "Δt = 1e-4 s",
        "1e-4 s",
        "140 elements",
        "1e-11 m",
        "(2√2·2/1)² ≈ 32",
        "2√2",
        "6 times",
        "k·1e-4 Pa",
        "30 %",
        "0.5–2",
        "1e-3, 5e-4, 2e-4, 1e-4",
        "four forced",
        "4 forced scenes",
        "ζ_k = α/(2ω_k)",
        "2ζ₁ω₁",
        "ω_max^",
        "−1 is",
        "1 % at f₁",
        "last 3 s of 4 s",
        "2, 2, 5.4, 12.3, 16.6 impacts",
        "2e-4, 1e-4, 5e-5, 2e-5, 1e-5 s",
        "c·sin(2πft)",
        " 1/s",
        "u(Lx, 0)",
        "8 window values",
        "spread is 2 %",
        "0 a fixed Δt",
        "ω_max·Δt ≫ 1",
        "140-element",
        "(−1: a fixed",
        "0: a fixed",
        "the windows of 3 s",
        "consistent with 0",
    ]);
    c.value("{380} settings", settings() as f64);
    c.value("in each of {3} processes", meta_of("processes"));
    c.value("The runs took {51.5} min", meta_of("total_s") / 60.0);
    // One row per run: the first quantity of each scene.
    let once: f64 = runs
        .rows
        .iter()
        .filter(|r| r.quantity == "rms_corner_m" || r.quantity == "first_impact_s")
        .map(|r| r.wall_s)
        .sum();
    c.value("{42.6} min for one run of each setting", once / 60.0);
    c.value("α = 2ζ₁ω₁ = {6.7645} 1/s", meta_of("alpha"));
    c.value("ω₁ = {338.227} rad/s", meta_of("omega1_reference"));
}

fn spread(c: &mut Claims, runs: &Runs) {
    c.value(
        "Over the {3} s of windows",
        meta_of("windows") * meta_of("window_target_s"),
    );
    for (quote, q) in [
        ("by {0.1}–{0.4} % (RMS free corner)", "rms_corner_m"),
        ("{2.5}–{4.8} % (impacts per period)", "impacts_per_period"),
        ("{1.6}–{4.1} % (energy removed", "contact_loss_per_period_J"),
        ("{1.1}–{3.3} % (mean energy.total)", "mean_energy_J"),
        ("{0.5}–{3.3} % (mean |base.force|)", "mean_abs_base_force_N"),
    ] {
        let relative: Vec<f64> = FORCED
            .iter()
            .map(|s| {
                let r = reference(runs, s, q);
                100.0 * r.spread / r.value.abs()
            })
            .collect();
        c.range(quote, &relative);
    }
    let check = table(&format!("{DIR}replica_check.csv"));
    let rows = check.select("quantity!=peak_corner_m window_spread>0");
    let ratios: Vec<f64> = rows
        .iter()
        .map(|r| r.number("replica_std") / r.number("window_spread"))
        .collect();
    c.value("has median {0.86}", median(&ratios));
    c.value("over {60} settings and quantities", ratios.len() as f64);
    c.range("(range {0.32}–{4.65}", &ratios);
    let worst = rows
        .iter()
        .zip(&ratios)
        .max_by(|a, b| a.1.total_cmp(b.1))
        .expect("ratios")
        .0;
    assert_eq!(
        (
            worst.text("quantity"),
            worst.text("scene"),
            worst.text("nx")
        ),
        ("mean_energy_J", "forced-35hz", "10"),
        "the prose names the largest ratio's setting"
    );
    c.value(
        "`forced-35hz` on Argyris 10×7 at Δt = {1e-4} s)",
        worst.number("dt"),
    );
}

fn time_step(c: &mut Claims, runs: &Runs) {
    c.value("ω_max = {7.61e6} rad/s", omega_max(PAPER));
    c.value("is ω_max·Δt = {761}", omega_max(PAPER) * 1e-4);
    let reference_dt = reference(runs, DAMPED, "rms_corner_m");
    c.value("Δt = 2e-7 s (ω_max·Δt = {1.52})", reference_dt.omega_max_dt);
    c.given(&["Δt = 2e-7 s"]);
    let from_to = |q: &str, scale: f64| {
        [
            runs.value(DAMPED, q, PAPER, 1e-4) * scale,
            reference(runs, DAMPED, q).value * scale,
        ]
    };
    c.values(
        "RMS free corner goes {6.51} → {5.87} mm",
        &from_to("rms_corner_m", 1e3),
    );
    c.values(
        "impacts per period {2.08} → {150}",
        &from_to("impacts_per_period", 1.0),
    );
    c.values(
        "obstacles per period {19.7} → {13.3} J",
        &from_to("contact_loss_per_period_J", 1.0),
    );
    c.values(
        "mean energy.total {9.45} → {54.6} J",
        &from_to("mean_energy_J", 1.0),
    );
    c.values(
        "mean |base.force| {2.2} → {35.7} kN",
        &from_to("mean_abs_base_force_N", 1e-3),
    );
    let (found, tried) = runs.within_noise_cases(&FORCED, &AVERAGES, &MESHES);
    let at: Vec<f64> = found.iter().map(|r| r.omega_max_dt).collect();
    c.value("within 2σ, in {67} of the", found.len() as f64);
    c.value("of the {84} (scene, quantity, mesh) cases", tried as f64);
    c.range("at ω_max·Δt between {0.46} and {165}", &at);
    c.value("(median {3.8})", median(&at));
    c.value(
        "{58} of them from ω_max·Δt ≤ 10",
        at.iter().filter(|&&x| x <= 10.0).count() as f64,
    );
    let at_paper = found
        .iter()
        .filter(|r| r.mesh == PAPER && r.dt >= 1e-4)
        .count();
    assert_eq!(at_paper, 0, "the prose says none settles at the paper's Δt");
    let all: Vec<f64> = MESHES.iter().map(|m| omega_max(m)).collect();
    c.range("ω_max spans {2.2e5}–{7.6e6} rad/s", &all);
    let points: Vec<(f64, f64)> = found.iter().map(|r| (omega_max(&r.mesh), r.dt)).collect();
    c.value("falls like ω_max^{−0.81}", fit_slope(&points));
    c.value(
        "{4} cases do so only beyond ω_max·Δt = 30",
        at.iter().filter(|&&x| x > 30.0).count() as f64,
    );
    // The mechanism: the paper's Δt removes more per period and holds less than the reference.
    let [loss, held] = ["contact_loss_per_period_J", "mean_energy_J"];
    let paper = |s: &str, q: &str| runs.value(s, q, PAPER, 1e-4);
    let holds = |s: &str| {
        paper(s, loss) > reference(runs, s, loss).value
            && paper(s, held) < reference(runs, s, held).value
    };
    c.value(
        "in {3} of the 4 forced scenes",
        FORCED.iter().filter(|s| holds(s)).count() as f64,
    );
    assert!(
        !holds("forced-35hz"),
        "the prose names forced-35hz as the exception"
    );
    c.values(
        "({20.5} → {21.8} J removed per period, {9.61} → {81.8} J held)",
        &[
            paper("forced-35hz", loss),
            reference(runs, "forced-35hz", loss).value,
            paper("forced-35hz", held),
            reference(runs, "forced-35hz", held).value,
        ],
    );
    let (rms, rms_tried) = runs.within_noise_cases(&FORCED, &["rms_corner_m"], &MESHES);
    c.value("it stays within its noise in {27} of", rms.len() as f64);
    c.value("{28} cases (at ω_max·Δt up to", rms_tried as f64);
    c.value(
        "up to {25.7}, fitted",
        span(&rms.iter().map(|r| r.omega_max_dt).collect::<Vec<_>>()).1,
    );
    let points: Vec<(f64, f64)> = rms.iter().map(|r| (omega_max(&r.mesh), r.dt)).collect();
    c.value("fitted exponent {−0.46}", fit_slope(&points));
    let spans: Vec<f64> = FORCED
        .iter()
        .flat_map(|s| MESHES.iter().map(move |m| (s, m)))
        .map(|(s, m)| {
            let values: Vec<f64> = runs
                .select(s, "rms_corner_m", m)
                .iter()
                .map(|r| r.value)
                .collect();
            let (lo, hi) = span(&values);
            1e3 * (hi - lo)
        })
        .collect();
    c.range("it spans {0.41}–{2.70} mm", &spans);
    let (impacts, impacts_tried) =
        runs.within_noise_cases(&FORCED, &["impacts_per_period"], &MESHES);
    c.value("stay within their noise in {7} of", impacts.len() as f64);
    rule_verdicts(c);
    c.value("{28} cases, only on", impacts_tried as f64);
    let mut on: Vec<&str> = impacts.iter().map(|r| r.mesh.as_str()).collect();
    on.sort();
    on.dedup();
    assert_eq!(
        on,
        ["argyris:2x1", "argyris:4x2", "fvs:4x3"],
        "the meshes the prose names"
    );
    let q = "impacts_per_period";
    c.values(
        "has {2.08} at 1e-4 s, {17.2} at 1e-5 s, {63.6} at 1e-6 s and {150} at 2e-7 s",
        &[1e-4, 1e-5, 1e-6, 2e-7].map(|dt| runs.value(DAMPED, q, PAPER, dt)),
    );
    c.given(&["at 1e-4 s,", "at 1e-5 s,", "at 1e-6 s and", "at 2e-7 s."]);
}

fn mesh_and_cost(c: &mut Claims, runs: &Runs) {
    let q = "mean_energy_J";
    let smallest = |m: &&str| runs.smallest(DAMPED, q, m).value;
    c.values(
        "mean energy.total is {15.8}, {33.1}, {43.0}, {54.6} J on Argyris",
        &MESHES[..4].iter().map(smallest).collect::<Vec<_>>(),
    );
    c.values(
        "and {22.9}, {30.1}, {32.3} J on FVS",
        &MESHES[4..].iter().map(smallest).collect::<Vec<_>>(),
    );
    // Forced statistics whose two finest meshes of each element agree.
    let quantities = [
        "rms_corner_m",
        "impacts_per_period",
        "contact_loss_per_period_J",
        "mean_energy_J",
        "mean_abs_base_force_N",
    ];
    let agreeing = FORCED
        .iter()
        .flat_map(|s| quantities.iter().map(move |q| (s, q)))
        .filter(|(s, q)| {
            [("argyris:6x4", "argyris:10x7"), ("fvs:7x5", "fvs:14x10")]
                .iter()
                .all(|(a, b)| super::study::agree(runs.smallest(s, q, a), runs.smallest(s, q, b)))
        })
        .count();
    c.value("only {4} forced statistics agree", agreeing as f64);
    c.value(
        "{4e-7} at ω_max of the paper's mesh",
        meta_of("alpha") / (2.0 * omega_max(PAPER)),
    );
    let (fine, finer) = (
        runs.smallest(DAMPED, q, "argyris:6x4").value,
        runs.smallest(DAMPED, q, PAPER).value,
    );
    c.value("differ by {21} % in", 100.0 * (finer - fine).abs() / finer);
    cost(c, runs);
}

/// The cheapest run of `scene` and `q` that reaches `tolerance` (%): its error plus uncertainty
/// is within it at its Δt and every smaller one on its mesh (the reference excluded).
pub fn cheapest<'a>(
    runs: &'a Runs,
    scene: &str,
    q: &str,
    tolerance: f64,
) -> Option<&'a super::study::Run> {
    let reference = reference(runs, scene, q);
    let within = |r: &&super::study::Run| {
        let (e, u) = error(r, reference);
        e + u <= tolerance
    };
    let mut best: Option<&super::study::Run> = None;
    for m in MESHES {
        let on = runs.select(scene, q, m);
        let not_reference = |r: &&&super::study::Run| !std::ptr::eq(**r, reference);
        let candidates: Vec<&&super::study::Run> = on.iter().filter(not_reference).collect();
        for (i, r) in candidates.iter().enumerate() {
            if candidates[i..].iter().all(|x| within(x)) {
                if best.is_none_or(|b| r.wall_s < b.wall_s) {
                    best = Some(**r);
                }
                break;
            }
        }
    }
    best
}

/// The (scene, quantity) pairs of the study besides the peak of the corner.
pub fn pairs() -> Vec<(&'static str, &'static str)> {
    let forced_q = [
        "rms_corner_m",
        "impacts_per_period",
        "contact_loss_per_period_J",
        "mean_energy_J",
        "mean_abs_base_force_N",
    ];
    let energy_q = [
        "first_impact_s",
        "energy_0.1s_J",
        "energy_0.3s_J",
        "impacts_to_0.3s",
    ];
    FORCED
        .iter()
        .flat_map(|s| forced_q.iter().map(move |q| (*s, *q)))
        .chain(energy_q.iter().map(|q| ("energy", *q)))
        .collect()
}

fn cost(c: &mut Claims, runs: &Runs) {
    let pairs = pairs();
    c.value("Of the {24} (scene, quantity) pairs", pairs.len() as f64);
    let reached = |tolerance: f64| -> Vec<(&str, &str, f64)> {
        pairs
            .iter()
            .filter_map(|(s, q)| cheapest(runs, s, q, tolerance).map(|r| (*s, *q, r.wall_s)))
            .collect()
    };
    let one = reached(1.0);
    c.value("{4} reach 1 % of the best-resolved run", one.len() as f64);
    c.value("and {8} reach 5 %", reached(5.0).len() as f64);
    let corners: Vec<f64> = one
        .iter()
        .filter(|(s, q, _)| s.starts_with("forced-60hz") && *q == "rms_corner_m")
        .map(|r| r.2)
        .collect();
    assert_eq!(corners.len(), 2, "the prose names both 60 Hz RMS corners");
    c.range("the 60 Hz RMS corners in {0.16}–{0.28} s per run", &corners);
    let others: Vec<(&str, &str)> = one
        .iter()
        .filter(|(s, _, _)| *s == "energy")
        .map(|(s, q, _)| (*s, *q))
        .collect();
    assert_eq!(
        others,
        [("energy", "first_impact_s"), ("energy", "energy_0.1s_J")],
        "the other two the prose names"
    );
    let paper_error = |q: &str| {
        FORCED
            .iter()
            .map(|s| error(runs.at(s, q, PAPER, 1e-4), reference(runs, s, q)).0)
            .collect::<Vec<f64>>()
    };
    c.values(
        "mean energy.total by {83} %, {88} %, {17} % and {34} %",
        &paper_error("mean_energy_J"),
    );
    c.values(
        "within {11.1} %, {16.5} %, {1.4} % and {2.1} %",
        &paper_error("rms_corner_m"),
    );
}

fn energy_scene(c: &mut Claims, runs: &Runs) {
    let reference = |q: &str| reference(runs, "energy", q);
    let paper = |q: &str| runs.at("energy", q, PAPER, 1e-4);
    let first = "first_impact_s";
    c.value("{6.246} ms best resolved", 1e3 * reference(first).value);
    c.value("{6.3} ms at the paper's Δt", 1e3 * paper(first).value);
    c.value(
        "at the paper's Δt ({0.9} %)",
        error(paper(first), reference(first)).0,
    );
    let e01 = "energy_0.1s_J";
    c.value(
        "still agree to {8.0e-4} relative",
        reference(e01).spread / reference(e01).value,
    );
    c.value("{15.2} J at the paper's settings", paper(e01).value);
    c.value("{24.6} J best resolved, and", reference(e01).value);
    c.values(
        "{26.4}, {25.6}, {24.4}, {24.6} J on the Argyris meshes",
        &MESHES[..4]
            .iter()
            .map(|m| runs.smallest("energy", e01, m).value)
            .collect::<Vec<_>>(),
    );
    let e03 = reference("energy_0.3s_J");
    let count = reference("impacts_to_0.3s");
    c.value(
        "scatter by {2.1} % in energy",
        100.0 * e03.spread / e03.value,
    );
    c.value(
        "and {13} % in impact count",
        100.0 * count.spread / count.value,
    );
    let q = "impacts_per_period";
    let ours: Vec<f64> = [2e-4, 1e-4, 5e-5, 2e-5, 1e-5]
        .iter()
        .flat_map(|&dt| {
            let r = runs.at(DAMPED, q, PAPER, dt);
            [r.value, r.spread]
        })
        .collect();
    c.values(
        "this study has {2} ± {0}, {2.08} ± {0.038}, {5.29} ± {0.21}, {11.7} ± {0.55}, {17.2} ± {0.73}",
        &ours,
    );
}

/// The statistics the rule of evidence finds converged (`statistics_verdicts.csv`, written by the
/// write step), the peak corner aside: (scene, quantity).
pub fn converged_statistics() -> Vec<(String, String)> {
    table(&format!("{DIR}statistics_verdicts.csv"))
        .select("element=both verdict=converged quantity!=peak_corner_m")
        .iter()
        .map(|r| (r.text("scene").to_string(), r.text("quantity").to_string()))
        .collect()
}

/// Whether the rule finds exactly the first impact and the α-damped 60 Hz RMS corner converged.
pub fn two_converge() -> bool {
    converged_statistics()
        == [
            ("energy".to_string(), "first_impact_s".to_string()),
            ("forced-60hz-damped".to_string(), "rms_corner_m".to_string()),
        ]
}

/// The relative spreads (%) of the time averages' best-resolved runs of the forced scenes.
pub fn time_average_spreads() -> Vec<f64> {
    let runs = Runs::load(&format!("{DIR}statistics.csv"));
    FORCED
        .iter()
        .flat_map(|s| {
            [
                "mean_energy_J",
                "mean_abs_base_force_N",
                "contact_loss_per_period_J",
            ]
            .map(|q| reference(&runs, s, q))
        })
        .map(|r| 100.0 * r.spread / r.value.abs())
        .collect()
}

/// The rule of evidence on this study: the two statistics it finds converged, and the spreads
/// that keep the others from it.
fn rule_verdicts(c: &mut Claims) {
    let verdicts = table(&format!("{DIR}statistics_verdicts.csv"));
    c.holds(
        "Judged by the rule at 1 %, two statistics of this study converge: the `energy` scene's \
         first impact and the α-damped 60 Hz scene's RMS corner",
        two_converge(),
    );
    c.holds(
        "The first impact converges by the rule",
        converged_statistics()
            .iter()
            .any(|(s, q)| s == "energy" && q == "first_impact_s"),
    );
    c.range(
        "leave the time averages uncertain by {0.5}–{4} %",
        &time_average_spreads(),
    );
    let peaks: Vec<f64> = verdicts
        .select("element=both quantity=peak_corner_m verdict=converged")
        .iter()
        .map(|r| 1e3 * r.number("value"))
        .collect();
    let (lo, hi) = span(&peaks);
    assert!(
        hi - lo < 1e-9,
        "the page gives one peak for every converged peak corner: {peaks:?}"
    );
    c.value("holds at the obstacle, {10} mm", hi);
}
