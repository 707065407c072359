//! What the contact did over the internal steps of one communication step, so that impacts
//! between communication points are not lost.
//!
//! An internal step belongs to the communication step whose span (t, t + h] contains its grid
//! time; a step computed ahead of t + h (the grid runs up to one step ahead,
//! [`interpolation`](super::interpolation)) is reported with the communication step that reaches
//! its time. Over those steps, with F_n the total contact force of step n (N, positive upward):
//!
//! * impacts = the number of steps at which the set of vertices in contact goes from empty to
//!   non-empty;
//! * impulse = Σ F_n Δt (N·s), the rectangle rule of ∫ F dt on the grid: summed over consecutive
//!   communication steps it is the same whatever their sizes;
//! * peak force = the F_n of largest magnitude, with its sign (0 without a step; the first of
//!   equal magnitudes);
//! * and the impacts and impulse of each of the first stops alike, from its own points' contact
//!   and forces.
//!
//! Each step adds to the summary in O(1).

use crate::obstacles::STOP_OUTPUTS;
use serde::{Deserialize, Serialize};

/// Contact over a set of internal steps (module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ContactSummary {
    /// Steps at which the contact set went from empty to non-empty.
    pub impacts: u64,
    /// Σ F_n Δt (N·s).
    pub impulse: f64,
    /// The F_n of largest magnitude, signed (N).
    pub peak_force: f64,
    /// The same per stop, for the first [`STOP_OUTPUTS`] stops (absent from states saved before
    /// stops existed: none).
    #[serde(default)]
    pub stops: [StopSummary; STOP_OUTPUTS],
}

/// The contact of one stop over a set of internal steps.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StopSummary {
    /// Steps at which the stop's points in contact went from none to some.
    pub impacts: u64,
    /// Σ F_n Δt of the stop's force (N·s).
    pub impulse: f64,
}

impl ContactSummary {
    /// Adds a step of total contact force `force` (N) and length `dt` (s) that was an impact or
    /// not.
    pub fn add(&mut self, force: f64, impact: bool, dt: f64) {
        self.impacts += u64::from(impact);
        self.impulse += force * dt;
        if force.abs() > self.peak_force.abs() {
            self.peak_force = force;
        }
    }

    /// Adds the stops' contact of a step of length `dt` (s): each stop's force (N) and whether
    /// it was an impact of that stop.
    pub fn add_stops(
        &mut self,
        forces: &[f64; STOP_OUTPUTS],
        impacts: &[bool; STOP_OUTPUTS],
        dt: f64,
    ) {
        for ((stop, &force), &impact) in self.stops.iter_mut().zip(forces).zip(impacts) {
            stop.impacts += u64::from(impact);
            stop.impulse += force * dt;
        }
    }

    /// Adds the steps summarised by `other`, which come after these.
    pub fn merge(&mut self, other: &ContactSummary) {
        self.impacts += other.impacts;
        self.impulse += other.impulse;
        if other.peak_force.abs() > self.peak_force.abs() {
            self.peak_force = other.peak_force;
        }
        for (stop, later) in self.stops.iter_mut().zip(&other.stops) {
            stop.impacts += later.impacts;
            stop.impulse += later.impulse;
        }
    }

    /// Checks a summary read from an untrusted source, named `what`: finite numbers, an impact
    /// count of at most `steps` (the internal steps it may cover), nothing at all over no step.
    /// The error names the field.
    pub fn check(&self, what: &str, steps: u64) -> Result<(), String> {
        if steps == 0 && *self != ContactSummary::default() {
            return Err(format!("{what}: {self:?} must be empty, it covers no step"));
        }
        let stops_finite = self.stops.iter().all(|s| s.impulse.is_finite());
        if !(self.impulse.is_finite() && self.peak_force.is_finite() && stops_finite) {
            return Err(format!(
                "{what}: impulse {} N s, peak force {} N and the stops' impulses must be finite",
                self.impulse, self.peak_force
            ));
        }
        if let Some(impacts) = std::iter::once(self.impacts)
            .chain(self.stops.iter().map(|s| s.impacts))
            .find(|&impacts| impacts > steps)
        {
            return Err(format!(
                "{what}: {impacts} impacts in at most {steps} internal steps"
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_impacts_sums_the_impulse_keeps_the_signed_peak() {
        let mut s = ContactSummary::default();
        for (force, impact) in [(0.0, false), (120.0, true), (-300.0, false), (300.0, false)] {
            s.add(force, impact, 1e-4);
        }
        assert_eq!(s.impacts, 1);
        assert!((s.impulse - 120.0e-4).abs() < 1e-18);
        assert_eq!(
            s.peak_force, -300.0,
            "the first of equal magnitudes, signed"
        );
    }

    #[test]
    fn merging_equals_adding_every_step() {
        let steps = [(5.0, true), (-7.0, false), (0.0, false), (2.0, true)];
        let mut whole = ContactSummary::default();
        let (mut first, mut second) = (ContactSummary::default(), ContactSummary::default());
        for (i, &(f, hit)) in steps.iter().enumerate() {
            whole.add(f, hit, 0.5);
            if i < 2 { &mut first } else { &mut second }.add(f, hit, 0.5);
        }
        first.merge(&second);
        assert_eq!(first, whole);
    }

    #[test]
    fn untrusted_summaries_are_checked() {
        let mut good = ContactSummary {
            impacts: 2,
            impulse: 1.0,
            peak_force: -3.0,
            ..ContactSummary::default()
        };
        good.add_stops(&[2.0; STOP_OUTPUTS], &[true; STOP_OUTPUTS], 0.5);
        assert!(good.check("reported", 2).is_ok());
        assert!(good.check("reported", 1).unwrap_err().contains("2 impacts"));
        let mut stop_bad = good;
        stop_bad.stops[3].impacts = 3;
        assert!(stop_bad
            .check("reported", 2)
            .unwrap_err()
            .contains("3 impacts"));
        stop_bad.stops[3] = StopSummary {
            impacts: 0,
            impulse: f64::INFINITY,
        };
        assert!(stop_bad
            .check("reported", 2)
            .unwrap_err()
            .contains("finite"));
        let bad = ContactSummary {
            impulse: f64::NAN,
            ..good
        };
        assert!(bad.check("reported", 5).unwrap_err().contains("finite"));
        let stale = ContactSummary { impacts: 0, ..good };
        assert!(stale
            .check("ahead", 0)
            .unwrap_err()
            .contains("covers no step"));
    }
}
