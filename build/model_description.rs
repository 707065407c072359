//! Reads and checks `modelDescription/modelDescription.xml` and generates the Rust variable table.
//!
//! Shared by `build.rs` (which fails the build on the first inconsistency) and by the test
//! `tests/model_description_checker.rs` (which feeds it broken descriptions). It uses only
//! quick-xml + serde, so that it runs at build time without the crate itself.

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

#[derive(Debug, Deserialize)]
struct CoSimulation {
    #[serde(rename = "@modelIdentifier")]
    model_identifier: String,
}

#[derive(Debug, Deserialize)]
struct UnitDefinitions {
    #[serde(rename = "Unit", default)]
    units: Vec<Named>,
}

#[derive(Debug, Deserialize)]
struct Named {
    #[serde(rename = "@name")]
    name: String,
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
struct LogCategories {
    #[serde(rename = "Category", default)]
    categories: Vec<Named>,
}

#[derive(Debug, Deserialize)]
struct DefaultExperiment {
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
#[derive(Debug, Deserialize)]
struct TypeAttrs {
    #[serde(rename = "@start")]
    start: Option<String>,
    #[serde(rename = "@min")]
    min: Option<String>,
    #[serde(rename = "@max")]
    max: Option<String>,
    #[serde(rename = "@unit")]
    unit: Option<String>,
    #[serde(rename = "@declaredType")]
    declared_type: Option<String>,
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
}

/// Variable kinds, as the Rust table names them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Real,
    Integer,
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

/// One checked variable.
#[derive(Clone, Debug)]
pub struct Variable {
    pub name: String,
    pub value_reference: u32,
    pub kind: Kind,
    pub causality: String,
    pub variability: String,
    pub initial: Option<String>,
    pub start: Option<Start>,
}

/// The checked model description: what the Rust code needs.
#[derive(Clone, Debug)]
pub struct Model {
    pub model_identifier: String,
    pub guid: String,
    pub log_categories: Vec<String>,
    pub default_start_time: f64,
    pub default_stop_time: f64,
    pub default_step_size: f64,
    pub variables: Vec<Variable>,
}

fn is_structured_name(name: &str) -> bool {
    !name.is_empty()
        && name.split('.').all(|part| {
            let mut chars = part.chars();
            matches!(chars.next(), Some(c) if c.is_ascii_alphabetic() || c == '_')
                && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
        })
}

/// The `initial` values FMI 2.0 (§2.2.7, table of causality × variability) allows, and the
/// default; `None` means the combination itself is illegal, `Some((vec![], _))` that no `initial`
/// may be given.
fn allowed_initial(
    causality: &str,
    variability: &str,
) -> Option<(Vec<&'static str>, Option<&'static str>)> {
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

/// Parses and checks a model description; the error names the variable (or element) at fault.
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
    let cs = root
        .co_simulation
        .ok_or("no <CoSimulation> element: this FMU is Co-Simulation")?;
    if !is_structured_name(&cs.model_identifier) || cs.model_identifier.contains('.') {
        return Err(format!(
            "modelIdentifier {:?} is not a C identifier",
            cs.model_identifier
        ));
    }
    let units: BTreeSet<String> = root
        .unit_definitions
        .map(|u| u.units.into_iter().map(|u| u.name).collect())
        .unwrap_or_default();
    let mut enums: BTreeMap<String, Vec<Item>> = BTreeMap::new();
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
            enums.insert(t.name, e.items);
        }
    }
    let log_categories: Vec<String> = root
        .log_categories
        .map(|l| l.categories.into_iter().map(|c| c.name).collect())
        .unwrap_or_default();
    let experiment = root
        .default_experiment
        .ok_or("no <DefaultExperiment>: importers need the default start, stop and step")?;
    let (start_time, stop_time, step_size) = match (
        experiment.start_time,
        experiment.stop_time,
        experiment.step_size,
    ) {
        (Some(a), Some(b), Some(h)) if a.is_finite() && b > a && h > 0.0 => (a, b, h),
        other => {
            return Err(format!(
                "DefaultExperiment needs startTime < stopTime and stepSize > 0, got {other:?}"
            ))
        }
    };

    let mut names = BTreeSet::new();
    let mut refs = BTreeMap::new();
    let mut variables = Vec::new();
    for v in root.model_variables.variables {
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
        let typed: Vec<(Kind, &TypeAttrs)> = [
            (Kind::Real, &v.real),
            (Kind::Integer, &v.integer),
            (Kind::Boolean, &v.boolean),
            (Kind::String, &v.string),
            (Kind::Enumeration, &v.enumeration),
        ]
        .into_iter()
        .filter_map(|(k, a)| a.as_ref().map(|a| (k, a)))
        .collect();
        let (kind, attrs) = match typed.as_slice() {
            [one] => *one,
            _ => {
                return Err(format!(
                    "{who}: needs exactly one type element (Real, Integer, …)"
                ))
            }
        };
        let causality = v.causality.clone().unwrap_or_else(|| "local".into());
        let variability = v.variability.clone().unwrap_or_else(|| {
            if matches!(kind, Kind::Real) {
                "continuous".into()
            } else {
                "discrete".into()
            }
        });
        if variability == "continuous" && kind != Kind::Real {
            return Err(format!("{who}: only Real variables may be continuous"));
        }
        let (allowed, default_initial) = allowed_initial(&causality, &variability).ok_or_else(|| {
            format!("{who}: causality {causality:?} with variability {variability:?} is not allowed by FMI 2.0")
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
        let needs_start =
            causality == "input" || matches!(initial.as_deref(), Some("exact") | Some("approx"));
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
        if let Some(unit) = &attrs.unit {
            if kind != Kind::Real {
                return Err(format!("{who}: only Real variables carry a unit"));
            }
            if !units.contains(unit) {
                return Err(format!("{who}: unit {unit:?} is not in <UnitDefinitions>"));
            }
        } else if kind == Kind::Real && causality != "independent" {
            return Err(format!(
                "{who}: every Real variable must declare its unit (SI)"
            ));
        }
        if kind == Kind::Enumeration {
            let name = attrs
                .declared_type
                .as_ref()
                .ok_or_else(|| format!("{who}: an Enumeration needs a declaredType"))?;
            let items = enums.get(name).ok_or_else(|| {
                format!("{who}: declaredType {name:?} is not an enumeration type")
            })?;
            if let Some(Start::Integer(s)) = start {
                if !items.iter().any(|i| i.value == s) {
                    return Err(format!("{who}: start {s} is not an item of {name:?}"));
                }
            }
        }
        let bound = |b: &Option<String>, what: &str| -> Result<Option<f64>, String> {
            b.as_ref()
                .map(|b| {
                    b.trim()
                        .parse::<f64>()
                        .ok()
                        .filter(|x| !x.is_nan())
                        .ok_or_else(|| format!("{who}: {what} {b:?} is not a number"))
                })
                .transpose()
        };
        let (min, max) = (bound(&attrs.min, "min")?, bound(&attrs.max, "max")?);
        if let (Some(lo), Some(hi)) = (min, max) {
            if lo > hi {
                return Err(format!("{who}: min {lo} > max {hi}"));
            }
        }
        let start_number = match &start {
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
        variables.push(Variable {
            name: v.name,
            value_reference: v.value_reference,
            kind,
            causality,
            variability,
            initial,
            start,
        });
    }

    // ModelStructure: <Outputs> lists exactly the outputs; <InitialUnknowns> every output with
    // initial = calculated; both in increasing index order (1-based into ModelVariables).
    let list = |l: &Option<UnknownList>| -> Vec<usize> {
        l.as_ref()
            .map(|l| l.unknowns.iter().map(|u| u.index).collect())
            .unwrap_or_default()
    };
    let structure = root.model_structure;
    let outputs_declared = list(&structure.outputs);
    let outputs_expected: Vec<usize> = variables
        .iter()
        .enumerate()
        .filter(|(_, v)| v.causality == "output")
        .map(|(i, _)| i + 1)
        .collect();
    if outputs_declared != outputs_expected {
        return Err(format!(
            "ModelStructure/Outputs lists indices {outputs_declared:?}, but the outputs are at {outputs_expected:?}"
        ));
    }
    let initial_declared = list(&structure.initial_unknowns);
    let initial_expected: Vec<usize> = variables
        .iter()
        .enumerate()
        .filter(|(_, v)| {
            (v.causality == "output" || v.causality == "calculatedParameter")
                && v.initial.as_deref() != Some("exact")
                && v.initial.as_deref() != Some("approx")
        })
        .map(|(i, _)| i + 1)
        .collect();
    if initial_declared != initial_expected {
        return Err(format!(
            "ModelStructure/InitialUnknowns lists indices {initial_declared:?}, but the calculated outputs are at {initial_expected:?}"
        ));
    }

    Ok(Model {
        model_identifier: cs.model_identifier,
        guid: root.guid,
        log_categories,
        default_start_time: start_time,
        default_stop_time: stop_time,
        default_step_size: step_size,
        variables,
    })
}

fn parse_start(who: &str, kind: Kind, s: &str) -> Result<Start, String> {
    let bad = || format!("{who}: start {s:?} is not a valid {kind:?}");
    Ok(match kind {
        Kind::Real => {
            let x: f64 = s.trim().parse().map_err(|_| bad())?;
            if !x.is_finite() {
                return Err(bad());
            }
            Start::Real(x)
        }
        Kind::Integer | Kind::Enumeration => Start::Integer(s.trim().parse().map_err(|_| bad())?),
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

/// Rust source for `$OUT_DIR/model_description.rs`, included by `src/fmi/variables.rs`.
pub fn generate(model: &Model) -> String {
    let mut out = String::new();
    out.push_str(
        "// Generated by build.rs from modelDescription/modelDescription.xml. Do not edit.\n\n",
    );
    out.push_str(&format!(
        "/// `modelIdentifier` of the Co-Simulation interface.\npub const MODEL_IDENTIFIER: &str = {:?};\n",
        model.model_identifier
    ));
    out.push_str(&format!(
        "/// `guid` of the model description; fmi2Instantiate checks the importer's against it.\npub const GUID: &str = {:?};\n",
        model.guid
    ));
    out.push_str(&format!(
        "/// The log categories declared in `<LogCategories>`.\npub const LOG_CATEGORIES: &[&str] = &{:?};\n",
        model.log_categories
    ));
    out.push_str(&format!(
        "/// `<DefaultExperiment>` startTime, stopTime and stepSize (s).\npub const DEFAULT_EXPERIMENT: [f64; 3] = [{:?}, {:?}, {:?}];\n\n",
        model.default_start_time, model.default_stop_time, model.default_step_size
    ));
    out.push_str("/// Value references, one constant per variable (dots become underscores).\npub mod vr {\n");
    for v in &model.variables {
        out.push_str(&format!(
            "    /// `{}`\n    pub const {}: u32 = {};\n",
            v.name,
            const_name(&v.name),
            v.value_reference
        ));
    }
    out.push_str("}\n\n");
    out.push_str("/// Every variable, in the order of `<ModelVariables>`.\npub const VARIABLES: &[Variable] = &[\n");
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
        out.push_str(&format!(
            "    Variable {{ name: {:?}, vr: {}, kind: Kind::{:?}, causality: Causality::{causality}, variability: Variability::{variability}, start: {start} }},\n",
            v.name, v.value_reference, v.kind
        ));
    }
    out.push_str("];\n");
    out
}
