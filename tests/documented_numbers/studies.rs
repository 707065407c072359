//! The claims of docs/studies.md: the studies in brief, from the same CSVs as their reports.

use super::claims::Claims;
use super::damping;
use super::data::{meta, table};
use super::statistics::{self as stats, AVERAGES, DAMPED, FORCED, MESHES, PAPER};
use super::study::{fit_slope, Runs};

pub fn claims() -> Claims {
    let mut c = Claims::new("docs/studies.md");
    c.given(&[
        "ζ = 0.5, 1 and 2 %",
        "(5 257 free dofs on Argyris), Δt down to 1e-6 s and on two meshes to 1e-7 s",
        "at ζ = 0.5 and 2 %",
        "above 1 kHz",
        "`1.04` ± 0.005, `5` ± 0.5, `2e-6` ± 0.5e-6",
        "\"within 1 %\"",
        "\"0.01–0.4 %\"",
        "(`10 × 7`, `10×7`)",
        "within 2σ",
        "2σ, settling",
        "under a second",
        "1e-3 to 1e-6 s",
        "0.1 s",
        "from 1e-3 s down to ω_max·Δt ≤ 1",
        "35 Hz (c = 9 mm) and 60 Hz (c = 2 mm",
        "ζ₁ = 1 %",
        "8 windows of ~0.375 s",
        "ω_max·Δt ≤ 10",
        "(−1 would be",
        "ω_max·Δt = 30",
        "Δt = 1e-4 s",
        "Δt = 1e-4, 1e-5, 1e-6, 2e-7 s",
        "1 % of the best-resolved",
        " 5 %.",
        "3 s window",
        "(35 Hz, 60 Hz)",
        "ζ = 1 % at f₁ and at 1, 5, 20 kHz; a modal ratio of 1 %",
        "Δt = 1e-4, 1e-5, 1e-6 s;",
        "down to 5e-8 s",
        "Δt = 1e-5 s gives",
        "the 35 Hz RMS base force",
        "from Δt = 1e-4 to 1e-7 s",
        "the 35 Hz base force",
        "so 1.04 is not within 1",
        "Table 1 case",
        "α-damped 35 Hz",
        "the 60 Hz RMS corners",
        "the 5 kHz pair",
        "at 35 Hz from",
    ]);
    c.defines(&[
        "The last pair agrees (|d₂| + 2σ within the tolerance)",
        "their Δt ladders step by 10, so three settings span two decades",
        "the periodic response at 1e-4 s that turns chaotic at 1e-5 s in the modal study",
        "plus 2σ of the value",
        "One tolerance, 1 %, for every verdict and mark",
        "(\"converged when both ladders pass at 1 %\")",
    ]);
    c.given(&[
        "at 1e-6 s",
        "at ζ = 1 %; at ζ = 0.5 and 2 % no mesh ran three Δt",
    ]);
    accuracy(&mut c);
    restitution(&mut c);
    statistics(&mut c);
    damping::brief(&mut c);
    c
}

fn accuracy(c: &mut Claims) {
    let runs = table("docs/accuracy/runs.csv");
    c.value("({406} runs,", runs.select("").len() as f64);
    c.value(
        "{14} min here;",
        meta("docs/accuracy/meta.csv", "total_s") / 60.0,
    );
    for mesh in ["mesh=argyris:10x7", "mesh=fvs:14x10"] {
        c.value(
            "second order in Δt ({2.00} on both",
            super::accuracy::dt_order(&runs, "free-smooth", mesh),
        );
    }
    let ratios = super::accuracy::clarabel_ratios(&runs);
    c.range("trajectories at {7}× to {151}× less", &ratios);
}

/// The restitution section, from docs/restitution/'s CSVs (the `energy` scene through the library,
/// `runs.csv`, and through the FMU, `fmu_energy.csv`).
fn restitution(c: &mut Claims) {
    c.given(&[
        "e ∈ [0, 1] (default 0",
        "§8",
        "at e = 1",
        "over 1 s at Δt = 1e-4 s",
        "at 1e-5 s, through",
        "after 1 s",
        "at e = 0, 0.25, 0.5, 0.75, 0.9 and 1",
        "Δt ≥ 5e-6 s",
        "at 1e-6 s.",
        "at Δt = 1e-4 s the energy",
        "u_{n+1}",
        "u_{n−1}",
        "for e > 0",
        "e = 1 keeps",
        "e < 1",
    ]);
    let runs = table("docs/restitution/runs.csv");
    let fmu = table("docs/restitution/fmu_energy.csv");
    let kept = |law: &str, e: f64, dt: f64| {
        let r = runs.one(&format!("law={law} e={e} dt={dt}"));
        r.number("energy_last_J") / r.number("energy_first_J")
    };
    c.values(
        "keeps the energy to {1.8e-15} over 1 s at Δt = 1e-4 s and to {1.3e-11} at 1e-5 s",
        &[1e-4, 1e-5].map(|dt| {
            fmu.one(&format!("dt={dt} obstacle=true"))
                .number("relative_change")
                .abs()
        }),
    );
    c.value(
        "the former default, lost {0.6} %",
        100.0 * (1.0 - kept("newton", 1.0, 1e-4)),
    );
    c.values(
        "the energy kept after 1 s is {31}, {29}, {33}, {51}, {59} and {100} %",
        &[0.0, 0.25, 0.5, 0.75, 0.9, 1.0].map(|e| 100.0 * kept("auto", e, 1e-4)),
    );
    let holds = |selection: &str| {
        runs.select(&format!("law=auto e=1 {selection}"))
            .iter()
            .map(|r| r.number("longest_hold"))
            .fold(0.0, f64::max)
    };
    c.values(
        "hover: for up to {9} consecutive steps at Δt ≥ 5e-6 s in the `energy` scene at e = 1, and \
         up to {53} at 1e-6 s",
        &[holds("dt>=5e-6"), holds("dt=1e-6")],
    );
}

fn statistics(c: &mut Claims) {
    let runs = Runs::load(&format!("{}statistics.csv", stats::DIR));
    let omega_max = stats::omega_max;
    let all: Vec<f64> = MESHES.iter().map(|m| omega_max(m)).collect();
    c.range("(ω_max from {2.2e5} to {7.6e6} rad/s", &all);
    let meta_of = |key: &str| meta(&format!("{}statistics_meta.csv", stats::DIR), key);
    c.value("reduced grid is {380} settings", stats::settings() as f64);
    c.value("{51.5} min of run time here", meta_of("total_s") / 60.0);
    c.value("in {3} processes side by side", meta_of("processes"));
    c.holds(
        "By the rule of evidence only the `energy` scene's first impact and the α-damped 60 Hz RMS \
         corner converge",
        stats::two_converge(),
    );
    c.range(
        "leave the time averages uncertain by {0.5}–{4} %",
        &stats::time_average_spreads(),
    );
    c.given(&["within 1 %. -", "α-damped 60 Hz RMS"]);
    let (found, tried) = runs.within_noise_cases(&FORCED, &AVERAGES, &MESHES);
    let at: Vec<f64> = found.iter().map(|r| r.omega_max_dt).collect();
    c.value("no verdict of convergence) in {67} of", found.len() as f64);
    c.value("of {84} (scene, quantity, mesh) cases", tried as f64);
    c.value(
        "{58} of them from",
        at.iter().filter(|&&x| x <= 10.0).count() as f64,
    );
    let points: Vec<(f64, f64)> = found.iter().map(|r| (omega_max(&r.mesh), r.dt)).collect();
    c.value("falls like ω_max^{−0.81} across", fit_slope(&points));
    c.value(
        "{4} cases only beyond",
        at.iter().filter(|&&x| x > 30.0).count() as f64,
    );
    c.value(
        "ω_max·Δt = {761}) they are far off",
        omega_max(PAPER) * 1e-4,
    );
    let reference = |q: &str| stats::reference(&runs, DAMPED, q).value;
    let paper = |q: &str| runs.value(DAMPED, q, PAPER, 1e-4);
    c.values(
        "holds {9.45} J on average against {54.6} J best resolved",
        &[paper("mean_energy_J"), reference("mean_energy_J")],
    );
    c.values(
        "is {2.2} kN against {35.7} kN",
        &[
            paper("mean_abs_base_force_N") / 1e3,
            reference("mean_abs_base_force_N") / 1e3,
        ],
    );
    let corner: Vec<f64> = FORCED
        .iter()
        .map(|s| {
            let r = runs.at(s, "rms_corner_m", PAPER, 1e-4);
            super::study::error(r, stats::reference(&runs, s, "rms_corner_m")).0
        })
        .collect();
    c.range("within {1.4}–{16.5} % at the paper's settings", &corner);
    let (rms, rms_tried) = runs.within_noise_cases(&FORCED, &["rms_corner_m"], &MESHES);
    c.values(
        "its noise in {27} of {28} (scene, mesh) cases",
        &[rms.len() as f64, rms_tried as f64],
    );
    c.values(
        "({2.1} → {17} → {64} → {150} per period",
        &[1e-4, 1e-5, 1e-6, 2e-7].map(|dt| runs.value(DAMPED, "impacts_per_period", PAPER, dt)),
    );
    c.values(
        "mean energy is {15.8}, {33.1}, {43.0}, {54.6} J on Argyris",
        &MESHES[..4]
            .iter()
            .map(|m| runs.smallest(DAMPED, "mean_energy_J", m).value)
            .collect::<Vec<_>>(),
    );
    let pairs = stats::pairs();
    let reached = |tolerance: f64| {
        pairs
            .iter()
            .filter(|(s, q)| stats::cheapest(&runs, s, q, tolerance).is_some())
            .count() as f64
    };
    c.value("{4} of the", reached(1.0));
    c.value("of the {24} statistics", pairs.len() as f64);
    c.value("and {8} reach", reached(5.0));
}
