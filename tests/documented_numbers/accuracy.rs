//! The claims of docs/accuracy/README.md (the accuracy study), from runs.csv,
//! reference_check.csv, frequencies.csv, table1.csv, paper_table1.csv (the paper's Table 1) and
//! meta.csv.

use super::claims::Claims;
use super::data::{meta, span, table, Row, Table};
use super::study::fit_slope;

const DIR: &str = "docs/accuracy/";
const PAPER_MESH: [(&str, &str); 2] = [("argyris", "nx=10 ny=7"), ("fvs", "nx=14 ny=10")];

pub fn claims() -> Claims {
    let mut c = Claims::new("docs/accuracy/README.md");
    let runs = table(&format!("{DIR}runs.csv"));
    c.given(&[
        "0.1 s",
        "2-core",
        "x86_64",
        "c(1 − cos 2πft)²/4",
        "35 Hz",
        "140-element",
        "(2 triangles per cell)",
        "1e-3, 5e-4, 2e-4, 1e-4, 5e-5, 2e-5, 1e-5, 5e-6, 2e-6 and 1e-6 s",
        "u(Lx, 0, t)",
        "1e-4 s",
        "Δt > 1e-4 s",
        "O(Δt²)",
        "1e-3 → 1e-6 s",
        "within 0.2 of 2",
        "between about 1 and 2",
        "ω·Δt ≪ 1",
        "√(D/ρe)(π/h)²/2π",
        "above 1.2",
        "Δt = 2e-6 s",
        "Argyris 20×14",
        "β = ½, e = 0",
        "Δt = 1e-6 s",
        "modes 1–6",
        "5 significant digits",
        "about 1e-5",
        "modes 2, 4 and 6",
        "~25 ms",
        "2010",
        "Δt = 1e-3 s",
        "n³",
        "about 1e-5 s",
        "(140 elements, Δt = 1e-4 to 1e-5 s)",
        "(q^p − 1)",
        "≥ 4×",
        "§7",
        "(53.821, 231.63, 335.41, 753.91, 941.26, 1447.8 Hz)",
        "t = horizon",
        "Δt = 1e-3 / 1e-4 / 1e-5",
        "Table 1: 140 elements, 1 s",
        "(10 Hz)",
        "Δt = 1e-3 times",
        "Δt = 2e-5 s on",
        "Δt = 1e-3, 1e-4, 1e-5 and 1e-6 s",
        "at 1e-6 s;",
        "Table 1.",
        "[0, the reference's first contact]",
    ]);
    set_up(&mut c, &runs);
    time(&mut c, &runs);
    space(&mut c, &runs);
    cost(&mut c, &runs);
    c
}

/// The selection of the paper's mesh of `element`.
fn paper(element: &str) -> String {
    let cells = PAPER_MESH
        .iter()
        .find(|p| p.0 == element)
        .expect("element")
        .1;
    format!("element={element} {cells}")
}

/// A number cell, or `None` when empty.
fn cell(r: &Row, column: &str) -> Option<f64> {
    let text = r.text(column);
    (!text.is_empty()).then(|| r.number(column))
}

/// The reference run of `scene`: Argyris 14×10 at Δt = 1e-6 s.
fn reference<'a>(runs: &'a Table, scene: &str) -> Row<'a> {
    runs.one(&format!(
        "scene={scene} strategy=fast mesh=argyris:14x10 dt=1e-6"
    ))
}

fn set_up(c: &mut Claims, runs: &Table) {
    c.value("{406} runs of 0.1 s each", runs.select("").len() as f64);
    c.value(
        "({6} with clarabel",
        runs.select("strategy=clarabel").len() as f64,
    );
    c.value(
        "the whole study took {857} s",
        meta(&format!("{DIR}meta.csv"), "total_s"),
    );
    c.value(
        "`energy` has {178} contact",
        reference(runs, "energy").number("impacts"),
    );
    c.value(
        "and `forced-35hz` {204}",
        reference(runs, "forced-35hz").number("impacts"),
    );
    for scene in ["free-smooth", "free"] {
        assert_eq!(
            reference(runs, scene).number("impacts"),
            0.0,
            "{scene}: none"
        );
    }
}

/// The fitted order in Δt of the time error alone on a mesh: the slope of `dt_rms` against Δt
/// over the levels ≥ 4× the mesh's finest Δt (its own reference).
pub fn dt_order(runs: &Table, scene: &str, mesh: &str) -> f64 {
    let family = runs.select(&format!("scene={scene} strategy=fast {mesh}"));
    let finest = span(&family.iter().map(|r| r.number("dt")).collect::<Vec<_>>()).0;
    let points: Vec<(f64, f64)> = family
        .iter()
        .filter_map(|r| cell(r, "dt_rms").map(|e| (r.number("dt"), e)))
        .filter(|&(dt, _)| dt >= 4.0 * finest * (1.0 - 1e-9))
        .collect();
    fit_slope(&points)
}

/// The fitted order in h of the space error alone at Δt = 1e-6 s.
fn h_order(runs: &Table, scene: &str, element: &str) -> f64 {
    let family = runs.select(&format!(
        "scene={scene} strategy=fast element={element} dt=1e-6"
    ));
    let points: Vec<(f64, f64)> = family
        .iter()
        .filter_map(|r| cell(r, "h_rms").map(|e| (r.number("h"), e)))
        .collect();
    fit_slope(&points)
}

fn time(c: &mut Claims, runs: &Table) {
    let orders = |scene: &str| PAPER_MESH.map(|(e, _)| dt_order(runs, scene, &paper(e)));
    c.values(
        "fitted orders {2.00} (Argyris) and {2.00} (FVS)",
        &orders("free-smooth"),
    );
    c.values(
        "second order: {1.50} (Argyris) and {1.49} (FVS)",
        &orders("free"),
    );
    let [ea, ef] = orders("energy");
    let [fa, ff] = orders("forced-35hz");
    c.values(
        "fitted orders in Δt {0.54} (Argyris) and {0.43} (FVS) for `energy`, {0.22} and {0.08}",
        &[ea, ef, fa, ff],
    );
    let errors = |scene: &str| {
        runs.select(&format!("scene={scene} strategy=fast {}", paper("argyris")))
            .iter()
            .filter_map(|r| cell(r, "dt_rms"))
            .filter(|&e| e > 0.0)
            .collect::<Vec<f64>>()
    };
    c.range("stays at {6e-4}–{1e-2} m (`energy`)", &errors("energy"));
    c.range(
        "and {7e-4}–{2e-3} m (`forced-35hz`)",
        &errors("forced-35hz"),
    );
    let check = table(&format!("{DIR}reference_check.csv"));
    let checked = |scene: &str, column: &str| check.one(&format!("scene={scene}")).number(column);

    for scene in ["energy", "forced-35hz"] {
        assert_eq!(check.one(&format!("scene={scene}")).text("time_dt"), "2e-6");
    }
    c.values(
        "by {2.51e-3} m and {1.10e-3} m RMS",
        &[
            checked("energy", "time_rms"),
            checked("forced-35hz", "time_rms"),
        ],
    );
    c.values(
        "mesh by {1.79e-3} m and {1.10e-3} m, as much",
        &[
            checked("energy", "space_rms"),
            checked("forced-35hz", "space_rms"),
        ],
    );
    c.values(
        "({4306} and {3341} steps with a QP",
        &["energy", "forced-35hz"].map(|s| reference(runs, s).number("qp_steps")),
    );
    // Up to the first impact, on Argyris 10×7: `energy` reaches its floor (within 1.5× of its
    // smallest error) at 2e-5 s; `forced-35hz` is smallest at the smallest Δt.
    let before = |scene: &str| {
        let mut rows: Vec<(f64, f64)> = runs
            .select(&format!("scene={scene} strategy=fast {}", paper("argyris")))
            .iter()
            .filter_map(|r| cell(r, "pre_rms").map(|e| (r.number("dt"), e)))
            .collect();
        rows.sort_by(|a, b| b.0.total_cmp(&a.0));
        rows
    };
    let energy = before("energy");
    let floor = span(&energy.iter().map(|r| r.1).collect::<Vec<_>>()).0;
    let first = energy.iter().find(|r| r.1 <= 1.5 * floor).expect("floor");
    assert!(
        (first.0 / 2e-5 - 1.0).abs() < 1e-9,
        "the floor starts at 2e-5 s"
    );
    c.value("({3.3e-6} m for `energy`", floor);
    let forced = before("forced-35hz");
    let last = forced.last().expect("runs");
    assert_eq!(
        last.1,
        span(&forced.iter().map(|r| r.1).collect::<Vec<_>>()).0
    );
    c.value("still falling at the smallest Δt, {2.5e-6} m", last.1);
    let energies = |scene: &str| {
        [1e-3, 1e-4, 1e-5, 1e-6].map(|dt| {
            runs.one(&format!(
                "scene={scene} strategy=fast {} dt={dt}",
                paper("argyris")
            ))
            .number("energy_end")
        })
    };
    c.values(
        "{9.7}, {15.2}, {18.9}, {23.5} J for `energy`",
        &energies("energy"),
    );
    c.values(
        "{13.2}, {9.7}, {19.1}, {46.2} J for `forced-35hz`",
        &energies("forced-35hz"),
    );
}

fn space(c: &mut Claims, runs: &Table) {
    for scene in ["free-smooth", "free"] {
        c.values(
            "fitted orders in h of {2.6} (Argyris) and {2.0} (FVS) without contact",
            &[h_order(runs, scene, "argyris"), h_order(runs, scene, "fvs")],
        );
    }
    let freqs = table(&format!("{DIR}frequencies.csv"));
    let errors = |element: &str, dofs: f64| {
        freqs
            .select(&format!("element={element} free_dofs={dofs}"))
            .iter()
            .map(|r| (r.number("frequency_hz") / r.number("reference_hz") - 1.0).abs())
            .collect::<Vec<f64>>()
    };
    let dofs = |element: &str| {
        let all: Vec<f64> = freqs
            .select(&format!("element={element}"))
            .iter()
            .map(|r| r.number("free_dofs"))
            .collect();
        span(&all)
    };
    let (a_coarse, a_fine) = dofs("argyris");
    let (f_coarse, f_fine) = dofs("fvs");
    c.range(
        "Argyris {5e-4}–{1e-3} on the coarsest mesh",
        &errors("argyris", a_coarse),
    );
    c.range("{3e-5}–{7e-5} on the finest", &errors("argyris", a_fine));
    c.range(
        "FVS {2e-3}–{3e-2} on the coarsest",
        &errors("fvs", f_coarse),
    );
    c.range("{2e-4}–{3e-3} on the finest. At", &errors("fvs", f_fine));
    // The finest Argyris mesh with no more free dofs than FVS's finest.
    let comparable = freqs
        .select(&format!("element=argyris free_dofs<={f_fine}"))
        .iter()
        .map(|r| r.number("free_dofs"))
        .fold(0.0, f64::max);
    c.value("(Argyris {1369} free dofs", comparable);
    c.value("FVS {1764})", f_fine);
    let ratios: Vec<f64> = errors("fvs", f_fine)
        .iter()
        .zip(errors("argyris", comparable))
        .map(|(f, a)| f / a)
        .collect();
    c.range("Argyris is {2}× to {26}× more accurate", &ratios);
}

/// The wall time of each clarabel run over that of the fast run of the same case.
pub fn clarabel_ratios(runs: &Table) -> Vec<f64> {
    runs.select("strategy=clarabel")
        .iter()
        .map(|r| {
            let same = ["scene", "element", "nx", "ny", "dt"]
                .map(|k| format!("{k}={}", r.text(k)))
                .join(" ");
            r.number("wall_s") / runs.one(&format!("strategy=fast {same}")).number("wall_s")
        })
        .collect()
}

fn cost(c: &mut Claims, runs: &Table) {
    let clarabel = runs.select("strategy=clarabel");
    let diffs: Vec<f64> = clarabel.iter().map(|r| r.number("diff_vs_fast")).collect();
    c.value("(largest corner difference {1.8e-11} m", span(&diffs).1);
    c.range("{7}× to {151}× the wall time", &clarabel_ratios(runs));
    let table1 = table(&format!("{DIR}table1.csv"));
    let paper_times = table(&format!("{DIR}paper_table1.csv"));
    let paper_over = |strategy: &str| {
        table1
            .select(&format!("strategy={strategy}"))
            .iter()
            .map(|r| {
                let at = format!("element={} dt={}", r.text("element"), r.text("dt"));
                paper_times.one(&at).number("cpu_s") / r.number("wall_s")
            })
            .collect::<Vec<f64>>()
    };
    let fast: Vec<f64> = table1
        .select("strategy=fast")
        .iter()
        .map(|r| r.number("wall_s"))
        .collect();
    c.range("take {0.21}–{0.34} s here", &fast);
    c.range("{320}× to {36358}× less", &paper_over("fast"));
    c.range("only {3}× to {10}× faster", &paper_over("clarabel"));
    for r in table1.select("strategy=clarabel") {
        assert_eq!(
            r.text("dt"),
            "1e-3",
            "the prose says clarabel ran at 1e-3 s"
        );
    }
    let share = |element: &str, dt: f64| {
        let r = runs.one(&format!(
            "scene=free strategy=fast {} dt={dt}",
            paper(element)
        ));
        100.0 * r.number("setup_s") / r.number("wall_s")
    };
    c.values(
        "on Argyris 10×7 {100} % at Δt = 1e-3 s, {81} % at 1e-6 s; on FVS 14×10 {100} % and {77} %",
        &[
            share("argyris", 1e-3),
            share("argyris", 1e-6),
            share("fvs", 1e-3),
            share("fvs", 1e-6),
        ],
    );
    let best = |scene: &str| {
        runs.select(&format!("scene={scene} strategy=fast ref_rms>0"))
            .iter()
            .filter(|r| !(r.text("element") == "argyris" && r.text("nx") == "14"))
            .map(|r| r.number("ref_rms"))
            .fold(f64::INFINITY, f64::min)
    };
    c.values(
        "are {8.0e-6} m (`free-smooth`), {2.6e-5} m (`free`), {2.5e-4} m (`energy`) and {6.8e-4} m",
        &["free-smooth", "free", "energy", "forced-35hz"].map(best),
    );
}
