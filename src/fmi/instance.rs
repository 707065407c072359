//! One FMU instance as safe Rust, generic over the FMI [`Version`] (its call-state table, its
//! model description, where a failure leaves it) and the [`Model`] it drives: the call-state
//! table looked up once per call, value references and their types, stage-then-commit sets, array
//! variables and the structural parameters that size them, output derivatives, the logger, and
//! the FMU state. The version modules add what only their version has and translate C calls into
//! these methods.

use super::call_state::{CallState, CallTable};
use super::ffi;
use super::logger::{LogSink, Logger, LOG_ALL, LOG_ERROR, LOG_WARNING};
use super::model::{self, Checked, Model, Phase, Setting, StepOptions, StepOutcome, Value};
use super::serialized;
use super::status::{Failure, Status};
use super::variables::{Causality, Description, Dimension, Kind, Start, Variable};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::cell::OnceCell;
use std::ffi::CString;

/// The kinds the Integer get and set functions serve.
const INTEGERS: &[Kind] = &[Kind::Integer, Kind::Enumeration];

/// What the generic instance needs to know of an FMI version.
pub trait Version: 'static {
    /// The states of the version's Co-Simulation state machine.
    type Mode: CallState + Serialize + DeserializeOwned + Send;
    /// The version's functions and their call-state table.
    type Function: CallTable<Mode = Self::Mode>;

    /// After instantiation and reset.
    const INSTANTIATED: Self::Mode;
    /// Initialization Mode.
    const INITIALIZATION: Self::Mode;
    /// Ready for the next communication step (FMI 2.0 StepComplete, FMI 3.0 Step Mode).
    const STEPPING: Self::Mode;
    /// After terminate.
    const TERMINATED: Self::Mode;
    /// Where a failure leaves the instance (FMI 2.0 Error, FMI 3.0 Terminated).
    const FAILED: Self::Mode;

    /// The set-debug-logging function.
    const SET_DEBUG_LOGGING: Self::Function;
    /// The enter-initialization-mode function.
    const ENTER_INITIALIZATION_MODE: Self::Function;
    /// The exit-initialization-mode function.
    const EXIT_INITIALIZATION_MODE: Self::Function;
    /// The terminate function.
    const TERMINATE: Self::Function;
    /// The reset function.
    const RESET: Self::Function;
    /// The get-FMU-state function.
    const GET_FMU_STATE: Self::Function;
    /// The set-FMU-state function.
    const SET_FMU_STATE: Self::Function;
    /// The free-FMU-state function.
    const FREE_FMU_STATE: Self::Function;
    /// The serialized-FMU-state-size function.
    const SERIALIZED_FMU_STATE_SIZE: Self::Function;
    /// The deserialize-FMU-state function.
    const DESERIALIZE_FMU_STATE: Self::Function;
    /// The do-step function.
    const DO_STEP: Self::Function;
    /// The get-output-derivatives function.
    const GET_OUTPUT_DERIVATIVES: Self::Function;

    /// The C name of instantiation and of the token it checks, for messages: ("fmi2Instantiate",
    /// "GUID").
    const INSTANTIATE: (&'static str, &'static str);

    /// The model's description of this version.
    fn description<M: Model>() -> &'static Description;

    /// The function that gets variables of `kind`.
    fn getter(kind: Kind) -> Self::Function;

    /// The function that sets variables of `kind`.
    fn setter(kind: Kind) -> Self::Function;

    /// Whether `failure` leaves the instance in [`Version::FAILED`]: FMI 2.0 for a call that
    /// failed part-way only, FMI 3.0 for every fmi3Error.
    fn fails_instance(failure: &Failure) -> bool;
}

/// An FMU state: the instance's state, the sizes set for its structural parameters (none in
/// FMI 2.0, so that its payload is unchanged) and the model's snapshot.
#[derive(Serialize, Deserialize)]
#[serde(bound = "", deny_unknown_fields)]
pub struct Snapshot<V: Version, M: Model> {
    mode: V::Mode,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    sizes: Vec<u64>,
    model: M::Snapshot,
}

impl<V: Version, M: Model> Clone for Snapshot<V, M> {
    fn clone(&self) -> Self {
        Snapshot {
            mode: self.mode,
            sizes: self.sizes.clone(),
            model: self.model.clone(),
        }
    }
}

/// What an FMU state pointer points to: a snapshot, and its serialized bytes once asked for, so
/// that the size query and the serialization encode it once.
pub struct StoredState<V: Version, M: Model> {
    snapshot: Snapshot<V, M>,
    bytes: OnceCell<Vec<u8>>,
}

impl<V: Version, M: Model> StoredState<V, M> {
    fn new(snapshot: Snapshot<V, M>) -> StoredState<V, M> {
        StoredState {
            snapshot,
            bytes: OnceCell::new(),
        }
    }
}

/// One FMU instance. It is `Send` whenever its model is: the host may call it from any thread,
/// one call at a time.
pub struct Instance<V: Version, M: Model> {
    name: String,
    log: Logger,
    mode: V::Mode,
    model: M,
    /// The values of the description's structural parameters, in its order.
    sizes: Vec<u64>,
    /// The texts of the last String get, which the host may read until its next call.
    texts: Vec<CString>,
}

/// The start values of the structural parameters of `description`, in its order.
fn start_sizes(description: &Description) -> Vec<u64> {
    description
        .variables
        .iter()
        .filter(|v| v.causality == Causality::StructuralParameter)
        .map(|v| match v.start {
            Some(Start::Integer(n)) => u64::try_from(n).expect("build.rs checks UInt64 starts"),
            _ => unreachable!("build.rs requires a start for every structural parameter"),
        })
        .collect()
}

impl<V: Version, M: Model> Instance<V, M> {
    /// Instantiation (Co-Simulation): checks the importer's token against the model description.
    /// A refusal is also sent to `sink` under logStatusError, so that the host learns why it got
    /// no instance.
    pub fn new(
        name: &str,
        token: &str,
        logging_on: bool,
        sink: Option<LogSink>,
    ) -> Result<Instance<V, M>, String> {
        let description = V::description::<M>();
        if token != description.token {
            let (function, what) = V::INSTANTIATE;
            let message = format!(
                "{function}: {what} {token:?} does not match this FMU's {:?}: the modelDescription.xml and the binary come from different builds",
                description.token
            );
            if let Some(mut sink) = sink {
                sink(Status::Error, LOG_ERROR, &message);
            }
            return Err(message);
        }
        Ok(Instance {
            name: name.to_string(),
            log: Logger::new(sink, description.log_categories, logging_on),
            mode: V::INSTANTIATED,
            model: M::new(),
            sizes: start_sizes(description),
            texts: Vec::new(),
        })
    }

    /// The instance name given at instantiation.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The model behind the instance.
    pub fn model(&self) -> &M {
        &self.model
    }

    /// The current state of the call-state machine.
    pub fn mode(&self) -> V::Mode {
        self.mode
    }

    /// Puts the instance in the state of failed calls (after a panic was caught).
    pub fn set_error_mode(&mut self) {
        self.mode = V::FAILED;
    }

    /// The FMU time (s).
    pub fn time(&self) -> f64 {
        self.model.time(self.mode.phase())
    }

    /// The one lookup in the call-state table every entry point starts with.
    pub fn enter(&self, function: V::Function) -> Result<Phase, Failure> {
        function
            .check(self.mode)
            .map(|()| self.mode.phase())
            .map_err(Failure::refused)
    }

    /// Moves to `mode` (a transition of the version's state machine, after its checks).
    pub(crate) fn move_to(&mut self, mode: V::Mode) {
        self.mode = mode;
    }

    /// The model, for the version's own calls.
    pub(crate) fn model_mut(&mut self) -> &mut M {
        &mut self.model
    }

    /// Turns a call's result into its status: logs a failure under logStatusError (a discarded
    /// query under logStatusWarning), moves to the failed state when the version says so, and
    /// traces successful calls under logAll.
    pub fn finish(&mut self, function: V::Function, result: Result<Status, Failure>) -> Status {
        match result {
            Ok(status) => {
                if self.log.enabled(LOG_ALL) {
                    let message = format!("{}: {status:?}", function.name());
                    self.log.log(status, LOG_ALL, &message);
                }
                status
            }
            Err(f) => {
                if V::fails_instance(&f) {
                    self.mode = V::FAILED;
                }
                let category = if f.status >= Status::Error {
                    LOG_ERROR
                } else {
                    LOG_WARNING
                };
                let message = format!("{}: {}", function.name(), f.message);
                self.log.log(f.status, category, &message);
                f.status
            }
        }
    }

    /// Set debug logging: switches the named categories (all when none is named).
    pub fn set_debug_logging(&mut self, on: bool, categories: &[&str]) -> Result<(), Failure> {
        self.enter(V::SET_DEBUG_LOGGING)?;
        self.log.switch(on, categories).map_err(Failure::refused)
    }

    /// Enter initialization mode, after the experiment (start and optional stop time, s) when the
    /// version passes it with this call (FMI 3.0).
    pub fn begin_initialization(
        &mut self,
        experiment: Option<(f64, Option<f64>)>,
    ) -> Result<(), Failure> {
        self.enter(V::ENTER_INITIALIZATION_MODE)?;
        if let Some((start, stop)) = experiment {
            self.model.setup_experiment(start, stop)?;
        }
        self.mode = V::INITIALIZATION;
        Ok(())
    }

    /// Exit initialization mode: the model checks its parameters and sets itself up; a warning
    /// it logs (settings whose impact statistics may not converge) makes the status Warning.
    pub fn exit_initialization_mode(&mut self) -> Result<Status, Failure> {
        self.enter(V::EXIT_INITIALIZATION_MODE)?;
        let status = self.model.exit_initialization(&mut self.log)?;
        self.mode = V::STEPPING;
        Ok(status)
    }

    /// Terminate.
    pub fn terminate(&mut self) -> Result<(), Failure> {
        self.enter(V::TERMINATE)?;
        self.mode = V::TERMINATED;
        Ok(())
    }

    /// Reset: back to the state right after instantiation, with the start values.
    pub fn reset(&mut self) -> Result<(), Failure> {
        self.enter(V::RESET)?;
        self.model.reset();
        self.log.reset();
        self.sizes = start_sizes(V::description::<M>());
        self.mode = V::INSTANTIATED;
        Ok(())
    }

    /// The variable with value reference `vr` of one of `kinds`, in this version's description.
    fn variable(&self, vr: u32, kinds: &[Kind]) -> Result<&'static Variable, Failure> {
        model::variable(V::description::<M>().variables, vr, kinds)
    }

    /// The current size of `dimension`.
    fn size(&self, dimension: &Dimension) -> u64 {
        match *dimension {
            Dimension::Fixed(n) => n,
            Dimension::Variable(vr) => self
                .structural_value(vr)
                .expect("build.rs checks that every dimension names a structural parameter"),
        }
    }

    /// The value set for the structural parameter with value reference `vr`.
    fn structural_value(&self, vr: u32) -> Option<u64> {
        V::description::<M>()
            .variables
            .iter()
            .filter(|v| v.causality == Causality::StructuralParameter)
            .position(|v| v.vr == vr)
            .map(|i| self.sizes[i])
    }

    /// Checks that the model's `shape` of array `v` is the one its dimensions declare now.
    fn check_shape(&self, v: &Variable, shape: &[u64]) -> Result<(), Failure> {
        let declared: Vec<u64> = v.dimensions.iter().map(|d| self.size(d)).collect();
        if declared == shape {
            return Ok(());
        }
        let sizes: Vec<String> = v
            .dimensions
            .iter()
            .zip(&declared)
            .map(|(d, n)| match d {
                Dimension::Fixed(_) => n.to_string(),
                Dimension::Variable(vr) => {
                    let name = V::description::<M>().variable(*vr).map_or("?", |s| s.name);
                    format!("{name} = {n}")
                }
            })
            .collect();
        Err(Failure::refused(format!(
            "{} is declared as {} values but the model has {shape:?}: set the structural parameters to that shape in Configuration Mode",
            v.name,
            sizes.join(" × ")
        )))
    }

    /// The value of scalar `v` in `phase`: the structural parameters and the independent variable
    /// are the instance's, the others the model's.
    fn scalar(&mut self, v: &Variable, phase: Phase) -> Result<Value, Failure> {
        match v.causality {
            Causality::StructuralParameter => Ok(Value::UInt64(
                self.structural_value(v.vr)
                    .expect("a structural parameter of the description"),
            )),
            Causality::Independent => Ok(Value::Real(self.model.time(phase))),
            _ => self.model.get(v, phase),
        }
    }

    /// Reads `vrs` of the given kinds into `out` through `convert`: one value per scalar, the
    /// elements of an array in row-major order; `out` must hold exactly that many.
    fn get<T>(
        &mut self,
        kinds: &[Kind],
        vrs: &[u32],
        out: &mut [T],
        convert: impl Fn(Value) -> Option<T>,
    ) -> Result<(), Failure> {
        let phase = self.enter(V::getter(kinds[0]))?;
        let mut index = 0;
        let n_values = out.len();
        let too_few = || {
            Failure::refused(format!(
                "nValues = {n_values} is too few for the variables asked for"
            ))
        };
        let internal = |name: &str| {
            Failure::refused(format!(
                "{name} has a value of another type (internal error)"
            ))
        };
        for &vr in vrs {
            let v = self.variable(vr, kinds)?;
            if v.is_array() {
                let array = self.model.get_array(v, phase)?;
                let shape = array.shape.clone();
                let values = array.values.to_vec();
                self.check_shape(v, &shape)?;
                let slots = out
                    .get_mut(index..index + values.len())
                    .ok_or_else(too_few)?;
                for (slot, &x) in slots.iter_mut().zip(&values) {
                    *slot = convert(Value::Real(x)).ok_or_else(|| internal(v.name))?;
                }
                index += values.len();
            } else {
                let value = self.scalar(v, phase)?;
                let slot = out.get_mut(index).ok_or_else(too_few)?;
                *slot = convert(value).ok_or_else(|| internal(v.name))?;
                index += 1;
            }
        }
        if index != n_values {
            return Err(Failure::refused(format!(
                "nValues = {n_values}, but the variables asked for hold {index} values"
            )));
        }
        Ok(())
    }

    /// Get of Real (fmi2Real, fmi3Float64) values.
    pub fn get_real(&mut self, vrs: &[u32], out: &mut [f64]) -> Result<(), Failure> {
        self.get(&[Kind::Real], vrs, out, |v| match v {
            Value::Real(x) => Some(x),
            _ => None,
        })
    }

    /// Get of Integer (fmi2Integer and enumerations, fmi3Int32) values.
    pub fn get_integer(&mut self, vrs: &[u32], out: &mut [i32]) -> Result<(), Failure> {
        self.get(INTEGERS, vrs, out, |v| match v {
            Value::Integer(i) => Some(i),
            _ => None,
        })
    }

    /// Get of fmi3UInt64 values (the structural parameters).
    pub fn get_uint64(&mut self, vrs: &[u32], out: &mut [u64]) -> Result<(), Failure> {
        self.get(&[Kind::UInt64], vrs, out, |v| match v {
            Value::UInt64(n) => Some(n),
            _ => None,
        })
    }

    /// Get of Boolean values.
    pub fn get_boolean(&mut self, vrs: &[u32], out: &mut [bool]) -> Result<(), Failure> {
        self.get(&[Kind::Boolean], vrs, out, |v| match v {
            Value::Boolean(b) => Some(b),
            _ => None,
        })
    }

    /// Get of String values: the texts, which the instance keeps until its next String get (the
    /// host copies them before its next call, as FMI requires). A NUL inside a text is
    /// returned as `\0`.
    pub fn get_string(&mut self, vrs: &[u32]) -> Result<&[CString], Failure> {
        let phase = self.enter(V::getter(Kind::String))?;
        let mut texts = Vec::with_capacity(vrs.len());
        for &vr in vrs {
            let v = self.variable(vr, &[Kind::String])?;
            texts.push(ffi::to_cstring(&self.model.get_string(v, phase)?));
        }
        self.texts = texts;
        Ok(&self.texts)
    }

    /// Set of Real values: every value is checked before any is applied.
    pub fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Result<(), Failure> {
        let items = values.iter().map(|&x| Setting::Value(Value::Real(x)));
        self.set(&[Kind::Real], vrs, values.len(), items)
    }

    /// Set of Integer values (and enumerations): all values or none.
    pub fn set_integer(&mut self, vrs: &[u32], values: &[i32]) -> Result<(), Failure> {
        let items = values.iter().map(|&i| Setting::Value(Value::Integer(i)));
        self.set(INTEGERS, vrs, values.len(), items)
    }

    /// Set of fmi3UInt64 values (the structural parameters): all values or none.
    pub fn set_uint64(&mut self, vrs: &[u32], values: &[u64]) -> Result<(), Failure> {
        let items = values.iter().map(|&n| Setting::Value(Value::UInt64(n)));
        self.set(&[Kind::UInt64], vrs, values.len(), items)
    }

    /// Set of Boolean values: all values or none.
    pub fn set_boolean(&mut self, vrs: &[u32], values: &[bool]) -> Result<(), Failure> {
        let items = values.iter().map(|&b| Setting::Value(Value::Boolean(b)));
        self.set(&[Kind::Boolean], vrs, values.len(), items)
    }

    /// Set of String values: all texts or none.
    pub fn set_string(&mut self, vrs: &[u32], values: &[&str]) -> Result<(), Failure> {
        let items = values.iter().map(|&text| Setting::Text(text));
        self.set(&[Kind::String], vrs, values.len(), items)
    }

    /// Refuses any value reference for a function of a type the model has no variable of (the
    /// string and other types): with none asked for, the call is checked and does nothing.
    pub fn check_absent_kind(
        &mut self,
        function: V::Function,
        kinds: &[Kind],
        vrs: &[u32],
    ) -> Result<(), Failure> {
        self.enter(function)?;
        match vrs.first() {
            None => Ok(()),
            Some(&vr) => self.variable(vr, kinds).map(|_| ()),
        }
    }

    /// Sets `n_values` values for `vrs` (stage then commit): every value is checked (type,
    /// settable now, its own range) into a draft, then what ties them together, and only then is
    /// the draft applied, so a refused call changes nothing. Every settable variable is a scalar,
    /// so there is one value per value reference. Structural parameters are the instance's,
    /// within their declared range.
    fn set<'t>(
        &mut self,
        kinds: &[Kind],
        vrs: &[u32],
        n_values: usize,
        values: impl Iterator<Item = Setting<'t>>,
    ) -> Result<(), Failure> {
        let phase = self.enter(V::setter(kinds[0]))?;
        if n_values != vrs.len() {
            return Err(Failure::refused(format!(
                "nValues = {n_values}, but the {} variables set take one value each",
                vrs.len()
            )));
        }
        let mut draft = self.model.draft();
        let mut sizes = self.sizes.clone();
        for (&vr, value) in vrs.iter().zip(values) {
            let v = self.variable(vr, kinds)?;
            model::check_settable(v, phase)?;
            if v.is_array() {
                return Err(Failure::refused(format!(
                    "{} is an array, which this FMU never takes as an input",
                    v.name
                )));
            }
            match value {
                Setting::Value(value) if v.causality == Causality::StructuralParameter => {
                    stage_size(&mut sizes, V::description::<M>(), v, value)?
                }
                Setting::Value(value) => self.model.stage(&mut draft, v, value, phase)?,
                Setting::Text(text) => self.model.stage_string(&mut draft, v, text, phase)?,
            }
        }
        self.model.commit(draft, phase)?;
        self.sizes = sizes;
        Ok(())
    }

    /// The derivatives of orders `orders` of the outputs `vrs` into `out`, serialized as
    /// `Instance::get` serializes values.
    pub fn output_derivatives(
        &mut self,
        vrs: &[u32],
        orders: &[i32],
        out: &mut [f64],
    ) -> Result<(), Failure> {
        let phase = self.enter(V::GET_OUTPUT_DERIVATIVES)?;
        let mut index = 0;
        let n_values = out.len();
        for (&vr, &order) in vrs.iter().zip(orders) {
            let v = self.variable(vr, &[Kind::Real])?;
            let derivative = self.model.output_derivative(v, order, phase)?;
            let values = match derivative {
                model::Derivative::Scalar(x) => vec![x],
                model::Derivative::Array(array) => {
                    let (shape, values) = (array.shape.clone(), array.values.to_vec());
                    self.check_shape(v, &shape)?;
                    values
                }
            };
            let slots = out.get_mut(index..index + values.len()).ok_or_else(|| {
                Failure::refused(format!(
                    "nValues = {n_values} is too few for the derivatives asked for"
                ))
            })?;
            slots.copy_from_slice(&values);
            index += values.len();
        }
        if index != n_values {
            return Err(Failure::refused(format!(
                "nValues = {n_values}, but the derivatives asked for hold {index} values"
            )));
        }
        Ok(())
    }

    /// One communication step, ended early only as `options` allow.
    pub fn step(&mut self, t: f64, h: f64, options: StepOptions) -> Result<StepOutcome, Failure> {
        self.enter(V::DO_STEP)?;
        self.model.do_step(t, h, options, &mut self.log)
    }

    /// Get FMU state: a copy of everything needed to continue from here.
    pub fn get_state(&mut self) -> Result<StoredState<V, M>, Failure> {
        let phase = self.enter(V::GET_FMU_STATE)?;
        Ok(StoredState::new(Snapshot {
            mode: self.mode,
            sizes: self.sizes.clone(),
            model: self.model.snapshot(phase),
        }))
    }

    /// Checks an untrusted snapshot completely: its mode and structural parameters here, the
    /// model's part by [`model::check`].
    fn validate(snapshot: &Snapshot<V, M>) -> Result<Checked<'_, M::Snapshot>, Failure> {
        let mode = snapshot.mode;
        if !mode.reachable() {
            return Err(Failure::refused(format!(
                "the FMU state is refused: it claims the {mode:?} state, which this FMU never enters"
            )));
        }
        if !V::GET_FMU_STATE.allowed_in(mode) {
            return Err(Failure::refused(format!(
                "the FMU state is refused: it claims the {mode:?} state, in which no FMU state is taken"
            )));
        }
        let description = V::description::<M>();
        let structural: Vec<&Variable> = description
            .variables
            .iter()
            .filter(|v| v.causality == Causality::StructuralParameter)
            .collect();
        if snapshot.sizes.len() != structural.len() {
            return Err(Failure::refused(format!(
                "the FMU state is refused: it holds {} structural parameter values, this FMU has {}",
                snapshot.sizes.len(),
                structural.len()
            )));
        }
        let mut sizes = snapshot.sizes.clone();
        for (v, &n) in structural.iter().zip(&snapshot.sizes) {
            stage_size(&mut sizes, description, v, Value::UInt64(n)).map_err(|f| {
                Failure::refused(format!("the FMU state is refused: {}", f.message))
            })?;
        }
        model::check::<M>(&snapshot.model, mode.phase())
    }

    /// Set FMU state: continues from `state`, in this or any instance of this FMU; a refused
    /// state changes nothing.
    pub fn set_state(&mut self, state: &StoredState<V, M>) -> Result<(), Failure> {
        self.enter(V::SET_FMU_STATE)?;
        let snapshot = &state.snapshot;
        let checked = Self::validate(snapshot)?;
        self.model.restore(checked)?;
        self.sizes = snapshot.sizes.clone();
        self.mode = snapshot.mode;
        Ok(())
    }

    /// Free FMU state: checks the call (the caller frees the state).
    pub fn free_state(&mut self) -> Result<(), Failure> {
        self.enter(V::FREE_FMU_STATE).map(|_| ())
    }

    /// The serialized-size query and the serialization: the bytes of `state`, encoded on the
    /// first request only.
    pub fn serialized<'a>(
        &mut self,
        function: V::Function,
        state: &'a StoredState<V, M>,
    ) -> Result<&'a [u8], Failure> {
        self.enter(function)?;
        if state.bytes.get().is_none() {
            let bytes = serialized::encode(&state.snapshot).map_err(Failure::refused)?;
            let _ = state.bytes.set(bytes);
        }
        Ok(state.bytes.get().expect("set above"))
    }

    /// Deserialize FMU state: decodes and validates the bytes completely before anything uses
    /// them.
    pub fn deserialize_state(&mut self, bytes: &[u8]) -> Result<StoredState<V, M>, Failure> {
        self.enter(V::DESERIALIZE_FMU_STATE)?;
        let snapshot: Snapshot<V, M> = serialized::decode(bytes).map_err(Failure::refused)?;
        Self::validate(&snapshot).map(|_| ())?;
        Ok(StoredState::new(snapshot))
    }
}

/// Writes `value` for structural parameter `v` of `description` into `sizes`, after checking it is
/// a UInt64 within the declared [min, max].
fn stage_size(
    sizes: &mut [u64],
    description: &Description,
    v: &Variable,
    value: Value,
) -> Result<(), Failure> {
    let Value::UInt64(n) = value else {
        return Err(Failure::refused(format!(
            "{} cannot take the value {value:?}",
            v.name
        )));
    };
    let (lo, hi) = (v.min.unwrap_or(0.0), v.max.unwrap_or(f64::INFINITY));
    if !((lo..=hi).contains(&(n as f64))) {
        return Err(Failure::refused(format!(
            "{} = {n} is invalid: it must lie in [{lo}, {hi}]",
            v.name
        )));
    }
    let i = description
        .variables
        .iter()
        .filter(|s| s.causality == Causality::StructuralParameter)
        .position(|s| s.vr == v.vr)
        .expect("a structural parameter of the description");
    sizes[i] = n;
    Ok(())
}
