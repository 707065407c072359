//! A forced trajectory with a stud under a free corner against an independent implementation of
//! the scheme.

use super::independent::{dense_restriction, free_part, rows_at, solve_few_rows};
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::matmul::sparse_dense_matmul;
use faer::sparse::SparseColMat;
use faer::{Accum, ColMut, ColRef, Mat, Par, Side};
use plate_impact::element::ElementKind;
use plate_impact::scene::{LinearChoice, Scene};
use plate_impact::scheme::Stepper;
use plate_impact::system::PlateSystem;

/// The paper's plate (clamped at x = 0) on its `element` mesh, its base shaken by
/// z = 5 mm · sin(2π · 35 Hz · t), over a disc stud of radius 1 cm under the free corner
/// (Lx, 0), 2 mm below the plate at rest; no upper obstacle, no load, e = 0, Δt = 1e-4 s.
fn stud_under_a_corner(element: ElementKind, linear: LinearChoice) -> Scene {
    let mut s = super::plates::paper_mesh(element);
    s.base.amplitude = 0.005;
    s.base.frequency = 35.0;
    s.obstacle.upper_enabled = false;
    s.obstacle.lower = -0.002;
    s.obstacle.lower_profile = "disc(x = 0.38, y = 0.015, radius = 0.01)".to_string();
    s.solver.linear = linear;
    s.validate().unwrap();
    s
}

/// The scheme of docs/scheme.md §2–§5 written directly in the absolute deflection u over all
/// dofs, dense: A = M + ½Δt²K; each step solves A_FF u_F = b_F − A_FC u_C for the free dofs F,
/// the clamp dofs C prescribed at z_{n+1} 𝟙 (with b = 2Mu_n − Au_{n−1} + ½Δt²(F_{n+1} + F_{n−1}),
/// and b = Mu_0 + ¼Δt²(F_1 + F_0) for the start step from rest), subject to r_i·u ≥ g1 + h_i at
/// the contact points, rows from the cell basis, the QP solved by enumerating active sets.
struct Reference {
    free: Vec<usize>,
    clamp: Vec<usize>,
    /// A, M over all dofs.
    a: SparseColMat<usize, f64>,
    mass: SparseColMat<usize, f64>,
    /// The factor of A_FF.
    factor: faer::linalg::solvers::Llt<f64>,
    translation: Vec<f64>,
    /// Rows over F and over C.
    rows_free: Vec<Vec<f64>>,
    rows_clamp: Vec<Vec<f64>>,
    /// g1 + h_i.
    bounds: Vec<f64>,
    /// u_{n−1}, u_n over all dofs.
    levels: [Vec<f64>; 2],
    steps: u64,
}

/// y = A x for a sparse A.
fn product(a: &SparseColMat<usize, f64>, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; a.nrows()];
    sparse_dense_matmul(
        ColMut::from_slice_mut(&mut y).as_mat_mut(),
        Accum::Replace,
        a.as_ref(),
        ColRef::from_slice(x).as_mat(),
        1.0,
        Par::Seq,
    );
    y
}

impl Reference {
    fn new(scene: &Scene) -> Reference {
        assert_eq!(scene.load.pressure, 0.0, "written for an unloaded plate");
        let plate = PlateSystem::new(scene).unwrap();
        let n = plate.disc.dof_count;
        let dt = scene.solver.time_step;
        let a = &plate.mass + &(&plate.stiffness * faer::Scale(0.5 * dt * dt));
        let free = plate.free.clone();
        let a_ff = dense_restriction(&a, &free);
        let points: Vec<[f64; 2]> = plate.layout.points.iter().map(|p| p.position).collect();
        let (rows_free, rows_all) = rows_at(&plate, &points);
        Reference {
            rows_clamp: rows_all
                .iter()
                .map(|r| free_part(r, &plate.clamp))
                .collect(),
            bounds: plate
                .layout
                .points
                .iter()
                .map(|p| scene.obstacle.lower + p.lower.unwrap().h)
                .collect(),
            factor: a_ff.llt(Side::Lower).unwrap(),
            translation: plate.translation.clone(),
            levels: [vec![0.0; n], vec![0.0; n]],
            clamp: plate.clamp.clone(),
            free,
            a,
            mass: plate.mass.clone(),
            rows_free,
            steps: 0,
        }
    }

    /// One step to the base value `z`; returns the contact forces (N).
    fn step(&mut self, z: f64, dt: f64) -> Vec<f64> {
        let [previous, current] = &self.levels;
        let start = self.steps == 0;
        let b: Vec<f64> = if start {
            product(&self.mass, current)
        } else {
            let m = product(&self.mass, current);
            let a = product(&self.a, previous);
            m.iter().zip(&a).map(|(m, a)| 2.0 * m - a).collect()
        };
        let mut next = vec![0.0; b.len()];
        for &d in &self.clamp {
            next[d] = z * self.translation[d];
        }
        let a_next = product(&self.a, &next);
        let rhs: Vec<f64> = self.free.iter().map(|&d| b[d] - a_next[d]).collect();
        let x_star = self.factor.solve(Mat::from_fn(rhs.len(), 1, |i, _| rhs[i]));
        let x_star: Vec<f64> = (0..rhs.len()).map(|i| x_star[(i, 0)]).collect();
        let u_clamp = free_part(&next, &self.clamp);
        let bounds: Vec<f64> = self
            .bounds
            .iter()
            .zip(&self.rows_clamp)
            .map(|(g, r)| g - r.iter().zip(&u_clamp).map(|(a, b)| a * b).sum::<f64>())
            .collect();
        let (x, mu) = solve_few_rows(&self.factor, &x_star, &self.rows_free, &bounds);
        for (k, &d) in self.free.iter().enumerate() {
            next[d] = x[k];
        }
        self.levels = [std::mem::take(&mut self.levels[1]), next];
        self.steps += 1;
        let scale = if start { 2.0 } else { 1.0 } / (dt * dt);
        mu.iter().map(|m| scale * m).collect()
    }
}

/// 600 steps (0.06 s, two base periods, the corner striking the stud) on both elements and both
/// linear backends against the reference: at every step u_{n+1} at every contact point and the
/// contact forces agree, and on the sparse backend (whose state is w over the free dofs) every
/// free dof of w = u − z𝟙. Both solve the same QPs exactly; what separates them is round-off,
/// which impacts amplify (the fast path and clarabel agree to ≈ 1e-13 m, tests/scheme.rs):
/// 1e-9 m and 1e-6 of the largest force bound it with a margin, while a contact missed, a wrong
/// row or a wrong active set shows as millimetres and newtons.
#[test]
fn a_stud_under_a_corner_follows_the_independent_scheme() {
    for element in [ElementKind::Argyris, ElementKind::Fvs] {
        for linear in [LinearChoice::Sparse, LinearChoice::Modal] {
            let scene = stud_under_a_corner(element, linear);
            let dt = scene.solver.time_step;
            let mut stepper = Stepper::new(&scene, 0.0).unwrap();
            let mut reference = Reference::new(&scene);
            let (mut worst_u, mut worst_force, mut largest_force) = (0.0f64, 0.0f64, 0.0f64);
            let mut contact_steps = 0;
            for n in 1..=600 {
                let z = scene.builtin_base(n as f64 * dt);
                stepper.step(z).unwrap();
                let forces = reference.step(z, dt);
                let u = &reference.levels[1];
                let values: Vec<f64> = reference
                    .rows_free
                    .iter()
                    .zip(&reference.rows_clamp)
                    .map(|(rf, rc)| {
                        let f: f64 = rf
                            .iter()
                            .zip(&free_part(u, &reference.free))
                            .map(|(a, b)| a * b)
                            .sum();
                        let c: f64 = rc
                            .iter()
                            .zip(&free_part(u, &reference.clamp))
                            .map(|(a, b)| a * b)
                            .sum();
                        f + c
                    })
                    .collect();
                for (a, b) in stepper.constrained_displacements().iter().zip(&values) {
                    worst_u = worst_u.max((a - b).abs());
                }
                if linear == LinearChoice::Sparse {
                    let w = stepper.state().current;
                    for (k, &d) in reference.free.iter().enumerate() {
                        let relative = u[d] - z * reference.translation[d];
                        worst_u = worst_u.max((w[k] - relative).abs());
                    }
                }
                for (a, b) in stepper.contact_forces().iter().zip(&forces) {
                    worst_force = worst_force.max((a - b).abs());
                    largest_force = largest_force.max(b.abs());
                }
                if forces.iter().any(|&f| f > 0.0) {
                    contact_steps += 1;
                }
            }
            println!(
                "{element:?} {linear:?}: {} contact points, {contact_steps} contact steps, largest force {largest_force:.1} N; worst |Δu| {worst_u:.1e} m, |Δf| {worst_force:.1e} N",
                reference.bounds.len()
            );
            assert!(contact_steps >= 10, "the corner strikes the stud");
            assert!(worst_u <= 1e-9, "{element:?} {linear:?}: {worst_u:e} m");
            assert!(
                worst_force <= 1e-6 * largest_force,
                "{element:?} {linear:?}: {worst_force:e} N"
            );
        }
    }
}
