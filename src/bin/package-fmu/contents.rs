//! What the FMUs carry besides the model description and the binaries: their documentation pages
//! and, in the layout of the FMI layered standard for references (FMI-LS-REF, version
//! 1.0.0-alpha.1), the shipped scenes as SSP parameter sets, their reference results and the
//! experiments that pair them (docs/fmu.md, "What the FMU carries").
//!
//! * `documentation/index.html`: `docs/fmu-documentation.md` rendered ([`documentation::html`]),
//!   followed by the section on this build ([`Build::about`]): its version and commit, where the
//!   full documentation lives, the licence;
//! * `documentation/fmi-ls-ref.html`: `docs/fmi-ls-ref.md` rendered, the page FMI-LS-REF
//!   recommends for what the references are, their intent and the deviations to expect;
//! * `extra/org.fmi-standard.fmi-ls-ref/fmi-ls-manifest.xml`: one `<Related>` per file below and
//!   both documentation pages, with its role (`parameter`, `experiment/validation`, `result`,
//!   `document`) and MIME type;
//! * `<scene>.ssv` per scene of `scenes/` (SSP 1.0 SystemStructureParameterValues): every FMU
//!   parameter by name with the value the FMU reports for that scene, in the units the model
//!   description declares;
//! * `<scene>.csv`: the scene's reference result, the golden result the test suite holds the FMU to
//!   (`tests/fmu/reference/`, from the x86_64 Linux binary);
//! * `experiments.exp` (the Experiments Format of the Modelica Association's harmonized
//!   specifications, MA-HS-Experiments, by its draft schema): per scene a transient simulation with
//!   its start and stop time and communication step, its parameter set and reference result.
//!
//! Paths in the manifest and in `experiments.exp` are relative to the folder that holds them.

use crate::documentation;
use crate::version::Build;
use plate_impact::fmi::model::Value;
use plate_impact::fmi::plate::{parameter_value, text_parameter};
use plate_impact::fmi::variables::{Causality, Kind, FMI2};
use plate_impact::scene::{Scene, NAMED_SCENES};
use std::fmt::Write;
use std::path::Path;

/// The folder of the layered standard for references in the FMU.
pub const LS_REF: &str = "extra/org.fmi-standard.fmi-ls-ref";
/// Where the golden results live in the repository.
const REFERENCES: &str = "tests/fmu/reference";
/// The communication step of the reference results (s).
pub const REFERENCE_STEP: f64 = 1e-3;
/// The experiments file, in `LS_REF` (MA-HS-Experiments asks for the suffix `.exp`).
const EXPERIMENTS: &str = "experiments.exp";
/// The page on the references, in the place FMI-LS-REF recommends, and its Markdown source.
const REFERENCES_PAGE: (&str, &str) = ("documentation/fmi-ls-ref.html", "docs/fmi-ls-ref.md");

/// One file of the FMU: its path in the archive and its bytes.
pub type Entry = (String, Vec<u8>);

/// The scene's parameter set: every FMI 2.0 parameter (the FMI 3.0 FMU has the same ones, and
/// its structural parameters keep their start values: every shipped scene has the default mesh
/// size) with the FMU's value for the scene.
pub fn ssv(name: &str, scene: &Scene) -> Result<String, String> {
    let mut out = format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
         <ssv:ParameterSet xmlns:ssv=\"http://ssp-standard.org/SSP1/SystemStructureParameterValues\" \
         version=\"1.0\" name=\"{name}\">\n  <ssv:Parameters>\n"
    );
    for v in FMI2
        .variables
        .iter()
        .filter(|v| v.causality == Causality::Parameter)
    {
        let fail = |e: plate_impact::fmi::status::Failure| format!("{name}: {}", e.message);
        if v.kind == Kind::String {
            let text = text_parameter(scene, v).map_err(fail)?;
            let _ = writeln!(
                out,
                "    <ssv:Parameter name=\"{}\"><ssv:String value=\"{}\"/></ssv:Parameter>",
                v.name,
                xml_escape(text)
            );
            continue;
        }
        let value = parameter_value(scene, v).map_err(fail)?;
        let element = match value {
            Value::Real(x) => format!("<ssv:Real value=\"{x:?}\"/>"),
            Value::Integer(i) => format!("<ssv:Integer value=\"{i}\"/>"),
            Value::Boolean(b) => format!("<ssv:Boolean value=\"{b}\"/>"),
            Value::UInt64(n) => format!("<ssv:Integer value=\"{n}\"/>"),
        };
        let _ = writeln!(
            out,
            "    <ssv:Parameter name=\"{}\">{element}</ssv:Parameter>",
            v.name
        );
    }
    out.push_str("  </ssv:Parameters>\n</ssv:ParameterSet>\n");
    Ok(out)
}

/// `text` with the five characters XML reserves written as entities, for an attribute value.
fn xml_escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
        .replace('\'', "&apos;")
}

/// The experiments in the MA-HS-Experiments format: per scene a `<TransientSimulation>` over its
/// horizon at the reference step, its parameter set and its reference result.
fn experiments(version: &str, scenes: &[(&str, Scene)]) -> String {
    let mut out = format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
         <Experiments name=\"PlateImpact {version}: the shipped scenes\" \
         description=\"each shipped scene run over its horizon against its reference result\">\n"
    );
    for (name, scene) in scenes {
        let _ = write!(
            out,
            "  <Experiment name=\"{name}\" description=\"the scene {name}\">\n\
             \x20   <TransientSimulation startTime=\"0\" stopTime=\"{:?}\" stepSize=\"{REFERENCE_STEP:?}\"/>\n\
             \x20   <Parameters source=\"{name}.ssv\"/>\n\
             \x20   <References source=\"{name}.csv\"/>\n  </Experiment>\n",
            scene.stop_time
        );
    }
    out.push_str("</Experiments>\n");
    out
}

/// The FMI-LS-REF manifest listing the files.
fn manifest(scenes: &[(&str, Scene)]) -> String {
    let mut out = String::from(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
         <fmiReferences xmlns:fmi-ls=\"http://fmi-standard.org/fmi-ls-manifest\" \
         fmi-ls:fmi-ls-name=\"org.fmi-standard.fmi-ls-ref\" fmi-ls:fmi-ls-version=\"1.0.0-alpha.1\" \
         fmi-ls:fmi-ls-description=\"Layered Standard providing information on related files included in an FMU.\">\n\
         \x20 <Related type=\"text/html\" source=\"../../documentation/index.html\" role=\"document\" \
         description=\"the model, every variable, the scheme's settings\"/>\n\
         \x20 <Related type=\"text/html\" source=\"../../documentation/fmi-ls-ref.html\" role=\"document\" \
         description=\"the reference results: what they hold, how to run them, the deviations to expect\"/>\n",
    );
    let _ = writeln!(
        out,
        "  <Related type=\"application/x-ma-hs-experiments\" source=\"{EXPERIMENTS}\" role=\"experiment/validation\" \
         description=\"each shipped scene run over its horizon against its reference result\"/>"
    );
    for (name, _) in scenes {
        let _ = write!(
            out,
            "  <Related type=\"application/x-ssp-parameter-set\" source=\"{name}.ssv\" role=\"parameter\" \
             description=\"the scene {name}: every parameter\"/>\n\
             \x20 <Related type=\"text/csv\" source=\"{name}.csv\" role=\"result\" \
             description=\"the scene {name}: every output at each {REFERENCE_STEP} s communication point\"/>\n"
        );
    }
    out.push_str("</fmiReferences>\n");
    out
}

/// Every extra file of both FMUs but the licences, read or generated from the repository at
/// `root` for `build`.
pub fn entries(root: &Path, build: &Build) -> Result<Vec<Entry>, String> {
    let version = &build.version;
    let read = |relative: &str| {
        std::fs::read_to_string(root.join(relative))
            .map_err(|e| format!("cannot read {relative}: {e}"))
    };
    let table = documentation::variable_table(&FMI2, &plate_impact::fmi::variables::FMI3);
    for file in documentation::TABLE_FILES {
        let text = read(file)?;
        if documentation::with_table(file, &text, &table)? != text {
            return Err(format!(
                "the variable table of {file} is stale: run `cargo run --release --bin \
                 package-fmu -- --write-docs`"
            ));
        }
    }
    let page = documentation::html(
        &format!("{}\n{}", read(documentation::PAGE_SOURCE)?, build.about()),
        &format!("PlateImpact {version}"),
    );
    let (references_page, references_source) = REFERENCES_PAGE;
    let references = documentation::html(
        &read(references_source)?,
        &format!("PlateImpact {version}: reference results"),
    );
    let scenes = NAMED_SCENES
        .iter()
        .map(|(name, _)| Scene::named(name).map(|s| (*name, s)))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| format!("a shipped scene does not load: {e}"))?;
    let mut entries: Vec<Entry> = vec![
        ("documentation/index.html".into(), page.into_bytes()),
        (references_page.into(), references.into_bytes()),
        (
            format!("{LS_REF}/fmi-ls-manifest.xml"),
            manifest(&scenes).into_bytes(),
        ),
        (
            format!("{LS_REF}/{EXPERIMENTS}"),
            experiments(version, &scenes).into_bytes(),
        ),
    ];
    for (name, scene) in &scenes {
        entries.push((
            format!("{LS_REF}/{name}.ssv"),
            ssv(name, scene)?.into_bytes(),
        ));
        let csv = format!("{REFERENCES}/{name}.csv");
        entries.push((format!("{LS_REF}/{name}.csv"), read(&csv)?.into_bytes()));
    }
    Ok(entries)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_parameter_set_names_every_parameter_once_with_its_type() {
        let scene = Scene::named("forced-35hz-damped").unwrap();
        let text = ssv("forced-35hz-damped", &scene).unwrap();
        let parameters = FMI2
            .variables
            .iter()
            .filter(|v| v.causality == Causality::Parameter);
        for v in parameters {
            assert_eq!(
                text.matches(&format!("name=\"{}\"", v.name)).count(),
                1,
                "{}",
                v.name
            );
        }
        for line in [
            "<ssv:Parameter name=\"base.frequency\"><ssv:Real value=\"35.0\"/></ssv:Parameter>",
            "<ssv:Parameter name=\"damping.stiffness_proportional\"><ssv:Real value=\"5.913e-5\"/></ssv:Parameter>",
            "<ssv:Parameter name=\"mesh.element\"><ssv:Integer value=\"1\"/></ssv:Parameter>",
            "<ssv:Parameter name=\"obstacle.upper_enabled\"><ssv:Boolean value=\"true\"/></ssv:Parameter>",
        ] {
            assert!(text.contains(line), "{line} not in\n{text}");
        }
    }

    #[test]
    fn the_manifest_lists_every_file_the_experiments_use() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let build = Build {
            version: "0.0.0".into(),
            commit: None,
            repository: "",
        };
        let entries = entries(root, &build).unwrap();
        let names: Vec<&str> = entries.iter().map(|(n, _)| n.as_str()).collect();
        let text = |name: &str| {
            let (_, bytes) = entries.iter().find(|(n, _)| n == name).unwrap();
            String::from_utf8(bytes.clone()).unwrap()
        };
        let manifest = text(&format!("{LS_REF}/fmi-ls-manifest.xml"));
        let experiments = text(&format!("{LS_REF}/{EXPERIMENTS}"));
        for (name, _) in NAMED_SCENES {
            for file in [format!("{name}.ssv"), format!("{name}.csv")] {
                assert!(names.contains(&format!("{LS_REF}/{file}").as_str()));
                assert!(manifest.contains(&format!("source=\"{file}\"")), "{file}");
                assert!(
                    experiments.contains(&format!("source=\"{file}\"")),
                    "{file}"
                );
            }
        }
        assert!(names.contains(&"documentation/index.html"));
        assert!(names.contains(&"documentation/fmi-ls-ref.html"));
        for page in ["index.html", "fmi-ls-ref.html"] {
            assert!(manifest.contains(&format!("source=\"../../documentation/{page}\"")));
        }
        assert!(manifest.contains(&format!("source=\"{EXPERIMENTS}\"")));
        assert!(experiments.contains("<TransientSimulation startTime=\"0\" stopTime=\"1.0\""));
        assert_eq!(entries.len(), 4 + 2 * NAMED_SCENES.len());
    }
}
