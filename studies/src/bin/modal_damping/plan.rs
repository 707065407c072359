//! What the modal damping study runs: its plates, scenes and meshes, the lines of the plan (a
//! scene, ratio and mesh down a ladder of Δt), the committed plan and the quick one, and the scene
//! of each setting.

use plate_impact::element::ElementKind;
use plate_impact::scene::Scene;
use plate_impact_studies::element::element_name;

/// A plate of the study.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Plate {
    /// The paper's steel plate, 0.4 × 0.2 × 0.01 m, obstacles at ±10 mm.
    Paper,
    /// The third plate: aluminium, 0.3 × 0.3 × 0.005 m, obstacles at ±5 mm (see the study's page).
    Aluminium,
}

/// A forced scene: a plate, its base sine.
#[derive(Clone, Copy, Debug)]
pub struct Forcing {
    pub label: &'static str,
    pub plate: Plate,
    pub frequency: f64,
    pub amplitude: f64,
}

/// The scenes of the study.
pub const SCENES: [Forcing; 3] = [
    Forcing {
        label: "forced-35hz",
        plate: Plate::Paper,
        frequency: 35.0,
        amplitude: 0.009,
    },
    Forcing {
        label: "forced-60hz",
        plate: Plate::Paper,
        frequency: 60.0,
        amplitude: 0.002,
    },
    Forcing {
        label: "aluminium-square",
        plate: Plate::Aluminium,
        frequency: 40.0,
        amplitude: 0.004,
    },
];

/// A mesh of the study.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mesh {
    pub element: ElementKind,
    pub nx: usize,
    pub ny: usize,
}

impl Mesh {
    pub fn name(&self) -> String {
        format!("{} {}x{}", element_name(self.element), self.nx, self.ny)
    }
}

/// One setting of the study: scene, ratio, mesh and Δt.
#[derive(Clone, Copy, Debug)]
pub struct Setting {
    pub forcing: Forcing,
    pub zeta: f64,
    pub mesh: Mesh,
    pub dt: f64,
}

/// A scene, ratio and mesh, run down a ladder of Δt until the time averages settle.
#[derive(Clone, Debug)]
pub struct Line {
    /// The part of the committed plan it belongs to (`--part`).
    pub part: &'static str,
    pub forcing: Forcing,
    pub zeta: f64,
    pub mesh: Mesh,
    /// Δt (s), decreasing.
    pub ladder: Vec<f64>,
    /// A run whose estimated CPU time exceeds this (s) is left out, with the smaller Δt of its
    /// line.
    pub max_run_cpu: f64,
    /// Perturbed replicas of each run.
    pub replicas: usize,
    /// Whether the per-period series of its runs are written (`modal_damping_periods.csv`).
    pub series: bool,
}

/// What the study runs.
pub struct Plan {
    pub name: &'static str,
    pub lines: Vec<Line>,
    /// Simulated time before the statistics (s).
    pub transient: f64,
    /// Simulated time of the statistics (s).
    pub duration: f64,
    /// Window length (s), for the window spread: the whole periods nearest to it.
    pub window: f64,
    /// A line stops refining Δt once the time averages of [`SETTLING`](super::run::SETTLING) at two successive Δt
    /// agree: differ by at most this relative tolerance or 2σ of their difference.
    pub settle_tolerance: f64,
    /// `name=value` scene parameters of every run.
    pub overrides: Vec<String>,
}

/// The scene of a setting: the plate's parameters, the forcing, the ratio, the mesh and Δt, then
/// the command line's `name=value` parameters (the FMU variable names, [`Scene::set_all`]).
pub fn scene_of(setting: &Setting, overrides: &[String]) -> Result<Scene, String> {
    let mut s = Scene::named("forced-35hz").map_err(|e| e.to_string())?;
    if setting.forcing.plate == Plate::Aluminium {
        s.plate.length = 0.3;
        s.plate.width = 0.3;
        s.plate.thickness = 0.005;
        s.material.young_modulus = 7e10;
        s.material.poisson_ratio = 0.33;
        s.material.density = 2700.0;
        s.obstacle.lower = -0.005;
        s.obstacle.upper = 0.005;
    }
    s.base.frequency = setting.forcing.frequency;
    s.base.amplitude = setting.forcing.amplitude;
    s.damping.modal_ratio = setting.zeta;
    s.mesh.element = setting.mesh.element;
    (s.mesh.nx, s.mesh.ny) = (setting.mesh.nx, setting.mesh.ny);
    s.solver.time_step = setting.dt;
    let pairs: Vec<(&str, &str)> = overrides.iter().filter_map(|o| o.split_once('=')).collect();
    s.set_all(&pairs).map_err(|e| e.to_string())?;
    Ok(s)
}

/// The committed study (docs/accuracy/modal_damping.md says why each part), in parts that
/// `--part` runs alone:
/// - `middle`: ζ = 1 % on both forced scenes of the paper's plate, the coarse and middle meshes
///   of both elements, Δt from 1e-4 s down to 1e-6 s until the time averages settle or a run
///   would cost more than its line's cap, two perturbed replicas on Argyris 10 × 7;
/// - `third`: the aluminium plate at ζ = 1 %, two Argyris meshes and one FVS mesh;
/// - `ratios`: ζ = 0.5 % and 2 % on both forced scenes, Argyris 10 × 7, 14 × 10 and FVS 14 × 10,
///   then at 35 Hz FVS 28 × 20 and Argyris 28 × 20, Δt = 1e-5 and 1e-6 s;
/// - `fine`: ζ = 1 % on both forced scenes, Argyris 20 × 14 at Δt = 1e-5 and 1e-6 s, then
///   Argyris 28 × 20 (5 257 free dofs) from Δt = 1e-4 s;
/// - `finedt`: Argyris 10 × 7 at ζ = 1 % and Δt = 1e-7 s, 60 Hz then 35 Hz; then FVS 28 × 20 at
///   35 Hz.
pub fn committed_plan() -> Plan {
    use ElementKind::{Argyris, Fvs};
    let mesh = |element, nx, ny| Mesh { element, nx, ny };
    let line = |part, forcing: Forcing, zeta, mesh, ladder: &[f64], max_run_cpu, replicas| Line {
        part,
        forcing,
        zeta,
        mesh,
        ladder: ladder.to_vec(),
        max_run_cpu,
        replicas,
        series: replicas > 0,
    };
    let mut lines = Vec::new();
    // Sized for about 15 CPU minutes on one core (the budget this machine had), in the order of
    // what the findings need, so that a run cut short keeps the first parts whole.
    // Part `middle`: ζ = 1 % on the paper's plate, both elements, coarse to middle meshes, Δt
    // down to 1e-6 s (a run at 1e-7 s costs 25–90 CPU s here); Argyris 10 × 7 with two replicas
    // (the replica spread).
    for forcing in [SCENES[0], SCENES[1]] {
        for (m, replicas) in [
            (mesh(Argyris, 4, 2), 0),
            (mesh(Argyris, 6, 4), 0),
            (mesh(Argyris, 10, 7), 2),
            (mesh(Argyris, 14, 10), 0),
            (mesh(Fvs, 7, 5), 0),
            (mesh(Fvs, 14, 10), 0),
            (mesh(Fvs, 28, 20), 0),
        ] {
            // The 1e-5 s run's CPU per step overestimates the 1e-6 s run's (more of its steps
            // solve a QP): FVS 28 × 20 at 1e-6 s is estimated at 130 CPU s and takes about 60.
            let cap = if m == mesh(Fvs, 28, 20) { 200.0 } else { 120.0 };
            lines.push(line(
                "middle",
                forcing,
                0.01,
                m,
                &LADDER[..3],
                cap,
                replicas,
            ));
        }
    }
    // Part `third`: the aluminium plate at ζ = 1 %, two meshes of each element, then at 0.5 % and
    // 2 % on the same meshes (each run under 20 CPU s at ζ = 1 %).
    for zeta in [0.01, 0.005, 0.02] {
        for m in [
            mesh(Argyris, 7, 7),
            mesh(Argyris, 10, 10),
            mesh(Fvs, 14, 14),
        ] {
            lines.push(line("third", SCENES[2], zeta, m, &LADDER[..3], 60.0, 0));
        }
    }
    // Part `ratios`: ζ = 0.5 % and 2 % on the paper's plate, one middle mesh of each element.
    for forcing in [SCENES[0], SCENES[1]] {
        for zeta in [0.005, 0.02] {
            for m in [
                mesh(Argyris, 10, 7),
                mesh(Argyris, 14, 10),
                mesh(Fvs, 14, 10),
            ] {
                lines.push(line("ratios", forcing, zeta, m, &LADDER[1..3], 60.0, 0));
            }
        }
    }
    // Then, at 35 Hz, each element's finest mesh at both ratios, FVS 28 × 20 (the cheaper) first:
    // whether the elements meet there as they do at ζ = 1 %. The cap lets Argyris 28 × 20's
    // 1e-6 s run happen (265 CPU s at ζ = 1 %).
    for m in [mesh(Fvs, 28, 20), mesh(Argyris, 28, 20)] {
        for zeta in [0.005, 0.02] {
            lines.push(line("ratios", SCENES[0], zeta, m, &LADDER[1..3], 600.0, 0));
        }
    }
    // And the same finest meshes at 60 Hz (ζ = 1 %: 47 and 120 CPU s at 1e-6 s).
    for m in [mesh(Fvs, 28, 20), mesh(Argyris, 28, 20)] {
        for zeta in [0.005, 0.02] {
            lines.push(line("ratios", SCENES[1], zeta, m, &LADDER[1..3], 600.0, 0));
        }
    }
    // Part `fine`: Argyris 20 × 14 at ζ = 1 % (its set-up, two dense eigendecompositions, about
    // 40 CPU s) from Δt = 1e-5 s; then Argyris 28 × 20 (5 257 free dofs, set-up by the band and
    // divide-and-conquer eigensolver, about 20 CPU s twice) on the whole ladder, 35 Hz first.
    for (m, ladder, cap) in [
        (mesh(Argyris, 20, 14), &LADDER[1..3], 250.0),
        (mesh(Argyris, 28, 20), &LADDER[..3], 600.0),
    ] {
        for forcing in [SCENES[0], SCENES[1]] {
            lines.push(line("fine", forcing, 0.01, m, ladder, cap, 0));
        }
    }
    // Part `finedt`: Δt = 1e-7 s on Argyris 10 × 7 at ζ = 1 %, 60 Hz then 35 Hz, without replicas
    // (about 1.3 µs per step at 1e-6 s, so 7e7 steps cost 70–100 CPU s): whether the RMS base
    // force and the 35 Hz corner, still moving at 1e-6 s, settle one decade further.
    for forcing in [SCENES[1], SCENES[0]] {
        lines.push(line(
            "finedt",
            forcing,
            0.01,
            mesh(Argyris, 10, 7),
            &LADDER[3..],
            200.0,
            0,
        ));
    }
    // Then FVS 28 × 20 at 35 Hz, the finest mesh whose 1e-7 s run fits (7.9 µs per step at
    // 1e-6 s, so about 9 CPU minutes): whether the 35 Hz corner and base force, which Argyris
    // 10 × 7 found settled at 1e-6 s, have settled on a fine mesh too.
    lines.push(line(
        "finedt",
        SCENES[0],
        0.01,
        mesh(Fvs, 28, 20),
        &LADDER[3..],
        900.0,
        0,
    ));
    Plan {
        name: "committed",
        lines,
        transient: 1.0,
        duration: 6.0,
        window: 1.0,
        settle_tolerance: 0.01,
        overrides: Vec::new(),
    }
}

/// The Δt ladder (s).
pub const LADDER: [f64; 4] = [1e-4, 1e-5, 1e-6, 1e-7];

pub fn quick_plan() -> Plan {
    Plan {
        name: "quick",
        lines: vec![Line {
            forcing: SCENES[0],
            zeta: 0.01,
            mesh: Mesh {
                element: ElementKind::Argyris,
                nx: 4,
                ny: 2,
            },
            ladder: vec![1e-4, 1e-5],
            part: "quick",
            max_run_cpu: 60.0,
            replicas: 2,
            series: true,
        }],
        transient: 0.5,
        duration: 1.5,
        window: 0.25,
        settle_tolerance: 0.01,
        overrides: Vec::new(),
    }
}

impl Plan {
    /// One line per line of the plan (`--plan`: what the study would run, without running it).
    pub fn print(&self) {
        for line in &self.lines {
            println!(
                "{:<9} {:<17} ζ={:<6} {:<14} Δt {:?} s, runs ≤ {} CPU s, {} replicas{}",
                line.part,
                line.forcing.label,
                line.zeta,
                line.mesh.name(),
                line.ladder,
                line.max_run_cpu,
                line.replicas,
                if line.series { ", series" } else { "" }
            );
        }
    }
}
