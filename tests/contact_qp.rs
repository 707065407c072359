//! The contact solvers against each other and against brute force.
//!
//! Random problems mimic a time step of the plate: bounds at about ±1 cm (the gap scale of the
//! paper's scenes), an unconstrained step that overshoots them at many vertices, some bounds
//! absent. Tolerances are stated in metres for that 1 cm gap scale, each with its reason.

// Index loops read closer to the formulas they check.
#![allow(clippy::needless_range_loop)]

use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, Side};
use plate_impact::contact::block_factor::NotPositiveDefinite;
use plate_impact::contact::cholesky::CholeskyAnalysis;
use plate_impact::contact::clarabel::{
    polish, reference_settings, solve_box_qp, solve_box_qp_with,
};
use plate_impact::contact::eliminated::EliminatedSystem;
use plate_impact::contact::first_guess::FirstGuess;
use plate_impact::contact::sparse_contact::{SparseContact, Subproblem};
use plate_impact::contact::{
    solve_box_lcp, ActiveSetSolver, BoundState, BoxQp, ContactRows, DelassusCache, DenseDelassus,
    PdasSettings, PdasStatus, WorkingSetSolver,
};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use std::sync::Arc;

/// Gap scale of the random problems (m).
const GAP: f64 = 0.01;
/// Agreement of the PDAS and Clarabel minimisers: the project's requirement of 1e-9 m for a 1 cm
/// gap (`docs/scheme.md` §9), i.e. 1e-7 of the gap scale.
const AGREE: f64 = 1e-9;
/// Bound violation allowed to the PDAS answer x = x* + A⁻¹Bᵀλ: the requirement of 1e-12 m per
/// step (`docs/scheme.md` §9); the active values are exact up to the round-off of two dense solves.
const PDAS_BOUND: f64 = 1e-12;
/// Bound violation allowed to Clarabel: its scaled feasibility tolerance 1e-12 times the 1 cm gap
/// scale, with a factor 10 for the unscaling.
const CLARABEL_BOUND: f64 = 1e-13;

/// One random box QP with everything the tests need, dense where that is simplest (n ≤ 300).
struct Problem {
    /// The rows that pick the constrained dofs `c`.
    rows: ContactRows,
    n: usize,
    a: SparseColMat<usize, f64>,
    b: Vec<f64>,
    c: Vec<usize>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    x_star: Vec<f64>,
    /// A⁻¹ Bᵀ, n × m.
    ainv_bt: Mat<f64>,
    /// W = B A⁻¹ Bᵀ, column-major m × m.
    w: Vec<f64>,
}

impl Problem {
    /// A = sparse symmetric R + a diagonal that makes it diagonally dominant (SPD, condition of a
    /// few tens to hundreds), scaled to mass-matrix-like magnitudes; x* overshooting ±GAP.
    fn random(rng: &mut StdRng, n: usize, m: usize) -> Problem {
        let density = 4.0 / n as f64;
        let mut dense = vec![0.0_f64; n * n];
        for j in 0..n {
            for i in 0..j {
                if rng.random::<f64>() < density {
                    let v = rng.random_range(-1.0..1.0);
                    dense[i + j * n] = v;
                    dense[j + i * n] = v;
                }
            }
        }
        for i in 0..n {
            let off: f64 = (0..n).map(|j| dense[i + j * n].abs()).sum();
            dense[i + i * n] = off + rng.random_range(0.05..1.0);
        }
        let scale = 3e-3;
        let mut trip = Vec::new();
        for j in 0..n {
            for i in 0..n {
                if dense[i + j * n] != 0.0 {
                    trip.push(Triplet::new(i, j, scale * dense[i + j * n]));
                }
            }
        }
        let a = SparseColMat::try_new_from_triplets(n, n, &trip).unwrap();
        let a_dense = Mat::from_fn(n, n, |i, j| scale * dense[i + j * n]);
        let x_target: Vec<f64> = (0..n).map(|_| rng.random_range(-3.0..3.0) * GAP).collect();
        let b: Vec<f64> = (0..n)
            .map(|i| (0..n).map(|j| a_dense[(i, j)] * x_target[j]).sum())
            .collect();
        // m distinct constrained dofs.
        let mut all: Vec<usize> = (0..n).collect();
        for k in 0..m {
            let r = rng.random_range(k..n);
            all.swap(k, r);
        }
        let mut c = all[..m].to_vec();
        c.sort_unstable();
        let mut lo = Vec::with_capacity(m);
        let mut hi = Vec::with_capacity(m);
        for _ in 0..m {
            let kind = rng.random_range(0..10);
            let l = -GAP * rng.random_range(0.8..1.2);
            let h = GAP * rng.random_range(0.8..1.2);
            lo.push(if kind == 0 { f64::NEG_INFINITY } else { l });
            hi.push(if kind == 1 { f64::INFINITY } else { h });
        }
        let llt = a_dense.llt(Side::Lower).unwrap();
        let bm = Mat::from_fn(n, 1, |i, _| b[i]);
        let xs = llt.solve(&bm);
        let x_star: Vec<f64> = (0..n).map(|i| xs[(i, 0)]).collect();
        let bt = Mat::from_fn(n, m, |i, j| if c[j] == i { 1.0 } else { 0.0 });
        let ainv_bt = llt.solve(&bt);
        let mut w = vec![0.0; m * m];
        for j in 0..m {
            for i in 0..m {
                w[i + j * m] = ainv_bt[(c[i], j)];
            }
        }
        Problem {
            rows: ContactRows::selection(&c),
            n,
            a,
            b,
            c,
            lo,
            hi,
            x_star,
            ainv_bt,
            w,
        }
    }

    fn m(&self) -> usize {
        self.c.len()
    }

    fn y_star(&self) -> Vec<f64> {
        self.c.iter().map(|&i| self.x_star[i]).collect()
    }

    fn qp(&self) -> BoxQp<'_> {
        BoxQp {
            a: self.a.as_ref(),
            b: &self.b,
            rows: &self.rows,
            lower: &self.lo,
            upper: &self.hi,
        }
    }

    /// x = x* + A⁻¹ Bᵀ λ.
    fn x_from_lambda(&self, lambda: &[f64]) -> Vec<f64> {
        let mut x = self.x_star.clone();
        for (j, &l) in lambda.iter().enumerate() {
            for (i, xi) in x.iter_mut().enumerate() {
                *xi += l * self.ainv_bt[(i, j)];
            }
        }
        x
    }

    /// Largest violations of (bounds, wrong λ sign or λ off the bound, stationarity) for (x, λ),
    /// in metres for the first two (λ measured by its effect λ_i W_ii on y) and relative to ‖b‖
    /// for the last.
    fn kkt(&self, x: &[f64], lambda: &[f64]) -> (f64, f64, f64) {
        let m = self.m();
        let mut bound: f64 = 0.0;
        let mut comp: f64 = 0.0;
        for i in 0..m {
            let y = x[self.c[i]];
            bound = bound.max(self.lo[i] - y).max(y - self.hi[i]);
            let effect = lambda[i] * self.w[i + i * m];
            // λ > 0 needs y = lo; λ < 0 needs y = hi: the product measures the violation.
            if effect > 0.0 {
                comp = comp.max(effect.min((y - self.lo[i]).abs()));
            } else if effect < 0.0 {
                comp = comp.max((-effect).min((y - self.hi[i]).abs()));
            }
        }
        let mut r = vec![0.0; self.n];
        let a = self.a.as_ref();
        for j in 0..self.n {
            let range = a.col_range(j);
            for (&i, &v) in a.row_idx()[range.clone()].iter().zip(&a.val()[range]) {
                r[i] += v * x[j];
            }
        }
        for i in 0..self.n {
            r[i] -= self.b[i];
        }
        for (k, &ci) in self.c.iter().enumerate() {
            r[ci] -= lambda[k];
        }
        let bnorm = self.b.iter().fold(0.0_f64, |s, v| s.max(v.abs()));
        let stat = r.iter().fold(0.0_f64, |s, v| s.max(v.abs())) / bnorm;
        (bound, comp, stat)
    }
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0_f64, |s, (x, y)| s.max((x - y).abs()))
}

#[test]
fn pdas_matches_clarabel_on_random_problems() {
    let mut rng = StdRng::seed_from_u64(20261124);
    let mut worst_agree: f64 = 0.0;
    let mut worst_pdas = (0.0_f64, 0.0_f64, 0.0_f64);
    let mut worst_clar = (0.0_f64, 0.0_f64, 0.0_f64);
    let mut total_active = 0;
    let mut solver = ActiveSetSolver::new();
    for trial in 0..40 {
        let n = rng.random_range(50..=300);
        let m = rng.random_range(10..=60);
        let p = Problem::random(&mut rng, n, m);
        let y_star = p.y_star();
        let mut w = DenseDelassus::new(m, p.w.clone());
        let mut states = vec![BoundState::Free; m];
        let report = solver.solve(
            &mut w,
            &y_star,
            &p.lo,
            &p.hi,
            &mut states,
            &PdasSettings::default(),
        );
        assert!(
            report.status.is_solved(),
            "trial {trial}: {:?}",
            report.status
        );
        let active = states.iter().filter(|s| s.is_active()).count();
        total_active += active;
        assert!(active >= 2, "trial {trial}: want contact-heavy problems");
        let x_pdas = p.x_from_lambda(solver.lambda());
        let reference = solve_box_qp(&p.qp()).unwrap();
        let agree = max_diff(&x_pdas, &reference.x);
        worst_agree = worst_agree.max(agree);
        assert!(
            agree <= AGREE,
            "trial {trial}: |x_pdas − x_clarabel| = {agree:e}"
        );
        assert_eq!(
            states, reference.states,
            "trial {trial}: active sets differ"
        );
        let kp = p.kkt(&x_pdas, solver.lambda());
        let kc = p.kkt(&reference.x, &reference.lambda);
        worst_pdas = (
            worst_pdas.0.max(kp.0),
            worst_pdas.1.max(kp.1),
            worst_pdas.2.max(kp.2),
        );
        worst_clar = (
            worst_clar.0.max(kc.0),
            worst_clar.1.max(kc.1),
            worst_clar.2.max(kc.2),
        );
        assert!(
            kp.0 <= PDAS_BOUND,
            "trial {trial}: PDAS bound violation {:e}",
            kp.0
        );
        assert!(
            kc.0 <= CLARABEL_BOUND,
            "trial {trial}: clarabel bound violation {:e}",
            kc.0
        );
        // Complementarity (λ on the wrong side, or nonzero off its bound): PDAS to its tolerance
        // 1e-11 × gap scale plus round-off; Clarabel to its agreement level.
        assert!(
            kp.1 <= 1e-12,
            "trial {trial}: PDAS complementarity {:e}",
            kp.1
        );
        assert!(
            kc.1 <= AGREE,
            "trial {trial}: clarabel complementarity {:e}",
            kc.1
        );
        // Stationarity A x − b − Bᵀλ: PDAS only rounds (dense solves, condition ≲ 1e3), Clarabel
        // stops at a scaled gap of 1e-12.
        assert!(kp.2 <= 1e-11, "trial {trial}: PDAS stationarity {:e}", kp.2);
        assert!(
            kc.2 <= 1e-7,
            "trial {trial}: clarabel stationarity {:e}",
            kc.2
        );
        // λ signs, exactly as the states say.
        for i in 0..m {
            match states[i] {
                BoundState::AtLower => assert!(solver.lambda()[i] >= 0.0),
                BoundState::AtUpper => assert!(solver.lambda()[i] <= 0.0),
                BoundState::Free => assert_eq!(solver.lambda()[i], 0.0),
            }
        }
        // Cached columns: same answer, and only the columns of indices that were ever active.
        let wd = p.w.clone();
        let mut lazy = DelassusCache::new(m, usize::MAX, |js: &[usize], out: &mut [f64]| {
            for (q, &j) in js.iter().enumerate() {
                out[q * m..(q + 1) * m].copy_from_slice(&wd[j * m..(j + 1) * m]);
            }
        });
        let lazy_sol = solve_box_lcp(
            &mut lazy,
            &y_star,
            &p.lo,
            &p.hi,
            &vec![BoundState::Free; m],
            &PdasSettings::default(),
        );
        assert_eq!(lazy_sol.lambda, solver.lambda());
        assert!(lazy.stats().computed >= active && lazy.stats().evicted == 0);
    }
    eprintln!(
        "random QPs: max |x_pdas − x_clarabel| = {worst_agree:.2e} m; \
         PDAS bound/compl/stat = {:.1e}/{:.1e}/{:.1e}; clarabel = {:.1e}/{:.1e}/{:.1e}; \
         mean active = {:.1}",
        worst_pdas.0,
        worst_pdas.1,
        worst_pdas.2,
        worst_clar.0,
        worst_clar.1,
        worst_clar.2,
        total_active as f64 / 40.0
    );
}

/// Random SPD W = Gᵀ G + δ I with G dense: off-diagonal entries of both signs, so not an
/// M-matrix; `coupling` near 1 makes it far from diagonal.
fn random_w(rng: &mut StdRng, m: usize, coupling: f64) -> Vec<f64> {
    let g: Vec<f64> = (0..m * m)
        .map(|k| {
            let v = rng.random_range(-1.0..1.0);
            if k % (m + 1) == 0 {
                v + 1.0 - coupling
            } else {
                v * coupling
            }
        })
        .collect();
    let mut w = vec![0.0; m * m];
    for j in 0..m {
        for i in 0..m {
            let mut s = if i == j { 0.05 } else { 0.0 };
            for k in 0..m {
                s += g[k + i * m] * g[k + j * m];
            }
            w[i + j * m] = s;
        }
    }
    w
}

/// Random y*, lo, hi at the gap scale, some bounds missing.
fn random_data(rng: &mut StdRng, m: usize) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let y: Vec<f64> = (0..m).map(|_| rng.random_range(-3.0..3.0) * GAP).collect();
    let mut lo = Vec::new();
    let mut hi = Vec::new();
    for _ in 0..m {
        let kind = rng.random_range(0..8);
        lo.push(if kind == 0 {
            f64::NEG_INFINITY
        } else {
            -GAP * rng.random_range(0.5..1.5)
        });
        hi.push(if kind == 1 {
            f64::INFINITY
        } else {
            GAP * rng.random_range(0.5..1.5)
        });
    }
    (y, lo, hi)
}

/// Dense Gaussian elimination with partial pivoting (test oracle only).
fn dense_solve(mut a: Vec<f64>, k: usize, mut r: Vec<f64>) -> Vec<f64> {
    for col in 0..k {
        let piv = (col..k)
            .max_by(|&x, &y| a[x + col * k].abs().total_cmp(&a[y + col * k].abs()))
            .unwrap();
        for j in 0..k {
            a.swap(col + j * k, piv + j * k);
        }
        r.swap(col, piv);
        for i in col + 1..k {
            let f = a[i + col * k] / a[col + col * k];
            for j in col..k {
                a[i + j * k] -= f * a[col + j * k];
            }
            r[i] -= f * r[col];
        }
    }
    for i in (0..k).rev() {
        let mut s = r[i];
        for j in i + 1..k {
            s -= a[i + j * k] * r[j];
        }
        r[i] = s / a[i + i * k];
    }
    r
}

/// Every one of the 3^m sets: keep those whose solve satisfies the KKT conditions (to 1e-12 of
/// the data scale `scale`). Returns (λ, y, states) of each.
#[allow(clippy::type_complexity)]
fn brute_force(
    w: &[f64],
    y_star: &[f64],
    lo: &[f64],
    hi: &[f64],
    scale: f64,
) -> Vec<(Vec<f64>, Vec<f64>, Vec<BoundState>)> {
    let m = y_star.len();
    let tol = 1e-12 * scale;
    let mut found = Vec::new();
    for code in 0..3usize.pow(m as u32) {
        let mut states = vec![BoundState::Free; m];
        let mut c = code;
        for s in states.iter_mut() {
            *s = [BoundState::Free, BoundState::AtLower, BoundState::AtUpper][c % 3];
            c /= 3;
        }
        let act: Vec<usize> = (0..m).filter(|&i| states[i].is_active()).collect();
        let bound = |i: usize| {
            if states[i] == BoundState::AtLower {
                lo[i]
            } else {
                hi[i]
            }
        };
        if act.iter().any(|&i| !bound(i).is_finite()) {
            continue;
        }
        let k = act.len();
        let sub: Vec<f64> = (0..k * k).map(|t| w[act[t % k] + act[t / k] * m]).collect();
        let rhs: Vec<f64> = act.iter().map(|&i| bound(i) - y_star[i]).collect();
        let la = dense_solve(sub, k, rhs);
        let mut lambda = vec![0.0; m];
        for (q, &i) in act.iter().enumerate() {
            lambda[i] = la[q];
        }
        let y: Vec<f64> = (0..m)
            .map(|i| y_star[i] + (0..m).map(|j| w[i + j * m] * lambda[j]).sum::<f64>())
            .collect();
        let ok = (0..m).all(|i| match states[i] {
            BoundState::Free => y[i] >= lo[i] - tol && y[i] <= hi[i] + tol,
            BoundState::AtLower => lambda[i] * w[i + i * m] >= -tol,
            BoundState::AtUpper => lambda[i] * w[i + i * m] <= tol,
        });
        if ok {
            found.push((lambda, y, states));
        }
    }
    found
}

#[test]
fn pdas_matches_brute_force_on_tiny_problems() {
    let mut rng = StdRng::seed_from_u64(7);
    let mut worst: f64 = 0.0;
    for trial in 0..300 {
        let m = rng.random_range(1..=6);
        let coupling = rng.random_range(0.0..0.9);
        let w = random_w(&mut rng, m, coupling);
        let (y_star, lo, hi) = random_data(&mut rng, m);
        let exact = brute_force(&w, &y_star, &lo, &hi, GAP);
        // Strict convexity: exactly one set passes (random data are not degenerate).
        assert_eq!(exact.len(), 1, "trial {trial}: {} KKT points", exact.len());
        let (lambda, y, states) = &exact[0];
        let mut dw = DenseDelassus::new(m, w.clone());
        let sol = solve_box_lcp(
            &mut dw,
            &y_star,
            &lo,
            &hi,
            &vec![BoundState::Free; m],
            &PdasSettings::default(),
        );
        assert!(
            sol.report.status.is_solved(),
            "trial {trial}: {:?}",
            sol.report
        );
        assert_eq!(&sol.states, states, "trial {trial}");
        // Same linear system, different elimination: agreement to round-off of the gap scale.
        let d = max_diff(&sol.y, y).max(
            lambda
                .iter()
                .zip(&sol.lambda)
                .enumerate()
                .fold(0.0_f64, |s, (i, (a, b))| {
                    s.max((a - b).abs() * w[i + i * m])
                }),
        );
        worst = worst.max(d);
        assert!(
            d <= 1e-14,
            "trial {trial}: differs from brute force by {d:e} m"
        );
    }
    eprintln!("tiny problems: max difference from brute force {worst:.1e} m");
}

#[test]
fn warm_start_from_the_solution_takes_one_iteration() {
    let mut rng = StdRng::seed_from_u64(11);
    let mut solver = ActiveSetSolver::new();
    for _ in 0..20 {
        let m = rng.random_range(5..=60);
        let w = random_w(&mut rng, m, 0.3);
        let (y_star, lo, hi) = random_data(&mut rng, m);
        let mut dw = DenseDelassus::new(m, w);
        let mut states = vec![BoundState::Free; m];
        let settings = PdasSettings::default();
        let cold = solver.solve(&mut dw, &y_star, &lo, &hi, &mut states, &settings);
        assert!(cold.status.is_solved());
        let lambda = solver.lambda().to_vec();
        let warm = solver.solve(&mut dw, &y_star, &lo, &hi, &mut states, &settings);
        assert_eq!(warm.status, PdasStatus::Solved);
        assert_eq!(warm.iterations, 1);
        assert!(max_diff(solver.lambda(), &lambda) <= 1e-12 * max_abs(&lambda));
    }
}

/// The method's answer does not depend on where it starts: from the first guess
/// (`contact::first_guess`), and solved again from the factor an earlier solve of the same W
/// left (`ActiveSetSolver::solve_again`, after y* changed at a few values, as when a step's
/// stand-ins are evaluated), it finds the active set and λ of a cold start. And the guess
/// saves iterations on these problems.
#[test]
fn the_first_guess_and_a_kept_factor_change_only_the_path() {
    let mut rng = StdRng::seed_from_u64(23);
    let settings = PdasSettings::default();
    let (mut from_cold, mut from_guess) = (0, 0);
    for trial in 0..40 {
        let m = rng.random_range(5..=60);
        let w = random_w(&mut rng, m, 0.3);
        let (mut y_star, lo, hi) = random_data(&mut rng, m);
        let mut dw = DenseDelassus::new(m, w);
        let mut cold = vec![BoundState::Free; m];
        let mut solver = ActiveSetSolver::new();
        let report = solver.solve(&mut dw, &y_star, &lo, &hi, &mut cold, &settings);
        assert!(report.status.is_solved(), "trial {trial}");
        from_cold += report.iterations;
        let lambda = solver.lambda().to_vec();
        let mut guessed = vec![BoundState::Free; m];
        FirstGuess::new().guess(&mut dw, &y_star, &lo, &hi, &mut guessed);
        let mut guided = ActiveSetSolver::new();
        let report = guided.solve(&mut dw, &y_star, &lo, &hi, &mut guessed, &settings);
        assert!(report.status.is_solved(), "trial {trial}");
        from_guess += report.iterations;
        assert_eq!(guessed, cold, "trial {trial}");
        assert!(max_diff(guided.lambda(), &lambda) <= 1e-12 * max_abs(&lambda));
        // A few values change; solved again from the kept factor and afresh.
        for i in (0..m).step_by(7) {
            y_star[i] += rng.random_range(-0.5..0.5) * GAP;
        }
        let mut again = guessed.clone();
        let report = guided.solve_again(&mut dw, &y_star, &lo, &hi, &mut again, &settings);
        assert!(report.status.is_solved(), "trial {trial}");
        let mut fresh = guessed;
        let report = solver.solve(&mut dw, &y_star, &lo, &hi, &mut fresh, &settings);
        assert!(report.status.is_solved(), "trial {trial}");
        assert_eq!(again, fresh, "trial {trial}");
        let scale = max_abs(solver.lambda());
        assert!(max_diff(guided.lambda(), solver.lambda()) <= 1e-12 * scale);
    }
    assert!(
        from_guess < from_cold,
        "{from_guess} iterations from the guess, {from_cold} cold"
    );
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0_f64, |s, x| s.max(x.abs()))
}

/// A cycle found by search: W = Gᵀ G + 10⁻³ I (SPD, not an M-matrix), a pure LCP (lo = 0, no
/// upper bound), warm start {1}. Plain PDAS visits {0, 2} → {1, 2} → … and returns to a set seen
/// before.
#[test]
fn a_known_cycle_falls_back_and_the_safeguard_solves_it() {
    let w = vec![
        1.7330604770155789,
        -1.3300549508592028,
        1.2262979371872704,
        -1.3300549508592028,
        1.092599814246574,
        -0.7625300772149712,
        1.2262979371872704,
        -0.7625300772149712,
        1.3272912075197625,
    ];
    let y_star = [
        -0.8148087773671082,
        0.6732562036647813,
        -0.06025784033171799,
    ];
    let lo = [0.0; 3];
    let hi = [f64::INFINITY; 3];
    let start = [BoundState::Free, BoundState::AtLower, BoundState::Free];
    let mut dw = DenseDelassus::new(3, w.clone());
    let bare = PdasSettings {
        safeguard: false,
        ..PdasSettings::default()
    };
    let sol = solve_box_lcp(&mut dw, &y_star, &lo, &hi, &start, &bare);
    assert_eq!(sol.report.status, PdasStatus::Cycled);
    assert!(!sol.report.status.is_solved());
    let safe = solve_box_lcp(&mut dw, &y_star, &lo, &hi, &start, &PdasSettings::default());
    assert_eq!(safe.report.status, PdasStatus::SolvedBySafeguard);
    let exact = brute_force(&w, &y_star, &lo, &hi, 1.0);
    assert_eq!(exact.len(), 1);
    assert_eq!(safe.states, exact[0].2);
    // Same system, different elimination: round-off of data of order 1.
    assert!(max_diff(&safe.y, &exact[0].1) <= 1e-14);
    assert!(max_diff(&safe.lambda, &exact[0].0) <= 1e-13);
}

/// The family the cycle above came from (nearly singular Gᵀ G, random warm starts): whatever
/// PDAS alone returns is either the brute-force answer or a fallback status, and with the
/// safeguard every instance is solved correctly.
#[test]
fn cycling_ends_in_fallback_or_the_right_answer() {
    let mut rng = StdRng::seed_from_u64(1);
    let trials = 20000;
    let mut fallbacks = 0;
    for trial in 0..trials {
        let m = rng.random_range(3..=5);
        let g: Vec<f64> = (0..m * m).map(|_| rng.random_range(-1.0..1.0)).collect();
        let mut w = vec![0.0; m * m];
        for j in 0..m {
            for i in 0..m {
                let mut s = if i == j { 1e-3 } else { 0.0 };
                for k in 0..m {
                    s += g[k + i * m] * g[k + j * m];
                }
                w[i + j * m] = s;
            }
        }
        let y_star: Vec<f64> = (0..m).map(|_| rng.random_range(-1.0..1.0)).collect();
        let lo = vec![0.0; m];
        let hi = vec![f64::INFINITY; m];
        let start: Vec<BoundState> = (0..m)
            .map(|_| {
                if rng.random_bool(0.5) {
                    BoundState::AtLower
                } else {
                    BoundState::Free
                }
            })
            .collect();
        let mut dw = DenseDelassus::new(m, w.clone());
        let bare = PdasSettings {
            safeguard: false,
            ..PdasSettings::default()
        };
        let sol = solve_box_lcp(&mut dw, &y_star, &lo, &hi, &start, &bare);
        let safe = solve_box_lcp(&mut dw, &y_star, &lo, &hi, &start, &PdasSettings::default());
        let exact = brute_force(&w, &y_star, &lo, &hi, 1.0);
        assert_eq!(exact.len(), 1, "trial {trial}");
        let (_, y, states) = &exact[0];
        // cond(W) reaches ~1e4 here: allow that much round-off on data of order 1.
        let close = |v: &[f64]| max_diff(v, y) <= 1e-11;
        match sol.report.status {
            PdasStatus::Solved => {
                assert_eq!(&sol.states, states, "trial {trial}");
                assert!(close(&sol.y), "trial {trial}");
                assert_eq!(safe.report.status, PdasStatus::Solved);
            }
            PdasStatus::Cycled | PdasStatus::MaxIterations => {
                fallbacks += 1;
                assert_eq!(
                    safe.report.status,
                    PdasStatus::SolvedBySafeguard,
                    "trial {trial}"
                );
            }
            other => panic!("trial {trial}: unexpected {other:?}"),
        }
        assert_eq!(&safe.states, states, "trial {trial}");
        assert!(close(&safe.y), "trial {trial}");
    }
    eprintln!("cycling: {fallbacks} of {trials} warm-started PDAS runs fell back; all solved");
    assert!(fallbacks > 0, "the family should exercise the fallback");
}

#[test]
fn bad_bounds_are_reported() {
    let mut w = DenseDelassus::new(1, vec![1.0]);
    let sol = solve_box_lcp(
        &mut w,
        &[0.0],
        &[1.0],
        &[-1.0],
        &[BoundState::Free],
        &PdasSettings::default(),
    );
    assert_eq!(sol.report.status, PdasStatus::InvalidInput);
}

#[test]
fn clarabel_errors_name_the_status() {
    let mut rng = StdRng::seed_from_u64(5);
    let p = Problem::random(&mut rng, 60, 20);
    let mut settings = reference_settings();
    settings.max_iter = 2;
    let err = solve_box_qp_with(&p.qp(), settings).unwrap_err();
    assert!(err.to_string().contains("MaxIterations"), "{err}");
}

/// The method before the block factor, as an oracle: every working set's W_𝒜𝒜 formed and solved
/// from scratch (Gaussian elimination), y = y* + W λ; refinement solves again from scratch.
struct FromScratch<'a> {
    w: &'a [f64],
    y_star: &'a [f64],
}

impl FromScratch<'_> {
    fn lambda_and_y(&self, active: &[usize], rhs: Vec<f64>, lambda: &mut [f64], y: &mut [f64]) {
        let m = self.y_star.len();
        let k = active.len();
        let sub: Vec<f64> = (0..k * k)
            .map(|t| self.w[active[t % k] + active[t / k] * m])
            .collect();
        let delta = dense_solve(sub, k, rhs);
        for (q, &i) in active.iter().enumerate() {
            lambda[i] += delta[q];
        }
        for i in 0..m {
            y[i] = self.y_star[i] + (0..m).map(|j| self.w[i + j * m] * lambda[j]).sum::<f64>();
        }
    }
}

impl WorkingSetSolver for FromScratch<'_> {
    fn dim(&self) -> usize {
        self.y_star.len()
    }

    fn solve(
        &mut self,
        active: &[usize],
        bound: &[f64],
        lambda: &mut [f64],
        y: &mut [f64],
        scale: &mut [f64],
    ) -> Result<(), NotPositiveDefinite> {
        let m = self.y_star.len();
        lambda.fill(0.0);
        let rhs = active
            .iter()
            .zip(bound)
            .map(|(&i, &b)| b - self.y_star[i])
            .collect();
        for &i in active {
            scale[i] = self.w[i + i * m];
        }
        self.lambda_and_y(active, rhs, lambda, y);
        Ok(())
    }

    fn refine(&mut self, active: &[usize], bound: &[f64], lambda: &mut [f64], y: &mut [f64]) {
        let rhs = active.iter().zip(bound).map(|(&i, &b)| b - y[i]).collect();
        self.lambda_and_y(active, rhs, lambda, y);
    }
}

/// Property: on random SPD W and random boxes, over sequences of related solves (y* drifting as in
/// successive time steps, so that working sets repeat or change by a few indices), the solver
/// that updates and reuses the factor of the active block returns the same active set as PDAS
/// with every block solved from scratch, and the same λ and y to round-off.
#[test]
fn factor_updates_and_reuse_match_solving_from_scratch() {
    let mut rng = StdRng::seed_from_u64(2027);
    let settings = PdasSettings::default();
    let (mut updated, mut reused, mut full) = (0, 0, 0);
    let mut worst: f64 = 0.0;
    for trial in 0..40 {
        let m = rng.random_range(5..=80);
        let coupling = rng.random_range(0.0..0.6);
        let w = random_w(&mut rng, m, coupling);
        let (mut y_star, lo, hi) = random_data(&mut rng, m);
        let mut dw = DenseDelassus::new(m, w.clone());
        let mut solver = ActiveSetSolver::new();
        let mut oracle = ActiveSetSolver::new();
        let mut states = vec![BoundState::Free; m];
        let mut oracle_states = states.clone();
        for step in 0..12 {
            // A few values move by up to 30 % of the gap, the others stay: nearby sets.
            for _ in 0..3 {
                let i = rng.random_range(0..m);
                y_star[i] += rng.random_range(-0.3..0.3) * GAP;
            }
            let report = solver.solve(&mut dw, &y_star, &lo, &hi, &mut states, &settings);
            let mut scratch = FromScratch {
                w: &w,
                y_star: &y_star,
            };
            let expected = oracle.solve_with(
                &mut scratch,
                &y_star,
                &lo,
                &hi,
                &mut oracle_states,
                &settings,
            );
            assert!(
                report.status.is_solved(),
                "trial {trial} step {step}: {report:?}"
            );
            assert_eq!(report.status, expected.status, "trial {trial} step {step}");
            assert_eq!(states, oracle_states, "trial {trial} step {step}");
            // W has condition up to ~1e3 here: λ and y agree to 1e3·ε of the gap scale.
            let d = max_diff(solver.y(), oracle.y()).max((0..m).fold(0.0_f64, |s, i| {
                s.max((solver.lambda()[i] - oracle.lambda()[i]).abs() * w[i + i * m])
            }));
            worst = worst.max(d);
            assert!(d <= 1e-13, "trial {trial} step {step}: differs by {d:e} m");
        }
        let stats = solver.factor().stats();
        updated += stats.appended + stats.deleted;
        reused += stats.reused;
        full += stats.full;
    }
    eprintln!(
        "factor updates: {updated} indices appended or deleted, {reused} solves reused the factor, \
         {full} full factorisations; worst difference from scratch {worst:.1e} m"
    );
    // The sequences must exercise every path of the factor.
    assert!(updated > 0 && reused > 0 && full > 0);
}

/// Property: on random sparse box QPs over sequences of right-hand sides, the active-set method
/// with the active dofs eliminated from A (primal) returns the active set and minimiser of the
/// Delassus-space method and of clarabel.
#[test]
fn eliminated_primal_matches_delassus_and_clarabel() {
    let mut rng = StdRng::seed_from_u64(99);
    let settings = PdasSettings::default();
    let mut worst_delassus: f64 = 0.0;
    let mut worst_clarabel: f64 = 0.0;
    let mut factorizations = 0;
    for trial in 0..15 {
        let n = rng.random_range(50..=200);
        let m = rng.random_range(10..=40);
        let mut p = Problem::random(&mut rng, n, m);
        let mut dw = DenseDelassus::new(m, p.w.clone());
        let analysis = CholeskyAnalysis::new(p.a.symbolic(), None).unwrap();
        let mut system = EliminatedSystem::new(Arc::new(p.a.clone()), analysis, &p.c).unwrap();
        let (mut delassus, mut primal) = (ActiveSetSolver::new(), ActiveSetSolver::new());
        let mut states = vec![BoundState::Free; m];
        let mut primal_states = states.clone();
        for step in 0..5 {
            if step > 0 {
                // The next "time step": b moves a little, x* with it.
                let a = p.a.as_ref();
                let dx: Vec<f64> = (0..n).map(|_| rng.random_range(-0.2..0.2) * GAP).collect();
                for j in 0..n {
                    for (i, &v) in a.row_idx_of_col(j).zip(a.val_of_col(j)) {
                        p.b[i] += v * dx[j];
                    }
                }
                for i in 0..n {
                    p.x_star[i] += dx[i];
                }
            }
            let y_star = p.y_star();
            let report = delassus.solve(&mut dw, &y_star, &p.lo, &p.hi, &mut states, &settings);
            assert!(report.status.is_solved(), "trial {trial} step {step}");
            let x_delassus = p.x_from_lambda(delassus.lambda());
            system.set_step(&p.b, &p.x_star);
            let report = primal.solve_with(
                &mut system,
                &y_star,
                &p.lo,
                &p.hi,
                &mut primal_states,
                &settings,
            );
            assert!(report.status.is_solved(), "trial {trial} step {step}");
            assert_eq!(states, primal_states, "trial {trial} step {step}");
            let x_primal = if states.iter().any(|s| s.is_active()) {
                system.x().to_vec()
            } else {
                p.x_star.clone()
            };
            let reference = solve_box_qp(&p.qp()).unwrap();
            assert!(reference.polished, "trial {trial} step {step}");
            assert_eq!(states, reference.states, "trial {trial} step {step}");
            let (d, c) = (
                max_diff(&x_primal, &x_delassus),
                max_diff(&x_primal, &reference.x),
            );
            worst_delassus = worst_delassus.max(d);
            worst_clarabel = worst_clarabel.max(c);
            // Two exact methods on systems of condition ≲ 1e3: round-off of the 1 cm gap scale.
            assert!(
                d <= 1e-13,
                "trial {trial} step {step}: |x_primal − x_delassus| = {d:e}"
            );
            assert!(
                c <= AGREE,
                "trial {trial} step {step}: |x_primal − x_clarabel| = {c:e}"
            );
            // On the bound exactly where active.
            for (i, s) in states.iter().enumerate() {
                match s {
                    BoundState::AtLower => assert_eq!(x_primal[p.c[i]], p.lo[i]),
                    BoundState::AtUpper => assert_eq!(x_primal[p.c[i]], p.hi[i]),
                    BoundState::Free => {}
                }
            }
        }
        factorizations += system.stats().factorizations;
    }
    eprintln!(
        "eliminated: max |x − x_delassus| = {worst_delassus:.1e} m, max |x − x_clarabel| = \
         {worst_clarabel:.1e} m, {factorizations} sparse factorisations"
    );
}

/// The polish outcome is visible: a clarabel answer stopped early is not certified, the polished
/// one is.
#[test]
fn clarabel_reports_whether_its_answer_is_polished() {
    let mut rng = StdRng::seed_from_u64(5);
    let p = Problem::random(&mut rng, 80, 20);
    let raw = solve_box_qp_with(&p.qp(), reference_settings()).unwrap();
    assert!(!raw.polished);
    let polished = solve_box_qp(&p.qp()).unwrap();
    assert!(polished.polished);
    // From the empty set, polish adds the violated bounds round by round and still certifies.
    let from_nothing = polish(&p.qp(), &vec![BoundState::Free; p.m()]).unwrap();
    assert!(from_nothing.polished);
    assert_eq!(from_nothing.states, polished.states);
}

/// The sparse backend's contact object: its unconstrained solve is x* to round-off, and each of
/// its subproblems (Delassus with cached columns, elimination, and the rule between them) returns
/// clarabel's active set and minimiser, also when a tiny column budget forces evictions.
#[test]
fn sparse_contact_solves_with_either_subproblem() {
    let mut rng = StdRng::seed_from_u64(31);
    let settings = PdasSettings::default();
    let mut used = [0usize; 2];
    for trial in 0..8 {
        let n = rng.random_range(60..=150);
        let m = rng.random_range(12..=40);
        let p = Problem::random(&mut rng, n, m);
        let reference = solve_box_qp(&p.qp()).unwrap();
        assert!(reference.polished);
        let a = Arc::new(p.a.clone());
        for (choice, budget) in [
            (None, usize::MAX),
            (Some(Subproblem::Delassus), usize::MAX),
            (Some(Subproblem::Delassus), 8 * m * 3),
            (Some(Subproblem::Eliminated), usize::MAX),
        ] {
            let mut contact = SparseContact::new(a.clone(), &p.rows, budget, None).unwrap();
            if let Some(choice) = choice {
                contact.force(choice);
            }
            let mut x_star = vec![0.0; n];
            contact.solve_unconstrained(&p.b, &mut x_star).unwrap();
            // Against the dense solve of the test problem: both round-off of condition ≲ 1e3.
            assert!(max_diff(&x_star, &p.x_star) <= 1e-14, "trial {trial}");
            let mut states = vec![BoundState::Free; m];
            let mut x = vec![0.0; n];
            let report = contact
                .solve(&p.b, &x_star, &p.lo, &p.hi, &mut states, &settings, &mut x)
                .unwrap();
            assert!(report.status.is_solved(), "trial {trial} {choice:?}");
            assert_eq!(states, reference.states, "trial {trial} {choice:?}");
            let d = max_diff(&x, &reference.x);
            assert!(d <= AGREE, "trial {trial} {choice:?}: {d:e}");
            used[usize::from(contact.last_subproblem() == Subproblem::Eliminated)] += 1;
            if budget < usize::MAX {
                assert!(contact.delassus().stats().evicted > 0, "trial {trial}");
            }
        }
    }
    assert!(used[0] > 0 && used[1] > 0);
}

/// At a load so large that the step's numbers lose all meaning (1e20 and 1e30 Pa on the paper's
/// Argyris mesh, both impact laws), a step either keeps every constrained vertex within the
/// obstacles or is refused with an error that names what went wrong (a vertex past its bound, or
/// an overflow) and leaves the stepper where it was: never Ok with the plate through an obstacle.
#[test]
fn a_huge_load_never_puts_the_plate_through_an_obstacle() {
    use plate_impact::element::ElementKind;
    use plate_impact::scene::Scene;
    use plate_impact::scheme::{Stepper, RESTORE_BOUND_TOLERANCE};
    for pressure in [1e20, 1e30] {
        for restitution in [0.0, 0.5] {
            let mut scene = Scene::named("forced-35hz").unwrap();
            scene.mesh.element = ElementKind::Argyris;
            scene.load.pressure = pressure;
            scene.solver.restitution = restitution;
            let (g1, g2) = (scene.obstacle.lower, scene.obstacle.upper);
            // What a step must keep: the tolerance of a restored state (the stepper's own check).
            let tolerance = RESTORE_BOUND_TOLERANCE * (g2 - g1);
            let mut stepper = Stepper::new(&scene, 0.0).unwrap();
            let case = format!("p = {pressure:e} Pa, e = {restitution}");
            let mut refused = false;
            for _ in 0..20 {
                let before = stepper.time();
                match stepper.step(0.0) {
                    Ok(_) => {
                        for (i, u) in stepper.constrained_displacements().iter().enumerate() {
                            assert!(
                                *u >= g1 - tolerance && *u <= g2 + tolerance,
                                "{case}: vertex {i} at u = {u} m accepted outside [{g1}, {g2}] m"
                            );
                        }
                    }
                    Err(e) => {
                        let text = e.to_string();
                        assert!(
                            (text.contains("constrained vertex") && text.contains("bound"))
                                || text.contains("non-finite"),
                            "{case}: {text}"
                        );
                        assert_eq!(stepper.time(), before, "{case}: a refused step moved time");
                        eprintln!("{case}: {text}");
                        refused = true;
                        break;
                    }
                }
            }
            eprintln!("{case}: refused {refused} at t = {} s", stepper.time());
        }
    }
}

/// A column of W = BA⁻¹Bᵀ has the same bits whether it is computed alone or within a block of
/// right-hand sides, at any place in it: the sparse backend's column cache computes the columns a
/// step needs together, so which columns share a block depends on the steps before, and a restored
/// state must continue bit for bit as the run it was taken from. Checked on the step matrix of a
/// plate (FVS 20 × 10, nested-dissection ordering) for blocks of 2 to 32 columns.
#[test]
fn a_delassus_column_has_the_same_bits_alone_or_in_a_block() {
    use faer::MatMut;
    use plate_impact::contact::ordering::nested_dissection;
    use plate_impact::element::ElementKind;
    use plate_impact::scene::Scene;
    use plate_impact::scheme::FreeSystem;
    use plate_impact::system::PlateSystem;
    let mut scene = Scene::named("forced-35hz").unwrap();
    scene.mesh.element = ElementKind::Fvs;
    (scene.mesh.nx, scene.mesh.ny) = (20, 10);
    let plate = PlateSystem::new(&scene).unwrap();
    let free = FreeSystem::new(&scene, &plate);
    let a = Arc::clone(&free.system);
    let order = nested_dissection(&free.nodes);
    let analysis = CholeskyAnalysis::new(a.symbolic(), Some(&order)).unwrap();
    let constrained = free.contact.selected().unwrap();
    let mut system = EliminatedSystem::new(Arc::clone(&a), analysis, constrained).unwrap();
    let (n, m) = (a.nrows(), constrained.len());
    let mut solve = |js: &[usize]| -> Mat<f64> {
        let mut block = Mat::<f64>::zeros(n, js.len());
        for (q, &j) in js.iter().enumerate() {
            block[(constrained[j], q)] = 1.0;
        }
        let view: MatMut<'_, f64> = block.as_mut();
        system.solve_unconstrained_unrefined_in_place(view).unwrap();
        block
    };
    let mut rng = StdRng::seed_from_u64(5);
    for width in [2, 3, 7, 16, 31, 32] {
        let js: Vec<usize> = (0..width).map(|_| rng.random_range(0..m)).collect();
        let together = solve(&js);
        for (q, &j) in js.iter().enumerate() {
            let alone = solve(&[j]);
            let same = (0..n).all(|i| alone[(i, 0)].to_bits() == together[(i, q)].to_bits());
            assert!(
                same,
                "column {j} differs alone and at place {q} of a block of {width}"
            );
        }
    }
}

/// A random box QP whose rows mix unit rows (a vertex's value) with general rows (a stop's own
/// point: the element's basis there), as a scene with local stops makes them.
struct GeneralRows {
    /// The matrix, b and x* of a [`Problem`] (its own unit rows are not used).
    base: Problem,
    rows: ContactRows,
    /// B, dense, m × n.
    dense: Vec<Vec<f64>>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    /// A⁻¹Bᵀ, n × m.
    ainv_bt: Mat<f64>,
    /// W = B A⁻¹ Bᵀ, column-major m × m.
    w: Vec<f64>,
}

impl GeneralRows {
    /// `units` unit rows on distinct unknowns and `general` rows of 3 to 8 unknowns each, whose
    /// weights sum to 1 with some negative (as a basis's values at a point do: Argyris and FVS
    /// reproduce constants, and their basis functions change sign); a general row takes one of
    /// the unit rows' unknowns half of the time, so that an active unit row fixes part of an
    /// active general row, the case the polish's Schur complement must handle. Bounds at the gap
    /// scale, some absent.
    fn random(rng: &mut StdRng, n: usize, units: usize, general: usize) -> GeneralRows {
        let base = Problem::random(rng, n, units);
        let mut dofs: Vec<Vec<usize>> = base.c.iter().map(|&d| vec![d]).collect();
        let mut weights: Vec<Vec<f64>> = vec![vec![1.0]; units];
        for _ in 0..general {
            let count = rng.random_range(3..=8);
            let mut row: Vec<usize> = Vec::new();
            if rng.random::<bool>() && units > 0 {
                row.push(base.c[rng.random_range(0..units)]);
            }
            while row.len() < count {
                let d = rng.random_range(0..n);
                if !row.contains(&d) {
                    row.push(d);
                }
            }
            let raw: Vec<f64> = (0..count).map(|_| rng.random_range(-0.3..1.0)).collect();
            let sum: f64 = raw.iter().sum();
            weights.push(raw.iter().map(|w| w / sum).collect());
            dofs.push(row);
        }
        let rows = ContactRows::new(dofs.iter().zip(&weights).map(|(d, w)| (&d[..], &w[..])));
        let m = rows.len();
        let dense: Vec<Vec<f64>> = (0..m).map(|i| rows.dense_row(i, n)).collect();
        let (mut lo, mut hi) = (Vec::with_capacity(m), Vec::with_capacity(m));
        for _ in 0..m {
            let kind = rng.random_range(0..10);
            let (l, h) = (
                -GAP * rng.random_range(0.8..1.2),
                GAP * rng.random_range(0.8..1.2),
            );
            lo.push(if kind == 0 { f64::NEG_INFINITY } else { l });
            hi.push(if kind == 1 { f64::INFINITY } else { h });
        }
        let llt = base.a.to_dense().llt(Side::Lower).unwrap();
        let ainv_bt = llt.solve(Mat::from_fn(n, m, |i, j| dense[j][i]));
        let mut w = vec![0.0; m * m];
        for j in 0..m {
            for i in 0..m {
                w[i + j * m] = (0..n).map(|k| dense[i][k] * ainv_bt[(k, j)]).sum();
            }
        }
        GeneralRows {
            base,
            rows,
            dense,
            lo,
            hi,
            ainv_bt,
            w,
        }
    }

    fn qp(&self) -> BoxQp<'_> {
        BoxQp {
            a: self.base.a.as_ref(),
            b: &self.base.b,
            rows: &self.rows,
            lower: &self.lo,
            upper: &self.hi,
        }
    }

    fn values(&self, x: &[f64]) -> Vec<f64> {
        self.dense
            .iter()
            .map(|r| r.iter().zip(x).map(|(a, b)| a * b).sum())
            .collect()
    }

    /// x = x* + A⁻¹Bᵀλ.
    fn x_from_lambda(&self, lambda: &[f64]) -> Vec<f64> {
        let mut x = self.base.x_star.clone();
        for (i, xi) in x.iter_mut().enumerate() {
            *xi += (0..lambda.len())
                .map(|j| self.ainv_bt[(i, j)] * lambda[j])
                .sum::<f64>();
        }
        x
    }

    /// Largest violations of the bounds (m), of complementarity (λ_i W_ii against the distance
    /// to the bound its sign names, m) and of stationarity A x − b − Bᵀλ (relative to max |b|).
    fn kkt(&self, x: &[f64], lambda: &[f64]) -> (f64, f64, f64) {
        let (y, m) = (self.values(x), self.rows.len());
        let (mut bound, mut comp) = (0.0f64, 0.0f64);
        for i in 0..m {
            bound = bound.max(self.lo[i] - y[i]).max(y[i] - self.hi[i]);
            let effect = lambda[i] * self.w[i + i * m];
            if effect > 0.0 {
                comp = comp.max(effect.min((y[i] - self.lo[i]).abs()));
            } else if effect < 0.0 {
                comp = comp.max((-effect).min((y[i] - self.hi[i]).abs()));
            }
        }
        let mut r: Vec<f64> = self.base.b.iter().map(|b| -b).collect();
        plate_impact::contact::add_product(self.base.a.as_ref(), x, 1.0, &mut r);
        self.rows
            .add_transpose(&lambda.iter().map(|l| -l).collect::<Vec<_>>(), &mut r);
        let scale = self.base.b.iter().fold(0.0f64, |s, v| s.max(v.abs()));
        (
            bound,
            comp,
            r.iter().fold(0.0f64, |s, v| s.max(v.abs())) / scale,
        )
    }
}

/// General rows (a stop's own points) mixed with unit rows, on 30 random problems: the
/// active-set method on the Delassus operator W = BA⁻¹Bᵀ, the sparse backend's contact object
/// (which solves general rows on W only, with columns BA⁻¹B_jᵀ computed on demand, also under a
/// budget that forces evictions) and clarabel polished on its active set through the Schur
/// complement of the active general rows (`clarabel::polish`) return the same active set and the
/// same minimiser, to the 1e-9 m the project requires ([`AGREE`]), each satisfying the KKT
/// conditions: bounds to [`PDAS_BOUND`] (the active-set answer) and to 1e-12 m (the polished one:
/// active rows solved exactly on their bounds), complementarity to 1e-12 m, stationarity to
/// 1e-11 of |b| (dense and sparse solves of a matrix of condition ≲ 1e3). The polish certifies
/// every answer (a general row its Schur complement mishandled would fail stationarity or the
/// bounds and be reported unpolished), also when it starts from no active set at all, and a
/// general row sharing an unknown with an active unit row is among the active ones.
#[test]
fn general_rows_agree_across_the_active_set_the_sparse_contact_and_the_polish() {
    let mut rng = StdRng::seed_from_u64(20261207);
    let settings = PdasSettings::default();
    let mut solver = ActiveSetSolver::new();
    let (mut worst, mut active_general, mut shared) = (0.0f64, 0, 0);
    for trial in 0..30 {
        let n = rng.random_range(60..=200);
        let units = rng.random_range(4..=20);
        let general = rng.random_range(4..=16);
        let p = GeneralRows::random(&mut rng, n, units, general);
        let m = p.rows.len();
        let reference = solve_box_qp(&p.qp()).unwrap();
        assert!(reference.polished, "trial {trial}: the polish certifies");
        let from_nothing = polish(&p.qp(), &vec![BoundState::Free; m]).unwrap();
        assert_eq!(from_nothing.states, reference.states, "trial {trial}");
        assert!(max_diff(&from_nothing.x, &reference.x) <= AGREE);
        let (bound, comp, stat) = p.kkt(&reference.x, &reference.lambda);
        assert!(
            bound <= 1e-12 && comp <= 1e-12 && stat <= 1e-11,
            "trial {trial}: clarabel {bound:e} {comp:e} {stat:e}"
        );
        // The active-set method on the dense Delassus operator.
        let y_star = p.values(&p.base.x_star);
        let mut w = DenseDelassus::new(m, p.w.clone());
        let mut states = vec![BoundState::Free; m];
        let report = solver.solve(&mut w, &y_star, &p.lo, &p.hi, &mut states, &settings);
        assert!(
            report.status.is_solved(),
            "trial {trial}: {:?}",
            report.status
        );
        assert_eq!(
            states, reference.states,
            "trial {trial}: active sets differ"
        );
        let x = p.x_from_lambda(solver.lambda());
        let (bound, comp, stat) = p.kkt(&x, solver.lambda());
        assert!(
            bound <= PDAS_BOUND && comp <= 1e-12 && stat <= 1e-11,
            "trial {trial}: PDAS {bound:e} {comp:e} {stat:e}"
        );
        worst = worst.max(max_diff(&x, &reference.x));
        // The sparse backend's contact object, without and with evictions.
        for budget in [usize::MAX, 8 * m * 3] {
            let mut contact =
                SparseContact::new(Arc::new(p.base.a.clone()), &p.rows, budget, None).unwrap();
            let mut x_star = vec![0.0; n];
            contact.solve_unconstrained(&p.base.b, &mut x_star).unwrap();
            let mut states = vec![BoundState::Free; m];
            let mut x = vec![0.0; n];
            let report = contact
                .solve(
                    &p.base.b,
                    &x_star,
                    &p.lo,
                    &p.hi,
                    &mut states,
                    &settings,
                    &mut x,
                )
                .unwrap();
            assert!(report.status.is_solved(), "trial {trial}");
            assert_eq!(contact.last_subproblem(), Subproblem::Delassus);
            assert_eq!(states, reference.states, "trial {trial}, budget {budget}");
            worst = worst.max(max_diff(&x, &reference.x));
        }
        let active = |i: usize| reference.states[i].is_active();
        active_general += (units..m).filter(|&i| active(i)).count();
        shared += (units..m)
            .filter(|&i| {
                active(i)
                    && p.rows
                        .row(i)
                        .0
                        .iter()
                        .any(|d| (0..units).any(|u| active(u) && p.rows.unit(u) == Some(*d)))
            })
            .count();
    }
    eprintln!("general rows: {active_general} active general rows ({shared} sharing an unknown with an active unit row); worst |x − x_clarabel| {worst:.1e} m");
    assert!(worst <= AGREE);
    assert!(
        active_general >= 30 && shared >= 3,
        "the problems exercise general rows"
    );
}
