//! An estimate of the memory that setting up and running a scene needs, from the scene alone
//! (before anything is assembled), so that a scene too large for the host can be refused with a
//! message that names the estimate.
//!
//! The sizes follow from the mesh and the clamp: V = (nx + 1)(ny + 1) vertices; Argyris has 6 dofs
//! per vertex and one per edge (E = nx(ny + 1) + (nx + 1)ny + nx·ny edges), of which the clamp
//! fixes 5 per clamp vertex (6 at a corner of two clamped sides) and one per clamped mesh edge;
//! FVS has 3 dofs per vertex, all fixed on the clamp. The m contact points are those of the
//! obstacles' layout ([`ObstacleLayout`]): with flat obstacles and the clamp on x = 0, the
//! nx(ny + 1) vertices off it.
//!
//! The memory, in parts (bytes; a sparse entry is an f64 and a usize index, 16 bytes; an assembly
//! triplet 24 bytes):
//!
//! * assembly: the element matrices as triplets, 2·cells·d² (d = 21 for Argyris, 12 for FVS), held
//!   while M and K are built (2·nnz entries, and about 8 bytes per triplet of workspace while one
//!   of them is sorted), where nnz ≈ 45 n (Argyris) or 27 n (FVS) entries over all n dofs
//!   (measured: 44.7 n and 26.1 n on 60 × 30, 45.1 n and 26.5 n on 100 × 50);
//! * the assembled system: M and K over all dofs and M_ff, K_ff, A_ff over the free ones, five
//!   sparse matrices, and what forming them and analysing A_ff leaves behind
//!   ([`SET_UP_TRANSIENT`] bytes per entry of A_ff);
//! * the modal backend (up to [`crate::backend_choice::MODAL_AUTO_LIMIT`] free dofs with `auto`): the dense
//!   generalized eigenproblem holds [`MODAL_DENSE_COPIES`] n × n matrices at its peak, then
//!   C = BΦ, its row-major copy and D⁻¹Cᵀ (3 m n) and W (m²); above
//!   [`DENSE_LIMIT`](crate::modes::DENSE_LIMIT) free dofs (a modal ratio, or `solver.linear =
//!   modal`) the reduction to a band holds [`MODAL_LARGE_COPIES`] n × n at its peak, and the
//!   modal data C and its row-major copy (2 m n) and W;
//! * the sparse backend: the Cholesky factor of A_ff, nnz(L) ≈ L₀ (n / n₀)^1.25 with (n₀, L₀) the
//!   factor measured with the ordering the backend keeps (nested dissection,
//!   [`crate::contact::ordering`]) on the 100 × 50 mesh (Argyris: 45 751 free dofs, 7 902 951
//!   entries; FVS: 15 300 free dofs, 1 414 620 entries): the fill grows a little faster than n
//!   (exponent 1.19–1.20 between 60 × 30 and 100 × 50), and 1.25 errs on the large side above
//!   the anchor;
//! * contact, at worst: on the modal path the factor of an active block of all m vertices (m²
//!   values); on the sparse path ([`crate::contact::sparse_contact`]) the Delassus columns within
//!   [`DEFAULT_DELASSUS_BUDGET`], the factor of an active block of up to
//!   [`delassus_limit`] indices, and for larger sets the primal elimination (a second numeric
//!   factor and a copy of A_ff).
//!
//! The estimate is the larger of the assembly peak and what the set-up holds afterwards, plus the
//! contact part. It is checked against the measured peak resident memory (`benches/solver.rs
//! -- --scale`) for both elements from 10 × 7 to 100 × 50 in the tests.

use crate::backend_choice::resolve as resolve_linear;
use crate::contact::delassus::DEFAULT_DELASSUS_BUDGET;
use crate::contact::sparse_contact::delassus_limit;
use crate::element::ElementKind;
use crate::error::Error;
use crate::mesh::grid_vertices;
use crate::obstacles::ObstacleLayout;
use crate::scene::{LinearChoice, Scene};

/// n × n dense matrices alive at the peak of the modal set-up (dense M_ff and K_ff, the Cholesky
/// factor of K_ff, the transformed pencil and its symmetric copy, the eigensolver's vectors and
/// workspace, the mode shapes): the peak resident memory measured 8.1 n² values at n = 1 951
/// (Argyris 20 × 10), the rest of the process included.
pub const MODAL_DENSE_COPIES: f64 = 8.0;

/// n × n dense matrices alive at the peak of the modal set-up above
/// [`DENSE_LIMIT`](crate::modes::DENSE_LIMIT) free dofs (the transformed pencil, the band
/// reduction's panels and the tridiagonal eigenvectors; Φ stays factored): peak resident memory
/// less the process, 2 m n and m² measured 3.2, 3.1, 3.0 n² on Argyris 20 × 14, 24 × 16, 28 × 20
/// and 2.5 n² on FVS 44 × 30.
pub const MODAL_LARGE_COPIES: f64 = 3.0;

/// Bytes per entry of A_ff that the set-up holds beyond the matrices it keeps, measured as the
/// resident memory after `Stepper::from_system` on FVS 40 × 20 to 100 × 50 (where the assembly is
/// not the peak): the two scaled copies of M_ff and K_ff that forming A makes, and the patterns
/// of the two symbolic analyses (minimum degree and nested dissection), which the allocator
/// keeps as its own free memory once they are released.
pub const SET_UP_TRANSIENT: f64 = 48.0;

/// Memory budget a set-up may need before it is refused: 4 GiB, a sixth of this 24 GiB machine.
pub const DEFAULT_MEMORY_BUDGET: usize = 4 << 30;

/// The sizes of a scene's discrete problem.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ProblemSize {
    /// Cells along x and y.
    pub mesh: (usize, usize),
    /// All dofs, clamp included.
    pub dofs: usize,
    /// Free dofs (n).
    pub free_dofs: usize,
    /// Obstacle-constrained vertices (m; 0 without obstacles).
    pub constrained: usize,
    /// Cells of the mesh (triangles for Argyris, quadrilaterals for FVS).
    pub cells: usize,
}

impl ProblemSize {
    /// The sizes of `scene`'s mesh (module docs), without assembling anything: an error when its
    /// clamp or profiles are invalid.
    pub fn of(scene: &Scene) -> Result<ProblemSize, Error> {
        let (nx, ny) = (scene.mesh.nx, scene.mesh.ny);
        let vertices = grid_vertices(scene.plate.length, scene.plate.width, nx, ny);
        let clamped = scene.clamped_edges()?;
        let tolerance = 1e-9 * scene.cell_size();
        let clamp_sides: Vec<usize> = vertices
            .iter()
            .map(|&p| clamped.sides_through(p, tolerance).len())
            .filter(|&sides| sides > 0)
            .collect();
        let clamped_edges = clamped.sides.iter().flatten().filter(|&&c| c).count();
        let (dofs, clamp, cells) = match scene.mesh.element {
            ElementKind::Argyris => {
                let edges = nx * (ny + 1) + (nx + 1) * ny + nx * ny;
                // 5 dofs per clamp vertex, 6 where two clamped sides meet, one per clamped edge.
                let fixed = clamp_sides.iter().map(|&s| 4 + s).sum::<usize>() + clamped_edges;
                (6 * vertices.len() + edges, fixed, 2 * nx * ny)
            }
            ElementKind::Fvs => (3 * vertices.len(), 3 * clamp_sides.len(), nx * ny),
        };
        let layout = ObstacleLayout::new(scene, &vertices, &clamped)?;
        Ok(ProblemSize {
            mesh: (nx, ny),
            dofs,
            free_dofs: dofs - clamp,
            constrained: layout.points.len(),
            cells,
        })
    }
}

/// The estimated memory of a set-up, in parts (bytes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MemoryEstimate {
    /// The sizes it was computed from.
    pub size: ProblemSize,
    /// The backend `auto` (or the scene's choice) gives.
    pub backend: LinearChoice,
    /// Peak while M and K are assembled.
    pub assembly: usize,
    /// The assembled sparse matrices kept afterwards.
    pub system: usize,
    /// The linear backend (dense modal data at its set-up peak, or the sparse factor).
    pub backend_data: usize,
    /// Contact structures at worst (every constrained vertex active).
    pub contact: usize,
}

impl MemoryEstimate {
    /// The estimate of `scene` (module docs): an error when its clamp or profiles are invalid.
    pub fn of(scene: &Scene) -> Result<MemoryEstimate, Error> {
        let size = ProblemSize::of(scene)?;
        let (n, m) = (size.free_dofs as f64, size.constrained as f64);
        let (entries_per_dof, cell_dofs, n0, l0) = match scene.mesh.element {
            ElementKind::Argyris => (45.0, 21.0, 45_751.0, 7_902_951.0),
            ElementKind::Fvs => (27.0, 12.0, 15_300.0, 1_414_620.0),
        };
        let backend = resolve_linear(scene, size.free_dofs);
        let nnz_all = entries_per_dof * size.dofs as f64;
        let nnz_free = entries_per_dof * n;
        let triplets_per_matrix = size.cells as f64 * cell_dofs * cell_dofs;
        let assembly = triplets_per_matrix * (2.0 * 24.0 + 8.0) + 2.0 * nnz_all * 16.0;
        let system = 2.0 * nnz_all * 16.0 + 3.0 * nnz_free * 16.0 + nnz_free * SET_UP_TRANSIENT;
        let (backend_data, contact) = match backend {
            // W is part of the modal data; the active block's factor may reach m × m.
            LinearChoice::Modal if size.free_dofs > crate::modes::DENSE_LIMIT => (
                8.0 * (MODAL_LARGE_COPIES * n * n + 2.0 * m * n + m * m),
                8.0 * m * m,
            ),
            LinearChoice::Modal => (
                8.0 * (MODAL_DENSE_COPIES * n * n + 3.0 * m * n + m * m),
                8.0 * m * m,
            ),
            _ => {
                let factor = l0 * (n / n0).powf(1.25) * 8.0;
                let columns = (8.0 * m * m).min(DEFAULT_DELASSUS_BUDGET as f64);
                let block = 8.0 * (delassus_limit(size.constrained) as f64).powi(2);
                let eliminated = factor + nnz_free * 16.0;
                (factor, columns + block + eliminated)
            }
        };
        Ok(MemoryEstimate {
            size,
            backend,
            assembly: assembly as usize,
            system: system as usize,
            backend_data: backend_data as usize,
            contact: contact as usize,
        })
    }

    /// The estimated peak of the set-up: the larger of the assembly peak and what the set-up
    /// holds afterwards.
    pub fn setup(&self) -> usize {
        self.assembly.max(self.system + self.backend_data)
    }

    /// The estimated peak of a run: [`Self::setup`] plus the contact structures at worst.
    pub fn total(&self) -> usize {
        self.setup() + self.contact
    }

    /// Ok when [`Self::total`] fits `budget` bytes; otherwise an error that names the estimate,
    /// its largest part and the budget.
    pub fn check(&self, budget: usize) -> Result<(), Error> {
        if self.total() <= budget {
            return Ok(());
        }
        let mib = |b: usize| b as f64 / (1u64 << 20) as f64;
        let parts = [
            ("assembly", self.assembly),
            ("assembled matrices", self.system),
            ("linear backend", self.backend_data),
            ("contact structures", self.contact),
        ];
        let (name, bytes) = parts.iter().max_by_key(|p| p.1).expect("four parts");
        Err(Error::invalid(
            "mesh.nx, mesh.ny",
            format!(
                "{} × {} ({:?} backend, {} free dofs, {} constrained vertices)",
                self.size.mesh.0,
                self.size.mesh.1,
                self.backend,
                self.size.free_dofs,
                self.size.constrained
            ),
            &format!(
                "needs an estimated {:.0} MiB (largest part: {name}, {:.0} MiB), more than the \
                 memory budget of {:.0} MiB",
                mib(self.total()),
                mib(*bytes),
                mib(budget)
            ),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system::PlateSystem;

    fn scene(element: ElementKind, nx: usize, ny: usize) -> Scene {
        let mut s = Scene::named("forced-35hz").unwrap();
        s.mesh.element = element;
        s.mesh.nx = nx;
        s.mesh.ny = ny;
        s
    }

    #[test]
    fn sizes_match_the_assembled_plate() {
        for (element, nx, ny) in [
            (ElementKind::Argyris, 1, 1),
            (ElementKind::Argyris, 10, 7),
            (ElementKind::Argyris, 7, 3),
            (ElementKind::Fvs, 1, 1),
            (ElementKind::Fvs, 14, 10),
            (ElementKind::Fvs, 9, 4),
        ] {
            let s = scene(element, nx, ny);
            let plate = PlateSystem::new(&s).unwrap();
            let size = ProblemSize::of(&s).unwrap();
            assert_eq!(size.dofs, plate.disc.dof_count, "{element:?} {nx}×{ny}");
            assert_eq!(size.free_dofs, plate.free.len(), "{element:?} {nx}×{ny}");
            assert_eq!(
                size.constrained,
                plate.contact_rows.len(),
                "{element:?} {nx}×{ny}"
            );
            assert_eq!(
                size.cells,
                plate.disc.mesh.cells.len(),
                "{element:?} {nx}×{ny}"
            );
        }
        let mut free_plate = scene(ElementKind::Fvs, 4, 2);
        free_plate.obstacle.lower_enabled = false;
        free_plate.obstacle.upper_enabled = false;
        assert_eq!(ProblemSize::of(&free_plate).unwrap().constrained, 0);
    }

    /// The set-up estimate against the peak resident memory measured by `cargo bench --bench
    /// solver -- --scale` (VmHWM after `Stepper::from_system`, the process's own few MiB
    /// included), on this machine.
    #[test]
    fn the_setup_estimate_follows_the_measured_peaks() {
        let measured_mib = [
            (ElementKind::Argyris, 10, 7, 41.1),
            (ElementKind::Argyris, 14, 10, 128.2),
            (ElementKind::Argyris, 20, 10, 249.0),
            (ElementKind::Argyris, 30, 15, 31.6),
            (ElementKind::Argyris, 40, 20, 52.8),
            (ElementKind::Argyris, 60, 30, 115.2),
            (ElementKind::Argyris, 80, 40, 198.3),
            (ElementKind::Argyris, 100, 50, 309.5),
            (ElementKind::Fvs, 10, 7, 9.3),
            (ElementKind::Fvs, 14, 10, 20.0),
            (ElementKind::Fvs, 20, 10, 35.0),
            (ElementKind::Fvs, 30, 15, 136.6),
            (ElementKind::Fvs, 40, 20, 14.4),
            (ElementKind::Fvs, 60, 30, 24.9),
            (ElementKind::Fvs, 80, 40, 42.7),
            (ElementKind::Fvs, 100, 50, 66.1),
        ];
        assert_estimates_follow(&measured_mib, LinearChoice::Auto);
    }

    /// As above for the modal backend above `DENSE_LIMIT` free dofs (`cargo bench --bench solver
    /// -- --case sweep-ELEMENT-NXxNY-modal`, VmHWM after the set-up; 2026-12-05).
    #[test]
    fn the_large_modal_estimate_follows_the_measured_peaks() {
        let measured_mib = [
            (ElementKind::Argyris, 20, 14, 193.9),
            (ElementKind::Argyris, 24, 16, 344.3),
            (ElementKind::Argyris, 28, 20, 696.3),
            (ElementKind::Fvs, 44, 30, 428.8),
        ];
        for &(element, nx, ny, _) in &measured_mib {
            let size = ProblemSize::of(&scene(element, nx, ny)).unwrap();
            assert!(size.free_dofs > crate::modes::DENSE_LIMIT);
        }
        assert_estimates_follow(&measured_mib, LinearChoice::Modal);
    }

    /// Each (element, nx, ny, measured peak in MiB) with the backend `linear`: the set-up estimate
    /// lies within 0.85–1.2 of the measured peak less the process's own.
    fn assert_estimates_follow(
        measured_mib: &[(ElementKind, usize, usize, f64)],
        linear: LinearChoice,
    ) {
        // The process's own peak before any set-up: 5 MiB, measured on a 1 × 1 mesh.
        let process = 5.0;
        for &(element, nx, ny, measured) in measured_mib {
            let mut scene = scene(element, nx, ny);
            scene.solver.linear = linear;
            let estimate = MemoryEstimate::of(&scene).unwrap();
            let ratio = estimate.setup() as f64 / (1u64 << 20) as f64 / (measured - process);
            println!("{element:?} {nx}×{ny}: estimate / measured = {ratio:.2}");
            // The spread of the calibration (assembly workspace, dense copies, fill exponent;
            // 2.5–3.2 n² at the peak of a large modal set-up about its 3.0), and a measured peak
            // rounded to 1 MiB.
            assert!(
                (0.85..=1.2).contains(&ratio),
                "{element:?} {nx}×{ny}: estimate / measured = {ratio:.2}"
            );
        }
    }

    #[test]
    fn an_estimate_over_the_budget_is_refused_by_name() {
        let estimate = MemoryEstimate::of(&scene(ElementKind::Argyris, 400, 400)).unwrap();
        assert_eq!(estimate.backend, LinearChoice::Sparse);
        let err = estimate
            .check(DEFAULT_MEMORY_BUDGET)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("mesh.nx, mesh.ny") && err.contains("400 × 400"),
            "{err}"
        );
        assert!(err.contains("MiB") && err.contains("4096 MiB"), "{err}");
        assert!(MemoryEstimate::of(&scene(ElementKind::Fvs, 14, 10))
            .unwrap()
            .check(DEFAULT_MEMORY_BUDGET)
            .is_ok());
    }

    /// The stepper refuses such a scene before assembling anything (which would take minutes and
    /// tens of GiB for 400 × 400 Argyris), with the estimate's message; meshes within the budget
    /// set up.
    #[test]
    fn the_stepper_refuses_a_scene_over_the_budget() {
        let err = match crate::scheme::Stepper::new(&scene(ElementKind::Argyris, 400, 400), 0.0) {
            Ok(_) => panic!("a 400 × 400 Argyris mesh must be refused"),
            Err(err) => err.to_string(),
        };
        let expected = MemoryEstimate::of(&scene(ElementKind::Argyris, 400, 400))
            .unwrap()
            .check(DEFAULT_MEMORY_BUDGET)
            .unwrap_err()
            .to_string();
        assert_eq!(err, expected);
        assert!(
            err.contains("largest part") && err.contains("budget"),
            "{err}"
        );
        assert!(crate::scheme::Stepper::new(&scene(ElementKind::Fvs, 14, 10), 0.0).is_ok());
    }
}
