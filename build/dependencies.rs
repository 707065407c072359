//! The `dependencies` of `<ModelStructure>`: what each output and initial unknown depends on.
//!
//! Every output and every initial unknown must declare its `dependencies`: an absent attribute
//! means "depends on every known" (FMI 2.0 and 3.0 alike), which an importer reads as direct
//! feedthrough from every input and so as an algebraic loop in any feedback coupling. Each listed
//! known must be one the standard allows for its list: at communication points the inputs and the
//! independent variable, in FMI 3.0 also the parameters; in Initialization Mode the inputs, the
//! variables with `initial = "exact"` (parameters, structural parameters) and the independent
//! variable. Both descriptions must declare the same dependencies, by name, apart from the knowns
//! only FMI 3.0 has. Whether a declared list is *true* is measured on the packaged FMUs by
//! `tests/fmu/test_dependencies.py`.

use crate::model_description::Variable;
use std::collections::BTreeSet;

/// The list of `<ModelStructure>` an unknown belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum List {
    /// `<Outputs>` (FMI 2.0) or `<Output>` (FMI 3.0): the knowns at communication points.
    Outputs,
    /// `<InitialUnknowns>` (FMI 2.0) or `<InitialUnknown>` (FMI 3.0): the knowns of
    /// Initialization Mode.
    InitialUnknowns,
}

impl List {
    fn name(self) -> &'static str {
        match self {
            List::Outputs => "Outputs",
            List::InitialUnknowns => "InitialUnknowns",
        }
    }

    /// Whether `v` is a known of this list in FMI `version` ("2.0" or "3.0").
    fn admits(self, version: &str, v: &Variable) -> bool {
        let always = v.causality == "input" || v.causality == "independent";
        match self {
            List::Outputs => always || (version == "3.0" && v.causality == "parameter"),
            List::InitialUnknowns => always || v.initial.as_deref() == Some("exact"),
        }
    }
}

/// One unknown of a list with the names of the knowns it depends on, in the description's order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Dependencies {
    pub list: List,
    pub unknown: String,
    pub knowns: Vec<String>,
}

/// The `dependencies` (and `dependenciesKind`) attributes of `unknown` in `list`, checked:
/// present, each entry a known of the list (`resolve` turns an entry into its variable: an index
/// in FMI 2.0, a value reference in FMI 3.0), the entries increasing (FMI 2.0 orders indices by
/// magnitude; FMI 3.0 value references follow the same rule here, so that no known is listed
/// twice), and a `dependenciesKind` of the same length with kinds the list allows.
pub fn check<'a>(
    version: &str,
    list: List,
    unknown: &Variable,
    dependencies: Option<&str>,
    kinds: Option<&str>,
    resolve: &dyn Fn(u64) -> Option<&'a Variable>,
) -> Result<Dependencies, String> {
    let who = format!("ModelStructure/{} {:?}", list.name(), unknown.name);
    let text = dependencies.ok_or_else(|| {
        format!("{who} declares no dependencies: without them it depends on every known, a direct feedthrough from every input; list what it depends on (dependencies=\"\" for nothing)")
    })?;
    let mut knowns = Vec::new();
    let mut last = None;
    for entry in text.split_whitespace() {
        let number: u64 = entry
            .parse()
            .map_err(|_| format!("{who}: dependency {entry:?} is not a number"))?;
        let known = resolve(number)
            .ok_or_else(|| format!("{who}: dependency {number} names no variable"))?;
        if !list.admits(version, known) {
            return Err(format!(
                "{who}: {:?} (causality {:?}) is not a known of {} in FMI {version}",
                known.name,
                known.causality,
                list.name()
            ));
        }
        if last.is_some_and(|l| l >= number) {
            return Err(format!(
                "{who}: dependencies must be listed once each, in increasing order ({number}, {:?}, is out of place)",
                known.name
            ));
        }
        last = Some(number);
        knowns.push(known.name.clone());
    }
    if let Some(kinds) = kinds {
        let allowed: &[&str] = match list {
            List::Outputs => &["dependent", "constant", "fixed", "tunable", "discrete"],
            List::InitialUnknowns => &["dependent", "constant"],
        };
        let kinds: Vec<&str> = kinds.split_whitespace().collect();
        if kinds.len() != knowns.len() {
            return Err(format!(
                "{who}: dependenciesKind has {} entries for {} dependencies",
                kinds.len(),
                knowns.len()
            ));
        }
        if let Some(kind) = kinds.iter().find(|k| !allowed.contains(k)) {
            return Err(format!(
                "{who}: dependenciesKind {kind:?} is not allowed here (allowed: {allowed:?})"
            ));
        }
    }
    Ok(Dependencies {
        list,
        unknown: unknown.name.clone(),
        knowns,
    })
}

/// The FMI 2.0 and FMI 3.0 descriptions declare the same dependencies for every unknown of
/// both, leaving out of the FMI 3.0 lists the knowns the FMI 2.0 description does not have (the
/// independent variable, structural parameters).
pub fn check_same(
    fmi2: &[Dependencies],
    fmi3: &[Dependencies],
    in_fmi2: &dyn Fn(&str) -> bool,
) -> Result<(), String> {
    for d2 in fmi2 {
        let d3 = fmi3
            .iter()
            .find(|d| d.list == d2.list && d.unknown == d2.unknown)
            .ok_or_else(|| {
                format!(
                    "ModelStructure/{} {:?} is in the FMI 2.0 description but not in the FMI 3.0 one",
                    d2.list.name(),
                    d2.unknown
                )
            })?;
        // As sets: FMI 2.0 lists indices, FMI 3.0 value references, each in increasing order.
        let shared: BTreeSet<&String> = d3.knowns.iter().filter(|k| in_fmi2(k)).collect();
        if shared != d2.knowns.iter().collect::<BTreeSet<_>>() {
            return Err(format!(
                "ModelStructure/{} {:?} depends on {:?} in the FMI 2.0 description but on {:?} in the FMI 3.0 one",
                d2.list.name(),
                d2.unknown,
                d2.knowns,
                d3.knowns
            ));
        }
    }
    Ok(())
}
