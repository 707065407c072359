//! The modal backend's precomputed data ([`ModalData`]: the diagonal systems, the constrained rows
//! C = BΦ, the screening's and the reach's weights, the projected forcing and outputs) and its
//! read-only field maps on modal coordinates q (w_f = Φq): sums, constrained values, energies,
//! projections and the conversions to and from free-dof vectors.

use super::pass::{lane_dot, Recurrence};
use super::reach::ReachMetric;
use super::remainder::BlockRemainder;
use crate::contact::{ContactRows, DenseDelassus};
use crate::modes::{ModeShapes, Modes};
use crate::scene::DampingCoefficients;
use crate::scheme::sums::{EnergyPieces, FieldSums};
use crate::scheme::vectors::{dot, sum_of_squares};
use crate::system::OUTPUT_POINTS;
use faer::linalg::matmul::matmul;
use faer::{Accum, Col, ColRef, Mat, MatMut, Par};

/// The diagonal system of one kind of step in modal coordinates: D = diag(d_k).
#[derive(Debug)]
pub(super) struct ModalSystem {
    /// d_k.
    pub(super) d: Vec<f64>,
    /// 1/d_k (a product per mode and step instead of a division).
    pub(super) inverse_d: Vec<f64>,
    /// Whether there is damping: without it every `lagged` weight is 1 and is not read.
    pub(super) damped: bool,
    /// (d_k − Δt c_k)/d_k, the weight of q_{n−1} after dividing by d_k: exactly 1 without damping.
    pub(super) lagged: Vec<f64>,
    /// Cᵀ scaled by D⁻¹ row-wise, stored as n × m: column i is D⁻¹ Cᵀ e_i = Φᵀ A⁻¹ Bᵀ e_i.
    /// Not kept on a basis above [`DENSE_LIMIT`](crate::modes::DENSE_LIMIT) modes: the
    /// correction there scales the rows of C it has just read for the values
    /// ([`ModalData::c_rows`]) by `inverse_d` instead of reading a second n × m matrix.
    pub(super) c_t_scaled: Option<Mat<f64>>,
    /// W = C D⁻¹ Cᵀ (m × m), precomputed.
    pub(super) delassus: DenseDelassus,
}

impl ModalSystem {
    /// The system with d_k = 1 + ½Δt²ω_k² + ½Δt c_k and the constrained rows `c` of Φ, keeping
    /// D⁻¹Cᵀ when `keep_scaled`.
    fn new(
        omega_squared: &[f64],
        damping: &DampingCoefficients,
        time_step: f64,
        c: &Mat<f64>,
        keep_scaled: bool,
    ) -> ModalSystem {
        let (m, n) = (c.nrows(), c.ncols());
        let coefficient: Vec<f64> = omega_squared
            .iter()
            .map(|&w2| damping.modal_coefficient(w2))
            .collect();
        let d: Vec<f64> = omega_squared
            .iter()
            .zip(&coefficient)
            .map(|(&w2, &ck)| 1.0 + 0.5 * time_step * time_step * w2 + 0.5 * time_step * ck)
            .collect();
        let c_t_scaled = Mat::from_fn(n, m, |k, i| c[(i, k)] / d[k]);
        let mut delassus = vec![0.0; m * m];
        matmul(
            MatMut::from_column_major_slice_mut(&mut delassus, m, m),
            Accum::Replace,
            c.as_ref(),
            c_t_scaled.as_ref(),
            1.0,
            Par::Seq,
        );
        ModalSystem {
            inverse_d: d.iter().map(|d| 1.0 / d).collect(),
            damped: !damping.is_zero(),
            lagged: d
                .iter()
                .zip(&coefficient)
                .map(|(&d, &ck)| (d - time_step * ck) / d)
                .collect(),
            c_t_scaled: keep_scaled.then_some(c_t_scaled),
            delassus: DenseDelassus::new(m, delassus),
            d,
        }
    }
}

/// Immutable data shared by every modal stepper of one scene.
#[derive(Debug)]
pub(in crate::scheme) struct ModalData {
    /// The system of every step but the start.
    pub(super) step: ModalSystem,
    /// The start step's undamped system, when damping makes it differ from `step`.
    pub(super) start: Option<ModalSystem>,
    /// ω_k².
    pub(super) omega_squared: Vec<f64>,
    /// c_k = α + βω_k² + 2ζ_mω_k (1/s), the modal damping coefficients.
    pub(super) damping: Vec<f64>,
    /// Φ (free dofs × modes), to map between modal coordinates and free-dof values.
    pub(super) shapes: ModeShapes,
    /// C = BΦ: the constrained rows of Φ (m × n).
    pub(super) c: Mat<f64>,
    /// Cᵀ (n × m): column i is row i of C, contiguous, for the values of single vertices.
    pub(super) c_rows: Mat<f64>,
    /// ‖(C_H)_i‖₂ per screening level and constrained vertex: the remainder's weights, H being
    /// the modes from the level's mode count on.
    pub(super) high_row_norms: Vec<Vec<f64>>,
    /// The mode counts of the screening levels that this basis has: [`SCREENING_LEVELS`] cut
    /// at n.
    pub(super) levels: Vec<usize>,
    /// The mode counts of the stand-in levels that this basis has: none up to
    /// [`DENSE_LIMIT`](crate::modes::DENSE_LIMIT) modes, whose values keep their bits, otherwise
    /// [`STAND_IN_LEVELS`] past the last screening level and short of n.
    pub(super) stand_in_levels: Vec<usize>,
    /// With stand-in levels: the mode count to which a stand-in that the contact solve reaches
    /// at a free vertex is summed before its full row ([`REACHED_LEVEL`] when short of n).
    pub(super) reached_level: Option<usize>,
    /// With stand-in levels: the blockwise bound on the part of a value past a level, which is
    /// every stand-in's slack.
    pub(super) remainder: Option<BlockRemainder>,
    /// ‖C_i‖₂ per constrained vertex: scales the round-off margin of the screening.
    pub(super) row_norms: Vec<f64>,
    /// The norm in which the reach of a proof is measured.
    pub(super) reach_metric: ReachMetric,
    /// Φᵀ f for the unit load, Φᵀ m₁ for the mass times the translation, and the output
    /// functionals (rows of E Φ).
    pub(super) load: Vec<f64>,
    pub(super) translation_mass: Vec<f64>,
    pub(super) outputs: [Vec<f64>; OUTPUT_POINTS],
}

/// The free-dof data of the plate that the modal backend projects onto its modes.
pub(in crate::scheme) struct FreeDofData<'a> {
    /// The constraint rows B over the free dofs.
    pub contact: &'a ContactRows,
    /// f_f for a 1 Pa pressure.
    pub load: &'a [f64],
    /// m₁ = (M𝟙)_f.
    pub translation_mass: &'a [f64],
    /// The output functionals over the free dofs.
    pub outputs: &'a [Vec<f64>; OUTPUT_POINTS],
    /// The damping (Rayleigh and modal ratio).
    pub damping: &'a DampingCoefficients,
}

impl ModalData {
    /// Precomputes the modal data from the eigenpairs and the free-dof data of the system.
    pub(in crate::scheme) fn new(modes: Modes, time_step: f64, free: FreeDofData<'_>) -> ModalData {
        let n = modes.omega_squared.len();
        let m = free.contact.len();
        let shapes = modes.shapes;
        let c = shapes.rows_of(free.contact);
        let large = n > crate::modes::DENSE_LIMIT;
        let step = ModalSystem::new(&modes.omega_squared, free.damping, time_step, &c, !large);
        let start = (!free.damping.is_zero()).then(|| {
            ModalSystem::new(
                &modes.omega_squared,
                &DampingCoefficients::default(),
                time_step,
                &c,
                !large,
            )
        });
        // Φᵀv.
        let project = |v: &[f64]| shapes.project(v);
        // ‖C_i‖ over the modes from `from` on.
        let row_norm = |i: usize, from: usize| c.row(i).subcols(from, n - from).norm_l2();
        let mut levels: Vec<usize> = SCREENING_LEVELS.iter().map(|&l| l.min(n)).collect();
        levels.dedup();
        let high_row_norms = levels
            .iter()
            .map(|&from| (0..m).map(|i| row_norm(i, from)).collect())
            .collect();
        let row_norms: Vec<f64> = (0..m).map(|i| row_norm(i, 0)).collect();
        let reach_metric = ReachMetric::new(
            &modes.omega_squared,
            REACH_WEIGHT_POWER,
            (0..m).map(|i| c.row(i).iter().copied().collect()).collect(),
        );
        let load = project(free.load);
        let translation_mass = project(free.translation_mass);
        let outputs = free.outputs.each_ref().map(|row| project(row));
        let mut data = ModalData {
            step,
            start,
            damping: modes
                .omega_squared
                .iter()
                .map(|&w2| free.damping.modal_coefficient(w2))
                .collect(),
            omega_squared: modes.omega_squared,
            shapes,
            c_rows: c.transpose().to_owned(),
            c,
            high_row_norms,
            levels,
            stand_in_levels: Vec::new(),
            reached_level: None,
            remainder: None,
            reach_metric,
            row_norms,
            load,
            translation_mass,
            outputs,
        };
        if large {
            data.set_stand_in_levels(&STAND_IN_LEVELS, REACHED_LEVEL);
        }
        data
    }

    /// Sets the stand-in levels to the mode counts of `levels` past the last screening level and
    /// short of n (increasing), the level of a reached stand-in to `reached` (when past them and
    /// short of n), and the blockwise remainder bound from the last screening level on with
    /// boundaries at all of them.
    pub(super) fn set_stand_in_levels(&mut self, levels: &[usize], reached: usize) {
        let n = self.c.ncols();
        let last_level = self.levels[self.levels.len() - 1];
        self.stand_in_levels = levels
            .iter()
            .copied()
            .filter(|&l| l > last_level && l < n)
            .collect();
        let deepest = self.stand_in_levels.last().copied().unwrap_or(last_level);
        self.reached_level = (reached > deepest && reached < n).then_some(reached);
        let mut depths = self.stand_in_levels.clone();
        depths.extend(self.reached_level);
        self.remainder = Some(BlockRemainder::new(&self.c, last_level, &depths));
    }

    /// The system of the start step or of the others.
    pub(super) fn system(&self, start: bool) -> &ModalSystem {
        match (&self.start, start) {
            (Some(system), true) => system,
            _ => &self.step,
        }
    }

    /// The recurrence of the start step or of the others, for the fused pass.
    pub(super) fn recurrence(&self, start: bool) -> Recurrence<'_> {
        let system = self.system(start);
        Recurrence {
            inverse_d: &system.inverse_d,
            lagged: &system.lagged,
            damped: system.damped,
            load: &self.load,
            translation_mass: &self.translation_mass,
            damping: &self.damping,
            reach_weights: &self.reach_metric.weights,
        }
    }
}

/// The numbers of low modes whose contribution the screening evaluates exactly, level by level
/// (see the module docs of [`super`]).
pub(super) const SCREENING_LEVELS: [usize; 4] = [4, 8, 16, 32];

/// The reach measures D in ‖x‖_w with w_k = ω_k^p for this p ([`ReachMetric`]). p = 1 keeps
/// the most steps covered per proof on the paper's meshes at Δt = 1e-6 s: over 0.5 s of the damped
/// forced 35 Hz scene on Argyris 10 × 7, 85 557 proofs for p = 0 (the Euclidean norm, which lets
/// the high modes' share of the motion count at full weight at every vertex), 23 402 for p = 2
/// (the energy norm, which lets the high modes' tiny amplitudes count at ω_max), 7 945 for p = 1.
const REACH_WEIGHT_POWER: f64 = 1.0;

/// The numbers of low modes over which a large basis sums, level by level, the value of a
/// vertex that the screening's last level leaves unproven, for its stand-in
/// ([`StandIns::values`](super::stand_ins::StandIns::values)). On Argyris 28 × 20 (5 257 modes,
/// 588 vertices) the forced 35 Hz scene's steps with a QP left ~200 vertices to exact values:
/// 128 modes prove about half of those inside, 512 a tenth more, 1 024 and 2 048 almost none more
/// (the rest lie past a bound in the prediction; measured with one Cauchy–Schwarz product as the
/// slack, before the blockwise bound).
pub(super) const STAND_IN_LEVELS: [usize; 2] = [128, 512];

/// The number of low modes over which a large basis sums a stand-in that the contact solve's
/// answer reaches at a free vertex (or that lies within its slack of a bound when nothing else
/// needs a contact solve), before reading its full row: on Argyris 28 × 20 such a stand-in is
/// settled there in two cases of three, and a step with a QP reads full rows at 42 vertices
/// instead of 62 (50 when summed to 1 024 modes).
pub(super) const REACHED_LEVEL: usize = 2048;

/// Number of low modes of the last screening level.
pub(super) const SCREENING_MODES: usize = SCREENING_LEVELS[SCREENING_LEVELS.len() - 1];

/// The field maps of the modal backend ([`FieldMaps`](crate::scheme::backend::FieldMaps) documents
/// each): every one reads the data only.
impl ModalData {
    /// n, the number of modes.
    pub(in crate::scheme) fn dimension(&self) -> usize {
        self.omega_squared.len()
    }

    pub(in crate::scheme) fn field_sums(&self, field: &[f64]) -> FieldSums {
        let low = SCREENING_MODES.min(field.len());
        FieldSums {
            norm_squared: sum_of_squares(&field[..low]) + sum_of_squares(&field[low..]),
            translation: lane_dot(&self.translation_mass, field),
            damping: None,
        }
    }

    pub(in crate::scheme) fn load_projection(&self, field: &[f64]) -> f64 {
        dot(&self.load, field)
    }

    /// Σ_i μ_i C_i(x − y), row by row over the non-zero μ_i.
    pub(in crate::scheme) fn multiplier_work(
        &self,
        next: &[f64],
        previous: &[f64],
        multipliers: &[f64],
    ) -> f64 {
        let c = &self.c;
        let difference = Col::from_fn(next.len(), |k| next[k] - previous[k]);
        multipliers
            .iter()
            .enumerate()
            .filter(|(_, &mu)| mu != 0.0)
            .map(|(i, &mu)| mu * (c.row(i) * &difference))
            .sum()
    }

    /// Φᵀ M_ff Φ = I and Φᵀ K_ff Φ = Ω², so ‖q‖ is the M-norm of w and wᵀKw ≤ ω²_max‖q‖².
    pub(in crate::scheme) fn magnitude_scale(&self, time_step: f64) -> f64 {
        let omega_squared_max = self.omega_squared.iter().fold(0.0, |a: f64, &b| a.max(b));
        let norm = |v: &[f64]| sum_of_squares(v).sqrt();
        let output_norm = self.outputs.iter().map(|r| norm(r)).fold(0.0, f64::max);
        [
            4.0 / (time_step * time_step),
            4.0 * norm(&self.translation_mass) / (time_step * time_step),
            2.0 * norm(&self.translation_mass) / time_step,
            omega_squared_max,
            norm(&self.load),
            output_norm,
        ]
        .into_iter()
        .fold(1.0, f64::max)
    }

    /// y = C q (the bound check: the floor cost of every exact method).
    pub(in crate::scheme) fn constrained_values(&self, q: &[f64], out: &mut [f64]) {
        let m = out.len();
        let q = faer::ColRef::from_slice(q);
        let mut y = faer::ColMut::from_slice_mut(out);
        debug_assert_eq!(y.nrows(), m);
        matmul(
            y.as_mut(),
            Accum::Replace,
            self.c.as_ref(),
            q,
            1.0,
            Par::Seq,
        );
    }

    /// (C q)_i alone, one dot over the modes with row i of C: what an impact law reads at the few
    /// vertices in contact (equal to entry i of [`ModalData::constrained_values`] to round-off).
    pub(in crate::scheme) fn constrained_value(&self, q: &[f64], i: usize) -> f64 {
        self.c_rows.col(i).transpose() * ColRef::from_slice(q)
    }

    /// w_f = Φ q.
    pub(in crate::scheme) fn to_free_dofs(&self, field: &[f64]) -> Vec<f64> {
        self.shapes.apply(field)
    }

    /// q = Φᵀ M_ff w.
    pub(in crate::scheme) fn field_of_free_dofs(&self, w: &[f64], field: &mut [f64]) {
        field.copy_from_slice(&self.shapes.coordinates(w));
    }

    pub(in crate::scheme) fn energy(
        &self,
        previous: &[f64],
        current: &[f64],
        time_step: f64,
    ) -> EnergyPieces {
        let mut pieces = EnergyPieces::default();
        for k in 0..current.len() {
            let (q1, q0) = (current[k], previous[k]);
            let v = (q1 - q0) / time_step;
            pieces.velocity_mass_velocity += v * v;
            pieces.translation_mass_velocity += self.translation_mass[k] * v;
            pieces.stiffness_current += self.omega_squared[k] * q1 * q1;
            pieces.stiffness_previous += self.omega_squared[k] * q0 * q0;
            pieces.load_current += self.load[k] * q1;
            pieces.load_previous += self.load[k] * q0;
        }
        pieces
    }

    /// Σ c_k (x_k − y_k)².
    pub(in crate::scheme) fn damping_quadratic(&self, x: &[f64], y: &[f64]) -> f64 {
        self.damping
            .iter()
            .zip(x.iter().zip(y))
            .map(|(&c, (a, b))| c * (a - b) * (a - b))
            .sum()
    }

    pub(in crate::scheme) fn output_values(&self, field: &[f64]) -> [f64; OUTPUT_POINTS] {
        self.outputs.each_ref().map(|row| dot(row, field))
    }
}
