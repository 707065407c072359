//! Screening many steps with one proof: the reach of a proven-inside reference.
//!
//! When the levelled screening ([`super`]) proves a prediction q_s inside the bounds, it also
//! proves by how much: every constrained vertex i has y_i(q_s) within [l_s + r_i, u_s − r_i] for
//! a margin r_i ≥ 0 (its distance to the nearer bound less the screening's slack). For any later
//! prediction q, y_i(q) = y_i(q_s) + C_i(q − q_s) with |C_i(q − q_s)| ≤ g_i D, where
//! D = ‖q − q_s‖_w in the weighted norm ‖x‖_w² = Σ_k w_k x_k² and g_i = (Σ_k C_ik²/w_k)^½
//! (Cauchy–Schwarz; [`ReachMetric`], w_k = ω_k), while the bounds relative to the base move by at
//! most δ = max(l − l_s, u_s − u, 0). So q is inside its bounds [l, u] when g_i D + δ ≤ r_i for
//! every i, which follows from either of two tests that cost O(1):
//!
//! * ρ = min_i r_i/g_i ≥ D and δ ≤ g_min (ρ − D)  (r_i − g_iD ≥ g_i(ρ − D)), or
//! * δ ≤ r_min − g_max D,
//!
//! with g_min, g_max the extremes over the rows that are not zero (a zero row holds its vertex at
//! the base, which [`check_base`](crate::scheme::state::check_base) keeps strictly inside the
//! gap). D comes from the step's fused pass ([`super::pass`]) at the cost of one subtraction, one
//! product and one multiply-add per mode. At small time steps a vertex moves by a tiny fraction
//! of its margin per step, so one proof covers tens to hundreds of steps, each of which then does
//! no bound check at all. Weighting by ω_k discounts the high modes, whose large entries C_ik
//! would otherwise let their small share of the motion count at full weight at every vertex. The
//! proof is about the vector q_s and the bounds l_s, u_s only, not about the trajectory that led
//! there, so it stays valid across a restored state or moved obstacles.
//!
//! Round-off: the computed y_i differs from the exact one by at most 1e-12 ‖C_i‖ ‖q‖ (the
//! screening's own margin, see [`super`]) ≤ 1e-12 g_i √w_max (‖q_s‖ + D/√w_min), and D² is
//! summed with a relative error below n ε < 1e-12; both are added to D.

/// The reference of the last proof and what it proves.
#[derive(Clone, Debug)]
pub(super) struct Reach {
    /// q_s (zeros before any proof: then D = ‖q‖).
    reference: Vec<f64>,
    /// ‖q_s‖.
    reference_norm: f64,
    /// [l_s, u_s], the bounds of the proof relative to the base.
    bounds: [f64; 2],
    /// ρ = min_i r_i/g_i over the non-zero rows (−∞ before any proof).
    radius: f64,
    /// r_min = min_i r_i over the non-zero rows (−∞ before any proof).
    margin: f64,
}

/// The weighted norm in which the reach measures D: ‖x‖_w² = Σ_k w_k x_k², with the rows' dual
/// norms g_i = (Σ_k C_ik²/w_k)^½, so that |C_i x| ≤ g_i ‖x‖_w (Cauchy–Schwarz).
#[derive(Clone, Debug)]
pub(super) struct ReachMetric {
    /// w_k.
    pub weights: Vec<f64>,
    /// g_i per constrained vertex.
    pub rows: Vec<f64>,
    /// The range of the non-zero g_i.
    pub range: RowNormRange,
    /// (min_k w_k)^½ and (max_k w_k)^½: ‖x‖ ≤ ‖x‖_w / √w_min and ‖C_i‖ ≤ g_i √w_max.
    pub root_min: f64,
    pub root_max: f64,
}

impl ReachMetric {
    /// The metric w_k = (ω_k²)^(p/2) (ω_k² floored at 1 s⁻², so that a rigid or nearly rigid
    /// mode keeps a positive weight) for the rows `rows` of C (each of length n).
    pub(super) fn new(omega_squared: &[f64], power: f64, rows: Vec<Vec<f64>>) -> ReachMetric {
        let weights: Vec<f64> = omega_squared
            .iter()
            .map(|&w2| w2.max(1.0).powf(power / 2.0))
            .collect();
        let rows: Vec<f64> = rows
            .iter()
            .map(|row| {
                row.iter()
                    .zip(&weights)
                    .map(|(c, w)| c * c / w)
                    .sum::<f64>()
                    .sqrt()
            })
            .collect();
        let (min, max) = weights
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), &w| (a.min(w), b.max(w)));
        ReachMetric {
            range: RowNormRange::of(&rows),
            rows,
            root_min: min.sqrt(),
            root_max: max.sqrt(),
            weights,
        }
    }
}

/// The extremes of the non-zero dual row norms g_i.
#[derive(Clone, Copy, Debug)]
pub(super) struct RowNormRange {
    pub min: f64,
    pub max: f64,
}

impl RowNormRange {
    /// The range of the non-zero `norms` (min = ∞, max = 0 when there is none).
    pub(super) fn of(norms: &[f64]) -> RowNormRange {
        norms.iter().filter(|&&c| c > 0.0).fold(
            RowNormRange {
                min: f64::INFINITY,
                max: 0.0,
            },
            |r, &c| RowNormRange {
                min: r.min.min(c),
                max: r.max.max(c),
            },
        )
    }
}

impl Reach {
    /// No proof yet, for fields of `dimension` modal coordinates.
    pub(super) fn none(dimension: usize) -> Reach {
        Reach {
            reference: vec![0.0; dimension],
            reference_norm: 0.0,
            bounds: [f64::NEG_INFINITY, f64::INFINITY],
            radius: f64::NEG_INFINITY,
            margin: f64::NEG_INFINITY,
        }
    }

    /// q_s, against which the fused pass measures D².
    pub(super) fn reference(&self) -> &[f64] {
        &self.reference
    }

    /// An upper bound on ‖q‖² from D² = ‖q − q_s‖_w²: (‖q_s‖ + D/√w_min)², finite exactly when
    /// D² is.
    pub(super) fn norm_squared_bound(&self, moved_squared: f64, metric: &ReachMetric) -> f64 {
        let norm = self.reference_norm + moved_squared.sqrt() / metric.root_min;
        norm * norm
    }

    /// Whether the proof covers a prediction at distance² `moved_squared` from q_s with the bounds
    /// `lower`, `upper` (the module docs' two tests).
    pub(super) fn covers(
        &self,
        moved_squared: f64,
        lower: f64,
        upper: f64,
        metric: &ReachMetric,
    ) -> bool {
        let rows = metric.range;
        let moved = moved_squared.sqrt();
        let norm = self.reference_norm + moved / metric.root_min;
        let distance = moved * (1.0 + 1e-12) + 1e-12 * metric.root_max * norm;
        let [lower_s, upper_s] = self.bounds;
        // Written so that equal infinite bounds (no obstacle) give 0.
        let shift_lower = if lower <= lower_s {
            0.0
        } else {
            lower - lower_s
        };
        let shift_upper = if upper >= upper_s {
            0.0
        } else {
            upper_s - upper
        };
        let shift = shift_lower.max(shift_upper);
        let by_ratio = self.radius >= distance && shift <= rows.min * (self.radius - distance);
        by_ratio || shift <= self.margin - rows.max * distance
    }

    /// Takes q as the new reference, proven inside [`lower`, `upper`] with the margins
    /// `margins[i]` ≥ 0 per vertex, `dual_row_norms[i]` = g_i, and ‖q‖ = `norm`.
    pub(super) fn prove(
        &mut self,
        q: &[f64],
        norm: f64,
        lower: f64,
        upper: f64,
        margins: impl Iterator<Item = f64>,
        dual_row_norms: &[f64],
    ) {
        self.reference.copy_from_slice(q);
        self.reference_norm = norm;
        self.bounds = [lower, upper];
        let (mut radius, mut margin) = (f64::INFINITY, f64::INFINITY);
        for (r, &c) in margins.zip(dual_row_norms) {
            if c > 0.0 {
                radius = radius.min(r / c);
                margin = margin.min(r);
            }
        }
        self.radius = radius;
        self.margin = margin;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Against the per-vertex condition ‖C_i‖D + δ ≤ r_i written out: whatever the two O(1)
    /// tests accept satisfies it for every vertex, and they accept most of what it does when the
    /// rows are of similar norms; without a proof nothing is covered.
    #[test]
    fn covered_predictions_satisfy_every_vertex_condition() {
        // Unit weights: g_i = ‖C_i‖ = the row norms below (rows of one entry each).
        let row_norms = [0.5, 1.0, 2.0, 0.0, 1.5];
        let margins = [1e-3, 2e-3, 4e-3, 0.0, 1e-3];
        let metric = ReachMetric::new(&[1.0], 0.0, row_norms.iter().map(|&c| vec![c]).collect());
        assert_eq!(metric.rows, row_norms);
        assert_eq!((metric.range.min, metric.range.max), (0.5, 2.0));
        let rows = &metric;
        let mut reach = Reach::none(1);
        assert!(!reach.covers(0.0, -1.0, 1.0, rows));
        reach.prove(&[0.1], 0.1, -0.01, 0.01, margins.into_iter(), &row_norms);
        let (mut accepted, mut true_cases) = (0, 0);
        for a in 0..60 {
            for b in 0..60 {
                let moved = 5e-5 * a as f64;
                let shift = 5e-5 * b as f64;
                let holds = row_norms
                    .iter()
                    .zip(&margins)
                    .filter(|(c, _)| **c > 0.0)
                    .all(|(c, r)| c * moved * (1.0 + 1e-9) + shift <= *r);
                // The bounds move toward the plate by `shift` on the lower side.
                let covered = reach.covers(moved * moved, -0.01 + shift, 0.01, rows);
                assert!(!covered || holds, "moved {moved} shift {shift}");
                accepted += usize::from(covered);
                true_cases += usize::from(holds);
            }
        }
        assert!(
            accepted > 0 && 2 * accepted >= true_cases,
            "{accepted} of {true_cases}"
        );
        // No obstacle on a side: an infinite bound that stays infinite shifts nothing.
        reach.prove(
            &[0.0],
            0.0,
            f64::NEG_INFINITY,
            0.01,
            margins.into_iter(),
            &row_norms,
        );
        assert!(reach.covers(0.0, f64::NEG_INFINITY, 0.01, rows));
        assert!(!reach.covers(0.0, -0.5, 0.01, rows));
    }

    /// The weighted metric bounds a row's product by Cauchy–Schwarz, |C_i x| ≤ g_i ‖x‖_w, with
    /// w_k = ω_k over frequencies spanning four decades, for rows and vectors of varied shape;
    /// and the bound is attained by x_k = C_ik/w_k (the equality case).
    #[test]
    fn weighted_rows_bound_every_product() {
        let n = 50;
        let omega_squared: Vec<f64> = (0..n).map(|k| (300.0 * 1.2f64.powi(k)).powi(2)).collect();
        let rows: Vec<Vec<f64>> = (0..6)
            .map(|i| {
                (0..n)
                    .map(|k| ((i * 7 + k * 3) as f64).sin() * (1.0 + k as f64).sqrt())
                    .collect()
            })
            .collect();
        let metric = ReachMetric::new(&omega_squared, 1.0, rows.clone());
        let norm_w = |x: &[f64]| -> f64 {
            x.iter()
                .zip(&metric.weights)
                .map(|(x, w)| w * x * x)
                .sum::<f64>()
                .sqrt()
        };
        for (i, row) in rows.iter().enumerate() {
            for case in 0..200 {
                let x: Vec<f64> = (0..n)
                    .map(|k| ((case * 13 + k * 5) as f64).cos() / (1.0 + k as f64))
                    .collect();
                let product: f64 = row.iter().zip(&x).map(|(c, x)| c * x).sum();
                assert!(product.abs() <= metric.rows[i] * norm_w(&x) * (1.0 + 1e-12));
            }
            let extremal: Vec<f64> = row
                .iter()
                .zip(&metric.weights)
                .map(|(c, w)| c / w)
                .collect();
            let product: f64 = row.iter().zip(&extremal).map(|(c, x)| c * x).sum();
            let bound = metric.rows[i] * norm_w(&extremal);
            assert!(
                (product - bound).abs() <= 1e-12 * bound,
                "row {i}: {product} vs {bound}"
            );
        }
    }
}
