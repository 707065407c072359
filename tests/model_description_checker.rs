//! The build-time checker of `modelDescription/modelDescription.xml` (shared with build.rs) accepts
//! the shipped description and rejects broken ones with a message naming the variable.

#[path = "../build/model_description.rs"]
mod model_description;

use model_description::{check, generate};

const XML: &str = include_str!("../modelDescription/modelDescription.xml");

/// The shipped XML with `from` replaced by `to` (which must occur exactly once).
fn broken(from: &str, to: &str) -> String {
    assert_eq!(XML.matches(from).count(), 1, "{from:?} must occur once");
    XML.replace(from, to)
}

fn rejected(xml: &str, words: &[&str]) {
    let err = check(xml).expect_err("the broken description was accepted");
    for w in words {
        assert!(err.contains(w), "{w:?} not in the message: {err}");
    }
}

#[test]
fn the_shipped_description_passes_and_generates_the_table() {
    let model = check(XML).unwrap();
    assert_eq!(model.variables.len(), 38);
    let code = generate(&model);
    assert!(code.contains("pub const PLATE_LENGTH: u32 = 1;"), "{code}");
    assert!(code.contains("pub const CONTACT_ACTIVE_NODES: u32 = 43;"));
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
        &broken(r#"<Real unit="N.s"/>"#, r#"<Real unit="N.s" start="0"/>"#),
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
        &broken("<Outputs>\n      <Unknown index=\"23\"/>\n", "<Outputs>\n"),
        &["ModelStructure/Outputs"],
    );
}

#[test]
fn not_xml() {
    rejected("<fmiModelDescription", &["cannot parse"]);
}
