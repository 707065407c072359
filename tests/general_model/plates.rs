//! The plates the tests share: the clamps of the spectra and the preloaded stud. Each test crate
//! uses some of them only, hence the allowance of dead code.
#![allow(dead_code)]

use super::ritz::{frequency_parameters, Ends};
use plate_impact::element::ElementKind;
use plate_impact::scene::{LinearChoice, Scene};
use plate_impact::system::PlateSystem;

/// One clamp of the three kinds: its `plate.clamp` text, the clamped ends of x and of y for the
/// Ritz reference, and the clamped sides by name for GetFEM.
pub struct Clamp {
    /// Its `plate.clamp` text.
    pub text: &'static str,
    /// The clamped ends of x (at 0, at Lx).
    pub x_ends: Ends,
    /// The clamped ends of y.
    pub y_ends: Ends,
    /// The clamped sides by name.
    pub sides: &'static [&'static str],
}

/// Two adjacent edges, two opposite edges (the short ones), all four.
pub const CLAMPS: [Clamp; 3] = [
    Clamp {
        text: "xmin, ymin",
        x_ends: (true, false),
        y_ends: (true, false),
        sides: &["xmin", "ymin"],
    },
    Clamp {
        text: "xmin, xmax",
        x_ends: (true, true),
        y_ends: (false, false),
        sides: &["xmin", "xmax"],
    },
    Clamp {
        text: "all",
        x_ends: (true, true),
        y_ends: (true, true),
        sides: &["xmin", "xmax", "ymin", "ymax"],
    },
];

/// Polynomials per direction of the Ritz reference. Its λ₁ … λ₆ move from 18 to 22 polynomials
/// by at most 4e-9 relative for the fully clamped plate and by at most 2.4e-5 (mode 6 of
/// "xmin, xmax") where a clamped edge meets a free one, whose corner singularity slows any
/// polynomial basis; halving successive changes bounds what remains below 3e-5.
pub const RITZ_COUNT: usize = 22;

/// How far below the Ritz reference a conforming λ_h may lie: the reference's own remaining
/// error (3e-5, [`RITZ_COUNT`]), since both are upper bounds of the exact λ.
pub const BELOW_RITZ: f64 = 3e-5;

/// The paper's plate, 0.4 m × 0.2 m (a/b = 2 with a = Lx the longer side), on an `element`
/// mesh of nx × ny cells, clamped on `clamp`.
pub fn scene(clamp: &str, element: ElementKind, nx: usize, ny: usize) -> Scene {
    let mut s = Scene::default();
    s.set("plate.clamp", clamp).unwrap();
    s.mesh.element = element;
    s.mesh.nx = nx;
    s.mesh.ny = ny;
    s
}

/// ω_k² of the six lowest modes of `scene` (rad²/s²).
pub fn omega_squared(scene: &Scene) -> Vec<f64> {
    let plate = PlateSystem::new(scene).unwrap();
    plate.modes().unwrap().omega_squared[..6].to_vec()
}

/// The six lowest λ_k = ω_k Lx²√(ρe/D) of the plate clamped on `clamp`.
pub fn parameters(clamp: &str, element: ElementKind, nx: usize, ny: usize) -> Vec<f64> {
    let s = scene(clamp, element, nx, ny);
    let scale = s.plate.length.powi(2) * (s.areal_mass() / s.bending_stiffness()).sqrt();
    omega_squared(&s)
        .iter()
        .map(|w2| w2.sqrt() * scale)
        .collect()
}

/// The Ritz reference of `clamp` for the 0.4 × 0.2 plate (ν = 0.3).
pub fn ritz_reference(clamp: &Clamp) -> Vec<f64> {
    frequency_parameters([0.4, 0.2], clamp.x_ends, clamp.y_ends, RITZ_COUNT, 0.3)
}

/// The paper's plate (clamped at x = 0) on an `element` mesh of nx × ny cells, pressed down by
/// the preload p₀ = −30 kPa onto the lower obstacle `profile` at the level −1 mm, without an
/// upper obstacle: free, its deflection under the stud would reach about −4.0 mm.
pub fn preloaded(profile: &str, element: ElementKind, nx: usize, ny: usize) -> Scene {
    let mut s = Scene::default();
    s.mesh.element = element;
    s.mesh.nx = nx;
    s.mesh.ny = ny;
    s.obstacle.upper_enabled = false;
    s.obstacle.lower = -0.001;
    s.obstacle.lower_profile = profile.to_string();
    s.initial.preload_pressure = -30_000.0;
    s.solver.linear = LinearChoice::Sparse;
    s.validate().unwrap();
    s
}

/// The default scene on the paper's 140-element mesh of `element` (Argyris 10 × 7, FVS 14 × 10).
pub fn paper_mesh(element: ElementKind) -> Scene {
    let mut s = Scene::default();
    s.mesh.element = element;
    if element == ElementKind::Fvs {
        s.mesh.nx = 14;
        s.mesh.ny = 10;
    }
    s
}
