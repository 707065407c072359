//! The contact-free modal step as one pass over the modes.
//!
//! A step advances every mode by its scalar recurrence (module docs of [`super`]) and needs three
//! sums over the new coordinates: m̂ᵀq_{n+1} (m̂ = Φᵀm₁, the base force), Σ c_k (q_{n+1} −
//! q_{n−1})_k² (the damping loss) and ‖q_{n+1} − q_s‖² against the screening's reference q_s
//! ([`super::reach`]). Formed in separate loops they read the coordinates four times; here one
//! loop reads each array once, a SIMD register of modes at a time (four on x86_64 with AVX2), under
//! [`pulp::Arch::dispatch`], which compiles it for the widest instruction set the processor
//! offers; the modes past the last whole register go through one more register, zero-padded
//! (a padded mode has q = 0 and adds exactly 0 to every sum). Each mode's new coordinate is
//! computed by the same operations in the same order as a scalar loop would (separate products
//! and sums, never fused into one rounding), so q_{n+1} is the same to the bit on any processor;
//! the sums are grouped by register lane and accumulate with fused multiply-adds where the
//! processor has them, so their last bits depend on the instruction set.

/// The per-mode weights of the step's recurrence
/// q_{n+1} = (w_c q_n + load·f̂_k + translation·m̂_k)/d_k − w_p·λ_k·q_{n−1}.
pub(super) struct Recurrence<'a> {
    /// 1/d_k.
    pub inverse_d: &'a [f64],
    /// λ_k = (d_k − Δt c_k)/d_k, the weight of q_{n−1}; read only when damped.
    pub lagged: &'a [f64],
    /// Whether λ_k is read (without damping it is exactly 1).
    pub damped: bool,
    /// f̂ = Φᵀf, the unit load.
    pub load: &'a [f64],
    /// m̂ = Φᵀm₁, the mass times the rigid translation.
    pub translation_mass: &'a [f64],
    /// c_k = α + βω_k² + 2ζ_mω_k, read only when damped.
    pub damping: &'a [f64],
    /// w_k, the weights of the reach's norm ‖x‖_w² = Σ w_k x_k².
    pub reach_weights: &'a [f64],
}

/// The sums of one pass, each over the new coordinates q_{n+1}.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct PassSums {
    /// m̂ᵀq_{n+1}, bit for bit as [`lane_dot`] gives it.
    pub translation: f64,
    /// Σ c_k (q_{n+1} − q_{n−1})_k² (0 without damping).
    pub damping: f64,
    /// ‖q_{n+1} − q_s‖_w².
    pub moved_squared: f64,
}

/// The step's weights: (w_c, w_p, load, translation) as in [`Recurrence`].
#[derive(Clone, Copy, Debug)]
pub(super) struct Weights {
    pub current: f64,
    pub previous: f64,
    pub load: f64,
    pub translation: f64,
}

/// Writes q_{n+1} into `next` and returns the pass's sums, `reference` being q_s.
pub(super) fn advance(
    recurrence: &Recurrence,
    weights: Weights,
    previous: &[f64],
    current: &[f64],
    reference: &[f64],
    next: &mut [f64],
) -> PassSums {
    let n = next.len();
    let r = recurrence;
    for v in [
        r.inverse_d,
        r.lagged,
        r.load,
        r.translation_mass,
        r.damping,
        previous,
        current,
        reference,
    ] {
        assert_eq!(v.len(), n, "every array of the pass has one entry per mode");
    }
    pulp::Arch::new().dispatch(Pass {
        recurrence,
        weights,
        previous,
        current,
        reference,
        next,
    })
}

/// aᵀb summed by register lane as [`advance`] sums its `translation`: the same bits for the same
/// vectors.
pub(super) fn lane_dot(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len(), "a dot product of vectors of one length");
    pulp::Arch::new().dispatch(LaneDot { a, b })
}

/// [`lane_dot`] as an operation for [`pulp::Arch::dispatch`].
struct LaneDot<'a> {
    a: &'a [f64],
    b: &'a [f64],
}

impl pulp::WithSimd for LaneDot<'_> {
    type Output = f64;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, simd: S) -> f64 {
        let (a, a_tail) = S::as_simd_f64s(self.a);
        let (b, b_tail) = S::as_simd_f64s(self.b);
        let mut sum = simd.splat_f64s(0.0);
        for (&a, &b) in a.iter().zip(b) {
            sum = simd.mul_add_e_f64s(a, b, sum);
        }
        let (a, b) = (
            simd.partial_load_f64s(a_tail),
            simd.partial_load_f64s(b_tail),
        );
        sum = simd.mul_add_e_f64s(a, b, sum);
        simd.reduce_sum_f64s(sum)
    }
}

/// The pass as an operation that [`pulp::Arch::dispatch`] compiles once per instruction set.
struct Pass<'a, 'r> {
    recurrence: &'a Recurrence<'r>,
    weights: Weights,
    previous: &'a [f64],
    current: &'a [f64],
    reference: &'a [f64],
    next: &'a mut [f64],
}

impl pulp::WithSimd for Pass<'_, '_> {
    type Output = PassSums;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, simd: S) -> PassSums {
        // Every step but the start has w_c = 2 and w_p = 1, which the loop then multiplies by as
        // constants (the same bits), and most scenes have no pressure.
        let w = self.weights;
        let regular = w.current == 2.0 && w.previous == 1.0;
        match (regular, self.recurrence.damped, w.load != 0.0) {
            (true, true, false) => self.run::<S, true, true, false>(simd),
            (true, false, false) => self.run::<S, true, false, false>(simd),
            (true, true, true) => self.run::<S, true, true, true>(simd),
            (true, false, true) => self.run::<S, true, false, true>(simd),
            (false, true, _) => self.run::<S, false, true, true>(simd),
            (false, false, _) => self.run::<S, false, false, true>(simd),
        }
    }
}

/// One register of every input array.
#[derive(Clone, Copy)]
struct Lanes<V> {
    inverse_d: V,
    lagged: V,
    load: V,
    mass: V,
    damping: V,
    previous: V,
    current: V,
    reference: V,
    reach_weight: V,
}

/// The running sums, one register each.
#[derive(Clone, Copy)]
struct Sums<V> {
    translation: V,
    damping: V,
    moved: V,
}

/// The step's weights in every lane.
struct Splat<V> {
    two: V,
    current: V,
    previous: V,
    load: V,
    translation: V,
}

/// q_{n+1} of one register of modes by the recurrence, with its terms added to the sums. A
/// function, not a closure, so that it is compiled with the dispatch's instruction set.
#[inline(always)]
fn register<S: pulp::Simd, const REGULAR: bool, const DAMPED: bool, const LOADED: bool>(
    simd: S,
    w: &Splat<S::f64s>,
    x: Lanes<S::f64s>,
    sums: &mut Sums<S::f64s>,
) -> S::f64s {
    let current_term = if REGULAR {
        simd.mul_f64s(w.two, x.current)
    } else {
        simd.mul_f64s(w.current, x.current)
    };
    let forced = if LOADED {
        simd.add_f64s(
            simd.add_f64s(current_term, simd.mul_f64s(w.load, x.load)),
            simd.mul_f64s(w.translation, x.mass),
        )
    } else {
        simd.add_f64s(current_term, simd.mul_f64s(w.translation, x.mass))
    };
    let lag = if REGULAR {
        x.lagged
    } else {
        simd.mul_f64s(w.previous, x.lagged)
    };
    let delayed = if DAMPED || !REGULAR {
        simd.mul_f64s(lag, x.previous)
    } else {
        x.previous
    };
    let q = simd.sub_f64s(simd.mul_f64s(forced, x.inverse_d), delayed);
    sums.translation = simd.mul_add_e_f64s(x.mass, q, sums.translation);
    if DAMPED {
        let stroke = simd.sub_f64s(q, x.previous);
        let weighted = simd.mul_f64s(x.damping, stroke);
        sums.damping = simd.mul_add_e_f64s(weighted, stroke, sums.damping);
    }
    let shift = simd.sub_f64s(q, x.reference);
    let weighted_shift = simd.mul_f64s(x.reach_weight, shift);
    sums.moved = simd.mul_add_e_f64s(weighted_shift, shift, sums.moved);
    q
}

impl Pass<'_, '_> {
    /// The loop, specialised on the weights being (2, 1), on damping and on a load.
    #[inline(always)]
    fn run<S: pulp::Simd, const REGULAR: bool, const DAMPED: bool, const LOADED: bool>(
        self,
        simd: S,
    ) -> PassSums {
        let r = self.recurrence;
        let w = self.weights;
        let (inverse_d, inverse_d_tail) = S::as_simd_f64s(r.inverse_d);
        let (lagged, lagged_tail) = S::as_simd_f64s(r.lagged);
        let (load, load_tail) = S::as_simd_f64s(r.load);
        let (mass, mass_tail) = S::as_simd_f64s(r.translation_mass);
        let (damping, damping_tail) = S::as_simd_f64s(r.damping);
        let (previous, previous_tail) = S::as_simd_f64s(self.previous);
        let (current, current_tail) = S::as_simd_f64s(self.current);
        let (reference, reference_tail) = S::as_simd_f64s(self.reference);
        let (reach_weight, reach_weight_tail) = S::as_simd_f64s(r.reach_weights);
        let (next, next_tail) = S::as_mut_simd_f64s(self.next);
        let [two, w_current, w_previous, w_load, w_translation] =
            [2.0, w.current, w.previous, w.load, w.translation].map(|x| simd.splat_f64s(x));
        let zero = simd.splat_f64s(0.0);
        let weights = Splat {
            two,
            current: w_current,
            previous: w_previous,
            load: w_load,
            translation: w_translation,
        };
        let mut sums = Sums {
            translation: zero,
            damping: zero,
            moved: zero,
        };
        for (k, q) in next.iter_mut().enumerate() {
            let x = Lanes {
                inverse_d: inverse_d[k],
                lagged: if DAMPED || !REGULAR { lagged[k] } else { zero },
                load: if LOADED { load[k] } else { zero },
                mass: mass[k],
                damping: if DAMPED { damping[k] } else { zero },
                previous: previous[k],
                current: current[k],
                reference: reference[k],
                reach_weight: reach_weight[k],
            };
            *q = register::<S, REGULAR, DAMPED, LOADED>(simd, &weights, x, &mut sums);
        }
        // The modes past the last whole register, zero-padded.
        let x = Lanes {
            inverse_d: simd.partial_load_f64s(inverse_d_tail),
            lagged: simd.partial_load_f64s(lagged_tail),
            load: simd.partial_load_f64s(load_tail),
            mass: simd.partial_load_f64s(mass_tail),
            damping: simd.partial_load_f64s(damping_tail),
            previous: simd.partial_load_f64s(previous_tail),
            current: simd.partial_load_f64s(current_tail),
            reference: simd.partial_load_f64s(reference_tail),
            reach_weight: simd.partial_load_f64s(reach_weight_tail),
        };
        let q = register::<S, REGULAR, DAMPED, LOADED>(simd, &weights, x, &mut sums);
        simd.partial_store_f64s(next_tail, q);
        PassSums {
            translation: simd.reduce_sum_f64s(sums.translation),
            damping: simd.reduce_sum_f64s(sums.damping),
            moved_squared: simd.reduce_sum_f64s(sums.moved),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The pass against the recurrence and the sums written out mode by mode: q_{n+1} to the bit
    /// (the same operations per mode), the sums to round-off (n ε of their terms' magnitude), and
    /// the translation bit for bit equal to `lane_dot` of the result; over lengths that exercise
    /// the remainder loop and every specialisation.
    #[test]
    fn pass_matches_the_mode_by_mode_recurrence() {
        for n in [1, 7, 8, 9, 61, 708] {
            let wave = |seed: f64| -> Vec<f64> {
                (0..n)
                    .map(|k| ((k as f64 + 1.0) * seed).sin() / (1.0 + k as f64))
                    .collect()
            };
            let inverse_d: Vec<f64> = wave(0.37).iter().map(|x| 1.0 / (1.5 + x)).collect();
            let lagged: Vec<f64> = wave(0.91).iter().map(|x| 1.0 - 0.01 * x.abs()).collect();
            let (load, mass, previous, current, reference) =
                (wave(1.3), wave(2.1), wave(0.7), wave(0.73), wave(0.71));
            let damping: Vec<f64> = wave(3.3).iter().map(|x| x.abs() * 10.0).collect();
            let reach_weights: Vec<f64> = (0..n).map(|k| 1.0 + k as f64).collect();
            for damped in [false, true] {
                let recurrence = Recurrence {
                    inverse_d: &inverse_d,
                    lagged: &lagged,
                    damped,
                    load: &load,
                    translation_mass: &mass,
                    damping: &damping,
                    reach_weights: &reach_weights,
                };
                for (current_weight, previous_weight, load_weight) in [
                    (2.0, 1.0, 0.0),
                    (2.0, 1.0, 0.3),
                    (1.0, 0.0, 0.0),
                    (1.0, 0.0, 0.2),
                ] {
                    let weights = Weights {
                        current: current_weight,
                        previous: previous_weight,
                        load: load_weight,
                        translation: -0.7,
                    };
                    let mut next = vec![0.0; n];
                    let sums = advance(
                        &recurrence,
                        weights,
                        &previous,
                        &current,
                        &reference,
                        &mut next,
                    );
                    let (mut translation, mut dissipation, mut moved) = (0.0, 0.0, 0.0);
                    for k in 0..n {
                        let lag = if damped { lagged[k] } else { 1.0 };
                        let q = (current_weight * current[k]
                            + load_weight * load[k]
                            + weights.translation * mass[k])
                            * inverse_d[k]
                            - previous_weight * lag * previous[k];
                        assert_eq!(next[k].to_bits(), q.to_bits(), "n {n} mode {k}");
                        translation += mass[k] * q;
                        if damped {
                            dissipation += damping[k] * (q - previous[k]).powi(2);
                        }
                        moved += reach_weights[k] * (q - reference[k]).powi(2);
                    }
                    let close = |a: f64, b: f64, scale: f64| {
                        assert!((a - b).abs() <= 1e-14 * scale, "n {n}: {a} vs {b}")
                    };
                    close(sums.translation, translation, n as f64);
                    close(sums.damping, dissipation, 10.0 * n as f64);
                    close(sums.moved_squared, moved, (n * n) as f64);
                    assert_eq!(sums.translation.to_bits(), lane_dot(&mass, &next).to_bits());
                }
            }
        }
    }
}
