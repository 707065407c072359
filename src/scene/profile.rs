//! Obstacle profiles (`obstacle.lower_profile`, `obstacle.upper_profile`; docs/model.md §5): the
//! shape of each obstacle over the plate, as heights h(x, y) relative to the obstacle's tunable
//! level g (`obstacle.lower`, `obstacle.upper`), so that the obstacle lies at g + h(x, y) where it
//! is present and is absent elsewhere (g₁ = −∞, g₂ = +∞ there). Written in the grammar of
//! [`super::text`]:
//!
//! ```text
//! flat                                   h = 0 over the whole plate (the default)
//! plane(slope_x = 0.01, slope_y = 0)     h = s_x (x − Lx/2) + s_y (y − Ly/2) over the whole plate
//! table(0, 0.001, 0.002; 0, 0, 0.001)    heights on a grid over the whole plate, bilinear between
//!                                        (rows from y = 0 to y = Ly, values from x = 0 to x = Lx)
//! point(x = 0.39, y = 0.01); disc(x = 0.2, y = 0.1, radius = 0.005, offset = -0.001);
//! rectangle(x0 = 0.1, y0 = 0.05, x1 = 0.15, y1 = 0.08)
//!                                        local stops, each at h = its offset (default 0), the
//!                                        obstacle absent elsewhere
//! ```
//!
//! Where two stops of one obstacle overlap, the one nearer the plate at rest acts (the highest
//! under the plate, the lowest over it).

use super::clamp::Side;
use super::text::{argument, keyword_numbers, number, parse_call, split_top_level};
use super::ObstacleSide;
use crate::error::Error;

/// Largest number of values in a table profile: a grid of 201 × 201, far finer than any mesh the
/// heights are sampled on (at most 401 vertices a side) needs to follow a smooth support.
pub const MAX_TABLE_VALUES: usize = 201 * 201;

/// Largest number of local stops on one obstacle.
pub const MAX_STOPS: usize = 1000;

/// The shape of one obstacle over the plate (module docs).
#[derive(Clone, Debug, PartialEq)]
pub enum Profile {
    /// h = 0 everywhere.
    Flat,
    /// h = s_x (x − Lx/2) + s_y (y − Ly/2) everywhere: a plane through the level at the plate's
    /// centre.
    Plane {
        /// [s_x, s_y] (m/m).
        slope: [f64; 2],
    },
    /// Heights on a grid over the plate, bilinear between its values.
    Table(Table),
    /// Local stops; the obstacle is absent elsewhere.
    Stops(Vec<Stop>),
}

/// Heights on a regular grid over the whole plate: `values[j][i]` at x = i Lx/(columns − 1),
/// y = j Ly/(rows − 1), at least 2 × 2.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    /// The rows, from y = 0 to y = Ly, each from x = 0 to x = Lx (m).
    pub values: Vec<Vec<f64>>,
}

/// One local stop: its shape and its height relative to the obstacle's level.
#[derive(Clone, Debug, PartialEq)]
pub struct Stop {
    /// Where it is.
    pub shape: StopShape,
    /// h (m): the stop lies at the obstacle's level plus this.
    pub offset: f64,
}

/// The footprint of a stop on the plate (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StopShape {
    /// A single point.
    Point([f64; 2]),
    /// A disc.
    Disc {
        /// Its centre.
        centre: [f64; 2],
        /// Its radius, > 0.
        radius: f64,
    },
    /// An axis-aligned rectangle.
    Rectangle {
        /// Its corner of least x and y.
        min: [f64; 2],
        /// Its corner of largest x and y.
        max: [f64; 2],
    },
}

impl StopShape {
    /// Whether `p` lies in the closed footprint, to `tolerance` (m).
    pub fn contains(&self, p: [f64; 2], tolerance: f64) -> bool {
        match *self {
            StopShape::Point(q) => distance(p, q) <= tolerance,
            StopShape::Disc { centre, radius } => distance(p, centre) <= radius + tolerance,
            StopShape::Rectangle { min, max } => {
                (0..2).all(|k| min[k] - tolerance <= p[k] && p[k] <= max[k] + tolerance)
            }
        }
    }

    /// The footprint's bounding box, [min, max] (m).
    pub fn bounding_box(&self) -> [[f64; 2]; 2] {
        match *self {
            StopShape::Point(q) => [q, q],
            StopShape::Disc { centre, radius } => [
                [centre[0] - radius, centre[1] - radius],
                [centre[0] + radius, centre[1] + radius],
            ],
            StopShape::Rectangle { min, max } => [min, max],
        }
    }

    /// The distance (m) from the footprint to the segment from `a` to `b`: 0 when they meet.
    pub fn distance_to_segment(&self, a: [f64; 2], b: [f64; 2]) -> f64 {
        match *self {
            StopShape::Point(q) => point_segment_distance(q, a, b),
            StopShape::Disc { centre, radius } => {
                (point_segment_distance(centre, a, b) - radius).max(0.0)
            }
            StopShape::Rectangle { min, max } => {
                // An axis-aligned segment (the plate's sides): clip it to the rectangle's span.
                let gap = |k: usize| {
                    let (lo, hi) = (a[k].min(b[k]), a[k].max(b[k]));
                    (min[k] - hi).max(lo - max[k]).max(0.0)
                };
                libm::hypot(gap(0), gap(1))
            }
        }
    }

    /// The stop's own points for a mesh of cell size `spacing` (m): a point stop's location; a
    /// disc's centre and its circle at a spacing of at most `spacing` (at least 8 points); a
    /// rectangle's centre and its outline at a spacing of at most `spacing` (its corners
    /// included). The interior of a patch larger than a cell holds mesh vertices, which the
    /// contact points take too (docs/model.md §5).
    pub fn own_points(&self, spacing: f64) -> Vec<[f64; 2]> {
        match *self {
            StopShape::Point(q) => vec![q],
            StopShape::Disc { centre, radius } => {
                let around = std::f64::consts::TAU * radius;
                let count = ((around / spacing).ceil() as usize).max(8);
                let mut points = vec![centre];
                points.extend((0..count).map(|k| {
                    let angle = std::f64::consts::TAU * k as f64 / count as f64;
                    [
                        centre[0] + radius * libm::cos(angle),
                        centre[1] + radius * libm::sin(angle),
                    ]
                }));
                points
            }
            StopShape::Rectangle { min, max } => {
                let mut points = vec![[0.5 * (min[0] + max[0]), 0.5 * (min[1] + max[1])]];
                let steps = |k: usize| (((max[k] - min[k]) / spacing).ceil() as usize).max(1);
                let (nx, ny) = (steps(0), steps(1));
                let at =
                    |k: usize, i: usize, n: usize| min[k] + (max[k] - min[k]) * i as f64 / n as f64;
                for i in 0..=nx {
                    points.push([at(0, i, nx), min[1]]);
                    points.push([at(0, i, nx), max[1]]);
                }
                for j in 1..ny {
                    points.push([min[0], at(1, j, ny)]);
                    points.push([max[0], at(1, j, ny)]);
                }
                points
            }
        }
    }

    /// A short description for messages: `disc at (0.2, 0.1) m, radius 0.005 m`.
    pub fn describe(&self) -> String {
        match *self {
            StopShape::Point([x, y]) => format!("point at ({x}, {y}) m"),
            StopShape::Disc { centre, radius } => format!(
                "disc at ({}, {}) m, radius {radius} m",
                centre[0], centre[1]
            ),
            StopShape::Rectangle { min, max } => format!(
                "rectangle ({}, {}) to ({}, {}) m",
                min[0], min[1], max[0], max[1]
            ),
        }
    }
}

impl Profile {
    /// Parses the profile text of `parameter` for a plate of `size` = [Lx, Ly] (m). The error names
    /// the parameter, the item at fault and why: an unknown kind, a missing or unknown argument,
    /// a value that is not a finite number, a stop outside the plate, a table that is not a grid.
    pub fn parse(text: &str, parameter: &str, size: [f64; 2]) -> Result<Profile, Error> {
        let fail = |why: String| Error::invalid(parameter, format!("\"{text}\""), &why);
        let trimmed = text.trim();
        if trimmed == "flat" {
            return Ok(Profile::Flat);
        }
        let items = split_top_level(trimmed, ';').map_err(fail)?;
        let first = parse_call(items[0]).map_err(fail)?;
        match first.name {
            "plane" | "table" if items.len() > 1 => Err(fail(format!(
                "combines a {} with other items: a profile is flat, one plane, one table, or \
                 local stops separated by ';'",
                first.name
            ))),
            "plane" => {
                let arguments = first.arguments.unwrap_or("");
                let values = keyword_numbers(arguments, &["slope_x", "slope_y"], "the plane")
                    .map_err(fail)?;
                let slope = ["slope_x", "slope_y"]
                    .map(|key| argument(&values, key, Some(0.0), "the plane").unwrap_or(0.0));
                Ok(Profile::Plane { slope })
            }
            "table" => Table::parse(first.arguments.unwrap_or(""))
                .map(Profile::Table)
                .map_err(fail),
            _ => {
                if items.len() > MAX_STOPS {
                    return Err(fail(format!(
                        "has {} stops, more than the {MAX_STOPS} one obstacle may have",
                        items.len()
                    )));
                }
                let stops = items
                    .iter()
                    .enumerate()
                    .map(|(k, item)| Stop::parse(item, k + 1, size))
                    .collect::<Result<Vec<Stop>, String>>()
                    .map_err(fail)?;
                Ok(Profile::Stops(stops))
            }
        }
    }

    /// Whether the obstacle lies under (or over) the whole plate.
    pub fn covers_plate(&self) -> bool {
        !matches!(self, Profile::Stops(_))
    }

    /// h at `p` for a profile over the whole plate (`None` for stops, which
    /// [`Profile::stop_height`] evaluates), on a plate of `size`.
    pub fn plate_height(&self, p: [f64; 2], size: [f64; 2]) -> Option<f64> {
        match self {
            Profile::Flat => Some(0.0),
            Profile::Plane { slope } => {
                Some(slope[0] * (p[0] - 0.5 * size[0]) + slope[1] * (p[1] - 0.5 * size[1]))
            }
            Profile::Table(table) => Some(table.height(p, size)),
            Profile::Stops(_) => None,
        }
    }

    /// The stop of a stops profile that acts at `p` (its footprint holds `p` to `tolerance`), as
    /// (index among the stops, h): the nearest to the plate at rest where several overlap (the
    /// highest for the lower obstacle, the lowest for the upper), the first on a tie. `None` for
    /// a profile over the whole plate, or where no stop is.
    pub fn stop_height(
        &self,
        p: [f64; 2],
        side: ObstacleSide,
        tolerance: f64,
    ) -> Option<(usize, f64)> {
        let Profile::Stops(stops) = self else {
            return None;
        };
        let nearer = |a: f64, b: f64| match side {
            ObstacleSide::Lower => a > b,
            ObstacleSide::Upper => a < b,
        };
        stops
            .iter()
            .enumerate()
            .filter(|(_, s)| s.shape.contains(p, tolerance))
            .fold(None, |best, (k, s)| match best {
                Some((_, h)) if !nearer(s.offset, h) => best,
                _ => Some((k, s.offset)),
            })
    }

    /// The height of the obstacle nearest to the plate at rest anywhere on the plate of `size`:
    /// the largest h for the lower obstacle, the smallest for the upper, with where it is, as
    /// (h, description). A plane's extremes lie at corners, a bilinear table's at grid values.
    pub fn nearest(&self, side: ObstacleSide, size: [f64; 2]) -> (f64, String) {
        let [lx, ly] = size;
        let nearer = |a: f64, b: f64| match side {
            ObstacleSide::Lower => a > b,
            ObstacleSide::Upper => a < b,
        };
        let pick = |candidates: Vec<(f64, String)>| {
            candidates
                .into_iter()
                .reduce(|a, b| if nearer(b.0, a.0) { b } else { a })
                .expect("a profile has at least one height")
        };
        match self {
            Profile::Flat => (0.0, "over the whole plate".to_string()),
            Profile::Plane { .. } => pick(
                [[0.0, 0.0], [lx, 0.0], [0.0, ly], [lx, ly]]
                    .iter()
                    .map(|&p| {
                        let h = self
                            .plate_height(p, size)
                            .expect("a plane covers the plate");
                        (h, format!("at the corner ({}, {}) m", p[0], p[1]))
                    })
                    .collect(),
            ),
            Profile::Table(table) => pick(
                table
                    .values
                    .iter()
                    .enumerate()
                    .flat_map(|(j, row)| {
                        row.iter().enumerate().map(move |(i, &h)| {
                            (h, format!("at table value {} of row {}", i + 1, j + 1))
                        })
                    })
                    .collect(),
            ),
            Profile::Stops(stops) => pick(
                stops
                    .iter()
                    .enumerate()
                    .map(|(k, s)| {
                        (
                            s.offset,
                            format!("at stop {} ({})", k + 1, s.shape.describe()),
                        )
                    })
                    .collect(),
            ),
        }
    }

    /// The height nearest to the plate at rest over the segments `segments` (each (side, from,
    /// to) along the plate's side), `None` where the obstacle lies over none of them: a stop
    /// counts when its footprint comes within `tolerance` (m) of a segment.
    pub fn nearest_over(
        &self,
        side: ObstacleSide,
        segments: &[(Side, f64, f64)],
        size: [f64; 2],
        tolerance: f64,
    ) -> Option<f64> {
        let nearer = |a: f64, b: f64| match side {
            ObstacleSide::Lower => a.max(b),
            ObstacleSide::Upper => a.min(b),
        };
        let mut heights = Vec::new();
        for &(edge, from, to) in segments {
            let (a, b) = (edge.point(size, from), edge.point(size, to));
            match self {
                Profile::Stops(stops) => heights.extend(
                    stops
                        .iter()
                        .filter(|s| s.shape.distance_to_segment(a, b) <= tolerance)
                        .map(|s| s.offset),
                ),
                Profile::Table(table) => {
                    // Bilinear along an axis-aligned segment: extremes at its ends and where
                    // it crosses grid lines.
                    let along_x = !edge.is_x_constant();
                    let (count, length) = if along_x {
                        (table.values[0].len(), size[0])
                    } else {
                        (table.values.len(), size[1])
                    };
                    let nodes = (0..count)
                        .map(|k| length * k as f64 / (count - 1) as f64)
                        .filter(|&t| from < t && t < to);
                    for t in [from, to].into_iter().chain(nodes) {
                        heights.push(table.height(edge.point(size, t), size));
                    }
                }
                _ => {
                    for p in [a, b] {
                        heights.extend(self.plate_height(p, size));
                    }
                }
            }
        }
        heights.into_iter().reduce(nearer)
    }
}

impl Stop {
    /// Parses stop number `index` (from 1) and checks it lies on the plate of `size`.
    fn parse(item: &str, index: usize, size: [f64; 2]) -> Result<Stop, String> {
        let label = format!("stop {index} ('{item}')");
        if item.is_empty() {
            return Err(format!(
                "has an empty {label}: a profile is flat, plane(…), table(…) or stops \
                 point(…), disc(…), rectangle(…) separated by ';'"
            ));
        }
        let call = parse_call(item)?;
        let known: &[&str] = match call.name {
            "point" => &["x", "y", "offset"],
            "disc" => &["x", "y", "radius", "offset"],
            "rectangle" => &["x0", "y0", "x1", "y1", "offset"],
            _ => {
                return Err(format!(
                    "has {label} of an unknown kind: a profile is flat, plane(…), table(…) or \
                     stops point(…), disc(…), rectangle(…) separated by ';'"
                ))
            }
        };
        let values = keyword_numbers(call.arguments.unwrap_or(""), known, &label)?;
        let get = |key: &str| argument(&values, key, None, &label);
        let offset = argument(&values, "offset", Some(0.0), &label)?;
        let [lx, ly] = size;
        let on_plate = |p: [f64; 2]| (0.0..=lx).contains(&p[0]) && (0.0..=ly).contains(&p[1]);
        let outside = |what: &str| {
            format!("has {label} with {what} outside the plate [0, {lx}] × [0, {ly}] m")
        };
        let shape = match call.name {
            "point" => {
                let p = [get("x")?, get("y")?];
                if !on_plate(p) {
                    return Err(outside("its point"));
                }
                StopShape::Point(p)
            }
            "disc" => {
                let centre = [get("x")?, get("y")?];
                let radius = get("radius")?;
                if radius <= 0.0 {
                    return Err(format!(
                        "has {label} with radius {radius} m: it must be > 0"
                    ));
                }
                if !on_plate(centre) {
                    return Err(outside("its centre"));
                }
                StopShape::Disc { centre, radius }
            }
            _ => {
                let (min, max) = ([get("x0")?, get("y0")?], [get("x1")?, get("y1")?]);
                if !(min[0] < max[0] && min[1] < max[1]) {
                    return Err(format!(
                        "has {label} with x0 ≥ x1 or y0 ≥ y1: a rectangle needs x0 < x1 and \
                         y0 < y1"
                    ));
                }
                if max[0] <= 0.0 || min[0] >= lx || max[1] <= 0.0 || min[1] >= ly {
                    return Err(outside("all of it"));
                }
                StopShape::Rectangle { min, max }
            }
        };
        Ok(Stop { shape, offset })
    }
}

impl Table {
    /// Parses `v, v, …; v, v, …` (rows separated by ';', values by ',' or spaces).
    fn parse(arguments: &str) -> Result<Table, String> {
        let rows = split_top_level(arguments, ';')?;
        let mut values = Vec::with_capacity(rows.len());
        let mut count = 0;
        for (j, row) in rows.iter().enumerate() {
            let row: Vec<f64> = row
                .split(|c: char| c == ',' || c.is_whitespace())
                .filter(|s| !s.is_empty())
                .enumerate()
                .map(|(i, v)| number(v, &format!("value {} of table row {}", i + 1, j + 1)))
                .collect::<Result<_, _>>()?;
            count += row.len();
            if count > MAX_TABLE_VALUES {
                return Err(format!(
                    "has a table of more than {MAX_TABLE_VALUES} values (201 × 201)"
                ));
            }
            values.push(row);
        }
        let columns = values[0].len();
        if values.len() < 2 || columns < 2 {
            return Err(format!(
                "has a table of {} rows of {columns} values: a table needs at least 2 rows of at \
                 least 2 values (rows from y = 0 to Ly separated by ';', values from x = 0 to Lx)",
                values.len()
            ));
        }
        if let Some(j) = values.iter().position(|r| r.len() != columns) {
            return Err(format!(
                "has table row {} of {} values where row 1 has {columns}: every row needs as many",
                j + 1,
                values[j].len()
            ));
        }
        Ok(Table { values })
    }

    /// The bilinear height at `p` on a plate of `size`.
    pub fn height(&self, p: [f64; 2], size: [f64; 2]) -> f64 {
        let (rows, columns) = (self.values.len(), self.values[0].len());
        // The cell of the grid holding the coordinate, and the fraction across it.
        let locate = |x: f64, length: f64, n: usize| {
            let t = (x / length).clamp(0.0, 1.0) * (n - 1) as f64;
            let k = (t.floor() as usize).min(n - 2);
            (k, t - k as f64)
        };
        let (i, s) = locate(p[0], size[0], columns);
        let (j, t) = locate(p[1], size[1], rows);
        let v = &self.values;
        (1.0 - t) * ((1.0 - s) * v[j][i] + s * v[j][i + 1])
            + t * ((1.0 - s) * v[j + 1][i] + s * v[j + 1][i + 1])
    }
}

fn distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    libm::hypot(a[0] - b[0], a[1] - b[1])
}

fn point_segment_distance(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let d = [b[0] - a[0], b[1] - a[1]];
    let length_squared = d[0] * d[0] + d[1] * d[1];
    let t = if length_squared > 0.0 {
        (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / length_squared).clamp(0.0, 1.0)
    } else {
        0.0
    };
    distance(p, [a[0] + t * d[0], a[1] + t * d[1]])
}

#[cfg(test)]
mod tests {
    use super::*;

    const SIZE: [f64; 2] = [0.4, 0.2];
    const LOWER: &str = "obstacle.lower_profile";

    fn parse(text: &str) -> Result<Profile, Error> {
        Profile::parse(text, LOWER, SIZE)
    }

    #[test]
    fn every_kind_parses() {
        assert_eq!(parse(" flat ").unwrap(), Profile::Flat);
        assert_eq!(
            parse("plane(slope_x = 0.01)").unwrap(),
            Profile::Plane { slope: [0.01, 0.0] }
        );
        let Profile::Table(t) = parse("table(0, 1, 2; 3 4 5)").unwrap() else {
            panic!("a table")
        };
        assert_eq!(t.values, vec![vec![0.0, 1.0, 2.0], vec![3.0, 4.0, 5.0]]);
        let Profile::Stops(stops) = parse(
            "point(x=0.39, y=0.01); disc(x=0.2, y=0.1, radius=0.005, offset=-0.001); \
             rectangle(x0=0.1, y0=0.05, x1=0.15, y1=0.08)",
        )
        .unwrap() else {
            panic!("stops")
        };
        assert_eq!(stops.len(), 3);
        assert_eq!(stops[0].shape, StopShape::Point([0.39, 0.01]));
        assert_eq!(stops[1].offset, -0.001);
        assert_eq!(
            stops[2].shape,
            StopShape::Rectangle {
                min: [0.1, 0.05],
                max: [0.15, 0.08]
            }
        );
    }

    #[test]
    fn bad_profiles_are_errors_naming_the_item() {
        for (text, expected) in [
            ("", "empty stop 1"),
            ("flat; point(x=0, y=0)", "unknown kind"),
            ("bump(x=0.1)", "stop 1 ('bump(x=0.1)') of an unknown kind"),
            ("point(x=0.1)", "lacks y in stop 1"),
            ("point(x=0.5, y=0.1)", "outside the plate"),
            (
                "point(x=0.1, y=0.1); disc(x=0.1, y=0.1, radius=0)",
                "stop 2",
            ),
            (
                "disc(x=-0.1, y=0.1, radius=0.2)",
                "its centre outside the plate",
            ),
            (
                "rectangle(x0=0.5, y0=0, x1=0.6, y1=0.1)",
                "all of it outside",
            ),
            ("rectangle(x0=0.2, y0=0, x1=0.1, y1=0.1)", "x0 < x1"),
            ("plane(slope_x = 0.1); point(x=0, y=0)", "combines a plane"),
            ("plane(tilt = 0.1)", "unknown argument 'tilt'"),
            ("table(1, 2)", "at least 2 rows"),
            ("table(1, 2; 3)", "row 2 of 1 values"),
            ("table(1, inf; 3, 4)", "not finite"),
            ("point(x=0.1, y=0.1", "never closed"),
        ] {
            let err = parse(text).unwrap_err().to_string();
            assert!(
                err.contains(LOWER) && err.contains(expected),
                "{text}: {err}"
            );
        }
    }

    #[test]
    fn heights_follow_the_profile() {
        let plane = parse("plane(slope_x = 0.01, slope_y = -0.02)").unwrap();
        assert_eq!(plane.plate_height([0.2, 0.1], SIZE), Some(0.0));
        let h = plane.plate_height([0.4, 0.0], SIZE).unwrap();
        assert!((h - (0.01 * 0.2 + 0.02 * 0.1)).abs() < 1e-17);
        assert_eq!(plane.nearest(ObstacleSide::Lower, SIZE).0, h);
        // Bilinear: the centre of a 2 × 2 table is the mean of its four values.
        let table = parse("table(0, 1; 2, 5)").unwrap();
        assert_eq!(table.plate_height([0.2, 0.1], SIZE), Some(2.0));
        assert_eq!(table.plate_height([0.4, 0.2], SIZE), Some(5.0));
        assert_eq!(table.nearest(ObstacleSide::Upper, SIZE).0, 0.0);
        let stops =
            parse("disc(x=0.2, y=0.1, radius=0.05, offset=0.001); point(x=0.2, y=0.1)").unwrap();
        assert_eq!(stops.plate_height([0.2, 0.1], SIZE), None);
        assert_eq!(
            stops.stop_height([0.2, 0.1], ObstacleSide::Lower, 1e-9),
            Some((0, 0.001))
        );
        assert_eq!(
            stops.stop_height([0.2, 0.1], ObstacleSide::Upper, 1e-9),
            Some((1, 0.0))
        );
        assert_eq!(
            stops.stop_height([0.3, 0.1], ObstacleSide::Lower, 1e-9),
            None
        );
    }

    /// Over the clamp: a stop counts where it meets a clamped segment, a table where its
    /// bilinear heights along the segment are extreme.
    #[test]
    fn heights_over_clamped_segments() {
        let clamp = [(Side::XMin, 0.0, 0.2)];
        let stops =
            parse("disc(x=0.01, y=0.1, radius=0.02, offset=0.003); point(x=0.3, y=0.1)").unwrap();
        assert_eq!(
            stops.nearest_over(ObstacleSide::Lower, &clamp, SIZE, 1e-9),
            Some(0.003)
        );
        let far = parse("point(x=0.3, y=0.1)").unwrap();
        assert_eq!(
            far.nearest_over(ObstacleSide::Lower, &clamp, SIZE, 1e-9),
            None
        );
        let table = parse("table(0, 0, 0; 1, 0, 0; 0, 0, 0)").unwrap();
        assert_eq!(
            table.nearest_over(ObstacleSide::Lower, &clamp, SIZE, 1e-9),
            Some(1.0)
        );
        assert_eq!(
            table.nearest_over(ObstacleSide::Upper, &clamp, SIZE, 1e-9),
            Some(0.0)
        );
    }

    #[test]
    fn own_points_cover_small_stops_at_the_mesh_spacing() {
        let disc = StopShape::Disc {
            centre: [0.2, 0.1],
            radius: 0.001,
        };
        let points = disc.own_points(0.04);
        assert_eq!(points.len(), 9, "the centre and 8 points on the circle");
        assert!(points
            .iter()
            .all(|&p| disc.contains(p, 1e-15) && distance(p, [0.2, 0.1]) <= 0.001 + 1e-15));
        let rectangle = StopShape::Rectangle {
            min: [0.1, 0.05],
            max: [0.2, 0.06],
        };
        let points = rectangle.own_points(0.04);
        // Centre, 4 × 2 along x (3 intervals of 0.0333 m ≤ 0.04 m), no interior row along y.
        assert_eq!(points.len(), 1 + 2 * 4);
        assert!(points.iter().all(|&p| rectangle.contains(p, 1e-15)));
        assert_eq!(rectangle.distance_to_segment([0.0, 0.0], [0.0, 0.2]), 0.1);
    }
}
