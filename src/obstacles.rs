//! Where the obstacles constrain the discrete plate: the contact points, each with the heights of
//! the obstacles over it (docs/model.md §5, "Where the constraint is enforced").
//!
//! The paper's admissible set is g₁(x) ≤ u(x) ≤ g₂(x) over the plate; the discrete problem imposes
//! it at a finite set of contact points p_i, on the deflection there through the element's basis,
//! u(p_i) = Σ_k φ_k(p_i) u_k (a row of B). The points are:
//!
//! * every mesh vertex off the clamp under or over an obstacle (for a flat, plane or table
//!   profile: every vertex off the clamp), in the mesh's vertex order; the row picks the vertex's
//!   value dof, exactly as before profiles existed;
//! * each stop's own points ([`StopShape::own_points`](crate::scene::StopShape::own_points): a point stop's location, a disc's centre
//!   and circle, a rectangle's centre and outline, at the mesh's cell size), so that a stop acts
//!   whatever the mesh: a stud smaller than a cell, or a point between vertices, still stops the
//!   plate. An own point within [`MERGE_FRACTION`] of a cell of a point already taken is merged
//!   into it (which then carries the stop too), so that no two rows are nearly equal.
//!
//! Points on the clamp are left out: the deflection there is the base's, which the base's own
//! guard keeps between the obstacles ([`ObstacleLayout::clamp_heights`]).

use crate::error::Error;
use crate::scene::profile::{Profile, MAX_STOPS};
use crate::scene::{ClampedEdges, ObstacleSide, Scene};
use std::collections::HashMap;

/// Two contact points closer than this fraction of the mesh's cell size are one: the own point
/// of a stop is merged into a vertex or another own point there.
pub const MERGE_FRACTION: f64 = 0.05;

/// The number of stops with outputs of their own (`stop1` … `stop8`): the first of the lower
/// obstacle's stops, then the upper's. Further stops act all the same, and count in the totals.
pub const STOP_OUTPUTS: usize = 8;

/// Largest number of own points (points that are not mesh vertices) the stops of one obstacle
/// may add: each is a row of the contact problem, and the modal backend holds a dense row of
/// the modes for each.
pub const MAX_OWN_POINTS: usize = 20_000;

/// The height of one obstacle over a contact point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Height {
    /// h (m), relative to the obstacle's level.
    pub h: f64,
    /// The stop that acts there, numbered over both obstacles (the lower obstacle's stops first),
    /// `None` for a profile over the whole plate.
    pub stop: Option<usize>,
}

/// One contact point.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactPoint {
    /// Where it is (m).
    pub position: [f64; 2],
    /// The mesh vertex it is, if it is one.
    pub vertex: Option<usize>,
    /// The lower obstacle's height there, `None` where it is absent.
    pub lower: Option<Height>,
    /// The upper obstacle's height there, `None` where it is absent.
    pub upper: Option<Height>,
}

impl ContactPoint {
    /// The height on `side`.
    pub fn height(&self, side: ObstacleSide) -> Option<Height> {
        match side {
            ObstacleSide::Lower => self.lower,
            ObstacleSide::Upper => self.upper,
        }
    }

    fn height_mut(&mut self, side: ObstacleSide) -> &mut Option<Height> {
        match side {
            ObstacleSide::Lower => &mut self.lower,
            ObstacleSide::Upper => &mut self.upper,
        }
    }
}

/// A stop of an enabled obstacle, as the per-stop outputs number them.
#[derive(Clone, Debug, PartialEq)]
pub struct StopLabel {
    /// The obstacle it belongs to.
    pub side: ObstacleSide,
    /// Its index in that obstacle's profile (from 0).
    pub index: usize,
}

/// The contact points of a scene on its mesh (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct ObstacleLayout {
    /// The points: mesh vertices first, in vertex order, then the stops' own points.
    pub points: Vec<ContactPoint>,
    /// The stops of the enabled obstacles, lower first: stop k of [`Height::stop`].
    pub stops: Vec<StopLabel>,
    /// Per side (lower, upper), the height nearest to the plate at rest over the clamp
    /// ([`Scene::clamp_heights`]).
    pub clamp_heights: [Option<f64>; 2],
}

impl ObstacleLayout {
    /// The layout of `scene` on its mesh, whose `vertices` are the structured grid's
    /// ([`crate::mesh::grid_vertices`], vertex (i, j) at index i + j (nx + 1)), with the clamp
    /// `clamped`. The scene's profiles must parse
    /// (a validated scene's do); an error names the profile whose stops need more own points
    /// than [`MAX_OWN_POINTS`].
    pub fn new(
        scene: &Scene,
        vertices: &[[f64; 2]],
        clamped: &ClampedEdges,
    ) -> Result<ObstacleLayout, Error> {
        let spacing = scene.cell_size();
        let tolerance = 1e-9 * spacing;
        let size = scene.size();
        let enabled: Vec<(ObstacleSide, Profile)> = ObstacleSide::BOTH
            .into_iter()
            .filter(|&side| scene.level(side).is_some())
            .map(|side| scene.profile(side).map(|p| (side, p)))
            .collect::<Result<_, _>>()?;
        // Stop numbering over both obstacles, lower first.
        let mut stops = Vec::new();
        let mut first_stop = [0usize; 2];
        for (side, profile) in &enabled {
            first_stop[side_index(*side)] = stops.len();
            if let Profile::Stops(list) = profile {
                stops.extend((0..list.len()).map(|index| StopLabel { side: *side, index }));
            }
        }
        let height_at = |side: ObstacleSide, profile: &Profile, p: [f64; 2]| match profile {
            Profile::Stops(_) => profile
                .stop_height(p, side, tolerance)
                .map(|(k, h)| Height {
                    h,
                    stop: Some(first_stop[side_index(side)] + k),
                }),
            _ => profile
                .plate_height(p, size)
                .map(|h| Height { h, stop: None }),
        };
        let on_clamp = |p: [f64; 2]| !clamped.sides_through(p, tolerance).is_empty();
        // The heights over every vertex: a profile over the plate everywhere, a stop over the
        // vertices of its bounding box that its footprint holds.
        let (nx, ny) = (scene.mesh.nx, scene.mesh.ny);
        let mut over: Vec<[Option<Height>; 2]> = vec![[None, None]; vertices.len()];
        for (side, profile) in &enabled {
            let s = side_index(*side);
            match profile {
                Profile::Stops(list) => {
                    for (k, stop) in list.iter().enumerate() {
                        let label = Height {
                            h: stop.offset,
                            stop: Some(first_stop[s] + k),
                        };
                        let [low, high] = stop.shape.bounding_box();
                        let range = |a: usize, n: usize| {
                            let cell = size[a] / n as f64;
                            let from = ((low[a] - tolerance) / cell).ceil().max(0.0) as usize;
                            let to = ((high[a] + tolerance) / cell).floor().min(n as f64);
                            from..(to.max(-1.0) + 1.0) as usize
                        };
                        for j in range(1, ny) {
                            for i in range(0, nx) {
                                let v = i + j * (nx + 1);
                                if !stop.shape.contains(vertices[v], tolerance) {
                                    continue;
                                }
                                let slot = &mut over[v][s];
                                if slot.is_none_or(|h| nearer(*side, label.h, h.h)) {
                                    *slot = Some(label);
                                }
                            }
                        }
                    }
                }
                _ => {
                    for (v, &p) in vertices.iter().enumerate() {
                        over[v][s] = profile
                            .plate_height(p, size)
                            .map(|h| Height { h, stop: None });
                    }
                }
            }
        }
        let mut points = Vec::new();
        for (v, &p) in vertices.iter().enumerate() {
            let [lower, upper] = over[v];
            if (lower.is_some() || upper.is_some()) && !on_clamp(p) {
                points.push(ContactPoint {
                    position: p,
                    vertex: Some(v),
                    lower,
                    upper,
                });
            }
        }
        let merge = MERGE_FRACTION * spacing;
        let mut buckets = Buckets::new(merge);
        if !stops.is_empty() {
            for (k, point) in points.iter().enumerate() {
                buckets.insert(point.position, k);
            }
        }
        for (side, profile) in &enabled {
            let Profile::Stops(list) = profile else {
                continue;
            };
            let mut own = 0;
            for (k, stop) in list.iter().enumerate() {
                let label = Height {
                    h: stop.offset,
                    stop: Some(first_stop[side_index(*side)] + k),
                };
                for q in stop.shape.own_points(spacing) {
                    let on_plate = (-tolerance..=size[0] + tolerance).contains(&q[0])
                        && (-tolerance..=size[1] + tolerance).contains(&q[1]);
                    if !on_plate || on_clamp(q) {
                        continue;
                    }
                    if let Some(existing) = buckets.near(q, &points) {
                        let slot = points[existing].height_mut(*side);
                        if slot.is_none_or(|h| nearer(*side, label.h, h.h)) {
                            *slot = Some(label);
                        }
                        continue;
                    }
                    own += 1;
                    if own > MAX_OWN_POINTS {
                        return Err(Error::invalid(
                            side.profile_parameter(),
                            format!("\"{}\"", profile_text(scene, *side)),
                            &format!(
                                "needs more than {MAX_OWN_POINTS} contact points of its own on \
                                 the {} × {} mesh (up to {MAX_STOPS} stops, each sampled at \
                                 the cell size): use fewer or smaller stops, or a table",
                                scene.mesh.nx, scene.mesh.ny
                            ),
                        ));
                    }
                    let mut point = ContactPoint {
                        position: q,
                        vertex: None,
                        lower: None,
                        upper: None,
                    };
                    for (other, other_profile) in &enabled {
                        *point.height_mut(*other) = height_at(*other, other_profile, q);
                    }
                    // The stop's own point lies in its footprint, so height_at found a stop; a
                    // point of a circle's round-off can miss it by an ulp: it is this stop's.
                    if point.height(*side).is_none() {
                        *point.height_mut(*side) = Some(label);
                    }
                    buckets.insert(q, points.len());
                    points.push(point);
                }
            }
        }
        Ok(ObstacleLayout {
            points,
            stops,
            clamp_heights: scene.clamp_heights()?,
        })
    }

    /// The heights of each side at every point, [h₁, h₂], with −∞ and +∞ where an obstacle is
    /// absent: the level plus the height is the bound ([`Scene::first_outside`]).
    pub fn heights(&self) -> [Vec<f64>; 2] {
        ObstacleSide::BOTH.map(|side| {
            let absent = match side {
                ObstacleSide::Lower => f64::NEG_INFINITY,
                ObstacleSide::Upper => f64::INFINITY,
            };
            self.points
                .iter()
                .map(|p| p.height(side).map_or(absent, |h| h.h))
                .collect()
        })
    }

    /// Whether every point is a mesh vertex (no stop adds points of its own).
    pub fn vertices_only(&self) -> bool {
        self.points.iter().all(|p| p.vertex.is_some())
    }
}

/// 0 for the lower side, 1 for the upper.
fn side_index(side: ObstacleSide) -> usize {
    match side {
        ObstacleSide::Lower => 0,
        ObstacleSide::Upper => 1,
    }
}

/// Whether height `a` lies nearer the plate at rest than `b` on `side`.
fn nearer(side: ObstacleSide, a: f64, b: f64) -> bool {
    match side {
        ObstacleSide::Lower => a > b,
        ObstacleSide::Upper => a < b,
    }
}

fn profile_text(scene: &Scene, side: ObstacleSide) -> &str {
    match side {
        ObstacleSide::Lower => &scene.obstacle.lower_profile,
        ObstacleSide::Upper => &scene.obstacle.upper_profile,
    }
}

/// Points bucketed on a grid of the merge distance, to find a point within it in O(1).
struct Buckets {
    size: f64,
    cells: HashMap<(i64, i64), Vec<usize>>,
}

impl Buckets {
    fn new(size: f64) -> Buckets {
        Buckets {
            size,
            cells: HashMap::new(),
        }
    }

    fn key(&self, p: [f64; 2]) -> (i64, i64) {
        (
            (p[0] / self.size).floor() as i64,
            (p[1] / self.size).floor() as i64,
        )
    }

    fn insert(&mut self, p: [f64; 2], index: usize) {
        let key = self.key(p);
        self.cells.entry(key).or_default().push(index);
    }

    /// The point of least index within the merge distance of `p`, if any.
    fn near(&self, p: [f64; 2], points: &[ContactPoint]) -> Option<usize> {
        let (i, j) = self.key(p);
        let mut found: Option<usize> = None;
        for di in -1..=1 {
            for dj in -1..=1 {
                for &k in self.cells.get(&(i + di, j + dj)).into_iter().flatten() {
                    let q = points[k].position;
                    if libm::hypot(q[0] - p[0], q[1] - p[1]) <= self.size {
                        found = Some(found.map_or(k, |f| f.min(k)));
                    }
                }
            }
        }
        found
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::grid_vertices;

    fn layout(scene: &Scene) -> ObstacleLayout {
        let vertices = grid_vertices(
            scene.plate.length,
            scene.plate.width,
            scene.mesh.nx,
            scene.mesh.ny,
        );
        ObstacleLayout::new(scene, &vertices, &scene.clamped_edges().unwrap()).unwrap()
    }

    /// Flat obstacles: every vertex off the clamp, in vertex order, heights 0, as before
    /// profiles existed.
    #[test]
    fn flat_obstacles_constrain_every_vertex_off_the_clamp() {
        let scene = Scene::default();
        let l = layout(&scene);
        let (nx, ny) = (scene.mesh.nx, scene.mesh.ny);
        assert_eq!(l.points.len(), nx * (ny + 1));
        assert!(l.vertices_only() && l.stops.is_empty());
        assert!(l.points.iter().all(|p| p.position[0] > 0.0
            && p.lower.unwrap().h == 0.0
            && p.upper.unwrap().h == 0.0));
        let vertices: Vec<usize> = l.points.iter().map(|p| p.vertex.unwrap()).collect();
        assert!(vertices.windows(2).all(|w| w[0] < w[1]));
        assert_eq!(l.clamp_heights, [Some(0.0), Some(0.0)]);
    }

    /// A point stop between vertices is a contact point of its own; a disc far smaller than a
    /// cell is merged to its centre; a stop at a vertex is that vertex.
    #[test]
    fn stops_add_their_own_points() {
        let mut scene = Scene::default();
        scene.obstacle.upper_enabled = false;
        scene.obstacle.lower_profile = "point(x=0.39, y=0.01); disc(x=0.2, y=0.1, radius=1e-5, \
                                        offset=0.002); point(x=0.4, y=0.2, offset=-0.001)"
            .to_string();
        scene.validate().unwrap();
        let l = layout(&scene);
        // The corner (0.4, 0.2) is the vertex of the third stop; the other two add one point each.
        assert_eq!(l.points.len(), 3, "{:?}", l.points);
        let corner = &l.points[0];
        assert_eq!(corner.position, [0.4, 0.2]);
        assert_eq!(
            corner.lower,
            Some(Height {
                h: -0.001,
                stop: Some(2)
            })
        );
        assert_eq!(l.points[1].position, [0.39, 0.01]);
        assert_eq!(l.points[1].vertex, None);
        assert_eq!(l.points[2].position, [0.2, 0.1]);
        assert_eq!(
            l.points[2].lower,
            Some(Height {
                h: 0.002,
                stop: Some(1)
            })
        );
        assert_eq!(l.stops.len(), 3);
        assert_eq!(l.clamp_heights, [None, None]);
    }

    /// A large stop takes the vertices inside it and its outline; the other obstacle's height
    /// reaches the stop's own points.
    #[test]
    fn a_large_stop_takes_its_vertices_and_outline() {
        let mut scene = Scene::default();
        scene.obstacle.lower_profile = "rectangle(x0=0.1, y0=0.05, x1=0.21, y1=0.15)".to_string();
        scene.obstacle.upper_profile = "plane(slope_x=0.01)".to_string();
        let l = layout(&scene);
        let inside = l.points.iter().filter(|p| p.lower.is_some()).count();
        // Vertices at x = 0.12, 0.16, 0.20 and y = 0.0571…, 0.0857…, 0.1143…, 0.1429…: 12;
        // the outline at the cell size 0.02857 m and the centre add to them.
        let vertices = l
            .points
            .iter()
            .filter(|p| p.lower.is_some() && p.vertex.is_some())
            .count();
        assert_eq!(vertices, 12);
        assert!(inside > vertices + 4, "{inside}");
        for p in l.points.iter().filter(|p| p.vertex.is_none()) {
            let upper = p.upper.unwrap().h;
            assert!((upper - 0.01 * (p.position[0] - 0.2)).abs() < 1e-15);
        }
    }
}
