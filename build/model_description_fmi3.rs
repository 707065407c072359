//! The FMI 3.0 model description (`modelDescription/modelDescription-fmi3.xml`): its parser and
//! the rules FMI 3.0 adds to those of [`crate::model_description::check_variable`] (typed variable
//! elements, `instantiationToken`, one independent variable, array dimensions bound to structural
//! parameters, `<ModelStructure><Output>` and `<InitialUnknown>` by value reference, the
//! Co-Simulation capability flags this FMU relies on), and [`check_same_variables`], which keeps
//! the FMI 2.0 and 3.0 descriptions from drifting apart.

use crate::dependencies::{self, Dependencies, List};
use crate::model_description::{
    category_names, check_variable, co_simulation, default_experiment, expected_structure,
    unit_names, CoSimulation, DefaultExperiment, Dimension, Initials, Kind, LogCategories, Model,
    RawVariable, Rules, Start, TypeAttrs, UnitDefinitions, Variable,
};
use serde::Deserialize;
use std::collections::{BTreeMap, BTreeSet};

#[derive(Debug, Deserialize)]
struct Root {
    #[serde(rename = "@fmiVersion")]
    fmi_version: String,
    #[serde(rename = "@modelName")]
    model_name: String,
    #[serde(rename = "@instantiationToken")]
    instantiation_token: Option<String>,
    #[serde(rename = "CoSimulation")]
    co_simulation: Option<CoSimulation>,
    #[serde(rename = "UnitDefinitions")]
    unit_definitions: Option<UnitDefinitions>,
    #[serde(rename = "LogCategories")]
    log_categories: Option<LogCategories>,
    #[serde(rename = "DefaultExperiment")]
    default_experiment: Option<DefaultExperiment>,
    #[serde(rename = "ModelVariables")]
    model_variables: ModelVariables,
    #[serde(rename = "ModelStructure")]
    model_structure: ModelStructure,
}

#[derive(Debug, Deserialize)]
struct ModelVariables {
    #[serde(rename = "$value", default)]
    variables: Vec<TypedVariable>,
}

/// A variable element: its name is its type. Only the types this FMU uses are accepted.
#[derive(Debug, Deserialize)]
enum TypedVariable {
    Float64(VariableElement),
    Int32(VariableElement),
    UInt64(VariableElement),
    Boolean(VariableElement),
    String(VariableElement),
}

#[derive(Debug, Deserialize)]
struct VariableElement {
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
    #[serde(rename = "@start")]
    start: Option<String>,
    #[serde(rename = "@min")]
    min: Option<String>,
    #[serde(rename = "@max")]
    max: Option<String>,
    #[serde(rename = "@unit")]
    unit: Option<String>,
    #[serde(rename = "@intermediateUpdate")]
    intermediate_update: Option<bool>,
    #[serde(rename = "Dimension", default)]
    dimensions: Vec<DimensionElement>,
    /// A String's start: `<Start value="…"/>` elements (one per element of an array).
    #[serde(rename = "Start", default)]
    start_elements: Vec<StartElement>,
}

#[derive(Debug, Deserialize)]
struct StartElement {
    #[serde(rename = "@value")]
    value: String,
}

#[derive(Debug, Deserialize)]
struct DimensionElement {
    #[serde(rename = "@start")]
    start: Option<u64>,
    #[serde(rename = "@valueReference")]
    value_reference: Option<u32>,
}

#[derive(Debug, Deserialize)]
struct ModelStructure {
    #[serde(rename = "Output", default)]
    outputs: Vec<Reference>,
    #[serde(rename = "InitialUnknown", default)]
    initial_unknowns: Vec<Reference>,
}

#[derive(Debug, Deserialize)]
struct Reference {
    #[serde(rename = "@valueReference")]
    value_reference: u32,
    #[serde(rename = "@dependencies")]
    dependencies: Option<String>,
    #[serde(rename = "@dependenciesKind")]
    dependencies_kind: Option<String>,
}

/// The `initial` values FMI 3.0 allows for a causality and variability, and the default (FMI 3.0,
/// "Definition of initial"; `None`: the combination is illegal).
fn allowed_initial(causality: &str, variability: &str) -> Option<Initials> {
    match (causality, variability) {
        ("structuralParameter" | "parameter", "fixed" | "tunable") => {
            Some((vec!["exact"], Some("exact")))
        }
        ("calculatedParameter" | "local", "fixed" | "tunable") => {
            Some((vec!["calculated", "approx"], Some("calculated")))
        }
        ("input", "discrete" | "continuous") => Some((vec!["exact"], Some("exact"))),
        ("output" | "local", "constant") => Some((vec!["exact"], Some("exact"))),
        ("output" | "local", "discrete" | "continuous") => {
            Some((vec!["calculated", "exact", "approx"], Some("calculated")))
        }
        ("independent", "continuous") => Some((vec![], None)),
        _ => None,
    }
}

/// FMI 3.0's rules: parameters default to fixed, floats to continuous.
const FMI3_RULES: Rules = Rules {
    version: "FMI 3.0",
    allowed_initial,
    input_needs_start: true,
    default_variability: |causality, kind| match causality {
        "structuralParameter" | "parameter" | "calculatedParameter" => "fixed",
        _ if kind == Kind::Real => "continuous",
        _ => "discrete",
    },
};

/// The name of the parameter that sets the FMU's internal step.
const TIME_STEP: &str = "solver.time_step";

/// A flag of `<CoSimulation>`: absent is false.
fn flag(value: &Option<String>) -> bool {
    value.as_deref() == Some("true")
}

/// Parses and checks an FMI 3.0 model description; the error names the variable (or element) at
/// fault.
pub fn check_fmi3(xml: &str) -> Result<Model, String> {
    let root: Root = quick_xml::de::from_str(xml).map_err(|e| format!("cannot parse: {e}"))?;
    if root.fmi_version != "3.0" {
        return Err(format!(
            "fmiVersion is {:?}, expected \"3.0\"",
            root.fmi_version
        ));
    }
    if root.model_name.is_empty() {
        return Err("modelName is empty".into());
    }
    let token = root
        .instantiation_token
        .filter(|t| !t.trim().is_empty())
        .ok_or("no instantiationToken: FMI 3.0 needs one, fmi3InstantiateCoSimulation checks it")?;
    let cs = co_simulation(root.co_simulation)?;
    check_capabilities(&cs)?;
    let units = unit_names(root.unit_definitions);
    let log_categories = category_names(root.log_categories);
    let (start_time, stop_time, step_size) = default_experiment(root.default_experiment)?;

    let mut names = BTreeSet::new();
    let mut refs = BTreeMap::new();
    let mut variables = Vec::new();
    for typed in root.model_variables.variables {
        variables.push(check_fmi3_variable(typed, &units, &mut names, &mut refs)?);
    }
    check_independent(&variables)?;
    check_dimensions(&variables)?;
    check_model_structure(&variables, &root.model_structure)?;
    let declared = declared_dependencies(&variables, &root.model_structure)?;
    check_no_fixed_internal_step(&cs)?;
    Ok(Model {
        fmi_version: root.fmi_version,
        model_name: root.model_name,
        model_identifier: cs.model_identifier.clone(),
        token,
        log_categories,
        default_start_time: start_time,
        default_stop_time: stop_time,
        default_step_size: step_size,
        co_simulation: cs,
        variables,
        dependencies: declared,
    })
}

/// The dependencies of every `<Output>` and `<InitialUnknown>`, checked by
/// [`dependencies::check`] (entries are value references).
fn declared_dependencies(
    variables: &[Variable],
    structure: &ModelStructure,
) -> Result<Vec<Dependencies>, String> {
    let resolve = |reference: u64| -> Option<&Variable> {
        variables
            .iter()
            .find(|v| u64::from(v.value_reference) == reference)
    };
    let mut declared = Vec::new();
    for (kind, unknowns) in [
        (List::Outputs, &structure.outputs),
        (List::InitialUnknowns, &structure.initial_unknowns),
    ] {
        for u in unknowns {
            let unknown = resolve(u64::from(u.value_reference))
                .expect("check_model_structure found every unknown");
            declared.push(dependencies::check(
                "3.0",
                kind,
                unknown,
                u.dependencies.as_deref(),
                u.dependencies_kind.as_deref(),
                &resolve,
            )?);
        }
    }
    Ok(declared)
}

/// One `<Float64>`, `<Int32>`, `<UInt64>`, `<Boolean>` or `<String>` element: the checks shared
/// with FMI 2.0 ([`check_variable`]), its `<Dimension>`s, and the FMI 3.0 rules on
/// intermediateUpdate, structural parameters and String starts (a `<Start>` element, not an
/// attribute).
fn check_fmi3_variable(
    typed: TypedVariable,
    units: &BTreeSet<String>,
    names: &mut BTreeSet<String>,
    refs: &mut BTreeMap<u32, String>,
) -> Result<Variable, String> {
    let (kind, e) = match typed {
        TypedVariable::Float64(e) => (Kind::Real, e),
        TypedVariable::Int32(e) => (Kind::Integer, e),
        TypedVariable::UInt64(e) => (Kind::UInt64, e),
        TypedVariable::Boolean(e) => (Kind::Boolean, e),
        TypedVariable::String(e) => (Kind::String, e),
    };
    let who = format!(
        "variable {:?} (valueReference {})",
        e.name, e.value_reference
    );
    let start = match (kind, &e.start_elements[..]) {
        (Kind::String, []) => None,
        (Kind::String, [start]) if e.start.is_none() => Some(start.value.clone()),
        (Kind::String, _) => {
            return Err(format!(
                "{who}: a scalar String takes its start as one <Start value=\"…\"/> element"
            ))
        }
        (_, []) => e.start,
        (_, _) => return Err(format!("{who}: only a String has <Start> elements")),
    };
    let dimensions = e
        .dimensions
        .iter()
        .map(|d| match (d.start, d.value_reference) {
            (Some(n), None) if n > 0 => Ok(Dimension::Fixed(n)),
            (None, Some(r)) => Ok(Dimension::Variable(r)),
            _ => Err(format!(
                "{who}: a <Dimension> needs either start > 0 or valueReference"
            )),
        })
        .collect::<Result<Vec<_>, _>>()?;
    let raw = RawVariable {
        name: e.name,
        value_reference: e.value_reference,
        description: e.description,
        kind,
        causality: e.causality,
        variability: e.variability,
        initial: e.initial,
        attrs: TypeAttrs {
            start,
            min: e.min,
            max: e.max,
            unit: e.unit,
            declared_type: None,
        },
        dimensions,
        intermediate_update: e.intermediate_update.unwrap_or(false),
    };
    let v = check_variable(raw, &FMI3_RULES, units, &BTreeMap::new(), names, refs)?;
    if v.intermediate_update
        && !(v.variability == "continuous" && matches!(v.causality.as_str(), "input" | "output"))
    {
        return Err(format!(
            "{who}: only continuous inputs and outputs may have intermediateUpdate = true"
        ));
    }
    if v.causality == "structuralParameter" && !v.dimensions.is_empty() {
        return Err(format!(
            "{who}: a structural parameter must not be an array"
        ));
    }
    Ok(v)
}

/// No fixedInternalStepSize: the internal step is the parameter `solver.time_step`, so a constant
/// in `<CoSimulation>` would be false whenever a host sets it (and importers such as fmpy take the
/// attribute as the basis of their output interval).
fn check_no_fixed_internal_step(cs: &CoSimulation) -> Result<(), String> {
    match &cs.fixed_internal_step_size {
        Some(step) => Err(format!(
            "CoSimulation fixedInternalStepSize = {step:?} must not be declared: the internal step is the parameter {TIME_STEP}, which a host may set"
        )),
        None => Ok(()),
    }
}

/// The capability flags this FMU's FMI 3.0 layer relies on: no Event Mode (impacts are resolved
/// inside the scheme), early return after an intermediate update only with intermediate updates,
/// a derivative order that is a number.
fn check_capabilities(cs: &CoSimulation) -> Result<(), String> {
    if flag(&cs.has_event_mode) {
        return Err("CoSimulation hasEventMode must be false: this FMU has no Event Mode (impacts are resolved inside the scheme)".into());
    }
    if flag(&cs.can_return_early_after_intermediate_update)
        && !flag(&cs.provides_intermediate_update)
    {
        return Err("CoSimulation canReturnEarlyAfterIntermediateUpdate needs providesIntermediateUpdate = true".into());
    }
    if let Some(order) = &cs.max_output_derivative_order {
        order.trim().parse::<u32>().map_err(|_| {
            format!("CoSimulation maxOutputDerivativeOrder {order:?} is not a natural number")
        })?;
    }
    Ok(())
}

/// Exactly one independent variable, a Real without start.
fn check_independent(variables: &[Variable]) -> Result<(), String> {
    let independent: Vec<&Variable> = variables
        .iter()
        .filter(|v| v.causality == "independent")
        .collect();
    match independent.as_slice() {
        [v] if v.kind == Kind::Real && v.dimensions.is_empty() => Ok(()),
        [v] => Err(format!(
            "variable {:?}: the independent variable must be a scalar Float64",
            v.name
        )),
        other => Err(format!(
            "FMI 3.0 needs exactly one independent variable (time), found {}",
            other.len()
        )),
    }
}

/// Every `<Dimension valueReference>` names a UInt64 structural parameter (or constant) with a
/// start above 0.
fn check_dimensions(variables: &[Variable]) -> Result<(), String> {
    let by_ref: BTreeMap<u32, &Variable> =
        variables.iter().map(|v| (v.value_reference, v)).collect();
    for v in variables {
        for d in &v.dimensions {
            let Dimension::Variable(r) = d else { continue };
            let size = by_ref.get(r).ok_or_else(|| {
                format!(
                    "variable {:?}: <Dimension valueReference=\"{r}\"> names no variable",
                    v.name
                )
            })?;
            let bound = size.causality == "structuralParameter" || size.variability == "constant";
            if size.kind != Kind::UInt64 || !bound {
                return Err(format!(
                    "variable {:?}: its dimension {:?} must be a UInt64 structural parameter or constant",
                    v.name, size.name
                ));
            }
            if !matches!(size.start, Some(Start::Integer(n)) if n > 0) {
                return Err(format!(
                    "variable {:?}: the start of the structural parameter {:?} must be larger than 0",
                    v.name, size.name
                ));
            }
        }
    }
    Ok(())
}

/// `<Output>` lists exactly the outputs, `<InitialUnknown>` the calculated outputs (and calculated
/// parameters), each in the order of `<ModelVariables>`, by value reference.
fn check_model_structure(variables: &[Variable], structure: &ModelStructure) -> Result<(), String> {
    let (outputs, initial_unknowns) = expected_structure(variables);
    let references = |positions: Vec<usize>| -> Vec<u32> {
        positions
            .into_iter()
            .map(|i| variables[i].value_reference)
            .collect()
    };
    let declared =
        |list: &[Reference]| -> Vec<u32> { list.iter().map(|r| r.value_reference).collect() };
    let (outputs, initial_unknowns) = (references(outputs), references(initial_unknowns));
    let outputs_declared = declared(&structure.outputs);
    if outputs_declared != outputs {
        return Err(format!(
            "ModelStructure/Output lists value references {outputs_declared:?}, but the outputs are {outputs:?}"
        ));
    }
    let initial_declared = declared(&structure.initial_unknowns);
    if initial_declared != initial_unknowns {
        return Err(format!(
            "ModelStructure/InitialUnknown lists value references {initial_declared:?}, but the calculated outputs are {initial_unknowns:?}"
        ));
    }
    Ok(())
}

/// The two descriptions declare the same model: the same name, identifier, log categories,
/// default experiment and shared capabilities, and every FMI 2.0 variable in FMI 3.0 with the same
/// value reference, type, causality, variability, initial (an FMI 2.0 input's implicit one is
/// FMI 3.0's exact), start, range, unit and description. FMI 3.0 may add only what FMI 2.0
/// cannot express: the independent variable, structural parameters and arrays (their value
/// references are their own, since each description's are unique).
pub fn check_same_variables(fmi2: &Model, fmi3: &Model) -> Result<(), String> {
    check_same_header(fmi2, fmi3)?;
    check_same_capabilities(&fmi2.co_simulation, &fmi3.co_simulation)?;
    for v2 in &fmi2.variables {
        let who = format!("variable {:?}", v2.name);
        let v3 = fmi3.by_name(&v2.name).ok_or_else(|| {
            format!("{who} of the FMI 2.0 description is missing from the FMI 3.0 one")
        })?;
        check_same_fields(&who, v2, v3)?;
        if !v3.dimensions.is_empty() {
            return Err(format!(
                "{who} is a scalar in FMI 2.0 but an array in FMI 3.0"
            ));
        }
    }
    for v3 in &fmi3.variables {
        if fmi2.by_name(&v3.name).is_some() {
            continue;
        }
        let who = format!("variable {:?}", v3.name);
        if v3.causality != "independent"
            && v3.causality != "structuralParameter"
            && v3.dimensions.is_empty()
        {
            return Err(format!(
                "{who} is only in the FMI 3.0 description: only the independent variable, structural parameters and arrays may be (FMI 2.0 cannot express them)"
            ));
        }
    }
    dependencies::check_same(&fmi2.dependencies, &fmi3.dependencies, &|name| {
        fmi2.by_name(name).is_some()
    })
}

/// The same model name, model identifier, log categories and default experiment.
fn check_same_header(fmi2: &Model, fmi3: &Model) -> Result<(), String> {
    let pairs = [
        ("modelName", &fmi2.model_name, &fmi3.model_name),
        (
            "modelIdentifier",
            &fmi2.model_identifier,
            &fmi3.model_identifier,
        ),
    ];
    for (what, a, b) in pairs {
        if a != b {
            return Err(format!(
                "the FMI 2.0 description has {what} {a:?}, the FMI 3.0 one {b:?}"
            ));
        }
    }
    if fmi2.log_categories != fmi3.log_categories {
        return Err(format!(
            "the log categories differ: FMI 2.0 {:?}, FMI 3.0 {:?}",
            fmi2.log_categories, fmi3.log_categories
        ));
    }
    let experiment = |m: &Model| {
        [
            m.default_start_time,
            m.default_stop_time,
            m.default_step_size,
        ]
    };
    if experiment(fmi2) != experiment(fmi3) {
        return Err(format!(
            "the DefaultExperiment differs: FMI 2.0 {:?}, FMI 3.0 {:?}",
            experiment(fmi2),
            experiment(fmi3)
        ));
    }
    Ok(())
}

/// The same Co-Simulation capabilities, under their names in each version.
fn check_same_capabilities(c2: &CoSimulation, c3: &CoSimulation) -> Result<(), String> {
    let capabilities = [
        (
            "canHandleVariableCommunicationStepSize",
            flag(&c2.can_handle_variable_communication_step_size),
            flag(&c3.can_handle_variable_communication_step_size),
        ),
        (
            "canGetAndSetFMUstate / canGetAndSetFMUState",
            flag(&c2.can_get_and_set_fmu_state_2),
            flag(&c3.can_get_and_set_fmu_state_3),
        ),
        (
            "canSerializeFMUstate / canSerializeFMUState",
            flag(&c2.can_serialize_fmu_state_2),
            flag(&c3.can_serialize_fmu_state_3),
        ),
        (
            "providesDirectionalDerivative / providesDirectionalDerivatives",
            flag(&c2.provides_directional_derivative),
            flag(&c3.provides_directional_derivatives),
        ),
    ];
    for (what, a, b) in capabilities {
        if a != b {
            return Err(format!(
                "CoSimulation {what} is {a} for FMI 2.0 but {b} for FMI 3.0"
            ));
        }
    }
    if c2.max_output_derivative_order != c3.max_output_derivative_order {
        return Err(format!(
            "CoSimulation maxOutputDerivativeOrder is {:?} for FMI 2.0 but {:?} for FMI 3.0",
            c2.max_output_derivative_order, c3.max_output_derivative_order
        ));
    }
    Ok(())
}

/// The same attributes of a variable in both descriptions (an FMI 2.0 input without initial
/// has the FMI 3.0 default, exact).
fn check_same_fields(who: &str, v2: &Variable, v3: &Variable) -> Result<(), String> {
    let initial2 = match (&v2.initial, v2.causality.as_str()) {
        (None, "input") => Some("exact".to_string()),
        (initial, _) => initial.clone(),
    };
    let fields: [(&str, String, String); 10] = [
        (
            "valueReference",
            v2.value_reference.to_string(),
            v3.value_reference.to_string(),
        ),
        ("type", format!("{:?}", v2.kind), format!("{:?}", v3.kind)),
        ("causality", v2.causality.clone(), v3.causality.clone()),
        (
            "variability",
            v2.variability.clone(),
            v3.variability.clone(),
        ),
        (
            "initial",
            format!("{initial2:?}"),
            format!("{:?}", v3.initial),
        ),
        (
            "start",
            format!("{:?}", v2.start),
            format!("{:?}", v3.start),
        ),
        ("min", format!("{:?}", v2.min), format!("{:?}", v3.min)),
        ("max", format!("{:?}", v2.max), format!("{:?}", v3.max)),
        ("unit", format!("{:?}", v2.unit), format!("{:?}", v3.unit)),
        (
            "description",
            format!("{:?}", v2.description),
            format!("{:?}", v3.description),
        ),
    ];
    for (what, a, b) in fields {
        if a != b {
            return Err(format!(
                "{who}: {what} is {a} in the FMI 2.0 description but {b} in the FMI 3.0 one"
            ));
        }
    }
    Ok(())
}
