//! The interface between the generic FMI machinery and a model binding (the role of
//! `model.h` in modelica's Reference-FMUs).
//!
//! The FMI-version-specific layer ([`super::fmi2`]) owns the call-state machine, the logger and
//! the C types; it maps its states onto a version-neutral [`Phase`] and calls a [`Model`] for
//! everything the model knows: its variables' values, its experiment, its steps and its state.
//! Rules that hold for every model live here: which variables may be set in which phase, and
//! stage-then-commit of a multi-value set.

use super::logger::Logger;
use super::status::{Failure, Status};
use super::variables::{Causality, Kind, Variability, Variable};
use serde::de::DeserializeOwned;
use serde::Serialize;

/// Where an instance stands, independently of the FMI version's state names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// Instantiated, before initialization: parameters and inputs get their start values.
    Instantiated,
    /// Initialization mode: as Instantiated, and outputs may be read.
    Initialization,
    /// Stepping: tunable parameters and inputs may be set, outputs describe the last step.
    Stepping,
    /// Terminated: values may be read, nothing else.
    Terminated,
    /// After a failed step (or an internal error): values may be read for debugging.
    Failed,
}

impl Phase {
    /// Whether the simulation has been set up and runs (or ran) in this phase.
    pub fn running(self) -> bool {
        matches!(self, Phase::Stepping | Phase::Terminated | Phase::Failed)
    }
}

/// One variable value, typed as FMI transports it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    /// fmi2Real.
    Real(f64),
    /// fmi2Integer (also enumerations).
    Integer(i32),
    /// fmi2Boolean.
    Boolean(bool),
}

/// What the FMI layer needs from a model. Every method that returns an error with
/// [`Aftermath::Unchanged`](super::status::Aftermath::Unchanged) must have changed nothing.
pub trait Model: Send + Sized {
    /// A copy of everything a set may change, into which values are staged before commit.
    type Draft;
    /// Everything needed to continue a run, in this or another instance (the FMU state).
    type Snapshot: Clone + Serialize + DeserializeOwned;

    /// The `guid` of the model description.
    const GUID: &'static str;
    /// The `<LogCategories>` of the model description.
    const LOG_CATEGORIES: &'static [&'static str];
    /// The variables of the model description.
    const VARIABLES: &'static [Variable];

    /// A model with every variable at its start value.
    fn new() -> Self;

    /// Back to the start values; may keep caches that make the next set-up cheaper.
    fn reset(&mut self);

    /// The experiment's start time and optional stop time (s).
    fn setup_experiment(&mut self, start: f64, stop: Option<f64>) -> Result<(), Failure>;

    /// The end of initialization: the last chance to refuse the parameters; sets the model up.
    fn exit_initialization(&mut self) -> Result<(), Failure>;

    /// The current time (s).
    fn time(&self, phase: Phase) -> f64;

    /// The value of `variable` (its kind already checked by the caller).
    fn get(&mut self, variable: &Variable, phase: Phase) -> Result<Value, Failure>;

    /// A draft holding the current values of everything a set may change.
    fn draft(&self) -> Self::Draft;

    /// Checks `value` for `variable` on its own and writes it into `draft` (the variable may be
    /// set in `phase`: checked by the caller with [`check_settable`]).
    fn stage(
        &self,
        draft: &mut Self::Draft,
        variable: &Variable,
        value: Value,
        phase: Phase,
    ) -> Result<(), Failure>;

    /// Checks what ties the staged values together (where `phase` requires it) and applies the
    /// draft; on an error nothing is applied.
    fn commit(&mut self, draft: Self::Draft, phase: Phase) -> Result<(), Failure>;

    /// Derivatives of inputs (variable, order ≥ 1, value) for the next step: all or nothing.
    fn set_input_derivatives(&mut self, items: &[(&Variable, i32, f64)]) -> Result<(), Failure>;

    /// One communication step from `t` of size `h`; `Ok(Status::Warning)` when something was
    /// logged as a warning. A failure part-way is [`Failure::broken`].
    fn do_step(&mut self, t: f64, h: f64, log: &mut Logger) -> Result<Status, Failure>;

    /// The model's state in `phase`.
    fn snapshot(&self, phase: Phase) -> Self::Snapshot;

    /// Checks a snapshot from an untrusted source (a deserialized byte buffer) for `phase`
    /// completely, without changing anything.
    fn validate(snapshot: &Self::Snapshot, phase: Phase) -> Result<(), Failure>;

    /// Continues from a validated snapshot taken in `phase`; on an error nothing changes.
    fn restore(&mut self, snapshot: &Self::Snapshot, phase: Phase) -> Result<(), Failure>;
}

/// Whether `variable` may be set in `phase`: parameters before initialization ends, tunable
/// parameters and inputs also while stepping; never outputs, and nothing once terminated or failed.
pub fn check_settable(variable: &Variable, phase: Phase) -> Result<(), Failure> {
    let configuring = matches!(phase, Phase::Instantiated | Phase::Initialization);
    let allowed = match variable.causality {
        Causality::Parameter => {
            configuring
                || (phase == Phase::Stepping && variable.variability == Variability::Tunable)
        }
        Causality::Input => configuring || phase == Phase::Stepping,
        _ => false,
    };
    if allowed {
        return Ok(());
    }
    Err(Failure::refused(match variable.causality {
        Causality::Parameter if variable.variability == Variability::Fixed => format!(
            "{} is a fixed parameter: set it before the end of initialization (phase now {phase:?})",
            variable.name
        ),
        Causality::Parameter | Causality::Input => format!(
            "{} cannot be set in the {phase:?} phase",
            variable.name
        ),
        causality => format!(
            "{} is an {causality:?}, it cannot be set",
            variable.name
        ),
    }))
}

/// The variable with value reference `vr` among `variables`, if its kind is one of `kinds`.
pub fn variable<'a>(
    variables: &'a [Variable],
    vr: u32,
    kinds: &[Kind],
) -> Result<&'a Variable, Failure> {
    match variables.iter().find(|v| v.vr == vr) {
        Some(v) if kinds.contains(&v.kind) => Ok(v),
        Some(v) => Err(Failure::refused(format!(
            "value reference {vr} is {} of type {:?}, use the matching function",
            v.name, v.kind
        ))),
        None => Err(Failure::refused(format!(
            "{vr} is not a value reference of this FMU"
        ))),
    }
}

/// Stage-then-commit of a multi-value set: every value is checked (type, settable now, its own
/// range) into a draft, then what ties them together, and only then is the draft applied, so a
/// refused call changes nothing.
pub fn set_values<M: Model>(
    model: &mut M,
    phase: Phase,
    kinds: &[Kind],
    values: impl Iterator<Item = (u32, Value)>,
) -> Result<(), Failure> {
    let mut draft = model.draft();
    for (vr, value) in values {
        let v = variable(M::VARIABLES, vr, kinds)?;
        check_settable(v, phase)?;
        model.stage(&mut draft, v, value, phase)?;
    }
    model.commit(draft, phase)
}
