//! The modal backend's shortcuts against their plain forms: the levelled screening against the
//! last level alone, the shortcuts near an obstacle against the levels, and the contact solve from
//! stand-in values against the solve from the exact values.

use super::data::{FreeDofData, ModalData, SCREENING_MODES};
use super::screening::{Screen, Screening};
use super::stand_ins::high_mode_part;
use super::{ModalBackend, Predicted, Valued};
use crate::contact::{BoundState, ContactRows, PdasSettings};
use crate::modes::{ModeShapes, Modes};
use crate::scene::DampingCoefficients;
use crate::scheme::bounds::ObstacleBounds;
use crate::scheme::vectors::sum_of_squares;
use faer::Mat;
use std::sync::Arc;

/// A modal data set with n = 60 modes and m = 12 constrained rows whose entries decay with the
/// mode number, like the rows of a plate's mode shapes.
fn synthetic_data() -> Arc<ModalData> {
    let (n, m) = (60, 12);
    let shapes = Mat::from_fn(n, n, |i, k| {
        ((i * 31 + k * 17) % 23) as f64 / 23.0 - 0.45 + if i == k { 1.0 } else { 0.0 }
    });
    let omega_squared: Vec<f64> = (0..n).map(|k| (1.0 + k as f64).powi(4)).collect();
    let constrained: Vec<usize> = (0..m).map(|i| 5 * i).collect();
    let zeros = vec![0.0; n];
    let outputs = std::array::from_fn(|_| zeros.clone());
    let damping = DampingCoefficients::default();
    Arc::new(ModalData::new(
        Modes {
            omega_squared,
            shapes: ModeShapes::dense(shapes, Mat::identity(n, n)),
        },
        1e-3,
        FreeDofData {
            contact: &ContactRows::selection(&constrained),
            load: &zeros,
            translation_mass: &zeros,
            outputs: &outputs,
            damping: &damping,
        },
    ))
}

/// The heights of flat obstacles over `m` contact points.
fn flat(m: usize) -> [Vec<f64>; 2] {
    [vec![0.0; m], vec![0.0; m]]
}

/// The bounds [`lower`, `upper`] of flat obstacles with `heights` [`flat`].
fn bounds(lower: f64, upper: f64, heights: &[Vec<f64>; 2]) -> ObstacleBounds<'_> {
    ObstacleBounds::new([lower, upper], heights)
}

/// Prediction `case` of a sweep from far inside the bounds of the tests below to past them,
/// with weight shifted from the low to the high modes as `case` grows.
fn swept_prediction(case: usize, n: usize) -> Vec<f64> {
    let decay = 0.2 + 0.05 * (case % 30) as f64;
    let amplitude = 1e-3 * (1.0 + (case / 30) as f64);
    (0..n)
        .map(|k| amplitude * ((case * 7 + k * 3) as f64).sin() / (1.0 + k as f64).powf(decay))
        .collect()
}

/// The levelled screening proves a prediction exactly when the last level alone (the lowest
/// 32 modes and the Cauchy–Schwarz bound on the rest) does, and whatever it proves is inside
/// the bounds when y = Cq is evaluated in full. The predictions sweep from far inside the
/// bounds to past them, with weight shifted from the low to the high modes.
#[test]
fn levels_decide_as_the_last_level_alone_and_prove_only_the_truth() {
    let data = synthetic_data();
    let mut screening = Screening::new(&data);
    let (n, m) = (data.c.ncols(), data.c.nrows());
    let mut proven_early = 0;
    let mut proven = 0;
    for case in 0..2000 {
        let q = swept_prediction(case, n);
        let (lower, upper) = (-0.05, 0.04);
        let heights = flat(m);
        // An infinite distance to the reach's reference: only the levels decide.
        let levelled = screening.screen(&data, f64::INFINITY, &q, bounds(lower, upper, &heights))
            == Screen::Proven;
        // The last level alone.
        let low = SCREENING_MODES;
        let high = sum_of_squares(&q[low..]).sqrt();
        let total = sum_of_squares(&q).sqrt();
        let mut exact_inside = true;
        let mut last_alone = true;
        for i in 0..m {
            let y_low: f64 = (0..low).map(|k| data.c[(i, k)] * q[k]).sum();
            let y: f64 = (0..n).map(|k| data.c[(i, k)] * q[k]).sum();
            let weight = data.c.row(i).subcols(low, n - low).norm_l2();
            let slack = weight * high + 1e-12 * data.row_norms[i] * total;
            last_alone &= y_low - slack >= lower && y_low + slack <= upper;
            exact_inside &= y >= lower && y <= upper;
        }
        assert_eq!(levelled, last_alone, "case {case}");
        assert!(!levelled || exact_inside, "case {case}: proved a violation");
        proven += usize::from(levelled);
        // Proven before the last level: the first level alone already proves it.
        let first = data.levels[0];
        let first_high = sum_of_squares(&q[first..]).sqrt();
        proven_early += usize::from((0..m).all(|i| {
            let y: f64 = (0..first).map(|k| data.c[(i, k)] * q[k]).sum();
            let slack = data.high_row_norms[0][i] * first_high + 1e-12 * data.row_norms[i] * total;
            y - slack >= lower && y + slack <= upper
        }));
    }
    // Both outcomes occur, and the first level decides some steps on its own.
    assert!(proven > 100 && proven < 1900, "{proven} proven of 2000");
    assert!(
        proven_early > 10,
        "{proven_early} proven by the first level"
    );
}

/// The shortcuts near an obstacle change nothing: trying the last level first (after a
/// prediction that failed every level) decides as the levels do and leaves the same low-mode
/// values bit for bit, and the exact values formed one run of vertices per product equal
/// ŷ_i + (C_H q_H)_i formed one vertex at a time, bit for bit.
#[test]
fn near_contact_shortcuts_are_bit_identical() {
    let data = synthetic_data();
    let mut levelled = Screening::new(&data);
    let mut shortcut = Screening::new(&data);
    let n = data.c.ncols();
    let (lower, upper) = (-0.05, 0.04);
    let heights = flat(data.c.nrows());
    let box_ = bounds(lower, upper, &heights);
    let (mut failed, mut mixed) = (0, 0);
    for case in 0..2000 {
        let q = swept_prediction(case, n);
        levelled.near = false;
        shortcut.near = true;
        let decided = levelled.screen(&data, f64::INFINITY, &q, box_);
        let screen = shortcut.screen(&data, f64::INFINITY, &q, box_);
        assert_eq!(decided, screen, "case {case}");
        let Screen::Unproven { norm_squared } = screen else {
            continue;
        };
        failed += 1;
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&levelled.low_values), bits(&shortcut.low_values));
        let mut out = vec![0.0; data.c.nrows()];
        shortcut.values(&data, norm_squared, &q, box_, true, &mut out);
        let stand_ins = shortcut.stand_ins.stand_in.iter().filter(|&&s| s).count();
        mixed += usize::from(stand_ins > 0 && stand_ins < data.c.nrows());
        for (i, &value) in out.iter().enumerate() {
            let expected = if shortcut.stand_ins.stand_in[i] {
                shortcut.low_values[i]
            } else {
                shortcut.low_values[i] + high_mode_part(&data, i, &q)
            };
            assert_eq!(
                value.to_bits(),
                expected.to_bits(),
                "case {case}, vertex {i}"
            );
        }
    }
    // Failures with stand-ins between runs of exact values occur.
    assert!(failed > 100, "{failed} predictions failed the screening");
    assert!(
        mixed > 10,
        "{mixed} failures with stand-ins and exact values"
    );
}

/// The contact solve from stand-in values ([`Screening::values`]) gives the same active set and
/// multipliers as the solve from the exact y* = Cq, over predictions that push a few vertices
/// past the bounds; some of them make the solution reach a stand-in, which must then be
/// evaluated and the solve repeated.
#[test]
fn stand_in_values_give_the_exact_solution() {
    let data = synthetic_data();
    let [solved, with_stand_ins, repeated, _] = compare_stand_ins_with_exact(data.clone(), data);
    // The cases exercise every path (1518, 1236 and 494 when written).
    assert!(solved > 500, "{solved} contact solves");
    assert!(
        with_stand_ins > 500,
        "{with_stand_ins} solves with stand-ins"
    );
    assert!(repeated > 100, "{repeated} solves that reached a stand-in");
}

/// As [`stand_in_values_give_the_exact_solution`] with the layout of a large basis: stand-in
/// levels (here after 40 and 50 of the 60 modes), where every vertex the screening leaves gets a
/// stand-in, even past a bound, and the solve evaluates the ones it reaches; and no D⁻¹Cᵀ, the
/// correction scaling rows of C instead, against the reference solve with D⁻¹Cᵀ.
#[test]
fn stand_in_levels_give_the_exact_solution() {
    let mut data = synthetic_data();
    let large = Arc::get_mut(&mut data).expect("a fresh data set");
    large.set_stand_in_levels(&[40, 50], 55);
    large.step.c_t_scaled = None;
    let [solved, with_stand_ins, repeated, settled] =
        compare_stand_ins_with_exact(data, synthetic_data());
    // Every solve starts from stand-ins and the ones past a bound must be reached (1518, 1518
    // and 1518 when written).
    assert!(solved > 500, "{solved} contact solves");
    assert_eq!(with_stand_ins, solved);
    assert!(repeated > 500, "{repeated} solves that reached a stand-in");
    assert!(
        settled > 100,
        "{settled} solves that settled a stand-in at the reached level"
    );
}

/// The values of a large basis decide feasibility exactly: a stand-in lies within its slack of
/// the exact value, and when they are asked for without unproven stand-ins, or when none of them
/// lies past a bound by more than its slack, every value is exact or a stand-in proven inside
/// its bounds, so that the values lie within the bounds exactly when the prediction does. Some
/// stand-ins are settled at the reached level, others summed to the end.
#[test]
fn large_basis_values_decide_feasibility_exactly() {
    let mut data = synthetic_data();
    let large = Arc::get_mut(&mut data).expect("a fresh data set");
    large.set_stand_in_levels(&[40, 50], 55);
    let (n, m) = (data.c.ncols(), data.c.nrows());
    let (lower, upper) = (-0.05, 0.04);
    let heights = flat(m);
    let box_ = bounds(lower, upper, &heights);
    let (mut kept, mut settled, mut exact_ones) = (0, 0, 0);
    for case in 0..2000 {
        let q = swept_prediction(case, n);
        let mut exact = vec![0.0; m];
        data.constrained_values(&q, &mut exact);
        let mut screening = Screening::new(&data);
        let Screen::Unproven { norm_squared } = screening.screen(&data, f64::INFINITY, &q, box_)
        else {
            continue;
        };
        for keep_unproven in [false, true] {
            let mut out = vec![0.0; m];
            screening.values(&data, norm_squared, &q, box_, keep_unproven, &mut out);
            let stand_ins = &screening.stand_ins;
            let proven = |i: usize| {
                out[i] - stand_ins.slack[i] >= lower && out[i] + stand_ins.slack[i] <= upper
            };
            let certainly_past = (0..m).any(|i| {
                stand_ins.stand_in[i]
                    && (out[i] + stand_ins.slack[i] < lower || out[i] - stand_ins.slack[i] > upper)
            });
            for i in 0..m {
                if stand_ins.stand_in[i] {
                    assert!(
                        (exact[i] - out[i]).abs() <= stand_ins.slack[i],
                        "case {case}, {i}"
                    );
                    assert!(
                        keep_unproven && certainly_past || proven(i),
                        "case {case}, {i}"
                    );
                    kept += usize::from(!proven(i));
                    settled += usize::from(stand_ins.depth[i] == 55);
                } else {
                    assert!((exact[i] - out[i]).abs() <= 1e-12, "case {case}, {i}");
                    exact_ones += 1;
                }
            }
            let admitted = out.iter().all(|&y| (lower..=upper).contains(&y));
            let feasible = exact.iter().all(|&y| (lower..=upper).contains(&y));
            assert!(
                !admitted || feasible,
                "case {case}: values admitted past a bound"
            );
        }
    }
    println!("{kept} unproven stand-ins kept, {settled} settled at the reached level, {exact_ones} exact");
    assert!(kept > 100 && settled > 100 && exact_ones > 100);
}

/// Runs the contact solves of the stand-in tests on `data`, asserting that each gives the
/// states, multipliers and corrected q of the solve from exact values on `reference` (the same
/// basis); returns the counts of solves, of solves with a stand-in, of solves that reached one
/// and of solves that left a stand-in summed to the reached level.
fn compare_stand_ins_with_exact(data: Arc<ModalData>, reference: Arc<ModalData>) -> [usize; 4] {
    let (n, m) = (data.c.ncols(), data.c.nrows());
    let settings = PdasSettings::default();
    let (lower, upper) = (-0.02, 0.02);
    let heights = flat(data.c.nrows());
    let box_ = bounds(lower, upper, &heights);
    let (mut solved, mut with_stand_ins, mut repeated, mut settled) = (0, 0, 0, 0);
    for case in 0..3000 {
        let amplitude = 5e-3 * 1.1f64.powi((case % 50) as i32);
        let q: Vec<f64> = (0..n)
            .map(|k| amplitude * ((case * 13 + k * 5) as f64).cos() / (1.0 + k as f64).powf(1.5))
            .collect();
        let mut exact = vec![0.0; m];
        data.constrained_values(&q, &mut exact);
        let (lo, hi) = (vec![lower; m], vec![upper; m]);
        let mut fast = ModalBackend::new(data.clone());
        // The prediction q with an infinite distance to the reach's reference: the levels decide.
        let predicted = Predicted {
            step: fast.step(false),
            moved_squared: f64::INFINITY,
        };
        let Some(unproven) = predicted.screen(&q, box_) else {
            continue;
        };
        if exact.iter().all(|&y| (lower..=upper).contains(&y)) {
            continue;
        }
        let mut values = vec![0.0; m];
        let valued = unproven.values(&q, box_, true, &mut values);
        let stand_ins = valued
            .step
            .screening
            .stand_ins
            .stand_in
            .iter()
            .filter(|&&s| s)
            .count();
        let mut fast_next = q.clone();
        let mut fast_states = vec![BoundState::Free; m];
        let (fast_report, corrected) = valued.solve(
            &mut fast_next,
            &values,
            &lo,
            &hi,
            &mut fast_states,
            &settings,
        );
        let fast_multipliers = corrected.map(|c| c.multipliers().to_vec());
        let mut reference = ModalBackend::new(reference.clone());
        let mut next = q.clone();
        let mut states = vec![BoundState::Free; m];
        let exact_stage = Valued {
            step: reference.step(false),
            stand_ins: false,
        };
        let (report, corrected) =
            exact_stage.solve(&mut next, &exact, &lo, &hi, &mut states, &settings);
        let multipliers = corrected.map(|c| c.multipliers().to_vec());
        assert!(
            report.status.is_solved() && fast_report.status.is_solved(),
            "case {case}"
        );
        let (fast_multipliers, multipliers) = (fast_multipliers.unwrap(), multipliers.unwrap());
        assert_eq!(fast_states, states, "case {case}");
        // Both solve W_AA λ = bound − y* on the same set with y* equal to round-off (n ε
        // relative): λ and q agree to the solve's round-off, cond(W_AA) ε ≪ 1e-9.
        let scale = multipliers.iter().fold(0.0f64, |a, b| a.max(b.abs()));
        for (a, b) in fast_multipliers.iter().zip(&multipliers) {
            assert!((a - b).abs() <= 1e-9 * scale, "case {case}: λ {a} vs {b}");
        }
        let q_scale = next.iter().fold(0.0f64, |a, b| a.max(b.abs()));
        for (a, b) in fast_next.iter().zip(&next) {
            assert!((a - b).abs() <= 1e-9 * q_scale, "case {case}: q {a} vs {b}");
        }
        solved += 1;
        with_stand_ins += usize::from(stand_ins > 0);
        let left = fast
            .screening
            .stand_ins
            .stand_in
            .iter()
            .filter(|&&s| s)
            .count();
        repeated += usize::from(left < stand_ins);
        let reached_level = data.reached_level.unwrap_or(n);
        settled += usize::from((0..m).any(|i| {
            fast.screening.stand_ins.stand_in[i]
                && fast.screening.stand_ins.depth[i] == reached_level
        }));
    }
    println!(
        "{solved} solves, {with_stand_ins} with stand-ins, {repeated} repeated, {settled} with \
         a stand-in settled at the reached level"
    );
    [solved, with_stand_ins, repeated, settled]
}
