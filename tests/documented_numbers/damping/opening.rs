//! The claims of damping.md's opening: the plan, the answer, the comparison of the models and
//! why β.

use super::*;

pub(super) fn regenerate(c: &mut Claims, d: &Study) {
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
    c.value("and 1e-7 s ({3} runs), which close", count("evidence"));
    c.given(&["Argyris 20 × 14 at 1e-5 and 1e-7 s ("]);
    let runs = d.csv.select("quantity=mean_energy_J part!=evidence");
    let wall: f64 = runs.iter().map(|r| r.number("wall_s")).sum();
    let evidence = d.csv.select("quantity=mean_energy_J part=evidence");
    c.value("the part `evidence` ({3} runs", evidence.len() as f64);
    c.value(
        "{569} s of wall time) ran later",
        evidence.iter().map(|r| r.number("wall_s")).sum(),
    );
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

pub(super) fn answer(c: &mut Claims, d: &Study) {
    c.value(
        "β = 2ζ₁/ω₁ = {5.913e-5} s, the preset",
        setting("beta", "damping.stiffness_proportional"),
    );
    let h = Headline::of(d);
    c.upper(
        "within {0.3} % of the best-resolved run (Argyris 14 × 10 at 1e-6 s) on",
        h.fvs_1e5,
    );
    rule_answer(c);
    c.values(
        "in {4.5} s (35 Hz) and {5.0} s (60 Hz) per run",
        &h.walls_fvs,
    );
    c.value(
        "Argyris 10 × 7 within {1.04} % (the 35 Hz RMS",
        h.argyris_1e5,
    );
    let rms = "rms_base_force_N";
    assert_eq!(
        h.argyris_1e5,
        d.error("forced-35hz", "beta", rms, "argyris:10x7", 1e-5)
            .abs(),
        "the page names the 35 Hz RMS base force as the largest"
    );
    c.values("base force) in {5.3} and {7.0} s.", &h.walls_argyris);
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
    c.range("in {0.7}–{1.3} s.", &h.walls_paper);
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
    c.upper("lie within {0.42} % (Δt)", time);
    c.upper("and {0.16} % (mesh) of it with β only, for the four", mesh);
    c.upper(
        "and mean base force by at most {0.09} %, but",
        h.finer_steady,
    );
    c.value("RMS base force by up to {1.05} %.", h.finer_moving);
}

pub(super) fn table_rows(c: &mut Claims, d: &Study) {
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
    let impacts: Vec<f64> = GRID[1..]
        .iter()
        .flat_map(|m| d.runs.select("forced-35hz/beta", "impacts_per_period", m))
        .filter(|r| r.dt <= 1e-6)
        .map(|r| r.value)
        .collect();
    c.range("mesh ({2}–{6} per period at", &impacts);
    rayleigh_rows(c, d);
}

pub(super) fn rayleigh_rows(c: &mut Claims, d: &Study) {
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
    let mut every: f64 = 0.0;
    for q in &FOUR[..2] {
        let reference = d.reference(s60, "rayleigh-5k", q).value;
        for v in grid_values(d, s60, "rayleigh-5k", q, &GRID) {
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
pub(super) fn pair_dip(model: &str) -> (f64, f64) {
    let zeta = setting(model, "damping.ratio");
    let (f1, f2) = (
        setting(model, "damping.frequency_low"),
        setting(model, "damping.frequency_high"),
    );
    // α = 2ζω₁ω₂/(ω₁ + ω₂), β = 2ζ/(ω₁ + ω₂): √(αβ) = 2ζ√(ω₁ω₂)/(ω₁ + ω₂).
    (2.0 * zeta * (f1 * f2).sqrt() / (f1 + f2), (f1 * f2).sqrt())
}

/// β (s) of a Rayleigh pair ζ at f₁ and f₂: 2ζ/(ω₁ + ω₂).
pub(super) fn pair_beta(model: &str) -> f64 {
    let zeta = setting(model, "damping.ratio");
    let (f1, f2) = (
        setting(model, "damping.frequency_low"),
        setting(model, "damping.frequency_high"),
    );
    2.0 * zeta / (2.0 * std::f64::consts::PI * (f1 + f2))
}

pub(super) fn why_beta(c: &mut Claims, d: &Study) {
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

/// The rule of evidence's verdicts that the answer states (`damping_verdicts.csv`, written by the
/// write step).
fn rule_answer(c: &mut Claims) {
    let verdicts = table(&format!("{DIR}damping_verdicts.csv"));
    let verdict = |scene: &str, model: &str, q: &str| {
        verdicts.one(&format!(
            "scene={scene} damping={model} quantity={q} element=both"
        ))
    };
    let converged =
        |scene: &str, model: &str, q: &str| verdict(scene, model, q).text("verdict") == "converged";
    c.defines(&[
        "a Δt ladder and a mesh ladder of three settings each that agree at 1 %, the ± their summed \
         bounds",
    ]);
    c.holds(
        "finds every time average converged at 60 Hz",
        FOUR.iter().all(|q| converged("forced-60hz", "beta", q)),
    );
    let three = ["mean_energy_J", "rms_corner_m", "mean_abs_base_force_N"];
    c.holds(
        "and at 35 Hz the mean energy, the RMS corner and the mean base force",
        three.iter().all(|q| converged("forced-35hz", "beta", q)),
    );
    let stated: Vec<f64> = three
        .iter()
        .zip([1.0, 1e3, 1e-3])
        .flat_map(|(q, scale)| {
            let v = verdict("forced-35hz", "beta", q);
            [
                v.number("value") * scale,
                100.0 * v.number("bound") / v.number("value").abs(),
            ]
        })
        .collect();
    c.values(
        "({8.6063} J ± {0.016} %, {6.8005} mm ± {0.15} %, {1.4340} kN ± {0.16} %)",
        &stated,
    );
    c.holds(
        "not the 35 Hz RMS base force",
        !converged("forced-35hz", "beta", "rms_base_force_N"),
    );
    let others = [
        "none",
        "alpha",
        "rayleigh-1k",
        "rayleigh-5k",
        "rayleigh-20k",
        "modal",
    ];
    let accepted: Vec<(&str, &str)> = others
        .iter()
        .flat_map(|m| FOUR.iter().map(move |q| (*m, *q)))
        .filter(|(m, q)| SCENES.iter().any(|s| converged(s, m, q)))
        .collect();
    c.holds(
        "No other model has a time average the rule accepts on both scenes",
        !accepted
            .iter()
            .any(|(m, q)| SCENES.iter().all(|s| converged(s, m, q))),
    );
    c.holds(
        "the rule accepts the RMS corner with the 1 kHz pair only",
        accepted == [("rayleigh-1k", "rms_corner_m")]
            && converged("forced-60hz", "rayleigh-1k", "rms_corner_m"),
    );
    let counts = verdicts.select("quantity=impacts_per_period element=both verdict=converged");
    c.holds(
        "impact counts only in the periodic response of β at 60 Hz",
        counts.len() == 1
            && counts[0].text("scene") == "forced-60hz"
            && counts[0].text("damping") == "beta",
    );
    c.holds(
        "The contact loss converges with no model",
        verdicts
            .select("quantity=contact_loss_per_period_J element=both verdict=converged")
            .is_empty(),
    );
    c.given(&[
        "at 1e-7 s on Argyris 14 × 10 and at 1e-5 and 1e-7 s on Argyris 20 × 14",
        "does not start at 1e-4 s",
    ]);
}
