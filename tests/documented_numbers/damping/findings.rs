//! The claims of damping.md's findings: the finer reference, the contact loss, the criterion of
//! the start-up warning and its threshold.

use super::*;

pub(super) fn finer_reference(c: &mut Claims, d: &Study) {
    let (s35, q) = ("forced-35hz", "rms_base_force_N");
    c.value(
        "RMS base force still rises by {0.68} %",
        -d.error(s35, "beta", q, "argyris:10x7", 1e-6),
    );
    c.value(
        "FVS 14 × 10 lies {0.14} % above it",
        d.error(s35, "beta", q, "fvs:14x10", 1e-6),
    );
    c.upper(
        "move by at most {0.09} % from the reference on the finer meshes",
        Headline::of(d).finer_steady,
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

pub(super) fn contact_loss(c: &mut Claims, d: &Study) {
    let q = "contact_loss_per_period_J";
    let loss = |scene: &str, mesh: &str, dt: f64| d.value(scene, "beta", q, mesh, dt);
    let on = |scene: &str, meshes: &[&str], dt: f64| {
        meshes
            .iter()
            .map(|m| loss(scene, m, dt))
            .collect::<Vec<f64>>()
    };
    let (from_4x2, fine) = (&GRID[1..], &GRID[2..]);
    let s35 = "forced-35hz";
    c.range(
        "it is {15.8}–{16.6} J per forcing period",
        &on(s35, from_4x2, 1e-4),
    );
    c.range(
        "{5.7}–{7.1} J at 1e-5 s on those from 6 × 4 on",
        &on(s35, fine, 1e-5),
    );
    c.value("({4.7} J on 4 × 2)", loss(s35, "argyris:4x2", 1e-5));
    c.range("{2.6}–{3.9} J at 1e-6 s", &on(s35, fine, 1e-6));
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
    let smallest = span(&grid_values(d, s35, "beta", q, fine)).0;
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

pub(super) fn criterion(c: &mut Claims, d: &Study) {
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
pub(super) fn threshold(c: &mut Claims, d: &Study) {
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

pub(super) fn adds(c: &mut Claims, d: &Study) {
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
        "1e-6 s (ζ_hf = {0.31}) stays",
        d.zeta_hf(s35, "rayleigh-5k", "argyris:10x7", 1e-6),
    );
    let spreads: Vec<f64> = ["argyris:10x7", REFERENCE, "fvs:14x10"]
        .iter()
        .flat_map(|m| {
            d.runs
                .select(&format!("{s35}/rayleigh-5k"), "mean_energy_J", m)
        })
        .filter(|r| r.dt <= 1e-6 * (1.0 + 1e-9))
        .map(|r| 100.0 * r.spread / r.value.abs())
        .collect();
    c.range("their spreads are {0.5}–{1.8} %", &spreads);
    let ladders = table(&format!("{DIR}damping_ladders.csv"));
    c.holds(
        "accepts none of these Δt ladders",
        ["argyris:10x7", REFERENCE, "fvs:14x10"].iter().all(|m| {
            ladders
                .select(&format!(
                    "scene=forced-35hz damping=rayleigh-5k quantity=mean_energy_J mesh={m} dt<=1e-6"
                ))
                .iter()
                .all(|r| r.text("dt_verdict") != "accepted")
        }),
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
