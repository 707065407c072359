//! Meshes of the plate's mid-plane: a general list of vertices and cells, plus constructors for
//! the structured meshes of the rectangle (0, Lx) × (0, Ly) (`docs/elements.md` §1).
//!
//! Cells list their vertices counter-clockwise. Edges are global and oriented from the lower to the
//! higher vertex id; `cell_edges[c][k]` is the edge joining local vertices k and k + 1 (mod the
//! number of vertices) of cell c. The global orientation is what makes the Argyris edge dofs
//! (normal derivatives) agree between the two cells that share an edge.

use std::collections::BTreeMap;

/// The shape of every cell of a mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CellShape {
    /// Three vertices.
    Triangle,
    /// Four vertices.
    Quadrilateral,
}

impl CellShape {
    /// Number of vertices of a cell of this shape.
    pub fn vertex_count(self) -> usize {
        match self {
            CellShape::Triangle => 3,
            CellShape::Quadrilateral => 4,
        }
    }
}

/// A conforming mesh of polygons with straight edges.
#[derive(Clone, Debug)]
pub struct Mesh {
    /// Vertex coordinates (m).
    pub vertices: Vec<[f64; 2]>,
    /// Shape shared by every cell.
    pub shape: CellShape,
    /// Vertex ids of each cell, counter-clockwise.
    pub cells: Vec<Vec<usize>>,
    /// Global edges as (lower vertex id, higher vertex id).
    pub edges: Vec<[usize; 2]>,
    /// For each cell, the global id of the edge from local vertex k to local vertex k + 1.
    pub cell_edges: Vec<Vec<usize>>,
    /// The structured grid the mesh was built on, if it was: lets [`Mesh::locate`] test the
    /// cells around a point only.
    pub grid: Option<Grid>,
}

/// The structured grid of a rectangle mesh: (0, Lx) × (0, Ly) in nx × ny cells, cell (i, j)
/// being cell i + j nx of a quadrilateral mesh, or its two triangles 2(i + j nx) and
/// 2(i + j nx) + 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    /// [Lx, Ly] (m).
    pub size: [f64; 2],
    /// [nx, ny].
    pub cells: [usize; 2],
}

impl Mesh {
    /// Builds the edge tables of a mesh from its vertices and counter-clockwise cells.
    ///
    /// # Panics
    /// If a cell has the wrong number of vertices, a vertex id is out of range, or a cell is not
    /// counter-clockwise with positive area (these are programming errors, not user input).
    pub fn new(vertices: Vec<[f64; 2]>, shape: CellShape, cells: Vec<Vec<usize>>) -> Mesh {
        // Ordered, not hashed: a HashMap's per-process random keys change its probing from run
        // to run, and with it the coverage the fuzz targets see, so that a fuzz run with a fixed
        // seed would not try the same inputs twice (docs/fuzzing.md).
        let mut edge_ids: BTreeMap<[usize; 2], usize> = BTreeMap::new();
        let mut edges = Vec::new();
        let mut cell_edges = Vec::with_capacity(cells.len());
        for cell in &cells {
            assert_eq!(
                cell.len(),
                shape.vertex_count(),
                "cell {cell:?} has the wrong vertex count"
            );
            assert!(
                cell.iter().all(|&v| v < vertices.len()),
                "cell {cell:?} names a missing vertex"
            );
            assert!(
                signed_area(&vertices, cell) > 0.0,
                "cell {cell:?} is not counter-clockwise"
            );
            let n = cell.len();
            let ids = (0..n)
                .map(|k| {
                    let (a, b) = (cell[k], cell[(k + 1) % n]);
                    let key = [a.min(b), a.max(b)];
                    *edge_ids.entry(key).or_insert_with(|| {
                        edges.push(key);
                        edges.len() - 1
                    })
                })
                .collect();
            cell_edges.push(ids);
        }
        Mesh {
            vertices,
            shape,
            cells,
            edges,
            cell_edges,
            grid: None,
        }
    }

    /// Structured triangle mesh of (0, lx) × (0, ly) with nx × ny cells, each cut by the diagonal from
    /// its lower-left to its upper-right corner: 2·nx·ny triangles. Vertex (i, j) has id
    /// i + j (nx + 1).
    pub fn rectangle_triangles(lx: f64, ly: f64, nx: usize, ny: usize) -> Mesh {
        let vertices = grid_vertices(lx, ly, nx, ny);
        let mut cells = Vec::with_capacity(2 * nx * ny);
        for j in 0..ny {
            for i in 0..nx {
                let [a, b, c, d] = grid_cell(nx, i, j);
                cells.push(vec![a, b, c]);
                cells.push(vec![a, c, d]);
            }
        }
        Mesh {
            grid: Some(Grid {
                size: [lx, ly],
                cells: [nx, ny],
            }),
            ..Mesh::new(vertices, CellShape::Triangle, cells)
        }
    }

    /// Structured quadrilateral mesh of (0, lx) × (0, ly) with nx × ny rectangular cells.
    /// Vertex (i, j) has id i + j (nx + 1).
    pub fn rectangle_quads(lx: f64, ly: f64, nx: usize, ny: usize) -> Mesh {
        let vertices = grid_vertices(lx, ly, nx, ny);
        let cells = (0..ny)
            .flat_map(|j| (0..nx).map(move |i| grid_cell(nx, i, j).to_vec()))
            .collect();
        Mesh {
            grid: Some(Grid {
                size: [lx, ly],
                cells: [nx, ny],
            }),
            ..Mesh::new(vertices, CellShape::Quadrilateral, cells)
        }
    }

    /// Coordinates of the vertices of cell `c`, in its counter-clockwise order.
    pub fn cell_coordinates(&self, c: usize) -> Vec<[f64; 2]> {
        self.cells[c].iter().map(|&v| self.vertices[v]).collect()
    }

    /// The largest edge length: the mesh size h.
    pub fn size(&self) -> f64 {
        self.edges
            .iter()
            .map(|&[a, b]| distance(self.vertices[a], self.vertices[b]))
            .fold(0.0, f64::max)
    }

    /// The cell of least id that contains point `p` (boundary included, with a tolerance
    /// relative to the cell size), or `None` when `p` lies outside the mesh. On a structured
    /// mesh only the cells of the grid cells around `p` are tested, which hold every cell that
    /// contains it, so the answer is the same as testing them all.
    pub fn locate(&self, p: [f64; 2]) -> Option<usize> {
        match self.grid {
            Some(grid) => {
                let per_cell = self.cells.len() / (grid.cells[0] * grid.cells[1]);
                let near = |k: usize| {
                    let t = p[k] / grid.size[k] * grid.cells[k] as f64;
                    let index = t.floor().clamp(0.0, (grid.cells[k] - 1) as f64) as usize;
                    index.saturating_sub(1)..(index + 2).min(grid.cells[k])
                };
                let mut candidates: Vec<usize> = near(1)
                    .flat_map(|j| near(0).map(move |i| i + j * grid.cells[0]))
                    .flat_map(|cell| (0..per_cell).map(move |k| per_cell * cell + k))
                    .collect();
                candidates.sort_unstable();
                candidates.into_iter().find(|&c| self.contains(c, p))
            }
            None => (0..self.cells.len()).find(|&c| self.contains(c, p)),
        }
    }

    /// Whether cell `c` contains `p`, boundary included to 1e-12 of its size squared.
    fn contains(&self, c: usize, p: [f64; 2]) -> bool {
        let xs = self.cell_coordinates(c);
        let n = xs.len();
        let scale = (0..n)
            .map(|k| distance(xs[k], xs[(k + 1) % n]))
            .fold(0.0, f64::max);
        // A convex cell contains p when p is left of (or on) every counter-clockwise edge.
        (0..n).all(|k| {
            let (a, b) = (xs[k], xs[(k + 1) % n]);
            let cross = (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
            cross >= -1e-12 * scale * scale
        })
    }
}

/// The vertices of the structured nx × ny grid of (0, lx) × (0, ly), vertex (i, j) at index
/// i + j (nx + 1): the vertices of [`Mesh::rectangle_triangles`] and [`Mesh::rectangle_quads`].
pub fn grid_vertices(lx: f64, ly: f64, nx: usize, ny: usize) -> Vec<[f64; 2]> {
    assert!(
        nx >= 1 && ny >= 1,
        "a structured mesh needs at least one cell each way"
    );
    (0..=ny)
        .flat_map(|j| (0..=nx).map(move |i| [lx * i as f64 / nx as f64, ly * j as f64 / ny as f64]))
        .collect()
}

/// Lower-left, lower-right, upper-right, upper-left vertex ids of grid cell (i, j).
fn grid_cell(nx: usize, i: usize, j: usize) -> [usize; 4] {
    let id = |i: usize, j: usize| i + j * (nx + 1);
    [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]
}

fn signed_area(vertices: &[[f64; 2]], cell: &[usize]) -> f64 {
    let n = cell.len();
    0.5 * (0..n)
        .map(|k| {
            let (a, b) = (vertices[cell[k]], vertices[cell[(k + 1) % n]]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum::<f64>()
}

fn distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    libm::hypot(b[0] - a[0], b[1] - a[1])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn structured_meshes_have_the_expected_counts() {
        let (nx, ny) = (10, 7);
        let tri = Mesh::rectangle_triangles(0.4, 0.2, nx, ny);
        assert_eq!(tri.vertices.len(), (nx + 1) * (ny + 1));
        assert_eq!(tri.cells.len(), 2 * nx * ny);
        // Horizontal, vertical and diagonal edges.
        assert_eq!(tri.edges.len(), nx * (ny + 1) + ny * (nx + 1) + nx * ny);
        let quad = Mesh::rectangle_quads(0.4, 0.2, 14, 10);
        assert_eq!(quad.cells.len(), 140);
        assert_eq!(quad.edges.len(), 14 * 11 + 10 * 15);
    }

    #[test]
    fn interior_edges_are_shared_by_two_cells_with_opposite_directions() {
        let mesh = Mesh::rectangle_triangles(1.0, 1.0, 3, 2);
        let mut uses = vec![Vec::new(); mesh.edges.len()];
        for (c, cell) in mesh.cells.iter().enumerate() {
            for k in 0..3 {
                uses[mesh.cell_edges[c][k]].push((cell[k], cell[(k + 1) % 3]));
            }
        }
        for (e, u) in uses.iter().enumerate() {
            assert!(
                u.len() == 1 || u.len() == 2,
                "edge {e} used {} times",
                u.len()
            );
            if u.len() == 2 {
                assert_eq!(u[0], (u[1].1, u[1].0), "edge {e} not traversed both ways");
            }
        }
    }

    #[test]
    fn locate_finds_the_cell_of_interior_and_corner_points() {
        let mesh = Mesh::rectangle_quads(0.4, 0.2, 4, 2);
        assert_eq!(mesh.locate([0.05, 0.05]), Some(0));
        assert_eq!(mesh.locate([0.35, 0.15]), Some(7));
        assert!(mesh.locate([0.4, 0.2]).is_some());
        assert!(mesh.locate([0.41, 0.1]).is_none());
    }

    /// The grid's shortcut finds the cell the full scan finds, on cell boundaries too.
    #[test]
    fn locate_on_a_grid_agrees_with_the_full_scan() {
        for mesh in [
            Mesh::rectangle_triangles(0.4, 0.2, 5, 3),
            Mesh::rectangle_quads(0.4, 0.2, 5, 3),
        ] {
            let scan = Mesh {
                grid: None,
                ..mesh.clone()
            };
            for i in 0..=20 {
                for j in 0..=12 {
                    let p = [0.4 * i as f64 / 20.0, 0.2 * j as f64 / 12.0];
                    assert_eq!(mesh.locate(p), scan.locate(p), "{p:?}");
                }
            }
            assert_eq!(mesh.locate([0.45, 0.1]), None);
        }
    }
}
