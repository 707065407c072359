//! The steady-state recorder: what each window (or forcing period) of a run accumulates step by
//! step, which window each step belongs to, and the loop that steps a run and records it.

use plate_impact::scheme::{Outputs, StepReport, Stepper};

/// Outputs (corner, energy), which cost an evaluation, are sampled at this interval, or every
/// step when Δt is larger (s).
pub const SAMPLE_INTERVAL: f64 = 1e-5;

/// Every `interval` (s) in steps of `dt`: round(interval/Δt), at least one step.
pub fn stride(interval: f64, dt: f64) -> usize {
    ((interval / dt).round() as usize).max(1)
}

/// What a window of a run accumulates: sums over its steps of what each step reports, and over
/// its samples of the outputs. The time averages of [`crate::windows::Quantity`] are ratios of
/// these sums.
#[derive(Clone, Copy, Debug, Default)]
pub struct Tally {
    /// Forcing periods the window spans: the denominator of the per-period quantities.
    pub periods: usize,
    /// Steps, impacts (`StepReport::impact`: the contact set went from empty to non-empty), the
    /// energy removed at the obstacles Σ `EnergyFlows::contact_loss` (J), Σ |F| and Σ F² of the
    /// force on the base `StepReport::base_force` (N, N²).
    pub steps: usize,
    pub impacts: usize,
    pub contact_loss: f64,
    pub base_force_abs: f64,
    pub base_force_squared: f64,
    /// Samples of the outputs, Σ `energy.total` (J), Σ u² of the free corner u(Lx, 0) (m²) and
    /// the largest |u| (m).
    pub samples: usize,
    pub energy: f64,
    pub corner_squared: f64,
    pub corner_peak: f64,
}

impl Tally {
    /// An empty window of `periods` forcing periods.
    pub fn spanning(periods: usize) -> Tally {
        Tally {
            periods,
            ..Tally::default()
        }
    }

    /// Adds a step: one step, its impact, its contact loss, |F| and F² of its base force.
    pub fn add_step(&mut self, report: &StepReport) {
        self.steps += 1;
        self.impacts += usize::from(report.impact);
        self.contact_loss += report.flows.contact_loss;
        self.base_force_abs += report.base_force.abs();
        self.base_force_squared += report.base_force * report.base_force;
    }

    /// Adds a sample of the outputs: `energy.total`, u² and |u| of the free corner.
    pub fn add_sample(&mut self, outputs: &Outputs) {
        self.samples += 1;
        self.energy += outputs.energy_total;
        self.corner_squared += outputs.corner1 * outputs.corner1;
        self.corner_peak = self.corner_peak.max(outputs.corner1.abs());
    }
}

impl AsRef<Tally> for Tally {
    fn as_ref(&self) -> &Tally {
        self
    }
}

impl AsMut<Tally> for Tally {
    fn as_mut(&mut self) -> &mut Tally {
        self
    }
}

/// Which window each step n ≥ 1 of a run belongs to.
#[derive(Clone, Debug)]
pub enum Windows {
    /// Windows of steps (b_j, b_{j+1}] between the bounds b_0 < b_1 < … < b_K: the K windows of a
    /// steady state after a transient of b_0 steps; the steps outside them belong to none.
    Bounds(Vec<usize>),
    /// The forcing periods from t = 0: step n (the interval ((n − 1)Δt, nΔt]) belongs to period
    /// ⌊(n − ½)Δt·f⌋, its midpoint's, the last of `count` periods taking any step beyond.
    Periods {
        dt: f64,
        frequency: f64,
        count: usize,
    },
}

impl Windows {
    /// The window of step `n`, if any.
    pub fn of(&self, n: usize) -> Option<usize> {
        match self {
            Windows::Bounds(bounds) => {
                let j = bounds.partition_point(|&b| b < n);
                (j >= 1 && j < bounds.len()).then(|| j - 1)
            }
            Windows::Periods {
                dt,
                frequency,
                count,
            } => Some((((n as f64 - 0.5) * dt * frequency) as usize).min(count - 1)),
        }
    }
}

/// Steps a run and records its windows.
pub struct Recorder {
    /// Which window each step belongs to.
    pub windows: Windows,
    /// The run's steps n = 1 … `steps`.
    pub steps: usize,
    /// Outputs are sampled at the steps n that are multiples of this ([`stride`]).
    pub stride: usize,
}

impl Recorder {
    /// Steps `stepper` from its current state through steps 1 … `steps`, the base moved by its
    /// scene's built-in motion z(nΔt), and adds each step in a window to that window's tally in
    /// `tallies` (its report; at every `stride`-th step a sample of the outputs); then calls
    /// `also(n, stepper, window)` for what a study records beyond the tally. A failed step is an
    /// error that names `label` and the step.
    pub fn run<T: AsMut<Tally>>(
        &self,
        stepper: &mut Stepper,
        label: &str,
        tallies: &mut [T],
        mut also: impl FnMut(usize, &Stepper, &mut T) -> Result<(), String>,
    ) -> Result<(), String> {
        let dt = stepper.scene().solver.time_step;
        for n in 1..=self.steps {
            let z = stepper.scene().builtin_base(n as f64 * dt);
            let report = stepper
                .step(z)
                .map_err(|e| format!("{label} step {n}: {e}"))?;
            let Some(window) = self.windows.of(n).and_then(|j| tallies.get_mut(j)) else {
                continue;
            };
            let tally = window.as_mut();
            tally.add_step(&report);
            if n % self.stride == 0 {
                tally.add_sample(&stepper.outputs());
            }
            also(n, stepper, window)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use plate_impact::element::ElementKind;
    use plate_impact::scene::Scene;

    #[test]
    fn bounds_take_the_steps_after_the_transient_window_by_window() {
        let windows = Windows::Bounds(vec![3, 5, 8]);
        let of: Vec<Option<usize>> = (1..=9).map(|n| windows.of(n)).collect();
        let none = None;
        assert_eq!(
            of,
            [
                none,
                none,
                none,
                Some(0),
                Some(0),
                Some(1),
                Some(1),
                Some(1),
                none
            ]
        );
    }

    #[test]
    fn a_step_belongs_to_the_period_of_its_midpoint() {
        // Four steps a period: steps 1-4 in period 0, 5-8 in period 1, anything later in the last.
        let periods = Windows::Periods {
            dt: 0.25,
            frequency: 1.0,
            count: 2,
        };
        let of: Vec<usize> = (1..=10).map(|n| periods.of(n).unwrap()).collect();
        assert_eq!(of, [0, 0, 0, 0, 1, 1, 1, 1, 1, 1]);
        assert_eq!(stride(1e-5, 1e-6), 10);
        assert_eq!(stride(1e-5, 1e-4), 1);
    }

    #[test]
    fn the_recorder_tallies_each_window_and_samples_every_stride() {
        let mut scene = Scene::named("forced-35hz").expect("a shipped scene");
        scene.mesh.element = ElementKind::Argyris;
        (scene.mesh.nx, scene.mesh.ny) = (2, 1);
        scene.solver.time_step = 1e-4;
        let mut stepper = Stepper::new(&scene, 0.0).expect("a stepper");
        let recorder = Recorder {
            windows: Windows::Bounds(vec![10, 40, 70]),
            steps: 80,
            stride: 3,
        };
        let mut tallies = vec![Tally::spanning(1); 2];
        let mut seen = Vec::new();
        recorder
            .run(&mut stepper, "test", &mut tallies, |n, _, _| {
                seen.push(n);
                Ok(())
            })
            .expect("the run");
        assert_eq!(seen, (11..=70).collect::<Vec<_>>());
        assert_eq!((tallies[0].steps, tallies[1].steps), (30, 30));
        // Multiples of 3 in 11..=40 and in 41..=70.
        assert_eq!((tallies[0].samples, tallies[1].samples), (10, 10));
        assert!(tallies
            .iter()
            .all(|t| t.energy > 0.0 && t.corner_squared > 0.0));
        assert!((stepper.time() - 80.0 * 1e-4).abs() < 1e-12);
    }
}
