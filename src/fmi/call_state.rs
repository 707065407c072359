//! What the call-state tables of both FMI versions share (modelica Reference-FMUs keep one mask
//! of allowed states per function): a version lists its states ([`CallState`]) and, for every
//! function that takes an instance, the states in which it may be called ([`CallTable`]). Every
//! entry point looks its function up once, before it reads or changes anything of the instance
//! (only its pointer arguments are checked first: a null one is refused in every state), and a
//! refusal names the state and the states that would allow the call.

use super::model::Phase;
use std::fmt::Debug;

/// Declares a version's `Function` enum (one variant per function that takes an instance, named
/// without the version prefix `$prefix`) and its list `Function::ALL`, in the order given, from
/// one list of names; the attributes given first document the enum. Its [`CallTable`] reads the
/// version's table: `Function::allowed`, the mask of the states (`Mode::bit`) it may be called
/// in.
macro_rules! call_functions {
    ($prefix:literal, $(#[$attr:meta])* ; $($name:ident,)*) => {
        $(#[$attr])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        #[allow(missing_docs)]
        pub enum Function {
            $($name,)*
        }

        impl Function {
            /// Every function, in the order given.
            pub const ALL: &[Function] = &[$(Function::$name,)*];
        }

        impl $crate::fmi::call_state::CallTable for Function {
            type Mode = Mode;

            fn allowed_in(self, mode: Mode) -> bool {
                self.allowed() & mode.bit() != 0
            }

            fn name(self) -> String {
                format!(concat!($prefix, "{:?}"), self)
            }
        }
    };
}
pub(crate) use call_functions;

/// The states of a version's Co-Simulation state machine.
pub trait CallState: Copy + Debug + PartialEq + 'static {
    /// Every state, in the standard's column order.
    const ALL: &'static [Self];

    /// Whether this FMU can be in this state (states for features it does not offer are never
    /// entered).
    fn reachable(self) -> bool;

    /// The version-neutral phase of this state.
    fn phase(self) -> Phase;
}

/// A version's functions and the table of the states each may be called in.
pub trait CallTable: Copy + Debug {
    /// The version's states.
    type Mode: CallState;

    /// Whether the function may be called in `mode`.
    fn allowed_in(self, mode: Self::Mode) -> bool;

    /// The C name, e.g. `fmi2DoStep`.
    fn name(self) -> String;

    /// Refuses a call in a state the table does not allow, naming the states that do.
    fn check(self, mode: Self::Mode) -> Result<(), String> {
        if self.allowed_in(mode) {
            return Ok(());
        }
        let allowed: Vec<Self::Mode> = Self::Mode::ALL
            .iter()
            .copied()
            .filter(|&m| m.reachable() && self.allowed_in(m))
            .collect();
        Err(format!(
            "not allowed in the {mode:?} state (allowed in {allowed:?})"
        ))
    }
}

/// Checks a version's table against the standard's, transcribed as (C name, row) in the order of
/// `functions`: the row has one mark per state of [`CallState::ALL`], `x` where the call is
/// allowed.
#[cfg(test)]
pub(crate) fn assert_standard_table<F: CallTable>(functions: &[F], standard: &[(&str, &str)]) {
    assert_eq!(functions.len(), standard.len());
    for (&function, &(name, row)) in functions.iter().zip(standard) {
        assert_eq!(function.name(), name);
        assert_eq!(row.len(), F::Mode::ALL.len(), "{name}");
        for (&mode, mark) in F::Mode::ALL.iter().zip(row.chars()) {
            assert_eq!(function.allowed_in(mode), mark == 'x', "{name} in {mode:?}");
            assert_eq!(function.check(mode).is_ok(), mark == 'x');
        }
    }
}
