//! The damping study's summaries in docs/studies.md and README.md.

use super::*;

/// The damping study's paragraph of docs/studies.md.
pub fn brief(c: &mut Claims) {
    let study = Study::load();
    let d = &study;
    let runs = d.csv.select("quantity=mean_energy_J part!=evidence");
    let wall: f64 = runs.iter().map(|r| r.number("wall_s")).sum();
    c.value("The committed run: {326} runs", runs.len() as f64);
    c.value("{84} min of run wall time here", wall / 60.0);
    let (_, mesh) = reference_checks(d, "beta");
    c.upper("at 1e-6 s agree within {0.16} %; finer meshes", mesh);
    let rule = beta_verdicts();
    c.holds(
        "time average converges by the rule of evidence but the 35 Hz RMS base force",
        SCENES.iter().all(|s| {
            FOUR.iter()
                .all(|q| rule(s, q) == (*s != "forced-35hz" || *q != "rms_base_force_N"))
        }),
    );
    c.upper(
        "mean energy within {1.4} %",
        d.worst("beta", &SCENES, &FOUR[..1], &PAPER_MESHES, &[1e-4]),
    );
    let h = Headline::of(d);
    c.value(
        "move the 35 Hz RMS base force by up to {1.05} %",
        h.finer_moving,
    );
    c.upper("the rest by at most {0.09} %)", h.finer_steady);
    c.upper("gives {0.3} % on FVS 14 × 10", h.fvs_1e5);
    c.value("({1.04} % on Argyris 10 × 7)", h.argyris_1e5);
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
    let h = Headline::of(d);
    c.upper(
        "`base.force` within {0.3} % of the best-resolved run",
        h.fvs_1e5,
    );
    let rule = beta_verdicts();
    c.holds(
        "the time averages converge by the rule `scripts/converge` uses",
        FOUR.iter().all(|q| {
            rule("forced-60hz", q) && (rule("forced-35hz", q) == (*q != "rms_base_force_N"))
        }),
    );
    c.holds(
        "but for the 35 Hz RMS base force",
        !rule("forced-35hz", "rms_base_force_N"),
    );
    c.defines(&["three Δt and three meshes that agree at 1 %"]);
    c.values("in {4.5} s (35 Hz) and {5.0} s (60 Hz) per", &h.walls_fvs);
    c.value("(Argyris 10 × 7: within {1.04} %", h.argyris_1e5);
    c.values("1.04 %, {5.3} and {7.0} s)", &h.walls_argyris);
    c.range("Δt = 1e-4 s ({0.7}–{1.3} s)", &h.walls_paper);
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
    c.upper("lies within {0.16} % of FVS 14 × 10", mesh);
    c.upper("move it by at most {0.09} % except", h.finer_steady);
    let (argyris, fvs) = limits(d);
    c.range("limit {2.4}–{3.7} % higher", &[argyris, fvs]);
    c.upper(
        "the runs stay within {1} % at 60 Hz",
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

/// The contact-loss paragraph of docs/limits.md.
pub fn limits_doc(c: &mut Claims) {
    let study = Study::load();
    let d = &study;
    c.given(&[
        "ζ₁ = 1 %",
        "at Δt = 1e-4 s",
        "at 1e-7 s",
        "at 5e-8 s",
        "35 Hz",
    ]);
    let q = "contact_loss_per_period_J";
    let s35 = "forced-35hz";
    let loss = |mesh: &str, dt: f64| d.value(s35, "beta", q, mesh, dt);
    let on = |meshes: &[&str], dt: f64| meshes.iter().map(|m| loss(m, dt)).collect::<Vec<f64>>();
    c.range("it is {15.8}–{16.6} J per forcing", &on(&GRID[1..], 1e-4));
    let at_1e7 = [
        "argyris:4x2",
        "argyris:6x4",
        "argyris:10x7",
        "fvs:7x5",
        "fvs:14x10",
    ];
    c.range("{1.1}–{2.4} J at 1e-7 s", &on(&at_1e7, 1e-7));
    c.value("{1.27} J at 5e-8 s", loss("fvs:14x10", 5e-8));
    c.value(
        "the mean energy stays at {8.607} J",
        d.value(s35, "beta", "mean_energy_J", "argyris:10x7", 1e-5),
    );
    c.value(
        "FVS 14 × 10 lies {35} % above Argyris 10 × 7",
        pct(loss("fvs:14x10", 1e-7), loss("argyris:10x7", 1e-7)),
    );
}

/// Whether the rule of evidence finds a time average of β converged (`damping_verdicts.csv`), as
/// `(scene, quantity) -> bool`.
fn beta_verdicts() -> impl Fn(&str, &str) -> bool {
    let verdicts = table(&format!("{DIR}damping_verdicts.csv"));
    move |scene: &str, q: &str| {
        verdicts
            .one(&format!(
                "scene={scene} damping=beta quantity={q} element=both"
            ))
            .text("verdict")
            == "converged"
    }
}
