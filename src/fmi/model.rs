//! The interface between the generic FMI machinery and a model binding (the role of
//! `model.h` in modelica's Reference-FMUs).
//!
//! The FMI-version-specific layers ([`super::fmi2`], [`super::fmi3`]) own their call-state
//! machines and C types; the generic [`Instance`](super::instance::Instance) maps their states
//! onto a version-neutral [`Phase`] and calls a [`Model`] for everything the model knows: its
//! variables' values, its experiment, its steps and its state. Rules that hold for every model
//! live here: which variables may be set in which phase.

use super::logger::Logger;
use super::status::{Failure, Status};
use super::variables::{Causality, Description, Kind, Variability, Variable};
use serde::de::DeserializeOwned;
use serde::Serialize;

/// Where an instance stands, independently of the FMI version's state names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// Instantiated, before initialization: parameters and inputs get their start values.
    Instantiated,
    /// FMI 3.0 Configuration Mode, before initialization: only structural parameters may be set.
    Configuration,
    /// Initialization mode: as Instantiated, and outputs may be read.
    Initialization,
    /// Stepping: tunable parameters and inputs may be set, outputs describe the last step.
    Stepping,
    /// Terminated: values may be read, nothing else.
    Terminated,
    /// After a failed step (or an internal error): values may be read for debugging. FMI 3.0 ends
    /// both a run and every failure in its one Terminated state, which is this phase: it may or
    /// may not hold a simulation.
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
    /// fmi2Real, fmi3Float64.
    Real(f64),
    /// fmi2Integer (also enumerations), fmi3Int32.
    Integer(i32),
    /// fmi3UInt64.
    UInt64(u64),
    /// fmi2Boolean, fmi3Boolean.
    Boolean(bool),
}

/// One value to set: typed as [`Value`], or a text (a String variable).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Setting<'a> {
    /// A scalar of a non-String type.
    Value(Value),
    /// The text of a String variable.
    Text(&'a str),
}

/// The values of an array variable: its shape (outermost dimension first) and its elements in
/// row-major order.
#[derive(Clone, Debug, PartialEq)]
pub struct Array<'a> {
    /// The size of each dimension.
    pub shape: Vec<u64>,
    /// As many values as the product of the sizes.
    pub values: &'a [f64],
}

/// The time derivative of an output: one value, or one per element of an array output.
#[derive(Clone, Debug, PartialEq)]
pub enum Derivative<'a> {
    /// d/dt of a scalar output.
    Scalar(f64),
    /// d/dt of each element of an array output, in its order.
    Array(Array<'a>),
}

/// How a communication step may end, as the importer allows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StepOptions {
    /// Whether the step may return early (FMI 3.0 `earlyReturnAllowed`).
    pub early_return: bool,
}

/// What a communication step did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StepOutcome {
    /// fmi3OK, or fmi3Warning when something was logged as a warning.
    pub status: Status,
    /// Whether the step ended before t + h (only when [`StepOptions::early_return`]); the model's
    /// time is where it ended.
    pub early_return: bool,
}

/// What the FMI layer needs from a model. Every method that returns an error with
/// [`Aftermath::Unchanged`](super::status::Aftermath::Unchanged) must have changed nothing.
pub trait Model: Send + Sized {
    /// A copy of everything a set may change, into which values are staged before commit.
    type Draft;
    /// Everything needed to continue a run, in this or another instance (the FMU state).
    type Snapshot: Clone + Serialize + DeserializeOwned;

    /// The model's FMI 2.0 description.
    const FMI2: &'static Description;
    /// The model's FMI 3.0 description: the variables of [`Model::FMI2`] and those only FMI 3.0
    /// can express.
    const FMI3: &'static Description;

    /// A model with every variable at its start value.
    fn new() -> Self;

    /// Back to the start values; may keep caches that make the next set-up cheaper.
    fn reset(&mut self);

    /// The experiment's start time and optional stop time (s).
    fn setup_experiment(&mut self, start: f64, stop: Option<f64>) -> Result<(), Failure>;

    /// The end of initialization: the last chance to refuse the parameters; sets the model up.
    /// Returns [`Status::Warning`] when the set-up itself is degraded; advice that changes no
    /// result goes to `log` while the call returns [`Status::Ok`], so that importers that stop at
    /// any other status run on (docs/fmu.md, "Errors and logging").
    fn exit_initialization(&mut self, log: &mut Logger) -> Result<Status, Failure>;

    /// The current time (s).
    fn time(&self, phase: Phase) -> f64;

    /// The value of scalar `variable` (its kind already checked by the caller).
    fn get(&mut self, variable: &Variable, phase: Phase) -> Result<Value, Failure>;

    /// The values of array `variable`, a Real output.
    fn get_array(&mut self, variable: &Variable, phase: Phase) -> Result<Array<'_>, Failure>;

    /// The text of String `variable` (its kind already checked by the caller).
    fn get_string(&mut self, variable: &Variable, phase: Phase) -> Result<String, Failure>;

    /// The derivative of order `order` (≥ 1) of output `variable` at the current time, a Real.
    fn output_derivative(
        &mut self,
        variable: &Variable,
        order: i32,
        phase: Phase,
    ) -> Result<Derivative<'_>, Failure>;

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

    /// As [`Model::stage`] for the text `value` of String `variable`.
    fn stage_string(
        &self,
        draft: &mut Self::Draft,
        variable: &Variable,
        value: &str,
        phase: Phase,
    ) -> Result<(), Failure>;

    /// Checks what ties the staged values together (where `phase` requires it) and applies the
    /// draft; on an error nothing is applied.
    fn commit(&mut self, draft: Self::Draft, phase: Phase) -> Result<(), Failure>;

    /// Derivatives of inputs (variable, order ≥ 1, value) for the next step: all or nothing.
    fn set_input_derivatives(&mut self, items: &[(&Variable, i32, f64)]) -> Result<(), Failure>;

    /// One communication step from `t` of size `h`, ended early only as `options` allow. A
    /// failure part-way is [`Failure::broken`].
    fn do_step(
        &mut self,
        t: f64,
        h: f64,
        options: StepOptions,
        log: &mut Logger,
    ) -> Result<StepOutcome, Failure>;

    /// The model's state in `phase`.
    fn snapshot(&self, phase: Phase) -> Self::Snapshot;

    /// Checks a snapshot from an untrusted source (a deserialized byte buffer) for `phase`
    /// completely, without changing anything. Called through [`check`] only.
    fn validate(snapshot: &Self::Snapshot, phase: Phase) -> Result<(), Failure>;

    /// Continues from a snapshot that [`check`] accepted; on an error nothing changes.
    fn restore(&mut self, snapshot: Checked<'_, Self::Snapshot>) -> Result<(), Failure>;
}

/// A snapshot that [`Model::validate`] accepted for the phase it was taken in: the only input
/// of [`Model::restore`], made by [`check`] alone, so that no snapshot is restored unchecked and
/// none is checked twice.
pub struct Checked<'a, S> {
    snapshot: &'a S,
    phase: Phase,
}

impl<'a, S> Checked<'a, S> {
    /// The snapshot.
    pub fn snapshot(&self) -> &'a S {
        self.snapshot
    }

    /// The phase it was taken in.
    pub fn phase(&self) -> Phase {
        self.phase
    }
}

/// Validates `snapshot`, taken in `phase`, for model `M` ([`Model::validate`]).
pub fn check<M: Model>(
    snapshot: &M::Snapshot,
    phase: Phase,
) -> Result<Checked<'_, M::Snapshot>, Failure> {
    M::validate(snapshot, phase)?;
    Ok(Checked { snapshot, phase })
}

/// Whether `variable` may be set in `phase`: parameters before initialization ends (not in
/// Configuration Mode), tunable parameters and inputs also while stepping, structural parameters
/// in Configuration Mode only; never outputs, and nothing once terminated or failed.
pub fn check_settable(variable: &Variable, phase: Phase) -> Result<(), Failure> {
    let configuring = matches!(phase, Phase::Instantiated | Phase::Initialization);
    let allowed = match variable.causality {
        Causality::Parameter => {
            configuring
                || (phase == Phase::Stepping && variable.variability == Variability::Tunable)
        }
        Causality::StructuralParameter => phase == Phase::Configuration,
        Causality::Input => configuring || phase == Phase::Stepping,
        _ => false,
    };
    if allowed {
        return Ok(());
    }
    Err(Failure::refused(match variable.causality {
        Causality::Parameter if variable.variability == Variability::Fixed && phase != Phase::Configuration => format!(
            "{} is a fixed parameter: set it before the end of initialization (phase now {phase:?})",
            variable.name
        ),
        Causality::StructuralParameter => format!(
            "{} is a structural parameter: set it in Configuration Mode (fmi3EnterConfigurationMode before initialization; phase now {phase:?})",
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
