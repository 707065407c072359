//! C¹ plate elements: the basis functions of one cell, in physical coordinates.
//!
//! Both elements (`docs/elements.md` §3–4) implement [`CellBasis`]. Their local dofs, and the
//! scaling that keeps the assembled matrices well conditioned (derivative dofs multiplied by powers
//! of the global length scale `h`, `docs/elements.md` §2), are:
//!
//! * Argyris (21 dofs): for local vertex k = 0, 1, 2 the six dofs at index 6k…6k+5 are
//!   (w, h w_x, h w_y, h² w_xx, h² w_xy, h² w_yy); dof 18 + k is h ∂w/∂n at the midpoint of the edge
//!   from local vertex k to k + 1, where n is the clockwise rotation of the unit tangent oriented from
//!   the lower to the higher *global* vertex id (so both cells of an edge agree).
//! * Reduced Fraeijs de Veubeke–Sanders (12 dofs): for local vertex k = 0…3 the dofs at 3k…3k+2 are
//!   (w, h w_x, h w_y).

pub mod argyris;
pub mod fvs;

use serde::{Deserialize, Serialize};

/// Value, gradient and Hessian of a scalar field at a point: hess = [f_xx, f_xy, f_yy].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Jet {
    /// f
    pub value: f64,
    /// [f_x, f_y]
    pub grad: [f64; 2],
    /// [f_xx, f_xy, f_yy]
    pub hess: [f64; 3],
}

/// The element family of a mesh (FMU variable `mesh.element`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ElementKind {
    /// Quintic Argyris triangle, 21 dofs.
    Argyris,
    /// Reduced Fraeijs de Veubeke–Sanders quadrilateral, 12 dofs.
    Fvs,
}

impl ElementKind {
    /// Parses `argyris` or `fvs`.
    pub fn parse(name: &str) -> Option<ElementKind> {
        match name {
            "argyris" => Some(ElementKind::Argyris),
            "fvs" => Some(ElementKind::Fvs),
            _ => None,
        }
    }

    /// The integer code of the FMU variable `mesh.element`: 1 for Argyris, 2 for FVS.
    pub fn code(self) -> i32 {
        match self {
            ElementKind::Argyris => 1,
            ElementKind::Fvs => 2,
        }
    }

    /// The element family of a `mesh.element` code, the inverse of [`ElementKind::code`].
    pub fn from_code(code: i32) -> Option<ElementKind> {
        match code {
            1 => Some(ElementKind::Argyris),
            2 => Some(ElementKind::Fvs),
            _ => None,
        }
    }
}

/// The shape functions of one element on one physical cell.
pub trait CellBasis {
    /// Number of local dofs (21 for Argyris, 12 for FVS).
    fn dof_count(&self) -> usize;

    /// Value, gradient and Hessian of every basis function at the physical point `p`, which lies in
    /// the cell (up to round-off). `out.len() == self.dof_count()`. For the FVS macro-element the
    /// Hessian is that of the sub-triangle containing `p` (it jumps across the diagonals).
    fn eval(&self, p: [f64; 2], out: &mut [Jet]);

    /// The local dofs applied to a smooth field given by its jet: the coefficients of its
    /// interpolant in this basis (with the dof scaling described in the module docs).
    fn interpolate(&self, field: &dyn Fn([f64; 2]) -> Jet) -> Vec<f64>;

    /// Physical quadrature points and weights, exact for every function that is a polynomial of
    /// total degree ≤ `degree` on each polynomial piece of the element.
    fn quadrature(&self, degree: usize) -> Vec<crate::quadrature::QuadPoint>;
}
