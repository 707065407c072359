//! The clamped part Γc of the plate's edge (`plate.clamp`, docs/model.md §4): any non-empty union
//! of the four edges and of segments of an edge, written in the grammar of [`super::text`]:
//!
//! ```text
//! xmin                       the edge x = 0 (the default, the paper's clamp)
//! xmin, xmax, ymin, ymax     all four edges (also: all)
//! ymin(0.1, 0.3)             the segment 0.1 m ≤ x ≤ 0.3 m of the edge y = 0
//! ```
//!
//! The edges are named by the coordinate that is constant on them: `xmin` is x = 0, `xmax` is
//! x = Lx, `ymin` is y = 0, `ymax` is y = Ly. A segment gives its two ends as the coordinate
//! along its edge (y on `xmin`/`xmax`, x on `ymin`/`ymax`), in metres.
//!
//! On a mesh the clamp is a set of mesh edges along the plate's boundary ([`ClampedEdges`]): a
//! mesh edge is clamped when its midpoint lies in a part, so a segment's ends move to the nearest
//! vertices (by at most half a cell), and a segment that covers no midpoint is an error rather
//! than a clamp of nothing.

use super::text::{number, parse_call, split_top_level};
use crate::error::Error;

/// The parameter this module parses.
pub const PARAMETER: &str = "plate.clamp";

/// One side of the rectangle (0, Lx) × (0, Ly), named by the coordinate constant on it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// x = 0.
    XMin,
    /// x = Lx.
    XMax,
    /// y = 0.
    YMin,
    /// y = Ly.
    YMax,
}

impl Side {
    /// The four sides, in the order of [`ClampedEdges::sides`].
    pub const ALL: [Side; 4] = [Side::XMin, Side::XMax, Side::YMin, Side::YMax];

    /// The side's name in `plate.clamp`.
    pub fn name(self) -> &'static str {
        match self {
            Side::XMin => "xmin",
            Side::XMax => "xmax",
            Side::YMin => "ymin",
            Side::YMax => "ymax",
        }
    }

    fn parse(name: &str) -> Option<Side> {
        Side::ALL.into_iter().find(|s| s.name() == name)
    }

    /// Whether x is constant on the side (then y runs along it).
    pub fn is_x_constant(self) -> bool {
        matches!(self, Side::XMin | Side::XMax)
    }

    /// The side's length on a plate of `lx` × `ly` (m).
    pub fn length(self, [lx, ly]: [f64; 2]) -> f64 {
        if self.is_x_constant() {
            ly
        } else {
            lx
        }
    }

    /// The point at `along` (m) on the side.
    pub fn point(self, [lx, ly]: [f64; 2], along: f64) -> [f64; 2] {
        match self {
            Side::XMin => [0.0, along],
            Side::XMax => [lx, along],
            Side::YMin => [along, 0.0],
            Side::YMax => [along, ly],
        }
    }
}

/// One clamped part: the segment `from` ≤ t ≤ `to` of `side`, t the coordinate along it (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClampPart {
    /// The side it lies on.
    pub side: Side,
    /// Its first end along the side (m).
    pub from: f64,
    /// Its second end (m), > `from`.
    pub to: f64,
}

/// The clamped part of the edge, as parsed from `plate.clamp`.
#[derive(Clone, Debug, PartialEq)]
pub struct Clamp {
    /// The parts, in the order given (their union is Γc).
    pub parts: Vec<ClampPart>,
}

impl Clamp {
    /// Parses `text` for a plate of `size` = [Lx, Ly] (m). The error names `plate.clamp`, the
    /// part at fault and why.
    pub fn parse(text: &str, size: [f64; 2]) -> Result<Clamp, Error> {
        let fail = |why: String| Error::invalid(PARAMETER, format!("\"{text}\""), &why);
        let mut parts = Vec::new();
        for (k, item) in split_top_level(text, ',')
            .map_err(fail)?
            .into_iter()
            .enumerate()
        {
            let label = format!("part {} ('{item}')", k + 1);
            if item.is_empty() {
                return Err(fail(format!(
                    "has an empty {label}: name an edge (xmin, xmax, ymin, ymax or all) or a \
                     segment such as ymin(0.1, 0.3); a plate clamped nowhere has no static \
                     equilibrium (its stiffness is singular)"
                )));
            }
            let call = parse_call(item).map_err(fail)?;
            if call.name == "all" && call.arguments.is_none() {
                parts.extend(Side::ALL.map(|side| whole(side, size)));
                continue;
            }
            let side = Side::parse(call.name).ok_or_else(|| {
                fail(format!(
                    "has {label} naming no edge: the edges are xmin (x = 0), xmax (x = Lx), ymin \
                     (y = 0) and ymax (y = Ly), or all"
                ))
            })?;
            let Some(arguments) = call.arguments else {
                parts.push(whole(side, size));
                continue;
            };
            let ends = split_top_level(arguments, ',').map_err(fail)?;
            let [from, to] = ends[..] else {
                return Err(fail(format!(
                    "has {label} with {} numbers where a segment takes two, its ends along the \
                     edge in m",
                    ends.len()
                )));
            };
            let from = number(from, &format!("the first end of {label}")).map_err(fail)?;
            let to = number(to, &format!("the second end of {label}")).map_err(fail)?;
            let length = side.length(size);
            if !(0.0 <= from && from < to && to <= length) {
                return Err(fail(format!(
                    "has {label} from {from} to {to} m: a segment needs 0 ≤ from < to ≤ {length} \
                     m, the length of edge {}",
                    side.name()
                )));
            }
            parts.push(ClampPart { side, from, to });
        }
        Ok(Clamp { parts })
    }

    /// The clamp on the structured mesh of `cells` = [nx, ny] cells of the plate of `size`: the
    /// boundary mesh edges whose midpoints lie in a part. An error (naming `plate.clamp`) when
    /// no mesh edge is clamped.
    pub fn on_mesh(&self, size: [f64; 2], cells: [usize; 2]) -> Result<ClampedEdges, Error> {
        let count = |side: Side| {
            if side.is_x_constant() {
                cells[1]
            } else {
                cells[0]
            }
        };
        let sides = Side::ALL.map(|side| {
            let n = count(side);
            let h = side.length(size) / n as f64;
            (0..n)
                .map(|k| {
                    let middle = (k as f64 + 0.5) * h;
                    let tolerance = 1e-9 * h;
                    self.parts.iter().any(|p| {
                        p.side == side && p.from - tolerance <= middle && middle <= p.to + tolerance
                    })
                })
                .collect::<Vec<bool>>()
        });
        let edges = ClampedEdges { size, sides };
        if edges.is_empty() {
            let text: Vec<String> = self
                .parts
                .iter()
                .map(|p| format!("{}({}, {})", p.side.name(), p.from, p.to))
                .collect();
            return Err(Error::invalid(
                PARAMETER,
                format!("\"{}\"", text.join(", ")),
                &format!(
                    "covers no edge of the {} × {} mesh (a mesh edge is clamped when its \
                     midpoint lies in a part): lengthen the segments or refine the mesh; a plate \
                     clamped nowhere has no static equilibrium (its stiffness is singular)",
                    cells[0], cells[1]
                ),
            ));
        }
        Ok(edges)
    }
}

/// The whole of `side`.
fn whole(side: Side, size: [f64; 2]) -> ClampPart {
    ClampPart {
        side,
        from: 0.0,
        to: side.length(size),
    }
}

/// The clamp on a structured mesh: per side, whether each of its mesh edges is clamped.
#[derive(Clone, Debug, PartialEq)]
pub struct ClampedEdges {
    /// [Lx, Ly] (m).
    pub size: [f64; 2],
    /// Per side of [`Side::ALL`], one flag per mesh edge along it, from its start (t = 0).
    pub sides: [Vec<bool>; 4],
}

impl ClampedEdges {
    /// Whether no mesh edge is clamped.
    pub fn is_empty(&self) -> bool {
        self.sides.iter().all(|s| s.iter().all(|&c| !c))
    }

    /// The flags of `side`.
    pub fn side(&self, side: Side) -> &[bool] {
        let k = Side::ALL.iter().position(|&s| s == side).expect("a side");
        &self.sides[k]
    }

    /// The clamped segments, merged where consecutive mesh edges are clamped: (side, from, to)
    /// in metres along the side.
    pub fn segments(&self) -> Vec<(Side, f64, f64)> {
        let mut out = Vec::new();
        for side in Side::ALL {
            let flags = self.side(side);
            let h = side.length(self.size) / flags.len() as f64;
            let mut k = 0;
            while k < flags.len() {
                if !flags[k] {
                    k += 1;
                    continue;
                }
                let start = k;
                while k < flags.len() && flags[k] {
                    k += 1;
                }
                out.push((side, start as f64 * h, k as f64 * h));
            }
        }
        out
    }

    /// The total clamped length (m).
    pub fn length(&self) -> f64 {
        self.segments().iter().map(|(_, a, b)| b - a).sum()
    }

    /// The sides along which the point `p` is clamped: those of the clamped mesh edges that have
    /// `p` as an end or contain it (within `tolerance` m of the side's line and of the edge).
    pub fn sides_through(&self, p: [f64; 2], tolerance: f64) -> Vec<Side> {
        let [lx, ly] = self.size;
        Side::ALL
            .into_iter()
            .filter(|&side| {
                let (across, line, along) = match side {
                    Side::XMin => (p[0], 0.0, p[1]),
                    Side::XMax => (p[0], lx, p[1]),
                    Side::YMin => (p[1], 0.0, p[0]),
                    Side::YMax => (p[1], ly, p[0]),
                };
                if (across - line).abs() > tolerance {
                    return false;
                }
                let flags = self.side(side);
                let h = side.length(self.size) / flags.len() as f64;
                // The mesh edges k with k h − tolerance ≤ along ≤ (k + 1) h + tolerance (none
                // for a point at no finite place along the side).
                let (low, high) = ((along - tolerance) / h - 1.0, (along + tolerance) / h);
                if !(low.is_finite() && high.is_finite()) {
                    return false;
                }
                let first = low.ceil().max(0.0);
                let last = high.floor().min((flags.len() - 1) as f64);
                first <= last && (first as usize..=last as usize).any(|k| flags[k])
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SIZE: [f64; 2] = [0.4, 0.2];

    #[test]
    fn edges_segments_and_all_parse() {
        let c = Clamp::parse("xmin", SIZE).unwrap();
        assert_eq!(
            c.parts,
            vec![ClampPart {
                side: Side::XMin,
                from: 0.0,
                to: 0.2
            }]
        );
        assert_eq!(Clamp::parse("all", SIZE).unwrap().parts.len(), 4);
        let c = Clamp::parse(" ymin(0.1, 0.3) , xmax ", SIZE).unwrap();
        assert_eq!(c.parts[0].side, Side::YMin);
        assert_eq!((c.parts[0].from, c.parts[0].to), (0.1, 0.3));
        assert_eq!(c.parts[1].side, Side::XMax);
    }

    #[test]
    fn bad_clamps_are_errors_naming_the_part() {
        for (text, expected) in [
            ("", "empty part 1"),
            ("xmin,", "empty part 2"),
            ("left", "naming no edge"),
            ("ymin(0.3, 0.1)", "0 ≤ from < to ≤ 0.4"),
            ("ymin(0.1, 0.5)", "0 ≤ from < to ≤ 0.4"),
            ("ymin(0.1)", "1 numbers where a segment takes two"),
            ("ymin(0.1, x)", "not a number"),
            ("ymin(0.1, NaN)", "not finite"),
        ] {
            let err = Clamp::parse(text, SIZE).unwrap_err().to_string();
            assert!(
                err.contains("plate.clamp") && err.contains(expected),
                "{text}: {err}"
            );
        }
    }

    /// A mesh edge is clamped when its midpoint lies in a part: the ends of a segment move to
    /// the nearest vertices, and a segment between two midpoints clamps nothing (an error).
    #[test]
    fn segments_round_to_the_mesh_edges_whose_midpoints_they_cover() {
        let c = Clamp::parse("ymin(0.11, 0.29)", SIZE).unwrap();
        let on = c.on_mesh(SIZE, [10, 7]).unwrap();
        // Cells of 0.04 m: midpoints 0.02, 0.06, …; 0.14 … 0.26 are in [0.11, 0.29].
        let segments = on.segments();
        assert_eq!(segments.len(), 1);
        let (side, from, to) = segments[0];
        assert_eq!(side, Side::YMin);
        assert!((from - 0.12).abs() < 1e-15 && (to - 0.28).abs() < 1e-15);
        assert!((on.length() - 0.16).abs() < 1e-15);
        // A midpoint at an end counts (ends included): 0.1 is the midpoint of 0.08 … 0.12.
        let tie = Clamp::parse("ymin(0.1, 0.11)", SIZE).unwrap();
        assert!((tie.on_mesh(SIZE, [10, 7]).unwrap().length() - 0.04).abs() < 1e-15);
        let tiny = Clamp::parse("ymin(0.105, 0.115)", SIZE).unwrap();
        let err = tiny.on_mesh(SIZE, [10, 7]).unwrap_err().to_string();
        assert!(err.contains("covers no edge of the 10 × 7 mesh"), "{err}");
        let all = Clamp::parse("all", SIZE)
            .unwrap()
            .on_mesh(SIZE, [4, 2])
            .unwrap();
        assert!((all.length() - 1.2).abs() < 1e-15);
        assert_eq!(
            all.sides_through([0.0, 0.0], 1e-12),
            vec![Side::XMin, Side::YMin]
        );
        let x0 = Clamp::parse("xmin", SIZE)
            .unwrap()
            .on_mesh(SIZE, [4, 2])
            .unwrap();
        assert_eq!(x0.sides_through([0.0, 0.1], 1e-12), vec![Side::XMin]);
        assert!(x0.sides_through([0.1, 0.0], 1e-12).is_empty());
    }
}
