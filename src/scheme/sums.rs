//! What a backend forms over fields for the stepper: the sums of one field that every step
//! needs, and the quadratic and linear forms of two consecutive fields that the discrete energy
//! needs.

/// The quadratic and linear forms of two consecutive fields that the discrete energy needs.
#[derive(Clone, Copy, Debug, Default)]
pub struct EnergyPieces {
    /// ẇᵀMẇ with ẇ = (w_n − w_{n−1})/Δt.
    pub velocity_mass_velocity: f64,
    /// m₁ᵀẇ.
    pub translation_mass_velocity: f64,
    /// w_nᵀ K w_n.
    pub stiffness_current: f64,
    /// w_{n−1}ᵀ K w_{n−1}.
    pub stiffness_previous: f64,
    /// fᵀ w_n.
    pub load_current: f64,
    /// fᵀ w_{n−1}.
    pub load_previous: f64,
}

/// The sums over a field that every step needs, formed in one pass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FieldSums {
    /// An upper bound on ‖x‖², the squared Euclidean norm in the backend's coordinates, equal to
    /// it to round-off from `FieldMaps::field_sums` (a prediction may give a looser one, see
    /// the modal backend's reach): finite exactly when every entry is finite and none is beyond
    /// ~1e154.
    pub norm_squared: f64,
    /// m₁ᵀw = 𝟙ᵀM w, the mass-weighted sum of the relative displacement (kg·m).
    pub translation: f64,
    /// For a prediction x = w_{n+1}: (x − w_{n−1})ᵀC(x − w_{n−1}) with C the damping matrix, when
    /// the backend formed it in the same pass (it then equals `FieldMaps::damping_quadratic` to
    /// round-off); `None` otherwise.
    pub damping: Option<f64>,
}
