//! The one table of every scene parameter's own range: the limits a value must meet whatever the
//! other parameters are. [`Scene::validate`] checks each value against it, the FMU checks each
//! value as it is set, and a test (tests/model_description_checker.rs) checks that the `min`, `max`
//! and `unit` of both model descriptions agree with it. Limits that tie parameters together (the
//! thickness below the shorter side, the sine amplitude inside the gap, the damping pair) stay as
//! code in [`Scene::validate`] and [`Damping::validate`](super::Damping::validate).

use super::{Scene, MAX_CELLS_PER_SIDE};
use crate::error::Error;

/// One end of a range: the value and whether the value itself is allowed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limit {
    /// The limit, in the parameter's unit.
    pub value: f64,
    /// Whether a parameter equal to the limit is allowed (a closed end, `[` or `]`).
    pub inclusive: bool,
}

/// One parameter's own range: a value x is accepted when it is finite, min ≤ x (min < x for an
/// exclusive min) and x ≤ max (x < max), each end present.
#[derive(Clone, Copy, Debug)]
pub struct Bound {
    /// The parameter's dotted name, its FMU variable name (`stop_time` is the one that is not).
    pub name: &'static str,
    /// The lower end, if any.
    pub min: Option<Limit>,
    /// The upper end, if any.
    pub max: Option<Limit>,
    /// The unit as the model descriptions declare it, `""` for an Integer.
    pub unit: &'static str,
    /// Why the range is what it is, added to the error message when not empty.
    pub reason: &'static str,
    /// The parameter's value in a scene (an integer as `f64`, the element family as its code).
    pub value: fn(&Scene) -> f64,
}

/// A closed end.
const fn closed(value: f64) -> Option<Limit> {
    Some(Limit {
        value,
        inclusive: true,
    })
}

/// An open end.
const fn open(value: f64) -> Option<Limit> {
    Some(Limit {
        value,
        inclusive: false,
    })
}

/// A finite value with the given ends, unit and reason.
const fn bound(
    name: &'static str,
    (min, max): Ends,
    unit: &'static str,
    reason: &'static str,
    value: fn(&Scene) -> f64,
) -> Bound {
    Bound {
        name,
        min,
        max,
        unit,
        reason,
        value,
    }
}

/// The two ends of a range, each optional.
type Ends = (Option<Limit>, Option<Limit>);

/// x > 0.
const POSITIVE: Ends = (open(0.0), None);
/// x ≥ 0.
const NON_NEGATIVE: Ends = (closed(0.0), None);
/// Any finite x.
const FINITE: Ends = (None, None);
/// 1 ≤ n ≤ [`MAX_CELLS_PER_SIDE`].
const CELLS: Ends = (closed(1.0), closed(MAX_CELLS_PER_SIDE as f64));
/// Why the obstacles have a sign.
const STARTS_BETWEEN: &str = "the plate starts at u = 0 between the obstacles";

/// Every scene parameter with a numeric value, in the order of the scene's fields: the FMU's 32
/// Real and Integer parameters and `stop_time`. The two obstacle switches, the texts
/// (`plate.clamp`, the obstacle profiles) and the library-only choices (`solver.qp`,
/// `solver.linear`, `solver.impact_law`) have no range.
pub const BOUNDS: [Bound; 33] = [
    bound("plate.length", POSITIVE, "m", "", |s| s.plate.length),
    bound("plate.width", POSITIVE, "m", "", |s| s.plate.width),
    bound("plate.thickness", POSITIVE, "m", "", |s| s.plate.thickness),
    bound("material.young_modulus", POSITIVE, "Pa", "", |s| {
        s.material.young_modulus
    }),
    bound(
        "material.poisson_ratio",
        (open(-1.0), open(0.5)),
        "1",
        "the range of a stable isotropic material",
        |s| s.material.poisson_ratio,
    ),
    bound("material.density", POSITIVE, "kg/m3", "", |s| {
        s.material.density
    }),
    bound(
        "mesh.element",
        (closed(1.0), closed(2.0)),
        "",
        "1 = Argyris triangles, 2 = FVS quadrilaterals",
        |s| f64::from(s.mesh.element.code()),
    ),
    bound(
        "mesh.nx",
        CELLS,
        "",
        "beyond, the dense parts of the set-up would take minutes",
        |s| s.mesh.nx as f64,
    ),
    bound(
        "mesh.ny",
        CELLS,
        "",
        "beyond, the dense parts of the set-up would take minutes",
        |s| s.mesh.ny as f64,
    ),
    bound("solver.time_step", POSITIVE, "s", "", |s| {
        s.solver.time_step
    }),
    bound(
        "solver.restitution",
        (closed(0.0), closed(1.0)),
        "1",
        "",
        |s| s.solver.restitution,
    ),
    bound(
        "obstacle.lower",
        (None, open(0.0)),
        "m",
        STARTS_BETWEEN,
        |s| s.obstacle.lower,
    ),
    bound(
        "obstacle.upper",
        (open(0.0), None),
        "m",
        STARTS_BETWEEN,
        |s| s.obstacle.upper,
    ),
    bound("load.pressure", FINITE, "Pa", "", |s| s.load.pressure),
    bound(
        "load.gravity",
        NON_NEGATIVE,
        "m/s2",
        "it acts downward, in -z",
        |s| s.load.gravity,
    ),
    bound("initial.preload_pressure", FINITE, "Pa", "", |s| {
        s.initial.preload_pressure
    }),
    bound("base.amplitude", NON_NEGATIVE, "m", "", |s| {
        s.base.amplitude
    }),
    bound("base.frequency", NON_NEGATIVE, "Hz", "", |s| {
        s.base.frequency
    }),
    bound("damping.mass_proportional", NON_NEGATIVE, "1/s", "", |s| {
        s.damping.mass_proportional
    }),
    bound(
        "damping.stiffness_proportional",
        NON_NEGATIVE,
        "s",
        "",
        |s| s.damping.stiffness_proportional,
    ),
    bound("damping.ratio", NON_NEGATIVE, "1", "", |s| s.damping.ratio),
    bound("damping.frequency_low", NON_NEGATIVE, "Hz", "", |s| {
        s.damping.frequency_low
    }),
    bound("damping.frequency_high", NON_NEGATIVE, "Hz", "", |s| {
        s.damping.frequency_high
    }),
    bound("damping.modal_ratio", NON_NEGATIVE, "1", "", |s| {
        s.damping.modal_ratio
    }),
    bound("probe1.x", FINITE, "m", "", |s| s.probe1.x),
    bound("probe1.y", FINITE, "m", "", |s| s.probe1.y),
    bound("probe2.x", FINITE, "m", "", |s| s.probe2.x),
    bound("probe2.y", FINITE, "m", "", |s| s.probe2.y),
    bound("probe3.x", FINITE, "m", "", |s| s.probe3.x),
    bound("probe3.y", FINITE, "m", "", |s| s.probe3.y),
    bound("probe4.x", FINITE, "m", "", |s| s.probe4.x),
    bound("probe4.y", FINITE, "m", "", |s| s.probe4.y),
    bound("stop_time", POSITIVE, "s", "", |s| s.stop_time),
];

impl Bound {
    /// The bound of parameter `name`, if it has one.
    pub fn of(name: &str) -> Option<&'static Bound> {
        BOUNDS.iter().find(|b| b.name == name)
    }

    /// Whether `x` is finite and within both ends.
    pub fn admits(&self, x: f64) -> bool {
        let above = |l: Limit| x > l.value || (l.inclusive && x == l.value);
        let below = |l: Limit| x < l.value || (l.inclusive && x == l.value);
        x.is_finite() && self.min.is_none_or(above) && self.max.is_none_or(below)
    }

    /// `Ok` when [`Bound::admits`] `x`, else the error naming the parameter, `x` and the range:
    /// `must lie in (-1, 0.5)`, `must be finite and > 0`, `must be finite`, with the reason after.
    pub fn check(&self, x: f64) -> Result<(), Error> {
        if self.admits(x) {
            return Ok(());
        }
        let range = match (self.min, self.max) {
            (Some(min), Some(max)) => format!(
                "must lie in {}{}, {}{}",
                if min.inclusive { "[" } else { "(" },
                min.value,
                max.value,
                if max.inclusive { "]" } else { ")" },
            ),
            (Some(min), None) => {
                format!(
                    "must be finite and {} {}",
                    if min.inclusive { ">=" } else { ">" },
                    min.value
                )
            }
            (None, Some(max)) => {
                format!(
                    "must be finite and {} {}",
                    if max.inclusive { "<=" } else { "<" },
                    max.value
                )
            }
            (None, None) => "must be finite".to_string(),
        };
        let limit = if self.reason.is_empty() {
            range
        } else {
            format!("{range} ({})", self.reason)
        };
        Err(Error::invalid(self.name, x, &limit))
    }
}

/// Checks `x` against the bound of parameter `name`, which must be in [`BOUNDS`].
pub(super) fn check(name: &str, x: f64) -> Result<(), Error> {
    Bound::of(name)
        .unwrap_or_else(|| panic!("{name} has no entry in BOUNDS"))
        .check(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each end is open or closed as declared; every non-finite value is refused.
    #[test]
    fn the_ends_are_open_or_closed_as_declared() {
        let nu = Bound::of("material.poisson_ratio").unwrap();
        assert!(nu.admits(0.3) && nu.admits(-0.999));
        assert!(!nu.admits(0.5) && !nu.admits(-1.0));
        let e = Bound::of("solver.restitution").unwrap();
        assert!(e.admits(0.0) && e.admits(1.0) && !e.admits(1.0 + 1e-16 * 4.0));
        let p = Bound::of("load.pressure").unwrap();
        assert!(p.admits(-1e30));
        for b in &BOUNDS {
            for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                assert!(!b.admits(x), "{} admits {x}", b.name);
            }
        }
    }

    /// The message names the parameter, the value, the range and the reason.
    #[test]
    fn the_message_names_the_value_and_the_range() {
        let cases = [
            (
                "material.poisson_ratio",
                0.5,
                "material.poisson_ratio = 0.5",
                "must lie in (-1, 0.5) (the range",
            ),
            ("mesh.nx", 401.0, "mesh.nx = 401", "must lie in [1, 400]"),
            (
                "obstacle.lower",
                0.0,
                "obstacle.lower = 0",
                "must be finite and < 0 (the plate starts",
            ),
            (
                "base.amplitude",
                -1e-3,
                "base.amplitude = -0.001",
                "must be finite and >= 0",
            ),
            (
                "load.pressure",
                f64::NAN,
                "load.pressure = NaN",
                "must be finite",
            ),
        ];
        for (name, x, value, range) in cases {
            let err = check(name, x).unwrap_err().to_string();
            assert!(err.contains(value) && err.contains(range), "{err}");
        }
    }

    /// Every entry reads its own field: a scene whose fields all differ reads differently in each.
    #[test]
    fn every_entry_reads_its_own_field() {
        let default = Scene::default();
        let mut names = Vec::new();
        for b in &BOUNDS {
            let old = default.get(b.name).unwrap();
            let changed = match old {
                serde_json::Value::String(_) => serde_json::json!("fvs"),
                serde_json::Value::Number(n) if n.is_u64() => {
                    serde_json::json!(n.as_u64().unwrap() + 1)
                }
                other => serde_json::json!(other.as_f64().unwrap() + 0.5),
            };
            let scene = default.with(b.name, changed).unwrap();
            assert_ne!((b.value)(&scene), (b.value)(&default), "{}", b.name);
            for other in BOUNDS.iter().filter(|o| o.name != b.name) {
                assert_eq!(
                    (other.value)(&scene),
                    (other.value)(&default),
                    "{} moved {}",
                    b.name,
                    other.name
                );
            }
            names.push(b.name);
        }
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), BOUNDS.len(), "no name twice");
    }
}
