//! The contact-free part of the scheme in the M-orthonormal eigenbasis of the clamped plate.
//!
//! With w_f = Φ q, Φᵀ M_ff Φ = I and Φᵀ K_ff Φ = Ω², the β = ½ scheme (SPEC §3) decouples into one
//! scalar recurrence per mode k, d_k = 1 + ½Δt²ω_k²:
//!   d_k q_{n+1} = 2 q_n − d_k q_{n−1} + (Φᵀ r)_k   (start step: d_k q_1 = q_0 + (Φᵀ r)_k),
//! where r is the free-dof forcing of the step. All modes are kept: this is the same scheme, not a
//! model reduction. A contact-free step costs O(n) plus the bound check y = C q with C = BΦ
//! (m × n dense), and the Delassus operator W = B A⁻¹ Bᵀ = C D⁻¹ Cᵀ is precomputed.

use super::{Propagator, StepForcing};
use crate::modes::Modes;
use faer::linalg::matmul::matmul;
use faer::{Accum, Col, Mat, Par};
use std::sync::Arc;

/// Immutable data shared by every modal stepper of one scene.
#[derive(Debug)]
pub struct ModalData {
    /// d_k = 1 + ½Δt²ω_k².
    d: Vec<f64>,
    /// ω_k².
    omega_squared: Vec<f64>,
    /// Φ (free dofs × modes), to map back to physical dofs.
    shapes: Mat<f64>,
    /// C = BΦ: the constrained rows of Φ (m × n).
    c: Mat<f64>,
    /// Cᵀ scaled by D⁻¹ row-wise, stored as n × m: column i is D⁻¹ Cᵀ e_i = Φᵀ A⁻¹ Bᵀ e_i.
    c_t_scaled: Mat<f64>,
    /// W = C D⁻¹ Cᵀ (m × m).
    delassus: Mat<f64>,
    /// Φᵀ f for the unit load, for the free part of the mass times the translation (Φᵀ m₁), and
    /// the output functionals (rows of E Φ).
    load: Vec<f64>,
    base: Vec<f64>,
    outputs: [Vec<f64>; 3],
    /// M_ff and Φ for mapping full vectors to modal coordinates: q = Φᵀ M_ff w.
    mass_free: Mat<f64>,
}

impl ModalData {
    /// Precomputes the modal data from the eigenpairs and the free-dof vectors of the system.
    pub fn new(
        modes: Modes,
        time_step: f64,
        constrained: &[usize],
        load_free: &[f64],
        base_free: &[f64],
        outputs_free: [Vec<f64>; 3],
        mass_free: Mat<f64>,
    ) -> ModalData {
        let n = modes.omega_squared.len();
        let m = constrained.len();
        let d: Vec<f64> = modes
            .omega_squared
            .iter()
            .map(|&w2| 1.0 + 0.5 * time_step * time_step * w2)
            .collect();
        let shapes = modes.shapes;
        let c = Mat::from_fn(m, n, |i, k| shapes[(constrained[i], k)]);
        let c_t_scaled = Mat::from_fn(n, m, |k, i| c[(i, k)] / d[k]);
        let mut delassus = Mat::zeros(m, m);
        matmul(
            delassus.as_mut(),
            Accum::Replace,
            c.as_ref(),
            c_t_scaled.as_ref(),
            1.0,
            Par::Seq,
        );
        let project = |v: &[f64]| -> Vec<f64> {
            (0..n)
                .map(|k| (0..v.len()).map(|i| shapes[(i, k)] * v[i]).sum())
                .collect()
        };
        let load = project(load_free);
        let base = project(base_free);
        let outputs = outputs_free.map(|row| project(&row));
        ModalData {
            d,
            omega_squared: modes.omega_squared,
            shapes,
            c,
            c_t_scaled,
            delassus,
            load,
            base,
            outputs,
            mass_free,
        }
    }
}

/// Modal state: q_{n−1}, q_n and the prediction q_{n+1}.
#[derive(Clone, Debug)]
pub struct ModalPropagator {
    data: Arc<ModalData>,
    previous: Vec<f64>,
    current: Vec<f64>,
    next: Vec<f64>,
}

impl ModalPropagator {
    /// A propagator at rest in the relative field `w0` (free dofs).
    pub fn new(data: Arc<ModalData>, w0: &[f64]) -> ModalPropagator {
        let q0 = to_modal(&data, w0);
        ModalPropagator {
            previous: q0.clone(),
            current: q0.clone(),
            next: q0,
            data,
        }
    }
}

/// q = Φᵀ M_ff w.
fn to_modal(data: &ModalData, w: &[f64]) -> Vec<f64> {
    let n = w.len();
    let w = Col::from_fn(n, |i| w[i]);
    let mw = &data.mass_free * &w;
    let q = data.shapes.transpose() * &mw;
    (0..n).map(|k| q[k]).collect()
}

impl Propagator for ModalPropagator {
    fn predict(&mut self, forcing: &StepForcing, constrained_out: &mut [f64]) {
        let data = &*self.data;
        let (load, base) = (forcing.load, forcing.base);
        if forcing.start {
            for k in 0..self.next.len() {
                let r = load * data.load[k] + base * data.base[k];
                self.next[k] = (self.current[k] + r) / data.d[k];
            }
        } else {
            for k in 0..self.next.len() {
                let r = load * data.load[k] + base * data.base[k];
                self.next[k] = (2.0 * self.current[k] + r) / data.d[k] - self.previous[k];
            }
        }
        constrained_values(data, &self.next, constrained_out);
    }

    fn delassus_column(&mut self, j: usize) -> &[f64] {
        self.data
            .delassus
            .col(j)
            .try_as_col_major()
            .expect("an owned matrix is column-major")
            .as_slice()
    }

    fn correct(&mut self, active: &[usize], multipliers: &[f64]) {
        for &i in active {
            let mu = multipliers[i];
            let column = self.data.c_t_scaled.col(i);
            for (q, &c) in self.next.iter_mut().zip(column.iter()) {
                *q += mu * c;
            }
        }
    }

    fn next_constrained(&self, out: &mut [f64]) {
        constrained_values(&self.data, &self.next, out);
    }

    fn free_field(&self, which: super::Level) -> Vec<f64> {
        let q = match which {
            super::Level::Previous => &self.previous,
            super::Level::Current => &self.current,
            super::Level::Next => &self.next,
        };
        let q = Col::from_fn(q.len(), |k| q[k]);
        let w = &self.data.shapes * &q;
        w.iter().copied().collect()
    }

    fn set_next(&mut self, w: &[f64]) {
        self.next = to_modal(&self.data, w);
    }

    fn accept(&mut self) {
        std::mem::swap(&mut self.previous, &mut self.current);
        std::mem::swap(&mut self.current, &mut self.next);
    }

    fn energy(&self, time_step: f64) -> super::EnergyPieces {
        let data = &*self.data;
        let mut pieces = super::EnergyPieces::default();
        for k in 0..self.current.len() {
            let (q1, q0) = (self.current[k], self.previous[k]);
            let v = (q1 - q0) / time_step;
            pieces.velocity_mass_velocity += v * v;
            pieces.translation_mass_velocity += data.base[k] * v;
            pieces.stiffness_current += data.omega_squared[k] * q1 * q1;
            pieces.stiffness_previous += data.omega_squared[k] * q0 * q0;
            pieces.load_current += data.load[k] * q1;
            pieces.load_previous += data.load[k] * q0;
        }
        pieces
    }

    fn output_values(&self) -> [f64; 3] {
        self.data
            .outputs
            .each_ref()
            .map(|row| row.iter().zip(&self.current).map(|(a, b)| a * b).sum())
    }

    fn state(&self) -> (Vec<f64>, Vec<f64>) {
        (self.previous.clone(), self.current.clone())
    }

    fn set_state(&mut self, previous: Vec<f64>, current: Vec<f64>) {
        self.next = current.clone();
        self.previous = previous;
        self.current = current;
    }

    fn dimension(&self) -> usize {
        self.current.len()
    }
}

/// y = C q (the bound check: the floor cost of every exact method).
fn constrained_values(data: &ModalData, q: &[f64], out: &mut [f64]) {
    let m = out.len();
    let q = faer::ColRef::from_slice(q);
    let mut y = faer::ColMut::from_slice_mut(out);
    debug_assert_eq!(y.nrows(), m);
    matmul(
        y.as_mut(),
        Accum::Replace,
        data.c.as_ref(),
        q,
        1.0,
        Par::Seq,
    );
}
