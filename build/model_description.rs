//! Reads and checks the hand-kept model descriptions (`modelDescription/modelDescription.xml`, FMI
//! 2.0, and `modelDescription/modelDescription-fmi3.xml`, FMI 3.0) and generates the Rust variable
//! tables.
//!
//! Shared by `build.rs` (which fails the build on the first inconsistency) and by the test
//! `tests/model_description_checker.rs` (which feeds it broken descriptions). It uses only
//! quick-xml + serde, so that it runs at build time without the crate itself. Each version is
//! parsed into the same [`Variable`] rows and checked by the same rules where FMI 2.0 and 3.0
//! agree ([`check_variable`]); `model_description_fmi3.rs` adds what only FMI 3.0 has and the
//! comparison of the two descriptions.

use crate::dependencies::{self, Dependencies, List};
use serde::Deserialize;
use std::collections::{BTreeMap, BTreeSet};

#[derive(Debug, Deserialize)]
struct Root {
    #[serde(rename = "@fmiVersion")]
    fmi_version: String,
    #[serde(rename = "@modelName")]
    model_name: String,
    #[serde(rename = "@guid")]
    guid: String,
    #[serde(rename = "CoSimulation")]
    co_simulation: Option<CoSimulation>,
    #[serde(rename = "UnitDefinitions")]
    unit_definitions: Option<UnitDefinitions>,
    #[serde(rename = "TypeDefinitions")]
    type_definitions: Option<TypeDefinitions>,
    #[serde(rename = "LogCategories")]
    log_categories: Option<LogCategories>,
    #[serde(rename = "DefaultExperiment")]
    default_experiment: Option<DefaultExperiment>,
    #[serde(rename = "ModelVariables")]
    model_variables: ModelVariables,
    #[serde(rename = "ModelStructure")]
    model_structure: ModelStructure,
}

/// The attributes of `<CoSimulation>` that the checks compare, kept as text.
#[derive(Debug, Deserialize)]
pub struct CoSimulation {
    #[serde(rename = "@modelIdentifier")]
    pub model_identifier: String,
    #[serde(rename = "@canHandleVariableCommunicationStepSize")]
    pub can_handle_variable_communication_step_size: Option<String>,
    #[serde(rename = "@maxOutputDerivativeOrder")]
    pub max_output_derivative_order: Option<String>,
    /// FMI 2.0 spelling.
    #[serde(rename = "@canGetAndSetFMUstate")]
    pub can_get_and_set_fmu_state_2: Option<String>,
    /// FMI 2.0 spelling.
    #[serde(rename = "@canSerializeFMUstate")]
    pub can_serialize_fmu_state_2: Option<String>,
    /// FMI 3.0 spelling.
    #[serde(rename = "@canGetAndSetFMUState")]
    pub can_get_and_set_fmu_state_3: Option<String>,
    /// FMI 3.0 spelling.
    #[serde(rename = "@canSerializeFMUState")]
    pub can_serialize_fmu_state_3: Option<String>,
    /// FMI 2.0.
    #[serde(rename = "@providesDirectionalDerivative")]
    pub provides_directional_derivative: Option<String>,
    /// FMI 3.0.
    #[serde(rename = "@providesDirectionalDerivatives")]
    pub provides_directional_derivatives: Option<String>,
    #[serde(rename = "@fixedInternalStepSize")]
    pub fixed_internal_step_size: Option<String>,
    #[serde(rename = "@hasEventMode")]
    pub has_event_mode: Option<String>,
    #[serde(rename = "@providesIntermediateUpdate")]
    pub provides_intermediate_update: Option<String>,
    #[serde(rename = "@canReturnEarlyAfterIntermediateUpdate")]
    pub can_return_early_after_intermediate_update: Option<String>,
}

#[derive(Debug, Deserialize)]
pub(crate) struct UnitDefinitions {
    #[serde(rename = "Unit", default)]
    pub units: Vec<Named>,
}

#[derive(Debug, Deserialize)]
pub(crate) struct Named {
    #[serde(rename = "@name")]
    pub name: String,
}

#[derive(Debug, Deserialize)]
struct TypeDefinitions {
    #[serde(rename = "SimpleType", default)]
    simple_types: Vec<SimpleType>,
}

#[derive(Debug, Deserialize)]
struct SimpleType {
    #[serde(rename = "@name")]
    name: String,
    #[serde(rename = "Enumeration")]
    enumeration: Option<EnumerationType>,
}

#[derive(Debug, Deserialize)]
struct EnumerationType {
    #[serde(rename = "Item", default)]
    items: Vec<Item>,
}

#[derive(Debug, Deserialize)]
struct Item {
    #[serde(rename = "@name")]
    name: String,
    #[serde(rename = "@value")]
    value: i64,
}

#[derive(Debug, Deserialize)]
pub(crate) struct LogCategories {
    #[serde(rename = "Category", default)]
    pub categories: Vec<Named>,
}

#[derive(Debug, Deserialize)]
pub(crate) struct DefaultExperiment {
    #[serde(rename = "@startTime")]
    start_time: Option<f64>,
    #[serde(rename = "@stopTime")]
    stop_time: Option<f64>,
    #[serde(rename = "@stepSize")]
    step_size: Option<f64>,
}

#[derive(Debug, Deserialize)]
struct ModelVariables {
    #[serde(rename = "ScalarVariable", default)]
    variables: Vec<ScalarVariable>,
}

#[derive(Debug, Deserialize)]
struct ScalarVariable {
    #[serde(rename = "@name")]
    name: String,
    #[serde(rename = "@valueReference")]
    value_reference: u32,
    #[serde(rename = "@description")]
    description: Option<String>,
    #[serde(rename = "@causality")]
    causality: Option<String>,
    #[serde(rename = "@variability")]
    variability: Option<String>,
    #[serde(rename = "@initial")]
    initial: Option<String>,
    #[serde(rename = "Real")]
    real: Option<TypeAttrs>,
    #[serde(rename = "Integer")]
    integer: Option<TypeAttrs>,
    #[serde(rename = "Boolean")]
    boolean: Option<TypeAttrs>,
    #[serde(rename = "String")]
    string: Option<TypeAttrs>,
    #[serde(rename = "Enumeration")]
    enumeration: Option<TypeAttrs>,
}

/// The attributes of the type element of a variable, all kept as text and parsed by kind.
#[derive(Debug, Default, Deserialize)]
pub(crate) struct TypeAttrs {
    #[serde(rename = "@start")]
    pub start: Option<String>,
    #[serde(rename = "@min")]
    pub min: Option<String>,
    #[serde(rename = "@max")]
    pub max: Option<String>,
    #[serde(rename = "@unit")]
    pub unit: Option<String>,
    #[serde(rename = "@declaredType")]
    pub declared_type: Option<String>,
}

#[derive(Debug, Deserialize)]
struct ModelStructure {
    #[serde(rename = "Outputs")]
    outputs: Option<UnknownList>,
    #[serde(rename = "InitialUnknowns")]
    initial_unknowns: Option<UnknownList>,
}

#[derive(Debug, Deserialize)]
struct UnknownList {
    #[serde(rename = "Unknown", default)]
    unknowns: Vec<Unknown>,
}

#[derive(Debug, Deserialize)]
struct Unknown {
    #[serde(rename = "@index")]
    index: usize,
    #[serde(rename = "@dependencies")]
    dependencies: Option<String>,
    #[serde(rename = "@dependenciesKind")]
    dependencies_kind: Option<String>,
}

/// Variable kinds, as the Rust table names them: `Real` is fmi2Real and fmi3Float64, `Integer`
/// fmi2Integer and fmi3Int32.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Real,
    Integer,
    UInt64,
    Boolean,
    String,
    Enumeration,
}

/// A start value, parsed by kind.
#[derive(Clone, Debug, PartialEq)]
pub enum Start {
    Real(f64),
    Integer(i64),
    Boolean(bool),
    String(String),
}

/// The size of one dimension of an array variable (FMI 3.0 `<Dimension>`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dimension {
    /// `start`: a fixed size.
    Fixed(u64),
    /// `valueReference`: the value of that structural parameter or constant.
    Variable(u32),
}

/// One variable as read from either version, before its checks.
pub(crate) struct RawVariable {
    pub name: String,
    pub value_reference: u32,
    pub description: Option<String>,
    pub kind: Kind,
    pub causality: Option<String>,
    pub variability: Option<String>,
    pub initial: Option<String>,
    pub attrs: TypeAttrs,
    pub dimensions: Vec<Dimension>,
    pub intermediate_update: bool,
}

/// One checked variable.
#[derive(Clone, Debug)]
pub struct Variable {
    pub name: String,
    pub value_reference: u32,
    pub description: Option<String>,
    pub kind: Kind,
    pub causality: String,
    pub variability: String,
    pub initial: Option<String>,
    pub start: Option<Start>,
    pub min: Option<f64>,
    pub max: Option<f64>,
    pub unit: Option<String>,
    pub dimensions: Vec<Dimension>,
    pub intermediate_update: bool,
}

/// The checked model description: what the Rust code needs, and what the two descriptions are
/// compared on.
#[derive(Debug)]
pub struct Model {
    pub fmi_version: String,
    pub model_name: String,
    pub model_identifier: String,
    /// `guid` (FMI 2.0) or `instantiationToken` (FMI 3.0).
    pub token: String,
    pub log_categories: Vec<String>,
    pub default_start_time: f64,
    pub default_stop_time: f64,
    pub default_step_size: f64,
    pub co_simulation: CoSimulation,
    pub variables: Vec<Variable>,
    /// What each output and initial unknown depends on, checked by [`dependencies::check`].
    pub dependencies: Vec<Dependencies>,
}

impl Model {
    /// The variable named `name`.
    pub fn by_name(&self, name: &str) -> Option<&Variable> {
        self.variables.iter().find(|v| v.name == name)
    }
}

pub(crate) fn is_structured_name(name: &str) -> bool {
    !name.is_empty()
        && name.split('.').all(|part| {
            let mut chars = part.chars();
            matches!(chars.next(), Some(c) if c.is_ascii_alphabetic() || c == '_')
                && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
        })
}

/// The `initial` values allowed for a causality and variability, and the default `initial`.
pub(crate) type Initials = (Vec<&'static str>, Option<&'static str>);

/// The `initial` values FMI 2.0 (§2.2.7, table of causality × variability) allows, and the
/// default; `None` means the combination itself is illegal, `Some((vec![], _))` that no `initial`
/// may be given.
fn allowed_initial(causality: &str, variability: &str) -> Option<Initials> {
    match (causality, variability) {
        ("parameter", "fixed" | "tunable") => Some((vec!["exact"], Some("exact"))),
        ("calculatedParameter", "fixed" | "tunable") => {
            Some((vec!["approx", "calculated"], Some("calculated")))
        }
        ("input", "discrete" | "continuous") => Some((vec![], None)),
        ("output", "constant") => Some((vec!["exact"], Some("exact"))),
        ("output", "discrete" | "continuous") => {
            Some((vec!["exact", "approx", "calculated"], Some("calculated")))
        }
        ("local", "constant") => Some((vec!["exact"], Some("exact"))),
        ("local", "fixed" | "tunable") => Some((vec!["approx", "calculated"], Some("calculated"))),
        ("local", "discrete" | "continuous") => {
            Some((vec!["exact", "approx", "calculated"], Some("calculated")))
        }
        ("independent", "continuous") => Some((vec![], None)),
        _ => None,
    }
}

/// The rules of one FMI version that [`check_variable`] applies.
pub(crate) struct Rules {
    /// "FMI 2.0" or "FMI 3.0", for messages.
    pub version: &'static str,
    /// The allowed `initial` values and the default for a causality and variability (see
    /// [`allowed_initial`]).
    pub allowed_initial: fn(&str, &str) -> Option<Initials>,
    /// Whether an input needs a start value.
    pub input_needs_start: bool,
    /// The variability of a variable that declares none, by causality and kind.
    pub default_variability: fn(&str, Kind) -> &'static str,
}

/// FMI 2.0's rules.
const FMI2_RULES: Rules = Rules {
    version: "FMI 2.0",
    allowed_initial,
    input_needs_start: true,
    default_variability: |_, kind| {
        if kind == Kind::Real {
            "continuous"
        } else {
            "discrete"
        }
    },
};

/// What every variable of every description must satisfy: a structured name used once, a value
/// reference used once, a legal causality × variability × initial for `rules`, a start value
/// exactly when one is required, within [min, max], a declared unit on every Real except the
/// independent variable, enumeration starts among the items. `units` and `enums` are the
/// description's unit names and enumeration types; `names` and `refs` collect what was seen.
pub(crate) fn check_variable(
    v: RawVariable,
    rules: &Rules,
    units: &BTreeSet<String>,
    enums: &BTreeMap<String, Vec<i64>>,
    names: &mut BTreeSet<String>,
    refs: &mut BTreeMap<u32, String>,
) -> Result<Variable, String> {
    let who = format!(
        "variable {:?} (valueReference {})",
        v.name, v.value_reference
    );
    if !is_structured_name(&v.name) {
        return Err(format!("{who}: name is not a structured FMI name"));
    }
    if !names.insert(v.name.clone()) {
        return Err(format!("{who}: the name is declared twice"));
    }
    if let Some(other) = refs.insert(v.value_reference, v.name.clone()) {
        return Err(format!("{who}: valueReference already used by {other:?}"));
    }
    let kind = v.kind;
    let attrs = &v.attrs;
    let causality = v.causality.clone().unwrap_or_else(|| "local".into());
    let variability = v
        .variability
        .clone()
        .unwrap_or_else(|| (rules.default_variability)(&causality, kind).into());
    if variability == "continuous" && kind != Kind::Real {
        return Err(format!("{who}: only Real variables may be continuous"));
    }
    let version = rules.version;
    let (allowed, default_initial) = (rules.allowed_initial)(&causality, &variability)
        .ok_or_else(|| {
            format!("{who}: causality {causality:?} with variability {variability:?} is not allowed by {version}")
        })?;
    let initial = match &v.initial {
        Some(i) if allowed.contains(&i.as_str()) => Some(i.clone()),
        Some(i) => {
            return Err(format!(
                "{who}: initial {i:?} is not allowed for causality {causality:?} / variability {variability:?} (allowed: {allowed:?})"
            ))
        }
        None => default_initial.map(String::from),
    };
    let needs_start = (causality == "input" && rules.input_needs_start)
        || matches!(initial.as_deref(), Some("exact") | Some("approx"));
    let start = match (&attrs.start, needs_start) {
        (None, true) => return Err(format!("{who}: a start value is required")),
        (Some(_), false) => {
            return Err(format!(
                "{who}: a start value is not allowed with initial {initial:?}"
            ))
        }
        (None, false) => None,
        (Some(s), true) => Some(parse_start(&who, kind, s)?),
    };
    check_unit(&who, kind, &causality, attrs.unit.as_deref(), units)?;
    if kind == Kind::Enumeration {
        check_enumeration(&who, attrs.declared_type.as_deref(), start.as_ref(), enums)?;
    }
    let (min, max) = check_bounds(
        &who,
        attrs.min.as_deref(),
        attrs.max.as_deref(),
        start.as_ref(),
    )?;
    Ok(Variable {
        name: v.name,
        value_reference: v.value_reference,
        description: v.description,
        kind,
        causality,
        variability,
        initial,
        start,
        min,
        max,
        unit: attrs.unit.clone(),
        dimensions: v.dimensions,
        intermediate_update: v.intermediate_update,
    })
}

/// A Real variable declares a unit of `<UnitDefinitions>` (the independent variable may omit
/// it); other kinds declare none.
fn check_unit(
    who: &str,
    kind: Kind,
    causality: &str,
    unit: Option<&str>,
    units: &BTreeSet<String>,
) -> Result<(), String> {
    match unit {
        Some(_) if kind != Kind::Real => Err(format!("{who}: only Real variables carry a unit")),
        Some(unit) if !units.contains(unit) => {
            Err(format!("{who}: unit {unit:?} is not in <UnitDefinitions>"))
        }
        None if kind == Kind::Real && causality != "independent" => Err(format!(
            "{who}: every Real variable must declare its unit (SI)"
        )),
        _ => Ok(()),
    }
}

/// An Enumeration names a declared enumeration type, and its start is one of its items.
fn check_enumeration(
    who: &str,
    declared_type: Option<&str>,
    start: Option<&Start>,
    enums: &BTreeMap<String, Vec<i64>>,
) -> Result<(), String> {
    let name =
        declared_type.ok_or_else(|| format!("{who}: an Enumeration needs a declaredType"))?;
    let items = enums
        .get(name)
        .ok_or_else(|| format!("{who}: declaredType {name:?} is not an enumeration type"))?;
    if let Some(Start::Integer(s)) = start {
        if !items.contains(s) {
            return Err(format!("{who}: start {s} is not an item of {name:?}"));
        }
    }
    Ok(())
}

/// min and max as numbers, min ≤ max, and a numeric start within them.
fn check_bounds(
    who: &str,
    min: Option<&str>,
    max: Option<&str>,
    start: Option<&Start>,
) -> Result<(Option<f64>, Option<f64>), String> {
    let bound = |b: Option<&str>, what: &str| -> Result<Option<f64>, String> {
        b.map(|b| {
            b.trim()
                .parse::<f64>()
                .ok()
                .filter(|x| !x.is_nan())
                .ok_or_else(|| format!("{who}: {what} {b:?} is not a number"))
        })
        .transpose()
    };
    let (min, max) = (bound(min, "min")?, bound(max, "max")?);
    if let (Some(lo), Some(hi)) = (min, max) {
        if lo > hi {
            return Err(format!("{who}: min {lo} > max {hi}"));
        }
    }
    let start_number = match start {
        Some(Start::Real(x)) => Some(*x),
        Some(Start::Integer(i)) => Some(*i as f64),
        _ => None,
    };
    if let Some(x) = start_number {
        if min.is_some_and(|lo| x < lo) || max.is_some_and(|hi| x > hi) {
            return Err(format!(
                "{who}: start {x} lies outside [min, max] = [{}, {}]",
                min.map_or("-inf".into(), |m| m.to_string()),
                max.map_or("inf".into(), |m| m.to_string())
            ));
        }
    }
    Ok((min, max))
}

/// The unit names of `<UnitDefinitions>`.
pub(crate) fn unit_names(units: Option<UnitDefinitions>) -> BTreeSet<String> {
    units
        .map(|u| u.units.into_iter().map(|u| u.name).collect())
        .unwrap_or_default()
}

/// The category names of `<LogCategories>`.
pub(crate) fn category_names(categories: Option<LogCategories>) -> Vec<String> {
    categories
        .map(|l| l.categories.into_iter().map(|c| c.name).collect())
        .unwrap_or_default()
}

/// The model identifier of `<CoSimulation>`, checked to be a C identifier.
pub(crate) fn co_simulation(cs: Option<CoSimulation>) -> Result<CoSimulation, String> {
    let cs = cs.ok_or("no <CoSimulation> element: this FMU is Co-Simulation")?;
    if !is_structured_name(&cs.model_identifier) || cs.model_identifier.contains('.') {
        return Err(format!(
            "modelIdentifier {:?} is not a C identifier",
            cs.model_identifier
        ));
    }
    Ok(cs)
}

/// `<DefaultExperiment>` startTime, stopTime and stepSize, checked.
pub(crate) fn default_experiment(
    experiment: Option<DefaultExperiment>,
) -> Result<(f64, f64, f64), String> {
    let experiment = experiment
        .ok_or("no <DefaultExperiment>: importers need the default start, stop and step")?;
    match (
        experiment.start_time,
        experiment.stop_time,
        experiment.step_size,
    ) {
        (Some(a), Some(b), Some(h)) if a.is_finite() && b > a && h > 0.0 => Ok((a, b, h)),
        other => Err(format!(
            "DefaultExperiment needs startTime < stopTime and stepSize > 0, got {other:?}"
        )),
    }
}

/// The positions (from 0) of the outputs, and of the initial unknowns: the outputs and calculated
/// parameters whose `initial` is neither exact nor approx; what `<ModelStructure>` must list, in
/// this order.
pub(crate) fn expected_structure(variables: &[Variable]) -> (Vec<usize>, Vec<usize>) {
    let outputs = variables
        .iter()
        .enumerate()
        .filter(|(_, v)| v.causality == "output")
        .map(|(i, _)| i)
        .collect();
    let initial_unknowns = variables
        .iter()
        .enumerate()
        .filter(|(_, v)| {
            (v.causality == "output" || v.causality == "calculatedParameter")
                && v.initial.as_deref() != Some("exact")
                && v.initial.as_deref() != Some("approx")
        })
        .map(|(i, _)| i)
        .collect();
    (outputs, initial_unknowns)
}

/// Parses and checks an FMI 2.0 model description; the error names the variable (or element) at
/// fault.
pub fn check(xml: &str) -> Result<Model, String> {
    let root: Root = quick_xml::de::from_str(xml).map_err(|e| format!("cannot parse: {e}"))?;
    if root.fmi_version != "2.0" {
        return Err(format!(
            "fmiVersion is {:?}, expected \"2.0\"",
            root.fmi_version
        ));
    }
    if root.model_name.is_empty() {
        return Err("modelName is empty".into());
    }
    let cs = co_simulation(root.co_simulation)?;
    let units = unit_names(root.unit_definitions);
    let mut enums: BTreeMap<String, Vec<i64>> = BTreeMap::new();
    for t in root
        .type_definitions
        .map(|t| t.simple_types)
        .unwrap_or_default()
    {
        if let Some(e) = t.enumeration {
            if e.items.is_empty() {
                return Err(format!("enumeration type {:?} has no items", t.name));
            }
            let mut values = BTreeSet::new();
            for item in &e.items {
                if !values.insert(item.value) {
                    return Err(format!(
                        "enumeration type {:?}: item {:?} repeats value {}",
                        t.name, item.name, item.value
                    ));
                }
            }
            enums.insert(t.name, e.items.iter().map(|i| i.value).collect());
        }
    }
    let log_categories = category_names(root.log_categories);
    let (start_time, stop_time, step_size) = default_experiment(root.default_experiment)?;

    let mut names = BTreeSet::new();
    let mut refs = BTreeMap::new();
    let mut variables = Vec::new();
    for v in root.model_variables.variables {
        let typed: Vec<(Kind, TypeAttrs)> = [
            (Kind::Real, v.real),
            (Kind::Integer, v.integer),
            (Kind::Boolean, v.boolean),
            (Kind::String, v.string),
            (Kind::Enumeration, v.enumeration),
        ]
        .into_iter()
        .filter_map(|(k, a)| a.map(|a| (k, a)))
        .collect();
        let Ok::<[_; 1], _>([(kind, attrs)]) = typed.try_into() else {
            return Err(format!(
                "variable {:?} (valueReference {}): needs exactly one type element (Real, Integer, …)",
                v.name, v.value_reference
            ));
        };
        let raw = RawVariable {
            name: v.name,
            value_reference: v.value_reference,
            description: v.description,
            kind,
            causality: v.causality,
            variability: v.variability,
            initial: v.initial,
            attrs,
            dimensions: Vec::new(),
            intermediate_update: false,
        };
        variables.push(check_variable(
            raw,
            &FMI2_RULES,
            &units,
            &enums,
            &mut names,
            &mut refs,
        )?);
    }

    // ModelStructure: <Outputs> lists exactly the outputs; <InitialUnknowns> every output with
    // initial = calculated; both in increasing index order (1-based into ModelVariables).
    let list = |l: &Option<UnknownList>| -> Vec<usize> {
        l.as_ref()
            .map(|l| l.unknowns.iter().map(|u| u.index).collect())
            .unwrap_or_default()
    };
    let structure = root.model_structure;
    let (outputs, initial_unknowns) = expected_structure(&variables);
    let one_based =
        |positions: Vec<usize>| -> Vec<usize> { positions.into_iter().map(|i| i + 1).collect() };
    let (outputs_expected, initial_expected) = (one_based(outputs), one_based(initial_unknowns));
    let outputs_declared = list(&structure.outputs);
    if outputs_declared != outputs_expected {
        return Err(format!(
            "ModelStructure/Outputs lists indices {outputs_declared:?}, but the outputs are at {outputs_expected:?}"
        ));
    }
    let initial_declared = list(&structure.initial_unknowns);
    if initial_declared != initial_expected {
        return Err(format!(
            "ModelStructure/InitialUnknowns lists indices {initial_declared:?}, but the calculated outputs are at {initial_expected:?}"
        ));
    }
    // The indices were checked above; a dependency is a 1-based index too.
    let resolve = |index: u64| -> Option<&Variable> {
        variables.get(usize::try_from(index).ok()?.checked_sub(1)?)
    };
    let mut declared = Vec::new();
    for (kind, unknowns) in [
        (List::Outputs, &structure.outputs),
        (List::InitialUnknowns, &structure.initial_unknowns),
    ] {
        for u in unknowns.iter().flat_map(|l| &l.unknowns) {
            declared.push(dependencies::check(
                "2.0",
                kind,
                &variables[u.index - 1],
                u.dependencies.as_deref(),
                u.dependencies_kind.as_deref(),
                &resolve,
            )?);
        }
    }

    Ok(Model {
        fmi_version: root.fmi_version,
        model_name: root.model_name,
        model_identifier: cs.model_identifier.clone(),
        token: root.guid,
        log_categories,
        default_start_time: start_time,
        default_stop_time: stop_time,
        default_step_size: step_size,
        co_simulation: cs,
        variables,
        dependencies: declared,
    })
}

pub(crate) fn parse_start(who: &str, kind: Kind, s: &str) -> Result<Start, String> {
    let bad = || format!("{who}: start {s:?} is not a valid {kind:?}");
    Ok(match kind {
        Kind::Real => {
            let x: f64 = s.trim().parse().map_err(|_| bad())?;
            if !x.is_finite() {
                return Err(bad());
            }
            Start::Real(x)
        }
        Kind::Integer | Kind::Enumeration => {
            let i: i64 = s.trim().parse().map_err(|_| bad())?;
            if kind == Kind::Integer && i32::try_from(i).is_err() {
                return Err(bad());
            }
            Start::Integer(i)
        }
        Kind::UInt64 => Start::Integer(
            s.trim()
                .parse::<u64>()
                .ok()
                .and_then(|u| i64::try_from(u).ok())
                .ok_or_else(bad)?,
        ),
        Kind::Boolean => Start::Boolean(match s.trim() {
            "true" | "1" => true,
            "false" | "0" => false,
            _ => return Err(bad()),
        }),
        Kind::String => Start::String(s.to_string()),
    })
}

fn const_name(variable: &str) -> String {
    variable.replace('.', "_").to_ascii_uppercase()
}

/// The Rust source of one description's table: `pub const {name}: Description`.
fn description_table(name: &str, model: &Model) -> String {
    let mut out = format!(
        "/// The FMI {} model description (`modelDescription.xml` of its FMU).\npub const {name}: Description = Description {{\n",
        model.fmi_version
    );
    out.push_str(&format!("    fmi_version: {:?},\n", model.fmi_version));
    out.push_str(&format!("    token: {:?},\n", model.token));
    out.push_str(&format!(
        "    log_categories: &{:?},\n",
        model.log_categories
    ));
    out.push_str(&format!(
        "    default_experiment: [{:?}, {:?}, {:?}],\n",
        model.default_start_time, model.default_stop_time, model.default_step_size
    ));
    out.push_str("    variables: &[\n");
    for v in &model.variables {
        let start = match &v.start {
            None => "None".to_string(),
            Some(Start::Real(x)) => format!("Some(Start::Real({x:?}))"),
            Some(Start::Integer(i)) => format!("Some(Start::Integer({i}))"),
            Some(Start::Boolean(b)) => format!("Some(Start::Boolean({b}))"),
            Some(Start::String(s)) => format!("Some(Start::String({s:?}))"),
        };
        let causality = match v.causality.as_str() {
            "parameter" => "Parameter",
            "structuralParameter" => "StructuralParameter",
            "calculatedParameter" => "CalculatedParameter",
            "input" => "Input",
            "output" => "Output",
            "independent" => "Independent",
            _ => "Local",
        };
        let variability = match v.variability.as_str() {
            "constant" => "Constant",
            "fixed" => "Fixed",
            "tunable" => "Tunable",
            "discrete" => "Discrete",
            _ => "Continuous",
        };
        let dimensions: Vec<String> = v
            .dimensions
            .iter()
            .map(|d| match d {
                Dimension::Fixed(n) => format!("Dimension::Fixed({n})"),
                Dimension::Variable(r) => format!("Dimension::Variable({r})"),
            })
            .collect();
        out.push_str(&format!(
            "        Variable {{ name: {:?}, vr: {}, kind: Kind::{:?}, causality: Causality::{causality}, variability: Variability::{variability}, start: {start}, min: {:?}, max: {:?}, unit: {:?}, description: {:?}, dimensions: &[{}], intermediate_update: {} }},\n",
            v.name, v.value_reference, v.kind, v.min, v.max, v.unit, v.description, dimensions.join(", "), v.intermediate_update
        ));
    }
    out.push_str("    ],\n};\n\n");
    out
}

/// Rust source for `$OUT_DIR/model_description.rs`, included by `src/fmi/variables.rs`: the model
/// identifier, one value-reference constant per variable of either description (checked to agree
/// by [`crate::model_description_fmi3::check_same_variables`]) and each description's table.
pub fn generate(fmi2: &Model, fmi3: &Model) -> String {
    let mut out = String::new();
    out.push_str(
        "// Generated by build.rs from modelDescription/modelDescription.xml and modelDescription-fmi3.xml. Do not edit.\n\n",
    );
    out.push_str(&format!(
        "/// `modelIdentifier` of the Co-Simulation interface (both FMI versions).\npub const MODEL_IDENTIFIER: &str = {:?};\n\n",
        fmi2.model_identifier
    ));
    out.push_str("/// Value references, one constant per variable (dots become underscores).\npub mod vr {\n");
    let mut seen = BTreeSet::new();
    for v in fmi2.variables.iter().chain(&fmi3.variables) {
        if seen.insert(&v.name) {
            out.push_str(&format!(
                "    /// `{}`\n    pub const {}: u32 = {};\n",
                v.name,
                const_name(&v.name),
                v.value_reference
            ));
        }
    }
    out.push_str("}\n\n");
    out.push_str(&description_table("FMI2", fmi2));
    out.push_str(&description_table("FMI3", fmi3));
    out
}
