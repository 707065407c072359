//! The build-time checkers of the model descriptions (shared with build.rs) accept the shipped FMI
//! 2.0 and 3.0 descriptions and reject broken ones with a message naming the variable or element;
//! the comparison of the two rejects every way they could drift apart.

#[path = "../build/dependencies.rs"]
mod dependencies;
#[path = "../build/model_description.rs"]
mod model_description;
#[path = "../build/model_description_fmi3.rs"]
mod model_description_fmi3;

use model_description::{check, generate};
use model_description_fmi3::{check_fmi3, check_same_variables};
use plate_impact::scene::{Bound, BOUNDS};

const XML: &str = include_str!("../modelDescription/modelDescription.xml");
const XML3: &str = include_str!("../modelDescription/modelDescription-fmi3.xml");

/// The shipped XML with `from` replaced by `to` (which must occur exactly once).
fn broken(from: &str, to: &str) -> String {
    assert_eq!(XML.matches(from).count(), 1, "{from:?} must occur once");
    XML.replace(from, to)
}

/// The shipped FMI 3.0 XML with `from` replaced by `to` (which must occur exactly once).
fn broken3(from: &str, to: &str) -> String {
    assert_eq!(XML3.matches(from).count(), 1, "{from:?} must occur once");
    XML3.replace(from, to)
}

fn rejected(xml: &str, words: &[&str]) {
    let err = check(xml).expect_err("the broken description was accepted");
    for w in words {
        assert!(err.contains(w), "{w:?} not in the message: {err}");
    }
}

fn rejected3(xml: &str, words: &[&str]) {
    let err = check_fmi3(xml).expect_err("the broken description was accepted");
    for w in words {
        assert!(err.contains(w), "{w:?} not in the message: {err}");
    }
}

/// An FMI 3.0 description that passes its own checks but disagrees with the FMI 2.0 one.
fn disagrees(xml3: &str, words: &[&str]) {
    let fmi3 = check_fmi3(xml3).expect("the FMI 3.0 description on its own is valid");
    let err = check_same_variables(&check(XML).unwrap(), &fmi3)
        .expect_err("the disagreement was accepted");
    for w in words {
        assert!(err.contains(w), "{w:?} not in the message: {err}");
    }
}

#[test]
fn the_shipped_descriptions_pass_agree_and_generate_the_tables() {
    let model = check(XML).unwrap();
    assert_eq!(model.variables.len(), 98);
    let model3 = check_fmi3(XML3).unwrap();
    assert_eq!(model3.variables.len(), 102);
    check_same_variables(&model, &model3).unwrap();
    let code = generate(&model, &model3);
    assert!(code.contains("pub const PLATE_LENGTH: u32 = 1;"), "{code}");
    assert!(code.contains("pub const CONTACT_ACTIVE_NODES: u32 = 43;"));
    assert!(code.contains("pub const PLATE_DISPLACEMENT: u32 = 70;"));
    assert!(code.contains("pub const BASE_MEAN_FORCE: u32 = 68;"));
    assert!(code.contains("pub const DAMPING_ALPHA: u32 = 22;"));
    assert!(code.contains("pub const SOLVER_FREE_DOFS: u32 = 24;"));
    assert!(code.contains("pub const SOLVER_BACKEND: u32 = 25;"));
    assert!(code.contains("pub const PLATE_CLAMP: u32 = 100;"));
    assert!(code.contains(r#"Some(Start::String("flat"))"#), "{code}");
    assert!(
        code.contains("pub const FMI2: Description")
            && code.contains("pub const FMI3: Description")
    );
    assert!(code.contains("dimensions: &[Dimension::Variable(71), Dimension::Variable(72)]"));
}

#[test]
fn duplicate_value_reference() {
    rejected(
        &broken(
            r#"name="plate.width" valueReference="2""#,
            r#"name="plate.width" valueReference="1""#,
        ),
        &["plate.width", "plate.length", "valueReference"],
    );
}

#[test]
fn duplicate_name() {
    rejected(
        &broken(r#"name="plate.width""#, r#"name="plate.length""#),
        &["plate.length", "declared twice"],
    );
}

#[test]
fn illegal_causality_variability() {
    rejected(
        &broken(
            r#"name="load.pressure" valueReference="11" causality="parameter" variability="tunable""#,
            r#"name="load.pressure" valueReference="11" causality="parameter" variability="continuous""#,
        ),
        &["load.pressure", "not allowed"],
    );
}

#[test]
fn illegal_initial() {
    rejected(
        &broken(
            r#"name="plate.thickness" valueReference="3" causality="parameter""#,
            r#"name="plate.thickness" valueReference="3" initial="calculated" causality="parameter""#,
        ),
        &["plate.thickness", "initial"],
    );
}

#[test]
fn start_outside_min_max() {
    rejected(
        &broken(
            r#"<Real unit="1" start="0.3" min="-1" max="0.5"/>"#,
            r#"<Real unit="1" start="0.7" min="-1" max="0.5"/>"#,
        ),
        &["material.poisson_ratio", "outside"],
    );
    rejected(
        &broken(
            r#"<Integer start="10" min="1" max="400"/>"#,
            r#"<Integer start="0" min="1" max="400"/>"#,
        ),
        &["mesh.nx", "outside"],
    );
}

#[test]
fn missing_or_forbidden_start() {
    rejected(
        &broken(
            r#"<Real unit="m" start="0"/></ScalarVariable>
    <!-- 23 -->"#,
            r#"<Real unit="m"/></ScalarVariable>
    <!-- 23 -->"#,
        ),
        &["base.displacement", "start value is required"],
    );
    rejected(
        &broken(
            r#"contact.impulse" valueReference="66" causality="output" variability="continuous" description="sum over the internal steps of the last communication step of the total contact force times the time step">
      <Real unit="N.s"/>"#,
            r#"contact.impulse" valueReference="66" causality="output" variability="continuous" description="sum over the internal steps of the last communication step of the total contact force times the time step">
      <Real unit="N.s" start="0"/>"#,
        ),
        &["contact.impulse", "not allowed"],
    );
}

#[test]
fn undeclared_unit() {
    rejected(
        &broken(
            r#"<Real unit="kg/m3" start="7770" min="0"/>"#,
            r#"<Real unit="kg/m^3" start="7770" min="0"/>"#,
        ),
        &["material.density", "kg/m^3"],
    );
}

#[test]
fn integer_start_outside_min_max() {
    rejected(
        &broken(
            r#"<Integer start="1" min="1" max="2"/>"#,
            r#"<Integer start="3" min="1" max="2"/>"#,
        ),
        &["mesh.element", "outside"],
    );
}

/// The shipped description has no enumeration (engines such as libcosim and Ecos ignore them),
/// but the checker still handles one: mesh.element declared as one, with a start that is no item.
#[test]
fn enumeration_start_not_an_item() {
    let types = r#"<TypeDefinitions>
    <SimpleType name="ElementKind">
      <Enumeration>
        <Item name="argyris" value="1"/>
        <Item name="fvs" value="2"/>
      </Enumeration>
    </SimpleType>
  </TypeDefinitions>
  <LogCategories>"#;
    let with_types = broken("<LogCategories>", types);
    let declared = |start: &str| {
        with_types.replace(
            r#"<Integer start="1" min="1" max="2"/>"#,
            &format!(r#"<Enumeration declaredType="ElementKind" start="{start}"/>"#),
        )
    };
    check(&declared("2")).expect("an enumeration with a valid start");
    rejected(&declared("3"), &["mesh.element", "not an item"]);
}

#[test]
fn model_structure_must_list_the_outputs() {
    rejected(
        &broken(
            "<Outputs>\n      <Unknown index=\"23\" dependencies=\"\"/>\n",
            "<Outputs>\n",
        ),
        &["ModelStructure/Outputs"],
    );
}

#[test]
fn every_unknown_declares_dependencies_on_knowns_of_its_list() {
    // Without the attribute an output would depend on every input: refused, naming it.
    rejected(
        &broken(
            r#"<Unknown index="23" dependencies=""/>"#,
            r#"<Unknown index="23"/>"#,
        ),
        &[
            "Outputs",
            "corner1.displacement",
            "declares no dependencies",
        ],
    );
    rejected3(
        &broken3(
            r#"<InitialUnknown valueReference="22" dependencies="15 17 18 19"/>"#,
            r#"<InitialUnknown valueReference="22"/>"#,
        ),
        &[
            "InitialUnknowns",
            "damping.alpha",
            "declares no dependencies",
        ],
    );
    // FMI 2.0 outputs at communication points know the inputs, not the parameters (22 is the
    // input base.displacement, 16 the parameter load.pressure).
    check(&broken(
        r#"<Unknown index="24" dependencies=""/>"#,
        r#"<Unknown index="24" dependencies="22"/>"#,
    ))
    .expect("an output may depend on an input");
    rejected(
        &broken(
            r#"<Unknown index="24" dependencies=""/>"#,
            r#"<Unknown index="24" dependencies="16"/>"#,
        ),
        &[
            "corner2.displacement",
            "load.pressure",
            "not a known of Outputs",
        ],
    );
    // An output is no known of initialization; order and repetition are checked.
    rejected(
        &broken(
            r#"<Unknown index="47" dependencies="7 8 9 42 48"/>"#,
            r#"<Unknown index="47" dependencies="7 8 9 23 48"/>"#,
        ),
        &["solver.backend", "corner1.displacement", "not a known"],
    );
    rejected(
        &broken(
            r#"<Unknown index="47" dependencies="7 8 9 42 48"/>"#,
            r#"<Unknown index="47" dependencies="7 9 8 42 48"/>"#,
        ),
        &["solver.backend", "out of place"],
    );
    rejected(
        &broken(
            r#"<Unknown index="46" dependencies="7 8 9 48"/>"#,
            r#"<Unknown index="46" dependencies="7 8 900 48"/>"#,
        ),
        &["solver.free_dofs", "900", "names no variable"],
    );
    rejected(
        &broken(
            r#"<Unknown index="46" dependencies="7 8 9 48"/>"#,
            r#"<Unknown index="46" dependencies="7 8 9 48" dependenciesKind="dependent fixed fixed fixed"/>"#,
        ),
        &[
            "solver.free_dofs",
            "dependenciesKind",
            "\"fixed\"",
            "not allowed",
        ],
    );
    rejected(
        &broken(
            r#"<Unknown index="46" dependencies="7 8 9 48"/>"#,
            r#"<Unknown index="46" dependencies="7 8 9 48" dependenciesKind="dependent fixed"/>"#,
        ),
        &["solver.free_dofs", "dependenciesKind", "2 entries for 4"],
    );
    // FMI 3.0 outputs also know the parameters.
    check_fmi3(&broken3(
        r#"<Output valueReference="31" dependencies=""/>"#,
        r#"<Output valueReference="31" dependencies="11"/>"#,
    ))
    .expect("an FMI 3.0 output may depend on a parameter");
}

#[test]
fn not_xml() {
    rejected("<fmiModelDescription", &["cannot parse"]);
}

#[test]
fn fmi3_needs_its_instantiation_token() {
    rejected3(
        &broken3(r#"instantiationToken="{derived-at-build-time}""#, ""),
        &["instantiationToken"],
    );
    rejected3(
        &broken3(r#"fmiVersion="3.0""#, r#"fmiVersion="2.0""#),
        &["fmiVersion"],
    );
}

#[test]
fn fmi3_needs_exactly_one_independent_variable() {
    let time = r#"<Float64 name="time" valueReference="0" causality="independent" variability="continuous" unit="s" description="the independent variable, the FMU time"/>"#;
    rejected3(&broken3(time, ""), &["exactly one independent", "found 0"]);
    let second = format!(
        "{time}\n    {}",
        time.replace(
            r#"name="time" valueReference="0""#,
            r#"name="clock" valueReference="99""#
        )
    );
    rejected3(
        &broken3(time, &second),
        &["exactly one independent", "found 2"],
    );
    rejected3(
        &broken3(time, &time.replace(r#"unit="s""#, r#"unit="s" start="0""#)),
        &["time", "start"],
    );
}

#[test]
fn fmi3_dimensions_name_uint64_structural_parameters() {
    rejected3(
        &broken3(
            r#"<Dimension valueReference="71"/>"#,
            r#"<Dimension valueReference="41"/>"#,
        ),
        &[
            "plate.displacement",
            "mesh.nx",
            "UInt64 structural parameter",
        ],
    );
    rejected3(
        &broken3(
            r#"<Dimension valueReference="71"/>"#,
            r#"<Dimension valueReference="999"/>"#,
        ),
        &["plate.displacement", "names no variable"],
    );
    rejected3(
        &broken3(r#"<Dimension valueReference="71"/>"#, r#"<Dimension/>"#),
        &["plate.displacement", "<Dimension>"],
    );
    rejected3(
        &broken3(r#"start="8" min="2""#, r#"start="0" min="0""#),
        &["plate.displacement", "mesh.vertex_rows", "larger than 0"],
    );
    rejected3(
        &broken3(
            r#"name="mesh.vertex_rows" valueReference="71" causality="structuralParameter" variability="fixed""#,
            r#"name="mesh.vertex_rows" valueReference="71" causality="parameter" variability="fixed""#,
        ),
        &["mesh.vertex_rows", "structural parameter"],
    );
}

#[test]
fn fmi3_model_structure_lists_outputs_by_value_reference() {
    rejected3(
        &broken3(
            "    <Output valueReference=\"70\" dependencies=\"\"/>\n",
            "",
        ),
        &["ModelStructure/Output", "70"],
    );
    rejected3(
        &broken3(
            "    <InitialUnknown valueReference=\"30\" dependencies=\"1 2 3 4 5 6 9 10 12 20 40 41 42 50 51 100 101 102 103\"/>\n",
            "",
        ),
        &["ModelStructure/InitialUnknown"],
    );
}

#[test]
fn fmi3_capabilities_this_fmu_relies_on() {
    rejected3(
        &broken3(r#"hasEventMode="false""#, r#"hasEventMode="true""#),
        &["hasEventMode", "no Event Mode"],
    );
    rejected3(
        &broken3(
            r#"canHandleVariableCommunicationStepSize="true""#,
            r#"canHandleVariableCommunicationStepSize="true" fixedInternalStepSize="1e-4""#,
        ),
        &["fixedInternalStepSize", "solver.time_step"],
    );
    let without_updates = XML3
        .replace(
            r#"providesIntermediateUpdate="true""#,
            r#"providesIntermediateUpdate="false""#,
        )
        .replace(
            r#"canReturnEarlyAfterIntermediateUpdate="false""#,
            r#"canReturnEarlyAfterIntermediateUpdate="true""#,
        );
    rejected3(&without_updates, &["providesIntermediateUpdate"]);
}

#[test]
fn fmi3_variable_rules() {
    rejected3(
        &broken3(
            r#"<Float64 name="plate.width" valueReference="2" causality="parameter" variability="fixed" unit="m""#,
            r#"<Float64 name="plate.width" valueReference="2" causality="parameter" variability="fixed""#,
        ),
        &["plate.width", "unit"],
    );
    rejected3(
        &broken3(
            r#"<Float64 name="load.pressure" valueReference="11" causality="parameter" variability="tunable""#,
            r#"<Float64 name="load.pressure" valueReference="11" causality="parameter" variability="tunable" intermediateUpdate="true""#,
        ),
        &["load.pressure", "intermediateUpdate"],
    );
    rejected3(
        &broken3(
            r#"<Float64 name="base.displacement" valueReference="20" causality="input" variability="continuous" unit="m" start="0""#,
            r#"<Float64 name="base.displacement" valueReference="20" causality="input" variability="continuous" unit="m""#,
        ),
        &["base.displacement", "start value is required"],
    );
    rejected3(
        &broken3(r#"<Int32 name="mesh.nx""#, r#"<Int16 name="mesh.nx""#),
        &["cannot parse"],
    );
}

#[test]
fn the_two_descriptions_may_not_drift_apart() {
    disagrees(
        &broken3(
            r#"unit="m" start="0.4" min="0""#,
            r#"unit="m" start="0.5" min="0""#,
        ),
        &["plate.length", "start"],
    );
    disagrees(
        &broken3(
            r#"name="base.amplitude" valueReference="13""#,
            r#"name="base.amplitude" valueReference="3000""#,
        ),
        &["base.amplitude", "valueReference"],
    );
    disagrees(
        &broken3(
            r#"description="cells along x""#,
            r#"description="cells in x""#,
        ),
        &["mesh.nx", "description"],
    );
    disagrees(
        &broken3(
            r#"name="obstacle.lower" valueReference="9" causality="parameter" variability="tunable""#,
            r#"name="obstacle.lower" valueReference="9" causality="parameter" variability="fixed""#,
        ),
        &["obstacle.lower", "variability"],
    );
    disagrees(
        &broken3(
            r#"<Float64 name="energy.kinetic""#,
            r#"<Float64 name="energy.kinetik""#,
        ),
        &["energy.kinetic", "missing"],
    );
    disagrees(
        &broken3(
            r#"maxOutputDerivativeOrder="1""#,
            r#"maxOutputDerivativeOrder="2""#,
        ),
        &["maxOutputDerivativeOrder"],
    );
    disagrees(
        &broken3(
            r#"<Category name="logAll""#,
            r#"<Category name="logEverything""#,
        ),
        &["log categories"],
    );
    // Dependencies by name: a known more or less in one description.
    disagrees(
        &broken3(
            r#"<InitialUnknown valueReference="24" dependencies="40 41 42 100"/>"#,
            r#"<InitialUnknown valueReference="24" dependencies="40 41 100"/>"#,
        ),
        &["solver.free_dofs", "FMI 2.0", "FMI 3.0"],
    );
    // The knowns only FMI 3.0 has may be listed there alone.
    let with_sizes = broken3(
        r#"<InitialUnknown valueReference="24" dependencies="40 41 42 100"/>"#,
        r#"<InitialUnknown valueReference="24" dependencies="40 41 42 71 100"/>"#,
    );
    check_same_variables(&check(XML).unwrap(), &check_fmi3(&with_sizes).unwrap())
        .expect("a structural parameter FMI 2.0 lacks");
    // A scalar only in FMI 3.0: FMI 2.0 could express it.
    let extra = r#"<Float64 name="time" valueReference="0""#;
    disagrees(
        &broken3(
            extra,
            &format!(
                r#"<Float64 name="extra.parameter" valueReference="98" causality="parameter" variability="fixed" unit="m" start="1"/>
    {extra}"#
            ),
        ),
        &["extra.parameter", "only in the FMI 3.0"],
    );
}

/// How the parameters of `model` disagree with the bounds table (`plate_impact::scene::BOUNDS`),
/// one line each: every parameter must declare exactly the table's ends as `min` and `max` (an
/// open end too: the XML has no exclusive bounds) and its unit, and every table entry but
/// `stop_time` must be a parameter. The vertex counts of FMI 3.0 are one more than the cell counts.
fn disagreements_with_bounds(model: &model_description::Model) -> Vec<String> {
    let mut found = Vec::new();
    let ends = |b: &Bound| (b.min.map(|l| l.value), b.max.map(|l| l.value));
    for v in &model.variables {
        let (expected, unit) = match (v.causality.as_str(), v.name.as_str()) {
            ("structuralParameter", "mesh.vertex_rows" | "mesh.vertex_columns") => {
                let (min, max) = ends(Bound::of("mesh.nx").unwrap());
                ((min.map(|x| x + 1.0), max.map(|x| x + 1.0)), "")
            }
            ("parameter", _) => match Bound::of(&v.name) {
                Some(b) => (ends(b), b.unit),
                None => ((None, None), ""),
            },
            _ => continue,
        };
        if (v.min, v.max) != expected {
            found.push(format!(
                "{}: min, max = {:?}, the table has {expected:?}",
                v.name,
                (v.min, v.max)
            ));
        }
        if v.unit.as_deref().unwrap_or("") != unit {
            found.push(format!(
                "{}: unit {:?}, the table has {unit:?}",
                v.name, v.unit
            ));
        }
    }
    for b in BOUNDS.iter().filter(|b| b.name != "stop_time") {
        let declared = model.variables.iter().find(|v| v.name == b.name);
        if declared.is_none_or(|v| v.causality != "parameter") {
            found.push(format!("{} is in the table but no parameter", b.name));
        }
    }
    found
}

#[test]
fn both_descriptions_declare_the_ranges_of_the_bounds_table() {
    for model in [check(XML).unwrap(), check_fmi3(XML3).unwrap()] {
        let found = disagreements_with_bounds(&model);
        assert!(found.is_empty(), "{}: {found:#?}", model.fmi_version);
    }
    // The comparison sees each way a description can drift from the table.
    for (xml, words) in [
        (
            broken(
                r#"<Real unit="1" start="0.3" min="-1" max="0.5"/>"#,
                r#"<Real unit="1" start="0.3" min="-1" max="0.49"/>"#,
            ),
            "material.poisson_ratio: min, max",
        ),
        (
            broken(
                r#"<Real unit="m" start="0.4" min="0"/>"#,
                r#"<Real unit="m" start="0.4"/>"#,
            ),
            "plate.length: min, max",
        ),
        (
            broken(
                r#"<Real unit="Hz" start="10" min="0"/>"#,
                r#"<Real unit="1/s" start="10" min="0"/>"#,
            ),
            "base.frequency: unit",
        ),
    ] {
        let found = disagreements_with_bounds(&check(&xml).unwrap());
        assert!(
            found.iter().any(|f| f.starts_with(words)),
            "{words}: {found:#?}"
        );
    }
    let rows = broken3(
        r#"start="8" min="2" max="401""#,
        r#"start="8" min="2" max="400""#,
    );
    let found = disagreements_with_bounds(&check_fmi3(&rows).unwrap());
    assert!(
        found
            .iter()
            .any(|f| f.starts_with("mesh.vertex_rows: min, max")),
        "{found:#?}"
    );
}
