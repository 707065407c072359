//! The clarabel reference solve of a step's QP, with a warning when its answer is only the rough
//! interior-point one.

use crate::contact::clarabel::{polish, reference_settings, solve_box_qp_with};
use crate::contact::{BoxQp, QpSolution};
use crate::error::Error;

/// clarabel with [`reference_settings`], then [`polish`]ed on its active set: the exact solution,
/// or, when the polish finds no KKT-certified solution, clarabel's own answer with a warning that
/// says so (it is accurate to clarabel's tolerances only, a few 1e-8 m on plate steps).
pub fn solve_reference(qp: &BoxQp<'_>) -> Result<(QpSolution, Option<String>), Error> {
    let raw = solve_box_qp_with(qp, reference_settings())?;
    Ok(polished_or_raw(polish(qp, &raw.states), raw))
}

/// The polished solution if there is one, else the raw one with the warning.
fn polished_or_raw(polished: Option<QpSolution>, raw: QpSolution) -> (QpSolution, Option<String>) {
    match polished {
        Some(solution) => (solution, None),
        None => {
            let active = raw.states.iter().filter(|s| s.is_active()).count();
            let warning = format!(
                "clarabel's answer could not be polished to a KKT-certified solution on its active \
                 set ({active} of {} constraints active): the step keeps the interior-point answer, \
                 accurate to clarabel's tolerances only",
                raw.states.len()
            );
            (raw, Some(warning))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::BoundState;

    /// Without a polished solution the raw one is kept, and the warning says what happened.
    #[test]
    fn a_failed_polish_keeps_the_raw_answer_with_a_warning() {
        let raw = QpSolution {
            x: vec![1.0, 2.0],
            lambda: vec![0.5],
            states: vec![BoundState::AtLower],
        };
        let (solution, warning) = polished_or_raw(None, raw.clone());
        assert_eq!(solution, raw);
        let warning = warning.expect("a warning");
        assert!(warning.contains("could not be polished"), "{warning}");
        assert!(warning.contains("1 of 1 constraints active"), "{warning}");
        let (solution, warning) = polished_or_raw(Some(raw.clone()), raw.clone());
        assert_eq!((solution, warning), (raw, None));
    }
}
