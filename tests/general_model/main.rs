//! The generalised model (docs/model.md: any clamped part Γc of the edge, obstacle profiles and
//! local stops whose contact rows go through the element's basis) against independent
//! references, on both elements. The refinement studies, slower, are in
//! tests/general_model_refinement/.

// Index loops read closer to the formulas they check.
#![allow(clippy::needless_range_loop)]

mod energy;
mod independent;
mod plates;
mod ritz;
mod spectra;
mod static_stud;
mod trajectory;
