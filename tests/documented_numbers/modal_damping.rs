//! The claims of docs/accuracy/modal_damping.md (the modal damping study), from
//! modal_damping.csv, modal_damping_bands.csv, modal_damping_meshes.csv and
//! modal_damping_meta.csv.

use super::claims::Claims;
use super::data::{table, Row, Table};
use std::f64::consts::PI;

const DIR: &str = "docs/accuracy/";

pub fn claims() -> Claims {
    let mut c = Claims::new("docs/accuracy/modal_damping.md");
    c.check_verdict_words();
    let runs = table(&format!("{DIR}modal_damping.csv"));
    let meshes = table(&format!("{DIR}modal_damping_meshes.csv"));
    design(&mut c, &meshes);
    c.value(
        "what ran took {54} CPU minutes in all",
        super::data::meta(&format!("{DIR}modal_damping_meta.csv"), "cpu_s") / 60.0,
    );
    finest_cost(&mut c, &runs, &meshes);
    findings(&mut c, &runs);
    c
}

/// The cost of the Argyris 28 × 20 line at 35 Hz, from its rows and its mesh's set-up.
fn finest_cost(c: &mut Claims, runs: &Table, meshes: &Table) {
    let rows: Vec<Row> = [1e-4, 1e-5, 1e-6]
        .iter()
        .map(|&dt| run(runs, E, "forced-35hz", 0.01, FINEST, dt))
        .collect();
    let eigenbasis = meshes
        .one(&format!("plate=Paper mesh={FINEST}"))
        .number("modes_cpu_s");
    let total: f64 = rows.iter().map(|r| r.number("cpu_s")).sum();
    c.value("line cost {381} CPU s in all", eigenbasis + total);
    let wall: f64 = rows.iter().map(|r| r.number("wall_s")).sum();
    c.value("in all ({7} wall minutes", wall / 60.0);
    c.value("the study's eigenbasis {13} CPU s", eigenbasis);
    let set_up: Vec<f64> = rows.iter().map(|r| r.number("set_up_cpu_s")).collect();
    c.range("each run's stepper set-up {17}–{19} CPU s", &set_up);
    let stepping: Vec<f64> = rows
        .iter()
        .map(|r| r.number("cpu_s") - r.number("set_up_cpu_s"))
        .collect();
    c.values("1e-5 and 1e-6 s {8}, {42} and {265} CPU s", &stepping);
    let per_step: Vec<f64> = rows.iter().map(|r| r.number("step_us")).collect();
    c.values("({114}, {60} and {38} µs per step)", &per_step);
    // A run at 1e-7 s: the 7 s of a run (1 s of transient, 6 s of steady state) in 7e7 steps at
    // the 1e-6 s run's CPU per step.
    c.value(
        "1e-6 s run, about {44} CPU minutes",
        7e7 * per_step[2] * 1e-6 / 60.0,
    );
    let cpu = |scene: &str, zeta: f64, mesh: &str, dt: f64| {
        run(runs, E, scene, zeta, mesh, dt).number("cpu_s")
    };
    c.value(
        "just under the cap, took {21} CPU s",
        cpu("forced-60hz", 0.02, "argyris:14x10", 1e-6),
    );
    c.values(
        "there its runs took {91} and {70} CPU s",
        &["forced-60hz", "forced-35hz"].map(|s| cpu(s, 0.01, "argyris:10x7", 1e-7)),
    );
}

/// The study's settings, as the page states them.
fn design(c: &mut Claims, meshes: &Table) {
    c.defines(&[
        "do the statistics converge",
        "\"When impact statistics converge\"",
        "It runs on the modal backend, at every mesh size",
        "whether what still moved between 1e-5 and 1e-6 s settles one decade further",
        "stops refining once the mean energy, the RMS corner and the mean and RMS base force at two \
         successive Δt agree (within 1 % or within 2σ of their difference)",
    ]);
    let damping = table("docs/accuracy/damping.csv");
    let at = |mesh: &str| {
        damping
            .one(&format!(
                "quantity={E} scene=forced-35hz damping=modal mesh={mesh} dt=1e-6"
            ))
            .number("value")
    };
    c.value(
        "with ζ = 1 % {15} % apart on Argyris 10 × 7 and FVS 14 × 10",
        100.0 * (at("argyris:10x7") / at("fvs:14x10") - 1.0),
    );
    c.given(&[
        "ζ of 0.5–2 %",
        "η ≈ 2ζ",
        "2ζω_k",
        "§10",
        "ζ = 1 %",
        "ζ ∈ {0.5 %, 1 %, 2 %}",
        "0.4 × 0.2 × 0.01 m",
        "x = 0",
        "±10 mm",
        "9 mm at 35 Hz",
        "2 mm at 60 Hz",
        "E = 70 GPa, ν = 0.33, ρ = 2700 kg/m³",
        "0.3 × 0.3 m, 5 mm thick",
        "±5 mm",
        "4 mm at 40 Hz",
        "aspect ratio is 1 instead of 2",
        "(S/2)",
        "(0.8 of the gap)",
        "Δt = 1e-4, 1e-5, 1e-6 s",
        "a shared 2-core machine",
        "about a quarter of a core",
        "Δt down to 1e-6 s",
        "Δt = 1e-5 and 1e-6 s",
        "ζ = 0.5 % and 2 %",
        "then 0.5 % and 2 %",
        "(5 257 free dofs",
        "about 2 CPU minutes",
        "1.7 GB",
        "at most 781 MiB resident",
        "the runs at 1e-4,",
        "2 000 free dofs",
        "capped at 600 CPU s",
        "cap of 60 CPU s",
        "at 60 and 35 Hz",
        "Δt = 1e-7 s",
        "more than two replicas",
        "1 s of transient from rest, then 6 s of steady state",
        "nearest 1 s (35, 60 and 40 periods)",
        "the 6 window values over √6",
        "2 more runs",
        "k·2.5e-11 m·√kg",
        "k·1e-11 m",
        "the 3 run values",
        "E_k = ½((q_k,n − q_k,n−1)/Δt)² + ¼ω_k²(q_k,n² + q_k,n−1²)",
        "(0–100 Hz, 100–300 Hz, 300 Hz–1 kHz, … 300 kHz–1 MHz, above)",
        "every 1e-4 s",
        "(to 1e-6 relative)",
        "M ≥ 5τ(M)",
        "2ζ",
    ]);
    let f1 = |plate: &str, mesh: &str| {
        meshes
            .one(&format!("plate={plate} mesh={mesh}"))
            .number("omega1_rad_s")
            / (2.0 * PI)
    };
    c.value(
        "first natural frequency f₁ = {53.8} Hz",
        f1("Paper", "argyris:14x10"),
    );
    c.value("(its f₁ is {47.7} Hz)", f1("Aluminium", "argyris:10x10"));
    // The modal density (S/2)·√(ρe/D) of each plate, from its parameters (written above).
    let density = |area: f64, rho: f64, e: f64, young: f64, nu: f64| {
        let d = young * e.powi(3) / (12.0 * (1.0 - nu * nu));
        area / 2.0 * (rho * e / d).sqrt()
    };
    c.value(
        "is {2.3} times the paper plate's",
        density(0.09, 2700.0, 0.005, 7e10, 0.33) / density(0.08, 7770.0, 0.01, 2.1e11, 0.3),
    );
}

/// The run of `quantity` of `scene` at ratio `zeta` on `mesh` (`argyris:10x7`) at Δt = `dt`.
fn run<'a>(runs: &'a Table, q: &str, scene: &str, zeta: f64, mesh: &str, dt: f64) -> Row<'a> {
    runs.one(&format!(
        "quantity={q} scene={scene} modal_ratio={zeta} mesh={mesh} dt={dt}"
    ))
}

/// The rule's verdict (`modal_damping_verdicts.csv`, written by the study's write step through
/// `plateimpact_tools.studies.evidence`) on `q` of `scene` at ratio `zeta` for `element`
/// ("argyris", "fvs" or "both").
fn verdict<'a>(verdicts: &'a Table, q: &str, scene: &str, zeta: f64, element: &str) -> Row<'a> {
    verdicts.one(&format!(
        "quantity={q} scene={scene} damping={zeta} element={element}"
    ))
}

/// The rule at one setting (`modal_damping_ladders.csv`): its Δt and mesh ladders.
fn ladder<'a>(ladders: &'a Table, q: &str, scene: &str, zeta: f64, mesh: &str, dt: f64) -> Row<'a> {
    ladders.one(&format!(
        "quantity={q} scene={scene} damping={zeta} mesh={mesh} dt={dt}"
    ))
}

/// The verdicts the study's write step wrote.
fn verdicts_table() -> Table {
    table(&format!("{DIR}modal_damping_verdicts.csv"))
}

/// The rule at every setting, as the write step wrote it.
fn ladders_table() -> Table {
    table(&format!("{DIR}modal_damping_ladders.csv"))
}

/// The four time averages.
const AVERAGES: [&str; 4] = [E, CORNER, "mean_abs_base_force_N", RMS_FORCE];

/// The value of [`run`], scaled (1e3 for mm from m, 1e-3 for kN from N, 100 for % from a share).
fn value(runs: &Table, q: &str, scene: &str, zeta: f64, mesh: &str, dt: f64, scale: f64) -> f64 {
    run(runs, q, scene, zeta, mesh, dt).number("value") * scale
}

/// The run of `quantity` of `scene` at ratio `zeta` on `mesh` at the smallest Δt it ran.
fn smallest_dt<'a>(runs: &'a Table, q: &str, scene: &str, zeta: f64, mesh: &str) -> Row<'a> {
    runs.select(&format!(
        "quantity={q} scene={scene} modal_ratio={zeta} mesh={mesh}"
    ))
    .into_iter()
    .min_by(|a, b| a.number("dt").total_cmp(&b.number("dt")))
    .expect("the mesh ran")
}

/// The values of `q` at 1e-6 s on `meshes`, scaled.
fn at_finest(
    runs: &Table,
    q: &str,
    scene: &str,
    zeta: f64,
    meshes: &[&str],
    scale: f64,
) -> Vec<f64> {
    meshes
        .iter()
        .map(|m| value(runs, q, scene, zeta, m, 1e-6, scale))
        .collect()
}

/// Every value of `q` on `meshes`, at every Δt each ran, scaled.
fn every_dt(
    runs: &Table,
    q: &str,
    scene: &str,
    zeta: f64,
    meshes: &[&str],
    scale: f64,
) -> Vec<f64> {
    meshes
        .iter()
        .flat_map(|m| {
            runs.select(&format!(
                "quantity={q} scene={scene} modal_ratio={zeta} mesh={m}"
            ))
        })
        .map(|r| r.number("value") * scale)
        .collect()
}

const E: &str = "mean_energy_J";
const CORNER: &str = "rms_corner_m";
const RMS_FORCE: &str = "rms_base_force_N";
const IMPACTS: &str = "impacts_per_period";
const ABOVE_1K: &str = "modal_share_above_1khz";
const ABOVE_10K: &str = "modal_share_above_10khz";
const ARGYRIS: [&str; 3] = ["argyris:6x4", "argyris:10x7", "argyris:14x10"];
const FVS: [&str; 3] = ["fvs:7x5", "fvs:14x10", "fvs:28x20"];
/// The finer Argyris mesh of the `fine` part, run at 35 Hz only.
const FINE: &str = "argyris:20x14";
/// The finest Argyris mesh (5 257 free dofs), the `fine` part on both forced scenes.
const FINEST: &str = "argyris:28x20";
/// The meshes whose 60 Hz mean energy and corner at ζ = 1 % the page and the warning give as one
/// span over every Δt (the 60 Hz meshes from Argyris 6 × 4 and FVS 14 × 10 up).
const SPAN_60HZ: [&str; 6] = [
    "argyris:6x4",
    "argyris:10x7",
    "argyris:14x10",
    FINEST,
    "fvs:14x10",
    "fvs:28x20",
];

/// What the study found.
fn findings(c: &mut Claims, runs: &Table) {
    c.given(&[
        "the 6 s of steady state",
        "\"at 1e-6 s\"",
        "Δt = 1e-4, 1e-5, 1e-6 and 1e-7 s",
        "from 1e-6 to 1e-7 s",
        "from 1e-4 s down",
        "ζ = 1 %",
        "the 1 s windows (35, 60 and 40 periods)",
        "at 1e-5 and 1e-6 s",
        "above 1/Δt",
        "with 1/Δt",
        "(35, 60 and 40 periods)",
        "the 6 s could not",
        "35 Hz",
        "60 Hz",
        "1e-4 s",
        "1e-5 s",
        "1e-6 s",
        "1e-5 to 1e-6 s",
        "1e-5 and 1e-6 s",
        "1 kHz",
        "10 kHz",
        "ratio of 1 %",
        "ratio of 1 %",
        "ζ = 2 %",
        "ζ = 0.5 %",
        "1e-7 s",
        "at 1 %,",
        "(1e-5 s only)",
        "at 2 % (Argyris",
        "1e-5, 1e-6, 1e-7 s",
    ]);
    c.defines(&[
        "a value is converged at a setting when its Δt ladder (that mesh at the setting's Δt and \
         the two larger it ran) and its mesh ladder (that Δt on the two next coarser meshes of its \
         element) both pass at 1 %",
        "the 1 % the rule asks of a pair",
        "less than a tenth of the tolerance, which the rule counts as no change",
        "a change after a flat pair is what the rule refuses as a plateau that ends",
        "the rule of `scripts/converge`",
        "What would settle the time averages",
        "Agreement of the two elements at one Δt says nothing of the Δt error they share, which is \
         why it is no verdict here",
    ]);
    let verdicts = verdicts_table();
    let not_converged = |scene: &str, quantities: &[&str]| {
        quantities
            .iter()
            .all(|q| verdict(&verdicts, q, scene, 0.01, "both").text("verdict") == "not converged")
    };
    c.holds(
        "counts of contact episodes rather than a statistic that converges",
        not_converged("forced-60hz", &[IMPACTS]),
    );
    c.holds(
        "counts and contact losses do not converge",
        not_converged("forced-35hz", &[IMPACTS, "contact_loss_per_period_J"]),
    );
    // The one converged verdict: none of its ladders' runs has an unresolved correlation time.
    let one = verdict(&verdicts, E, "forced-60hz", 0.01, "both");
    let (mesh, dt) = (one.text("mesh").to_string(), one.number("dt"));
    let element = mesh.split(':').next().expect("element:NXxNY");
    let mut resolved = true;
    for ladder_dt in one.text("dt_ladder").split(' ') {
        let r = run(
            runs,
            E,
            "forced-60hz",
            0.01,
            &mesh,
            ladder_dt.parse().expect("Δt"),
        );
        resolved &= r.text("tau_resolved") == "true";
    }
    for cells in one.text("mesh_ladder").split(' ') {
        let r = run(
            runs,
            E,
            "forced-60hz",
            0.01,
            &format!("{element}:{cells}"),
            dt,
        );
        resolved &= r.text("tau_resolved") == "true";
    }
    c.holds(
        "the one converged verdict (60 Hz, ζ = 1 %, mean energy) rests on none of them",
        resolved,
    );
    verdict_claims(c);
    sixty(c, runs);
    thirty_five(c, runs);
    energy(c, runs);
    correlation(c, runs);
    ratios(c, runs);
    third(c, runs);
}

/// The rule's verdicts the page states: one time average converged, and why the others are not.
fn verdict_claims(c: &mut Claims) {
    let verdicts = verdicts_table();
    let converged: Vec<Row> = verdicts
        .select("element=both verdict=converged")
        .into_iter()
        .filter(|r| AVERAGES.contains(&r.text("quantity")))
        .collect();
    let one = converged.len() == 1
        && converged[0].text("scene") == "forced-60hz"
        && converged[0].number("damping") == 0.01
        && converged[0].text("quantity") == E
        && converged[0].text("mesh") == FINEST
        && converged[0].number("dt") == 1e-6;
    c.holds(
        "of the four time averages, on both forced scenes and the third plate at the three ratios, \
         one is converged: the mean energy at 60 Hz and ζ = 1 %",
        one,
    );
    let v = verdict(&verdicts, E, "forced-60hz", 0.01, "both");
    c.values(
        "the mean energy at 60 Hz and ζ = 1 %, {13.53} ± {0.10} J (Argyris 28 × 20 at 1e-6 s)",
        &[v.number("value"), v.number("bound")],
    );
    // Why the others are not: no Δt ladder at 0.5 and 2 %, no mesh ladder on the third plate, and
    // at 35 Hz, ζ = 1 %, every Δt ladder to 1e-6 s starts at 1e-4 s and disagrees.
    let ladders = ladders_table();
    let rows = |selection: &str| ladders.select(selection);
    let two_dt = [0.005, 0.02].iter().all(|z| {
        rows(&format!("damping={z} scene!=aluminium-square"))
            .iter()
            .all(|r| r.text("dt_verdict") == "none")
    });
    c.holds("At ζ = 0.5 % and 2 % every mesh ran two Δt", two_dt);
    c.holds(
        "so no Δt ladder exists; the aluminium plate ran two meshes per element, so no mesh ladder \
         exists",
        rows("scene=aluminium-square")
            .iter()
            .all(|r| r.text("mesh_verdict") == "none"),
    );
    let at_35 = rows("scene=forced-35hz damping=0.01 dt=1e-6");
    c.holds(
        "every Δt ladder that ends at 1e-6 s starts with the periodic response at 1e-4 s (below), \
         which disagrees with the rest",
        at_35.iter().all(|r| {
            !AVERAGES.contains(&r.text("quantity"))
                || ["none", "refused"].contains(&r.text("dt_verdict"))
                    && (r.text("dt_verdict") == "none" || r.text("dt_ladder").starts_with("0.0001"))
        }),
    );
    c.holds(
        "and the two ladders that end at 1e-7 s have no mesh ladder beside them",
        rows("scene=forced-35hz damping=0.01 dt=1e-7")
            .iter()
            .all(|r| r.text("mesh_verdict") == "none"),
    );
}

fn sixty(c: &mut Claims, runs: &Table) {
    let s = "forced-60hz";
    c.range(
        "On every mesh from Argyris 6 × 4 and FVS 14 × 10 up, at every Δt from 1e-4 s down, the \
         mean energy lies within {13.47}–{13.55} J",
        &every_dt(runs, E, s, 0.01, &SPAN_60HZ, 1.0),
    );
    c.range(
        "RMS free corner within {7.154}–{7.176} mm",
        &every_dt(runs, CORNER, s, 0.01, &SPAN_60HZ, 1e3),
    );
    let lowest = |mesh: &str| {
        every_dt(runs, E, s, 0.01, &[mesh], 1.0)
            .into_iter()
            .fold(f64::INFINITY, f64::min)
    };
    c.values(
        "(Argyris 4 × 2 down to {13.14} J, FVS 7 × 5 down to {13.06} J)",
        &[lowest("argyris:4x2"), lowest("fvs:7x5")],
    );
    // The corner's ladders on both 28 × 20 meshes: the first change under a tenth of the
    // tolerance (the rule's floor), the second above it, both under 0.2 %.
    for mesh in [FINEST, "fvs:28x20"] {
        let v = [1e-4, 1e-5, 1e-6].map(|dt| value(runs, CORNER, s, 0.01, mesh, dt, 1.0));
        let (d1, d2) = ((v[1] / v[0] - 1.0).abs(), (v[2] / v[1] - 1.0).abs());
        assert!(
            d1 < 0.001 && d2 > d1 && d2 < 0.002,
            "the page says the 60 Hz corner on {mesh} moved by less than 0.1 %, then by more \
             (under 0.2 %): {d1}, {d2}"
        );
    }
    c.given(&["less than 0.2 %", "from 1e-4 to 1e-5 s"]);
    // The two 28 × 20 meshes at 1e-6 s: energy and corner at every ratio, the RMS base force at 1 %.
    let gap = |q: &str, z: f64| {
        let at = |m: &str| value(runs, q, s, z, m, 1e-6, 1.0);
        100.0 * (at(FINEST) / at("fvs:28x20") - 1.0).abs()
    };
    let elements = [0.005, 0.01, 0.02]
        .iter()
        .flat_map(|&z| [gap(E, z), gap(CORNER, z)])
        .chain([gap(RMS_FORCE, 0.01)])
        .fold(0.0, f64::max);
    c.upper(
        "The two elements lie within {0.3} % of each other at 60 Hz on the energy and the corner \
         at every ratio, and at ζ = 1 % on the RMS base force at 1e-6 s",
        elements,
    );
    c.upper(
        "At 1e-6 s the RMS base force lies within {0.1} % on the two finest meshes, from above",
        gap(RMS_FORCE, 0.01),
    );
    let argyris = [ARGYRIS.as_slice(), &[FINEST]].concat();
    c.values(
        "({5.57}, {5.56}, {5.52}, {5.48} kN on 6 × 4",
        &at_finest(runs, RMS_FORCE, s, 0.01, &argyris, 1e-3),
    );
    c.values(
        "({5.35}, {5.46}, {5.49} kN on 7 × 5",
        &at_finest(runs, RMS_FORCE, s, 0.01, &FVS, 1e-3),
    );
    let a = value(runs, RMS_FORCE, s, 0.01, FINEST, 1e-6, 1.0);
    let f = value(runs, RMS_FORCE, s, 0.01, "fvs:28x20", 1e-6, 1.0);
    c.value("the two finest {0.1} % apart", 100.0 * (a / f - 1.0).abs());
    let ladder = |q: &str, mesh: &str, dts: &[f64], scale: f64| -> Vec<f64> {
        dts.iter()
            .map(|&dt| value(runs, q, s, 0.01, mesh, dt, scale))
            .collect()
    };
    let four = [1e-4, 1e-5, 1e-6, 1e-7];
    let force = ladder(RMS_FORCE, "argyris:10x7", &four, 1e-3);
    c.values("it is {4.70}, {5.26}, {5.56} and {5.53} kN", &force);
    c.value(
        "the last step −{0.6} %",
        100.0 * (1.0 - force[3] / force[2]),
    );
    let mean_force = ladder("mean_abs_base_force_N", "argyris:10x7", &four[2..], 1.0);
    c.value(
        "(the mean |base.force| −{0.4} %)",
        100.0 * (1.0 - mean_force[1] / mean_force[0]),
    );
    c.value(
        "its first step of that ladder moved it by {5.8} %",
        100.0 * (force[2] / force[1] - 1.0),
    );
    c.values(
        "({4.70}, {5.25} and {5.48} kN on Argyris",
        &ladder(RMS_FORCE, FINEST, &four[..3], 1e-3),
    );
    c.values(
        "(Argyris 10 × 7: {2.2}, {5.9}, {14.0}, {23.1} at the four Δt)",
        &ladder(IMPACTS, "argyris:10x7", &four, 1.0),
    );
}

fn thirty_five(c: &mut Claims, runs: &Table) {
    let s = "forced-35hz";
    let finest = |q: &str, meshes: &[&str], scale: f64| at_finest(runs, q, s, 0.01, meshes, scale);
    let periodic = [ARGYRIS.as_slice(), FVS.as_slice(), &[FINEST]].concat();
    let at_1e4: Vec<f64> = periodic
        .iter()
        .map(|m| value(runs, E, s, 0.01, m, 1e-4, 1.0))
        .collect();
    c.range(
        "At 1e-4 s every mesh from Argyris 6 × 4 and FVS 7 × 5 up settles on the same periodic \
         response (two impacts per period, mean energy {8.46}–{8.81} J)",
        &at_1e4,
    );
    let impacts: Vec<f64> = periodic
        .iter()
        .map(|m| value(runs, IMPACTS, s, 0.01, m, 1e-4, 1.0))
        .collect();
    assert!(
        impacts.iter().all(|n| (n - 2.0).abs() < 0.05),
        "the page says two impacts per period at 1e-4 s: {impacts:?}"
    );
    let argyris = [ARGYRIS.as_slice(), &[FINE, FINEST]].concat();
    let energy_a = finest(E, &argyris, 1.0);
    let energy_f = finest(E, &FVS, 1.0);
    c.values(
        "energy is {11.67}, {11.21}, {10.48}, {9.90} and {9.80} J",
        &energy_a,
    );
    c.values("and {11.20}, {9.81} and {9.81} J on FVS", &energy_f);
    c.values(
        "Argyris fell by {0.72} and {0.59} J over the two refinements",
        &[energy_a[1] - energy_a[2], energy_a[2] - energy_a[3]],
    );
    c.value("by {0.10} J over the last one", energy_a[3] - energy_a[4]);
    // "About twice the two runs' spreads combined": the last step over √(σ₁² + σ₂²).
    let spread = |mesh: &str| run(runs, E, s, 0.01, mesh, 1e-6).number("spread");
    let combined = spread(FINE).hypot(spread(FINEST));
    let steps = (energy_a[3] - energy_a[4]) / combined;
    assert!(
        (1.5..2.5).contains(&steps),
        "the page says the last Argyris step is about twice its spread ({steps:.2})"
    );
    let (f14, f28) = (
        run(runs, E, s, 0.01, "fvs:14x10", 1e-6),
        run(runs, E, s, 0.01, "fvs:28x20", 1e-6),
    );
    c.holds(
        "while FVS 14 × 10 and 28 × 20 agree within their spreads",
        (f14.number("value") - f28.number("value")).abs()
            <= 2.0 * f14.number("spread").hypot(f28.number("spread")),
    );
    c.value(
        "moving, {0.15} % below FVS 28 × 20",
        100.0 * (1.0 - energy_a[4] / energy_f[2]),
    );
    let moved = |mesh: &str| {
        100.0
            * (value(runs, E, s, 0.01, mesh, 1e-6, 1.0) / value(runs, E, s, 0.01, mesh, 1e-5, 1.0)
                - 1.0)
    };
    let moved_finest = [moved(FINEST), moved("fvs:28x20")];
    c.values(
        "moved by {0.3} % (Argyris 28 × 20) and {0.6} % (FVS 28 × 20)",
        &moved_finest,
    );
    let corner_a = finest(CORNER, &argyris, 1e3);
    let corner_f = finest(CORNER, &FVS, 1e3);
    c.values(
        "alike: {6.32}, {6.52}, {6.57} and {6.61} mm",
        &corner_a[1..],
    );
    c.values("{6.51}, {6.56} and {6.61} mm on the FVS", &corner_f);
    c.value(
        "finest {0.1} % apart",
        100.0 * (corner_f[2] / corner_a[4] - 1.0).abs(),
    );
    let force_a = finest(RMS_FORCE, &argyris, 1e-3);
    let force_f = finest(RMS_FORCE, &FVS, 1e-3);
    c.values(
        "({7.92}, {7.84}, {7.80}, {7.84}, {7.80} kN on the Argyris",
        &force_a,
    );
    c.values("{6.36}, {7.34}, {7.80} kN on the FVS", &force_f);
    c.upper(
        "the finest within {0.1} % of each other)",
        100.0 * (force_a[4] / force_f[2] - 1.0).abs(),
    );
    c.upper(
        "The RMS base force at 1e-6 s lies within {0.1} % on the two finest meshes, approached",
        100.0 * (force_a[4] / force_f[2] - 1.0).abs(),
    );
    let rise = |mesh: &str, now: f64| {
        100.0 * (now / value(runs, RMS_FORCE, s, 0.01, mesh, 1e-5, 1e-3) - 1.0)
    };
    c.values(
        "it rose by {65} % from 1e-5 to 1e-6 s on Argyris 28 × 20 and by {58} %",
        &[rise(FINEST, force_a[4]), rise("fvs:28x20", force_f[2])],
    );
    c.values(
        "({15.4}, {20.2}, {26.9}, {29.1}, {29.9} on the",
        &finest(IMPACTS, &argyris, 1.0),
    );
    let fine_dofs = runs.one(&format!(
        "quantity={E} scene={s} modal_ratio=0.01 mesh={FINE} dt=1e-6"
    ));
    c.value(
        "Argyris 20 × 14 line ({2 675} free dofs)",
        fine_dofs.number("free_dofs"),
    );
    let fell = |mesh: &str| {
        100.0
            * (1.0
                - value(runs, CORNER, s, 0.01, mesh, 1e-6, 1.0)
                    / value(runs, CORNER, s, 0.01, mesh, 1e-5, 1.0))
    };
    let corner_fell = [fell(FINEST), fell("fvs:28x20")];
    c.values(
        "it fell by {1.9} % on Argyris 28 × 20 and by {2.0} % on FVS 28 × 20",
        &corner_fell,
    );
    finer_dt(c, runs);
    c.value(
        "on Argyris 28 × 20, whose 1e-7 s run would take about {44} CPU minutes",
        7e7 * run(runs, E, s, 0.01, FINEST, 1e-6).number("step_us") * 1e-6 / 60.0,
    );
    finer_dt_fine(c, runs);
    // The largest gap (%) between Argyris mesh `k` and FVS 28 × 20 over the energy, the corner
    // and the RMS base force at 1e-6 s.
    let worst_against_fvs = |k: usize| {
        [
            (&energy_a, &energy_f),
            (&corner_a, &corner_f),
            (&force_a, &force_f),
        ]
        .iter()
        .map(|(a, f)| 100.0 * (a[k] / f[2] - 1.0).abs())
        .fold(0.0, f64::max)
    };
    let worst_finest = worst_against_fvs(4);
    c.upper("at 1e-6 s agree within {0.2} %", worst_finest);
    c.upper(
        "at 35 Hz their finest meshes lie within {0.2} % on the mean energy",
        worst_finest,
    );
    c.upper("and 28 × 20 to come within {0.2} %", worst_finest);
    let fine_vs_fvs = worst_against_fvs(3);
    c.upper("Argyris needs 20 × 14 to come within {1} %", fine_vs_fvs);
    let all = [energy_a, energy_f].concat();
    let (lo, hi) = super::data::span(&all);
    c.value("is up to {19} % high", 100.0 * (hi / lo - 1.0));
}

/// Argyris 10 × 7 at ζ = 1 % and 35 Hz, from 1e-6 to 1e-7 s (part `finedt`).
fn finer_dt(c: &mut Claims, runs: &Table) {
    let s = "forced-35hz";
    let mesh = "argyris:10x7";
    let pair =
        |q: &str, scale: f64| [1e-6, 1e-7].map(|dt| value(runs, q, s, 0.01, mesh, dt, scale));
    let finest = 0.5
        * (value(runs, E, s, 0.01, FINEST, 1e-6, 1.0)
            + value(runs, E, s, 0.01, "fvs:28x20", 1e-6, 1.0));
    c.value(
        "a middle mesh, {14} % above the finest",
        100.0 * (value(runs, E, s, 0.01, mesh, 1e-6, 1.0) / finest - 1.0),
    );
    let change = |v: [f64; 2]| 100.0 * (1.0 - v[1] / v[0]);
    let force = pair(RMS_FORCE, 1e-3);
    c.values("went from {7.84} to {7.47} kN", &force);
    c.value("kN (−{4.8} %)", change(force));
    let energy = pair(E, 1.0);
    c.values("from {11.21} to {11.08} J", &energy);
    c.value("J (−{1.1} %)", change(energy));
    let corner = pair(CORNER, 1e3);
    c.values("from {6.32} to {6.23} mm", &corner);
    c.value("mm (−{1.5} %)", change(corner));
    // "Each change within twice the two runs' spreads combined": the study's 2σ rule.
    for q in [E, CORNER, RMS_FORCE] {
        let [a, b] = [1e-6, 1e-7].map(|dt| run(runs, q, s, 0.01, mesh, dt));
        let difference = (a.number("value") - b.number("value")).abs();
        let two_sigma = 2.0 * a.number("spread").hypot(b.number("spread"));
        assert!(
            difference <= two_sigma,
            "the page says {q} moved within 2σ from 1e-6 to 1e-7 s: {difference} > {two_sigma}"
        );
    }
    let relative: Vec<f64> = [E, RMS_FORCE]
        .iter()
        .flat_map(|q| [1e-6, 1e-7].map(|dt| run(runs, q, s, 0.01, mesh, dt)))
        .map(|r| 100.0 * r.number("spread") / r.number("value"))
        .collect();
    c.range("spreads are {1}–{2} % there", &relative);
}

/// The largest change (%) of the four time averages on `mesh` at ζ = 1 % and 35 Hz from
/// Δt = 1e-6 to 1e-7 s.
fn largest_dt_change(runs: &Table, mesh: &str) -> f64 {
    AVERAGES
        .iter()
        .map(|q| {
            let [a, b] = [1e-6, 1e-7].map(|dt| value(runs, q, "forced-35hz", 0.01, mesh, dt, 1.0));
            100.0 * (b / a - 1.0).abs()
        })
        .fold(0.0, f64::max)
}

/// [`largest_dt_change`] on FVS 28 × 20.
fn largest_fine_dt_change(runs: &Table) -> f64 {
    largest_dt_change(runs, "fvs:28x20")
}

/// FVS 28 × 20 at ζ = 1 % and 35 Hz, from 1e-6 to 1e-7 s (part `finedt`), against 1e-5 to 1e-6 s.
fn finer_dt_fine(c: &mut Claims, runs: &Table) {
    let s = "forced-35hz";
    let mesh = "fvs:28x20";
    let at = |q: &str, dt: f64| run(runs, q, s, 0.01, mesh, dt);
    let pair = |q: &str, scale: f64| {
        let [a, b] = [1e-6, 1e-7].map(|dt| at(q, dt));
        [
            a.number("value") * scale,
            a.number("spread") * scale,
            b.number("value") * scale,
            b.number("spread") * scale,
        ]
    };
    let change = |q: &str, from: f64, to: f64| {
        100.0 * (at(q, to).number("value") / at(q, from).number("value") - 1.0)
    };
    c.value(
        "ω_max·Δt = {0.94}), moved",
        at(E, 1e-7).number("omega_max_dt"),
    );
    for (quote, q, scale) in [
        (
            "mean energy went from {9.81} ± {0.05} to {9.72} ± {0.02} J",
            E,
            1.0,
        ),
        (
            "corner from {6.614} ± {0.007} to {6.582} ± {0.007} mm",
            CORNER,
            1e3,
        ),
        (
            "force from {7.80} ± {0.07} to {7.71} ± {0.06} kN",
            RMS_FORCE,
            1e-3,
        ),
        (
            "|base.force| from {4.58} ± {0.04} to {4.52} ± {0.02} kN",
            "mean_abs_base_force_N",
            1e-3,
        ),
    ] {
        c.values(quote, &pair(q, scale));
    }
    let four = [E, CORNER, RMS_FORCE, "mean_abs_base_force_N"];
    let fine: Vec<f64> = four.iter().map(|q| change(q, 1e-6, 1e-7)).collect();
    c.values("J ({−1.0} %), the RMS corner", &fine[..1]);
    c.values("mm ({−0.5} %), the RMS", &fine[1..2]);
    c.values("kN ({−1.1} %) and the mean", &fine[2..3]);
    c.values("kN ({−1.3} %),", &fine[3..]);
    let largest = largest_fine_dt_change(runs);
    let coarse = largest_dt_change(runs, "argyris:10x7");
    c.values(
        "FVS 28 × 20 moved by up to {1.3} % and Argyris 10 × 7 by up to {4.8} %",
        &[largest, coarse],
    );
    c.values(
        "At 1e-6 s the time averages are within {1.3} % (FVS 28 × 20) and {4.8} % (Argyris 10 × 7)",
        &[largest, coarse],
    );
    let ladders = ladders_table();
    let refused = ["argyris:10x7", "fvs:28x20"].iter().all(|m| {
        AVERAGES.iter().all(|q| {
            let r = ladder(&ladders, q, s, 0.01, m, 1e-7);
            r.text("dt_ladder") == "1e-05 1e-06 1e-07"
                && r.text("dt_verdict") == "refused"
                && r.text("dt_why") == "a pair disagrees"
        })
    });
    c.holds(
        "The rule refuses all eight of these Δt ladders (1e-5, 1e-6, 1e-7 s on the two meshes): in \
         each, a pair differs by more than the tolerance once twice its noise is added",
        refused,
    );
    c.given(&["by about 1 %"]);
    let coarse: Vec<f64> = four.iter().map(|q| change(q, 1e-5, 1e-6)).collect();
    c.values(
        "against {+0.6} %, {−2.0} %, {+58} % and {+31} % from 1e-5",
        &coarse,
    );
    c.values(
        "({37.4} on Argyris 10 × 7 and {62.5} on FVS 28 × 20 at 1e-7 s, against {31.7} at 1e-6 s)",
        &[
            value(runs, IMPACTS, s, 0.01, "argyris:10x7", 1e-7, 1.0),
            at(IMPACTS, 1e-7).number("value"),
            at(IMPACTS, 1e-6).number("value"),
        ],
    );
    let loss = "contact_loss_per_period_J";
    c.values(
        "on FVS 28 × 20 ({4.23} to {2.05} J)",
        &[
            at(loss, 1e-6).number("value"),
            at(loss, 1e-7).number("value"),
        ],
    );
    c.value(
        "with {1 764} free dofs it does",
        at(E, 1e-7).number("free_dofs"),
    );
    c.values(
        "at 35 Hz ({450} CPU s, {6.4} µs per step;",
        &[at(E, 1e-7).number("cpu_s"), at(E, 1e-7).number("step_us")],
    );
}

/// Whether every line of `scene` at ζ = 0.5 % and 2 % has no Δt ladder (two Δt per mesh).
fn two_dt_only(scene: &str) -> bool {
    let ladders = ladders_table();
    [0.005, 0.02].iter().all(|z| {
        ladders
            .select(&format!("scene={scene} damping={z}"))
            .iter()
            .all(|r| r.text("dt_verdict") == "none")
    })
}

fn ratios(c: &mut Claims, runs: &Table) {
    let s = "forced-35hz";
    let v = |zeta: f64, mesh: &str, dt: f64| value(runs, E, s, zeta, mesh, dt, 1.0);
    let spreads: Vec<f64> = runs
        .select(&format!("scene={s} modal_ratio=0.02 dt=1e-6"))
        .iter()
        .filter(|r| [E, CORNER, "mean_abs_base_force_N", RMS_FORCE].contains(&r.text("quantity")))
        .map(|r| 100.0 * r.number("spread") / r.number("value"))
        .collect();
    c.upper(
        "(spreads below {0.3} % at 1e-6 s)",
        spreads.iter().cloned().fold(0.0, f64::max),
    );
    // The middle meshes, Argyris 10 × 7 against FVS 14 × 10.
    let (a2, f2) = (v(0.02, "argyris:10x7", 1e-6), v(0.02, "fvs:14x10", 1e-6));
    c.values(
        "gives {8.92} J on Argyris 10 × 7 and {9.19} J on FVS 14 × 10 ({3.1} % apart)",
        &[a2, f2, 100.0 * (f2 / a2 - 1.0)],
    );
    let (a5, f5) = (v(0.005, "argyris:10x7", 1e-6), v(0.005, "fvs:14x10", 1e-6));
    c.values(
        "ζ = 0.5 % gives {12.34} and {10.97} J ({12} % apart)",
        &[a5, f5, 100.0 * (a5 / f5 - 1.0)],
    );
    let middle_apart = (f2 / a2 - 1.0).abs().min((a5 / f5 - 1.0).abs());
    c.holds(
        "On the middle meshes the elements disagree",
        middle_apart > 0.01,
    );
    let finest_apart = [0.005, 0.02]
        .map(|z| (v(z, FINEST, 1e-6) / v(z, "fvs:28x20", 1e-6) - 1.0).abs())
        .into_iter()
        .fold(0.0, f64::max);
    c.holds(
        "The middle meshes' disagreement was the mesh's, not the ratio's",
        middle_apart > 0.01 && finest_apart < 0.01,
    );
    // The finest meshes at 1e-6 s, Argyris then FVS 28 × 20, ζ = 0.5 % then 2 %.
    let finest = |q: &str, scale: f64| -> Vec<f64> {
        [0.005, 0.02]
            .iter()
            .flat_map(|&z| [FINEST, "fvs:28x20"].map(|m| value(runs, q, s, z, m, 1e-6, scale)))
            .collect()
    };
    let energy = finest(E, 1.0);
    c.values(
        "the mean energy is {10.83} J on Argyris 28 × 20 and {10.77} J on FVS 28 × 20 at \
         ζ = 0.5 %, {9.12} and {9.07} J at ζ = 2 %",
        &energy,
    );
    let apart = |v: &[f64]| 100.0 * (v[0] / v[1] - 1.0).abs();
    let worst = apart(&energy[..2]).max(apart(&energy[2..]));
    c.upper("({0.6} % apart at both ratios)", worst);
    c.upper(
        "28 × 20 meshes lie within {0.6} % of each other on the mean energy",
        worst,
    );
    c.values(
        "the RMS corner {6.55} and {6.57} mm, {6.63} and {6.60} mm",
        &finest(CORNER, 1e3),
    );
    c.values(
        "the RMS base force {8.90} and {9.06} kN, {6.14} and {6.09} kN",
        &finest(RMS_FORCE, 1e-3),
    );
    // From 1e-5 to 1e-6 s on each 28 × 20 mesh (%), in the same order.
    let moved = |q: &str| -> Vec<f64> {
        [0.005, 0.02]
            .iter()
            .flat_map(|&z| {
                [FINEST, "fvs:28x20"].map(|m| {
                    100.0
                        * (value(runs, q, s, z, m, 1e-6, 1.0) / value(runs, q, s, z, m, 1e-5, 1.0)
                            - 1.0)
                })
            })
            .collect()
    };
    let e = moved(E);
    c.values(
        "the mean energy moved by +{2.2} % (Argyris 28 × 20) and +{5.2} %",
        &e[..2],
    );
    c.values("by −{4.4} % and −{4.7} % at ζ = 2 %", &[-e[2], -e[3]]);
    let at_one = [FINEST, "fvs:28x20"].map(|m| {
        100.0
            * (value(runs, E, s, 0.01, m, 1e-6, 1.0) / value(runs, E, s, 0.01, m, 1e-5, 1.0) - 1.0)
    });
    c.values("at ζ = 1 % it moved by {0.3} % and {0.6} %", &at_one);
    let largest_at_one = at_one[0].abs().max(at_one[1].abs());
    c.holds(
        "in mean energy ζ = 1 % moved least",
        e.iter().all(|x| x.abs() > largest_at_one),
    );
    let corner: Vec<f64> = moved(CORNER).iter().map(|x| -x).collect();
    c.range("the corner fell by {3.0}–{4.1} % on both", &corner);
    let force = moved(RMS_FORCE);
    c.values(
        "rose by {87} % and {58} % at ζ = 0.5 %, {21} % and {19} % at ζ = 2 %",
        &force,
    );
    c.holds(
        "With two Δt per mesh there is no Δt ladder, and the rule gives no verdict",
        two_dt_only(s),
    );
    c.values(
        "rose the more the lighter the ratio (+{21}, +{65} and +{87} % at ζ = 2, 1 and 0.5 %)",
        &[0.02, 0.01, 0.005].map(|z| {
            100.0
                * (value(runs, RMS_FORCE, s, z, FINEST, 1e-6, 1.0)
                    / value(runs, RMS_FORCE, s, z, FINEST, 1e-5, 1.0)
                    - 1.0)
        }),
    );
    c.given(&["at ζ = 2, 1 and 0.5 %"]);
    sixty_ratios(c, runs);
}

/// ζ = 0.5 % and 2 % at 60 Hz, on Argyris 10 × 7, 14 × 10, 28 × 20 and FVS 14 × 10, 28 × 20.
fn sixty_ratios(c: &mut Claims, runs: &Table) {
    let s = "forced-60hz";
    let meshes = [
        "argyris:10x7",
        "argyris:14x10",
        "argyris:28x20",
        "fvs:14x10",
        "fvs:28x20",
    ];
    // The 28 × 20 meshes' largest gap on energy and corner (%).
    let gap = |q: &str, z: f64| {
        let last = |m: &str| smallest_dt(runs, q, s, z, m).number("value");
        100.0 * (last("argyris:28x20") / last("fvs:28x20") - 1.0).abs()
    };
    c.upper(
        "28 × 20 meshes lie within {0.3} % of each other on the mean energy and the RMS corner",
        [
            gap(E, 0.005),
            gap(E, 0.02),
            gap(CORNER, 0.005),
            gap(CORNER, 0.02),
        ]
        .into_iter()
        .fold(0.0, f64::max),
    );
    // Every mesh that ran both Δt, its change from 1e-5 to 1e-6 s (%).
    let moved = |q: &str| -> Vec<f64> {
        [0.005, 0.02]
            .iter()
            .flat_map(|&z| {
                meshes.iter().filter_map(move |m| {
                    let at = |dt: f64| {
                        runs.select(&format!(
                            "quantity={q} scene={s} modal_ratio={z} mesh={m} dt={dt}"
                        ))
                        .first()
                        .map(|r| r.number("value"))
                    };
                    Some(100.0 * (at(1e-6)? / at(1e-5)? - 1.0))
                })
            })
            .collect()
    };
    let largest = [moved(E), moved(CORNER)]
        .concat()
        .iter()
        .map(|x| x.abs())
        .fold(0.0, f64::max);
    c.upper("each mesh within {0.8} % of its 1e-5 s value", largest);
    c.range("1e-6 s, by {1.3}–{5.6} %", &moved(RMS_FORCE));
    let largest = |z: f64| -> (String, f64) {
        meshes
            .iter()
            .filter_map(|m| {
                let at = |dt: f64| {
                    runs.select(&format!(
                        "quantity={RMS_FORCE} scene={s} modal_ratio={z} mesh={m} dt={dt}"
                    ))
                    .first()
                    .map(|r| r.number("value"))
                };
                Some((m.to_string(), 100.0 * (at(1e-6)? / at(1e-5)? - 1.0)))
            })
            .fold((String::new(), f64::NEG_INFINITY), |a, b| {
                if b.1 > a.1 {
                    b
                } else {
                    a
                }
            })
    };
    let (half_mesh, half) = largest(0.005);
    let (two_mesh, two) = largest(0.02);
    assert_eq!(
        (half_mesh.as_str(), two_mesh.as_str()),
        (FINEST, "argyris:10x7"),
        "the page names the meshes whose RMS base force rose most at 60 Hz"
    );
    c.value(
        "the largest rise at ζ = 0.5 % is Argyris 28 × 20's ({5.6} %)",
        half,
    );
    c.value("at ζ = 2 % Argyris 10 × 7's ({3.8} %)", two);
    let at = |m: &str, dt: f64| value(runs, RMS_FORCE, s, 0.005, m, dt, 1.0);
    c.value(
        "Argyris 28 × 20 at 1e-6 s lies {6.0} % above Argyris 14 × 10 at 1e-5 s",
        100.0 * (at("argyris:28x20", 1e-6) / at("argyris:14x10", 1e-5) - 1.0),
    );
    c.value(
        "at 1e-5 s the two meshes are {0.35} % apart",
        100.0 * (at("argyris:28x20", 1e-5) / at("argyris:14x10", 1e-5) - 1.0),
    );
    c.holds(
        "with two Δt per mesh the rule gives no verdict",
        two_dt_only(s),
    );
    let middle_gap = |z: f64| {
        let last = |m: &str| smallest_dt(runs, E, s, z, m).number("value");
        100.0 * (last("argyris:14x10") / last("fvs:14x10") - 1.0).abs()
    };
    c.upper(
        "their middle meshes within {0.7} % at 60 Hz",
        middle_gap(0.005).max(middle_gap(0.02)),
    );
}

fn third(c: &mut Claims, runs: &Table) {
    let s = "aluminium-square";
    let meshes = ["argyris:10x10", "fvs:14x14"];
    let at = |q: &str, scale: f64, dt: f64| -> Vec<f64> {
        meshes
            .iter()
            .map(|m| value(runs, q, s, 0.01, m, dt, scale))
            .collect()
    };
    c.values("mean energy ({0.483} and {0.485} J)", &at(E, 1.0, 1e-6));
    c.values("corner ({3.25} and {3.26} mm)", &at(CORNER, 1e3, 1e-6));
    let changes: Vec<f64> = [E, CORNER]
        .iter()
        .flat_map(|q| {
            let (fine, coarse) = (at(q, 1.0, 1e-6), at(q, 1.0, 1e-5));
            (0..2).map(move |k| 100.0 * (fine[k] / coarse[k] - 1.0).abs())
        })
        .collect();
    c.upper(
        "each within {0.3} % of its value",
        changes.iter().cloned().fold(0.0, f64::max),
    );
    let coarse = run(runs, E, s, 0.01, "argyris:7x7", 1e-6);
    c.values(
        "({0.52} ± {0.03} J)",
        &[coarse.number("value"), coarse.number("spread")],
    );
    let force = at(RMS_FORCE, 1e-3, 1e-6);
    c.values("the two meshes is {0.419} and {0.466} kN", &force);
    c.value("kN, {11} % apart", 100.0 * (force[1] / force[0] - 1.0));
    let energy = at(E, 1.0, 1e-6);
    let corner = at(CORNER, 1.0, 1e-6);
    c.upper(
        "the two elements lie within {0.5} % on the energy and the corner",
        100.0
            * (energy[1] / energy[0] - 1.0)
                .abs()
                .max((corner[1] / corner[0] - 1.0).abs()),
    );
    c.holds(
        "With two meshes per element there is no mesh ladder, and the rule gives no verdict on \
         this plate at any ratio",
        ladders_table()
            .select("scene=aluminium-square")
            .iter()
            .all(|r| r.text("mesh_verdict") == "none" && r.text("verdict") == "not converged"),
    );
    c.values(
        "above 1 kHz ({20.9} and {22.8} %)",
        &at(ABOVE_1K, 100.0, 1e-6),
    );
    third_ratios(c, runs);
}

/// The aluminium plate at ζ = 0.5 % and 2 %, Argyris 10 × 10 and FVS 14 × 14 at 1e-6 s.
fn third_ratios(c: &mut Claims, runs: &Table) {
    let s = "aluminium-square";
    let at = |q: &str, zeta: f64, scale: f64| -> Vec<f64> {
        ["argyris:10x10", "fvs:14x14"]
            .iter()
            .map(|m| value(runs, q, s, zeta, m, 1e-6, scale))
            .collect()
    };
    let apart = |v: &[f64]| 100.0 * (v[1] / v[0] - 1.0).abs();
    c.values("well: {3.225} and {3.231} mm", &at(CORNER, 0.005, 1e3));
    c.values("{3.279} and {3.285} mm at ζ = 2 %", &at(CORNER, 0.02, 1e3));
    c.given(&["(Argyris 10 × 10 and FVS 14 × 14 at 1e-6 s)"]);
    let e_half = at(E, 0.005, 1.0);
    c.upper("within {1.5} % at ζ = 0.5 %", apart(&e_half));
    c.values("({0.516} and {0.508} J;", &e_half);
    let coarse = value(runs, E, s, 0.005, "argyris:7x7", 1e-6, 1.0);
    c.value(
        "chaotic, is {11} % higher",
        100.0 * (coarse / e_half[0] - 1.0),
    );
    let e_two = at(E, 0.02, 1.0);
    c.upper("within {0.9} % at ζ = 2 %", apart(&e_two));
    c.values("({0.466} and {0.470} J)", &e_two);
    let f_two = at(RMS_FORCE, 0.02, 1e-3);
    c.value("two meshes is {3.1} % apart", apart(&f_two));
    c.values("({0.428} and {0.441} kN)", &f_two);
    let f_half = at(RMS_FORCE, 0.005, 1e-3);
    c.value("it is {22} % apart", apart(&f_half));
    c.values("({0.350} and {0.426} kN)", &f_half);
    c.values(
        "here too ({39.0} and {31.4} % at 0.5 %",
        &at(ABOVE_1K, 0.005, 100.0),
    );
    c.values("{14.6} and {14.0} % at 2 %", &at(ABOVE_1K, 0.02, 100.0));
    c.given(&[
        "at 2 %, against 20.9 and 22.8 % at 1 %",
        "% at 0.5 %,",
        "the 6 s do not resolve",
    ]);
}

fn energy(c: &mut Claims, runs: &Table) {
    let share = |q: &str, s: &str, meshes: &[&str]| at_finest(runs, q, s, 0.01, meshes, 100.0);
    let argyris = [ARGYRIS.as_slice(), &[FINE, FINEST]].concat();
    let above_1k = share(ABOVE_1K, "forced-35hz", &argyris);
    c.values(
        "at 35 Hz: {10.4}, {11.7}, {13.5}, {17.1} and {19.1} %",
        &above_1k,
    );
    c.values(
        "by {1.9} points from Argyris 20 × 14 to 28 × 20 against {3.6} the step before",
        &[above_1k[4] - above_1k[3], above_1k[3] - above_1k[2]],
    );
    let energy = at_finest(runs, E, "forced-35hz", 0.01, &[FINE, FINEST], 1.0);
    c.value(
        "changed by only {1.0} % from Argyris 20 × 14 to 28 × 20",
        100.0 * (1.0 - energy[1] / energy[0]),
    );
    c.values(
        "{9.6}, {15.9} and {18.3} % on FVS",
        &share(ABOVE_1K, "forced-35hz", &FVS),
    );
    c.range(
        "it lies within {1.7}–{2.7} % on all",
        &[
            share(ABOVE_10K, "forced-35hz", &argyris),
            share(ABOVE_10K, "forced-35hz", &FVS),
        ]
        .concat(),
    );
    c.values(
        "changes little with the mesh: {1.98}, {1.86}, {1.85} and {1.80} %",
        &share(
            ABOVE_1K,
            "forced-60hz",
            &[ARGYRIS.as_slice(), &[FINEST]].concat(),
        ),
    );
    c.values(
        "{1.92}, {1.84} and {1.81} % on the FVS",
        &share(ABOVE_1K, "forced-60hz", &FVS),
    );
    let by_ratio: Vec<f64> = [0.005, 0.01, 0.02]
        .iter()
        .flat_map(|&z| {
            at_finest(
                runs,
                ABOVE_1K,
                "forced-35hz",
                z,
                &[FINEST, "fvs:28x20"],
                100.0,
            )
        })
        .collect();
    c.values(
        "at 35 Hz: {25.7} and {25.0} % at ζ = 0.5 %, {19.1} and {18.3} % at 1 %, {14.9} and {14.6} % at 2 %",
        &by_ratio,
    );
}

fn correlation(c: &mut Claims, runs: &Table) {
    let quantities = [E, CORNER, "mean_abs_base_force_N", RMS_FORCE, IMPACTS];
    let taus: Vec<f64> = quantities
        .iter()
        .flat_map(|q| runs.select(&format!("quantity={q}")))
        .map(|r| r.number("tau_periods"))
        .collect();
    let unresolved: Vec<Row> = quantities
        .iter()
        .flat_map(|q| runs.select(&format!("quantity={q} tau_resolved=false")))
        .collect();
    let rows = quantities
        .iter()
        .map(|q| runs.select(&format!("quantity={q}")).len())
        .sum::<usize>();
    c.values(
        "resolve (Sokal's window reached a quarter of the series): {42} of the {585} rows",
        &[unresolved.len() as f64, rows as f64],
    );
    let longest = unresolved
        .iter()
        .max_by(|a, b| a.number("tau_periods").total_cmp(&b.number("tau_periods")))
        .expect("unresolved runs");
    assert_eq!(
        (longest.text("scene"), longest.text("nx")),
        ("aluminium-square", "7"),
        "the page names the aluminium plate on Argyris 7 × 7 as the longest"
    );
    c.value("τ up to {68} periods", longest.number("tau_periods"));
    c.value(
        "a median of {0.7} forcing periods",
        super::study::median(&taus),
    );
    let ratios: Vec<f64> = quantities[..4]
        .iter()
        .flat_map(|q| {
            runs.select(&format!(
                "quantity={q} mesh=argyris:10x7 replicas=2 dt<=1e-5"
            ))
        })
        .map(|r| r.number("replica_spread") / r.number("window_spread"))
        .collect();
    c.range("the two replicas is {0.1}–{1.8} times", &ratios);
}

/// The mean energy at 35 Hz on the two 28 × 20 meshes (Argyris, FVS) at ratio `zeta` and Δt `dt`.
fn finest_energies(runs: &Table, zeta: f64, dt: f64) -> [f64; 2] {
    [FINEST, "fvs:28x20"].map(|m| value(runs, E, "forced-35hz", zeta, m, dt, 1.0))
}

/// How far (%) the mean energy at 35 Hz moved from Δt = 1e-5 to 1e-6 s on the two 28 × 20 meshes
/// at ζ = 0.5 % and 2 %.
fn ratio_energy_moves(runs: &Table) -> Vec<f64> {
    [0.005, 0.02]
        .iter()
        .flat_map(|&z| {
            let (fine, coarse) = (
                finest_energies(runs, z, 1e-6),
                finest_energies(runs, z, 1e-5),
            );
            [0, 1].map(|k| 100.0 * (fine[k] / coarse[k] - 1.0).abs())
        })
        .collect()
}

/// The README's bullet on the study.
pub fn readme(c: &mut Claims) {
    c.given(&["A modal ratio of 0.5–2 %", "at 60 Hz and ζ = 1 %"]);
    let verdicts = verdicts_table();
    let converged: Vec<Row> = verdicts
        .select("element=both verdict=converged")
        .into_iter()
        .filter(|r| AVERAGES.contains(&r.text("quantity")))
        .collect();
    c.holds(
        "one time average converges, the mean energy at 60 Hz and ζ = 1 %",
        converged.len() == 1
            && converged[0].text("scene") == "forced-60hz"
            && converged[0].text("quantity") == E,
    );
    c.values(
        "the mean energy at 60 Hz and ζ = 1 % ({13.53} ± {0.10} J)",
        &[converged[0].number("value"), converged[0].number("bound")],
    );
    c.holds(
        "the others lack three agreeing Δt or meshes",
        AVERAGES.iter().all(|q| {
            verdicts
                .select(&format!("element=both quantity={q}"))
                .iter()
                .filter(|r| r.text("verdict") != "converged")
                .all(|r| r.text("why") == "neither element converges")
        }),
    );
}

/// The numbers of the start-up warning's modal-ratio finding (`MODAL_RATIO_FINDING`), each as the
/// warning writes it, from the study's CSV: the warning restates the page and must move with it.
pub fn warning_numbers() -> Vec<String> {
    let runs = table(&format!("{DIR}modal_damping.csv"));
    let mut stated = Vec::new();
    let verdicts = verdicts_table();
    let one = verdict(&verdicts, E, "forced-60hz", 0.01, "both");
    assert_eq!(
        one.text("verdict"),
        "converged",
        "the warning names one converged average"
    );
    stated.push(format!(
        "the mean energy ({:.2} J within {:.2} J, Argyris 28 x 20 at solver.time_step = 1e-6 s)",
        one.number("value"),
        one.number("bound")
    ));
    assert_eq!((one.text("mesh"), one.number("dt")), (FINEST, 1e-6));
    // Up to the stated digit, as the warning states its bounds.
    let up = |x: f64, digits: i32| (x * 10f64.powi(digits)).ceil() / 10f64.powi(digits);
    let s = "forced-35hz";
    let pair = |zeta: f64, dt: f64| finest_energies(&runs, zeta, dt);
    let [a, f] = pair(0.01, 1e-6);
    stated.push(format!("1 % ({:.2} J)", 0.5 * (a + f)));
    let apart = |[a, f]: [f64; 2]| 100.0 * (a / f - 1.0).abs();
    stated.push(format!(
        "within {:.1} % of each other on the mean energy at 1 %",
        up(apart(pair(0.01, 1e-6)), 1)
    ));
    let ratios = apart(pair(0.005, 1e-6)).max(apart(pair(0.02, 1e-6)));
    stated.push(format!("and {:.1} % at 0.5 and 2 %", up(ratios, 1)));
    let f14 = value(&runs, E, s, 0.01, "fvs:14x10", 1e-6, 1.0);
    let middle = 100.0 * (f14 / a - 1.0).abs().max((f14 / f - 1.0).abs());
    stated.push(format!(
        "FVS 14 x 10 within {:.1} % of them at 1 %",
        up(middle, 1)
    ));
    let moved = ratio_energy_moves(&runs);
    let (lo, hi) = super::data::span(&moved);
    stated.push(format!("moved by {lo:.0} to {hi:.0} % at 0.5 and 2 %"));
    let force: Vec<f64> = [0.005, 0.01, 0.02]
        .iter()
        .flat_map(|&z| {
            [FINEST, "fvs:28x20"].map(|m| {
                100.0
                    * (value(&runs, RMS_FORCE, s, z, m, 1e-6, 1.0)
                        / value(&runs, RMS_FORCE, s, z, m, 1e-5, 1.0)
                        - 1.0)
            })
        })
        .collect();
    let largest = force.iter().cloned().fold(0.0, f64::max);
    stated.push(format!("base force by up to {largest:.0} %"));
    stated.push(format!(
        "moved by up to {:.1} % on FVS 28 x 20 and {:.1} % on Argyris 10 x 7",
        up(largest_fine_dt_change(&runs), 1),
        up(largest_dt_change(&runs, "argyris:10x7"), 1)
    ));
    let energies = [
        at_finest(
            &runs,
            E,
            s,
            0.01,
            &[ARGYRIS.as_slice(), &[FINE, FINEST]].concat(),
            1.0,
        ),
        at_finest(&runs, E, s, 0.01, &FVS, 1.0),
    ]
    .concat();
    let (lo, hi) = super::data::span(&energies);
    stated.push(format!("up to {:.0} % high", 100.0 * (hi / lo - 1.0)));
    stated
}
