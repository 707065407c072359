//! Global dofs, sparse assembly of M, K and the pressure load, the clamp, and point evaluation
//! (`docs/elements.md` §5–6).
//!
//! Global dof numbering: vertex v carries dofs `k·v … k·v + k − 1` in the element's local vertex
//! order (k = 6 for Argyris: w, h w_x, h w_y, h² w_xx, h² w_xy, h² w_yy; k = 3 for FVS: w, h w_x,
//! h w_y); Argyris edge e then carries dof `6·n_vertices + e` (h ∂w/∂n at its midpoint, normal
//! oriented as in [`crate::element`]).

use crate::element::argyris::ArgyrisCell;
use crate::element::fvs::FvsCell;
use crate::element::{CellBasis, ElementKind, Jet};
use crate::mesh::Mesh;
use crate::scene::{ClampedEdges, Side};
use faer::sparse::{SparseColMat, Triplet};

/// Quadrature degree for the stiffness: on affine cells the Hessian of a quintic is cubic, so the
/// integrand of a(φ_i, φ_j) is P6 for Argyris; FVS pieces are cubic, Hessians P1, products P2.
fn stiffness_degree(kind: ElementKind) -> usize {
    match kind {
        ElementKind::Argyris => 6,
        ElementKind::Fvs => 2,
    }
}

/// Quadrature degree for the consistent mass: products of two basis functions (P5·P5 = P10,
/// P3·P3 = P6 per FVS piece).
fn mass_degree(kind: ElementKind) -> usize {
    match kind {
        ElementKind::Argyris => 10,
        ElementKind::Fvs => 6,
    }
}

/// Vertex dofs per vertex.
pub fn dofs_per_vertex(kind: ElementKind) -> usize {
    match kind {
        ElementKind::Argyris => 6,
        ElementKind::Fvs => 3,
    }
}

/// A linear functional on the global dof vector: u ↦ Σₖ `weights[k]` · `u[dofs[k]]`.
#[derive(Clone, Debug, PartialEq)]
pub struct PointFunctional {
    /// Global dofs involved.
    pub dofs: Vec<usize>,
    /// Their weights.
    pub weights: Vec<f64>,
}

impl PointFunctional {
    /// Applies the functional to a global dof vector.
    pub fn apply(&self, u: &[f64]) -> f64 {
        self.dofs
            .iter()
            .zip(&self.weights)
            .map(|(&d, &w)| w * u[d])
            .sum()
    }
}

/// The C¹ finite element space on a mesh: dof numbering, cell bases and assembly.
#[derive(Clone, Debug)]
pub struct Discretization {
    /// The mesh (triangles for Argyris, quadrilaterals for FVS).
    pub mesh: Mesh,
    /// The element family.
    pub element: ElementKind,
    /// Length scale of the derivative dofs (m): the mesh size.
    pub h: f64,
    /// Total number of global dofs.
    pub dof_count: usize,
    cell_dofs: Vec<Vec<usize>>,
}

impl Discretization {
    /// The space of `element` on `mesh`.
    ///
    /// # Panics
    /// If the mesh's cell shape does not match the element (a programming error).
    pub fn new(mesh: Mesh, element: ElementKind) -> Discretization {
        let expected = match element {
            ElementKind::Argyris => crate::mesh::CellShape::Triangle,
            ElementKind::Fvs => crate::mesh::CellShape::Quadrilateral,
        };
        assert_eq!(mesh.shape, expected, "{element:?} needs {expected:?} cells");
        let k = dofs_per_vertex(element);
        let nv = mesh.vertices.len();
        let cell_dofs = (0..mesh.cells.len())
            .map(|c| {
                let mut dofs: Vec<usize> = mesh.cells[c]
                    .iter()
                    .flat_map(|&v| (k * v)..(k * v + k))
                    .collect();
                if element == ElementKind::Argyris {
                    dofs.extend(mesh.cell_edges[c].iter().map(|&e| k * nv + e));
                }
                dofs
            })
            .collect();
        let dof_count = k * nv
            + if element == ElementKind::Argyris {
                mesh.edges.len()
            } else {
                0
            };
        let h = mesh.size();
        Discretization {
            mesh,
            element,
            h,
            dof_count,
            cell_dofs,
        }
    }

    /// The structured mesh of (0, lx) × (0, ly) with nx × ny cells that suits `element`.
    pub fn rectangle(
        element: ElementKind,
        lx: f64,
        ly: f64,
        nx: usize,
        ny: usize,
    ) -> Discretization {
        let mesh = match element {
            ElementKind::Argyris => Mesh::rectangle_triangles(lx, ly, nx, ny),
            ElementKind::Fvs => Mesh::rectangle_quads(lx, ly, nx, ny),
        };
        Discretization::new(mesh, element)
    }

    /// Global dofs of cell `c`, in the element's local order.
    pub fn cell_dofs(&self, c: usize) -> &[usize] {
        &self.cell_dofs[c]
    }

    /// The basis of cell `c`.
    pub fn cell_basis(&self, c: usize) -> Box<dyn CellBasis> {
        let ids = &self.mesh.cells[c];
        let x = |k: usize| self.mesh.vertices[ids[k]];
        match self.element {
            ElementKind::Argyris => Box::new(ArgyrisCell::new(
                [x(0), x(1), x(2)],
                [ids[0], ids[1], ids[2]],
                self.h,
            )),
            ElementKind::Fvs => Box::new(FvsCell::new([x(0), x(1), x(2), x(3)], self.h)),
        }
    }

    /// The value dof (w) of vertex `v`.
    pub fn value_dof(&self, v: usize) -> usize {
        dofs_per_vertex(self.element) * v
    }

    /// The vertices of the clamp Γc (`clamp`, on this mesh), sorted, each with the sides of the
    /// plate along which it is clamped (two at a corner where two clamped sides meet).
    pub fn clamped_vertices(&self, clamp: &ClampedEdges) -> Vec<(usize, Vec<Side>)> {
        let tolerance = 1e-9 * self.h;
        (0..self.mesh.vertices.len())
            .map(|v| (v, clamp.sides_through(self.mesh.vertices[v], tolerance)))
            .filter(|(_, sides)| !sides.is_empty())
            .collect()
    }

    /// The dofs the clamp `clamp` fixes (`docs/elements.md` §5), sorted: at every vertex of Γc
    /// w (= z(t)), w_x and w_y; for Argyris also the second derivatives that u = z and ∂u/∂n = 0
    /// along each clamped side through the vertex fix (along x = const: w_yy and w_xy; along
    /// y = const: w_xx and w_xy; all three at a corner of two clamped sides) and the normal
    /// derivative at the midpoint of every mesh edge of Γc. Every one of them is 0 except the
    /// value dofs, which equal z(t).
    pub fn clamp_dofs(&self, clamp: &ClampedEdges) -> Vec<usize> {
        let k = dofs_per_vertex(self.element);
        let mut dofs: Vec<usize> = Vec::new();
        for (v, sides) in self.clamped_vertices(clamp) {
            let mut local = vec![0, 1, 2];
            if self.element == ElementKind::Argyris {
                for side in sides {
                    // Along x = const the tangent is y: w_yy (5) and w_xy (4); else w_xx (3).
                    local.extend(if side.is_x_constant() { [4, 5] } else { [3, 4] });
                }
            }
            local.sort_unstable();
            local.dedup();
            dofs.extend(local.into_iter().map(|j| k * v + j));
        }
        if self.element == ElementKind::Argyris {
            let tolerance = 1e-9 * self.h;
            let nv = self.mesh.vertices.len();
            dofs.extend(
                self.mesh
                    .edges
                    .iter()
                    .enumerate()
                    .filter(|(_, &[a, b])| {
                        let (pa, pb) = (self.mesh.vertices[a], self.mesh.vertices[b]);
                        let middle = [0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1])];
                        // An edge of Γc: its midpoint and both ends clamped along one side.
                        clamp.sides_through(middle, tolerance).iter().any(|side| {
                            let ends = [
                                clamp.sides_through(pa, tolerance),
                                clamp.sides_through(pb, tolerance),
                            ];
                            ends.iter().all(|s| s.contains(side))
                        })
                    })
                    .map(|(e, _)| k * nv + e),
            );
        }
        dofs.sort_unstable();
        dofs
    }

    /// Global dof vector of the interpolant of a smooth field (given by its jet). Shared dofs are
    /// written by every cell that holds them; they agree because the dofs are global functionals.
    pub fn interpolate(&self, field: &dyn Fn([f64; 2]) -> Jet) -> Vec<f64> {
        let mut u = vec![0.0; self.dof_count];
        for c in 0..self.mesh.cells.len() {
            let local = self.cell_basis(c).interpolate(field);
            for (&d, &value) in self.cell_dofs[c].iter().zip(&local) {
                u[d] = value;
            }
        }
        u
    }

    /// The functional u ↦ u(p) for a point of the plate, or `None` when `p` is outside the mesh.
    pub fn point_functional(&self, p: [f64; 2]) -> Option<PointFunctional> {
        let c = self.mesh.locate(p)?;
        let basis = self.cell_basis(c);
        let mut jets = vec![Jet::default(); basis.dof_count()];
        basis.eval(p, &mut jets);
        Some(PointFunctional {
            dofs: self.cell_dofs[c].clone(),
            weights: jets.iter().map(|j| j.value).collect(),
        })
    }

    /// Consistent mass M_ij = ∫ ρe φ_i φ_j and stiffness
    /// K_ij = D ∫ [(1 − ν)(φ_i,xx φ_j,xx + 2 φ_i,xy φ_j,xy + φ_i,yy φ_j,yy) + ν Δφ_i Δφ_j]
    /// (`docs/elements.md` §6), each with a quadrature exact for its integrand, as sparse symmetric
    /// matrices.
    pub fn assemble(
        &self,
        areal_mass: f64,
        bending_stiffness: f64,
        poisson_ratio: f64,
    ) -> (SparseColMat<usize, f64>, SparseColMat<usize, f64>) {
        let n_local = self.cell_dofs.first().map_or(0, Vec::len);
        let mut mass = Vec::with_capacity(self.mesh.cells.len() * n_local * n_local);
        let mut stiffness = Vec::with_capacity(mass.capacity());
        let mut jets = vec![Jet::default(); n_local];
        let mut m_loc = vec![0.0; n_local * n_local];
        let mut k_loc = vec![0.0; n_local * n_local];
        let nu = poisson_ratio;
        for c in 0..self.mesh.cells.len() {
            let basis = self.cell_basis(c);
            m_loc.fill(0.0);
            k_loc.fill(0.0);
            for q in basis.quadrature(mass_degree(self.element)) {
                basis.eval(q.point, &mut jets);
                let w = q.weight * areal_mass;
                for i in 0..n_local {
                    let wi = w * jets[i].value;
                    for j in 0..n_local {
                        m_loc[i * n_local + j] += wi * jets[j].value;
                    }
                }
            }
            for q in basis.quadrature(stiffness_degree(self.element)) {
                basis.eval(q.point, &mut jets);
                let w = q.weight * bending_stiffness;
                for i in 0..n_local {
                    let [ixx, ixy, iyy] = jets[i].hess;
                    for j in 0..n_local {
                        let [jxx, jxy, jyy] = jets[j].hess;
                        let bending = (1.0 - nu) * (ixx * jxx + 2.0 * ixy * jxy + iyy * jyy)
                            + nu * (ixx + iyy) * (jxx + jyy);
                        k_loc[i * n_local + j] += w * bending;
                    }
                }
            }
            let dofs = &self.cell_dofs[c];
            for i in 0..n_local {
                for j in 0..n_local {
                    mass.push(Triplet::new(dofs[i], dofs[j], m_loc[i * n_local + j]));
                    stiffness.push(Triplet::new(dofs[i], dofs[j], k_loc[i * n_local + j]));
                }
            }
        }
        let n = self.dof_count;
        let build = |t: &[Triplet<usize, usize, f64>]| {
            SparseColMat::try_new_from_triplets(n, n, t).expect("assembly indices are in range")
        };
        (build(&mass), build(&stiffness))
    }

    /// Load vector of a uniform pressure of 1 Pa: F_i = ∫ φ_i (m²); scale by p for p Pa.
    pub fn unit_load(&self) -> Vec<f64> {
        let mut f = vec![0.0; self.dof_count];
        let degree = match self.element {
            ElementKind::Argyris => 5,
            ElementKind::Fvs => 3,
        };
        for c in 0..self.mesh.cells.len() {
            let basis = self.cell_basis(c);
            let mut jets = vec![Jet::default(); basis.dof_count()];
            for q in basis.quadrature(degree) {
                basis.eval(q.point, &mut jets);
                for (&d, j) in self.cell_dofs[c].iter().zip(&jets) {
                    f[d] += q.weight * j.value;
                }
            }
        }
        f
    }
}
