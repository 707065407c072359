//! The claims of docs/scheme.md §8 (restitution): its measurements of the `energy` scene and the
//! forced scenes, from docs/restitution/'s CSVs (`runs.csv`: the library at e and Δt under each
//! law; `fmu_energy.csv`: e = 1 through the FMU; `contact_loss.csv`: the scenes at e = 1).

use super::claims::Claims;
use super::data::{span, table, Table};

pub fn claims() -> Claims {
    let mut c = Claims::new("docs/scheme.md");
    c.only_section(
        "8. Restitution: impact laws that keep energy",
        "the other sections derive the scheme: their numbers are equation and section numbers, \
         not measurements",
    );
    c.skip_block(
        "2. the law is imposed",
        "an independent implementation's run, not part of this repository, with no data here",
    );
    c.skip_block(
        "The plain θ = ½ implementation",
        "the same implementation's run: one measurement, not part of this repository",
    );
    c.skip_block(
        "**What the tests check**",
        "what tests/restitution.rs asserts, with the tolerances it fails beyond",
    );
    formulas(&mut c);
    let runs = table("docs/restitution/runs.csv");
    energy(&mut c, &runs);
    position(&mut c, &runs);
    c
}

/// The numbers of the section's symbols, equations, references and settings.
fn formulas(c: &mut Claims) {
    c.given(&[
        "## 8",
        "close to 0 (§6)",
        "e ∈ [0, 1]",
        "e = 0",
        "e > 0",
        "e = 1",
        "e < 1",
        "e → 0",
        "_{n+1",
        "_{n−1",
        "_{−1}",
        "_{k+1",
        "t_{n−1}",
        "t_{n+1}",
        "§3",
        "§4",
        "§5",
        "§6",
        "§9, step 1",
        "§10",
        "§12",
        "≥ 0",
        "≤ 0",
        "> 0",
        "0 ≤",
        "(1 − e)",
        "1/(2Δt)",
        "(2Δt)",
        "2m repeated",
        "2 |v| Δt",
        "v_0 = 0",
        "10⁻⁶ of the gap",
        "IJNME 40, 1997",
        "CMAME 195, 2006",
        "IJNME 53, 2002",
        "ZAMM 2016",
        "(e = 1e-300",
        "every term is 0",
        "and 0 at e",
        "(U_k > 0)",
        "1. the smooth part",
        "3. a contact",
        "4. contacts",
        "over 1 s",
        "Δt = 1e-4, 5e-5, 2.5e-5 and 1e-5 s",
        "at Δt = 1e-4 s",
        "at 1e-5 s",
        "Down to 1e-6 s",
        "e = 0.25, 0.5, 0.9 and 1",
        "after 1 s",
    ]);
}

/// The energy a law keeps: E at 1 s over E at the first step, `law` at e and Δt.
fn kept(runs: &Table, law: &str, e: f64, dt: f64) -> f64 {
    let r = runs.one(&format!("law={law} e={e} dt={dt}"));
    r.number("energy_last_J") / r.number("energy_first_J")
}

fn energy(c: &mut Claims, runs: &Table) {
    let fmu = table("docs/restitution/fmu_energy.csv");
    let steps = [1e-4, 5e-5, 2.5e-5, 1e-5];
    c.values(
        "|E(1 s)/E(Δt) − 1| = {1.8e-15}, {2.1e-14}, {3.1e-12} and {1.3e-11}",
        &steps.map(|dt| {
            fmu.one(&format!("dt={dt} obstacle=true"))
                .number("relative_change")
                .abs()
        }),
    );
    c.given(&["|E(1 s)/E(Δt) − 1|"]);
    let newton: Vec<f64> = steps
        .iter()
        .map(|&dt| 100.0 * (1.0 - kept(runs, "newton", 1.0, dt)))
        .collect();
    c.range("Newton's law loses {0.6} to {1} %", &newton);
    let contacts: Vec<f64> = fmu
        .select("obstacle=true")
        .iter()
        .map(|r| r.number("contact_loss_J").abs())
        .collect();
    c.upper("own share is below {7e-12} J", span(&contacts).1);
    let resolves: Vec<f64> = runs
        .select("law=auto e=1")
        .iter()
        .map(|r| r.number("resolved_steps"))
        .collect();
    c.range("it happens in {0} to {15} steps per second", &resolves);
    let forced = table("docs/restitution/contact_loss.csv");
    let both: Vec<f64> = ["forced-30hz", "forced-35hz"]
        .iter()
        .map(|s| {
            forced
                .one(&format!("scene={s} law=auto"))
                .number("resolved_steps")
        })
        .collect();
    assert_eq!(
        both[0], both[1],
        "the page gives one count for both forced scenes"
    );
    c.value("and in {3} of `forced-30hz`", both[0]);
    c.values(
        "The persistent law here keeps {29}, {33}, {59} and {100} %",
        &[0.25, 0.5, 0.9, 1.0].map(|e| 100.0 * kept(runs, "auto", e, 1e-4)),
    );
    c.values(
        "and Newton's law {30}, {36}, {63} and {99.4} %",
        &[0.25, 0.5, 0.9, 1.0].map(|e| 100.0 * kept(runs, "newton", e, 1e-4)),
    );
    let paper = runs.one("law=auto e=0 dt=1e-4");
    let newton0 = runs.one("law=newton e=0 dt=1e-4");
    c.values(
        "It keeps {11.29} J of {31.98} J after 1 s where the paper keeps {9.82} J",
        &[
            newton0.number("energy_last_J"),
            newton0.number("energy_first_J"),
            paper.number("energy_last_J"),
        ],
    );
    c.value(
        "above the obstacle ({0.44} mm in the `energy` scene)",
        1e3 * newton0.number("turn_m"),
    );
}

fn position(c: &mut Claims, runs: &Table) {
    let at = |law: &str, dt: f64, column: &str| {
        runs.one(&format!("law={law} e=1 dt={dt}")).number(column)
    };
    c.values(
        "contacts turn up to {0.51} mm above g1 at Δt = 1e-4 s and {0.096} mm at 1e-5 s",
        &[1e-4, 1e-5].map(|dt| 1e3 * at("auto", dt, "turn_m")),
    );
    c.values(
        "(Newton's law: {0.81} and {0.10} mm)",
        &[1e-4, 1e-5].map(|dt| 1e3 * at("newton", dt, "turn_m")),
    );
    c.values(
        "vertices hover up to {0.28} and {0.051} mm",
        &[1e-4, 1e-5].map(|dt| 1e3 * at("auto", dt, "hover_m")),
    );
    c.values(
        "for at most {5} to {7} consecutive steps",
        &[1e-4, 1e-5].map(|dt| at("auto", dt, "longest_hold")),
    );
    // The observed order over the two decades: log(turn(1e-4)/turn(1e-6)) / log(100).
    let order = |law: &str| (at(law, 1e-4, "turn_m") / at(law, 1e-6, "turn_m")).ln() / 100f64.ln();
    c.values(
        "falls like Δt^{0.73} (Newton's law: Δt^{0.81})",
        &[order("auto"), order("newton")],
    );
    c.values(
        "grows from {8.6} to {18.7} m/s",
        &[1e-4, 1e-6].map(|dt| at("auto", dt, "fastest_arrival_m_s")),
    );
}
