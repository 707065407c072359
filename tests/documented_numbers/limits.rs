//! The claims of docs/limits.md: its paragraph on `energy.contact_loss`, from the damping study.

use super::claims::Claims;
use super::damping;

pub fn claims() -> Claims {
    let mut c = Claims::new("docs/limits.md");
    c.skip_block(
        "Measured by the stability matrix",
        "the stability matrix's method: its bounds are asserted by tests/stability.rs and \
         tests/fmu/test_stability.py, which commit no CSV",
    );
    c.skip_block(
        "| what |",
        "the stability matrix's measurements, asserted by tests/stability.rs and \
         tests/fmu/test_stability.py (no committed CSV)",
    );
    c.skip_block(
        "The output `edge_mid.displacement`",
        "a property of the C¹ interpolant between vertices; its 1e-6 m is one observation \
         (ny = 3) that no committed data hold",
    );
    damping::limits_doc(&mut c);
    c
}
