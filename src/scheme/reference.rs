//! The clarabel reference solve of a step's QP, with a warning when its answer is only the rough
//! interior-point one.

use crate::contact::clarabel::solve_box_qp;
use crate::contact::{BoxQp, QpSolution};
use crate::error::Error;

/// clarabel polished on its active set ([`solve_box_qp`]): the exact solution, or, when the
/// polish finds no KKT-certified solution, clarabel's own answer with a warning that says so (it
/// is accurate to clarabel's tolerances only, a few 1e-8 m on plate steps).
pub fn solve_reference(qp: &BoxQp<'_>) -> Result<(QpSolution, Option<String>), Error> {
    let solution = solve_box_qp(qp)?;
    let warning = polish_warning(&solution);
    Ok((solution, warning))
}

/// The warning for a solution whose polish failed, naming how many constraints were active.
fn polish_warning(solution: &QpSolution) -> Option<String> {
    if solution.polished {
        return None;
    }
    let active = solution.states.iter().filter(|s| s.is_active()).count();
    Some(format!(
        "clarabel's answer could not be polished to a KKT-certified solution on its active set \
         ({active} of {} constraints active): the step keeps the interior-point answer, accurate \
         to clarabel's tolerances only",
        solution.states.len()
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::BoundState;

    /// An unpolished solution gets a warning that says what happened; a polished one none.
    #[test]
    fn a_failed_polish_is_named_in_a_warning() {
        let mut solution = QpSolution {
            polished: false,
            x: vec![1.0, 2.0],
            lambda: vec![0.5],
            states: vec![BoundState::AtLower],
        };
        let warning = polish_warning(&solution).expect("a warning");
        assert!(warning.contains("could not be polished"), "{warning}");
        assert!(warning.contains("1 of 1 constraints active"), "{warning}");
        solution.polished = true;
        assert_eq!(polish_warning(&solution), None);
    }
}
