//! Variables ↔ the plate's data: parameters are [`Scene`] fields named by their dotted path (the
//! variable name), read and written through [`Scene::get`] and [`Scene::with`]; outputs are
//! [`Outputs`] fields and, for what happened over the last communication step, [`LastStep`]
//! fields; the one input is the external base displacement.

use crate::backend_choice;
use crate::budget::ProblemSize;
use crate::element::ElementKind;
use crate::fmi::model::Value;
use crate::fmi::status::Failure;
use crate::fmi::variables::{vr, Causality, Kind, Variable, FMI2};
use crate::obstacles::STOP_OUTPUTS;
use crate::scene::{Bound, Clamp, LinearChoice, Profile, Scene, PROBES};
use crate::simulation::contact_summary::ContactSummary;
use crate::simulation::{bound_tolerance, Outputs};
use crate::system::FREQUENCIES;

/// The value of a parameter in `scene`, typed as the variable declares it: a direct field read
/// (`field`), no JSON.
pub fn parameter(scene: &Scene, v: &Variable) -> Result<Value, Failure> {
    field(scene, v.name).ok_or_else(|| {
        Failure::refused(format!("{} has no field binding (internal error)", v.name))
    })
}

/// The field of parameter `name` in `scene` as the FMI value its variable declares: reals as
/// `Real`, switches as `Boolean`, cell counts and the element family (its [`ElementKind::code`]) as
/// `Integer`. `None` for a name that is no parameter, or a cell count beyond `i32` (no valid
/// scene has one). A test checks every FMU parameter reads here as through the scene's JSON.
fn field(s: &Scene, name: &str) -> Option<Value> {
    let real = |x: f64| Some(Value::Real(x));
    let count = |n: usize| i32::try_from(n).ok().map(Value::Integer);
    match name {
        "plate.length" => real(s.plate.length),
        "plate.width" => real(s.plate.width),
        "plate.thickness" => real(s.plate.thickness),
        "material.young_modulus" => real(s.material.young_modulus),
        "material.poisson_ratio" => real(s.material.poisson_ratio),
        "material.density" => real(s.material.density),
        "mesh.element" => Some(Value::Integer(s.mesh.element.code())),
        "mesh.nx" => count(s.mesh.nx),
        "mesh.ny" => count(s.mesh.ny),
        "solver.time_step" => real(s.solver.time_step),
        "solver.restitution" => real(s.solver.restitution),
        "obstacle.lower_enabled" => Some(Value::Boolean(s.obstacle.lower_enabled)),
        "obstacle.upper_enabled" => Some(Value::Boolean(s.obstacle.upper_enabled)),
        "obstacle.lower" => real(s.obstacle.lower),
        "obstacle.upper" => real(s.obstacle.upper),
        "load.pressure" => real(s.load.pressure),
        "load.gravity" => real(s.load.gravity),
        "initial.preload_pressure" => real(s.initial.preload_pressure),
        "base.amplitude" => real(s.base.amplitude),
        "base.frequency" => real(s.base.frequency),
        "damping.mass_proportional" => real(s.damping.mass_proportional),
        "damping.stiffness_proportional" => real(s.damping.stiffness_proportional),
        "damping.ratio" => real(s.damping.ratio),
        "damping.frequency_low" => real(s.damping.frequency_low),
        "damping.frequency_high" => real(s.damping.frequency_high),
        "damping.modal_ratio" => real(s.damping.modal_ratio),
        _ => probe_coordinate(s, name).map(Value::Real),
    }
}

/// `probeK.x` or `probeK.y` of `scene`, K = 1 … [`PROBES`](crate::scene::PROBES).
fn probe_coordinate(scene: &Scene, name: &str) -> Option<f64> {
    let (probe, axis) = name.strip_prefix("probe")?.split_once('.')?;
    let k: usize = probe.parse().ok()?;
    let probe = scene.probes().get(k.checked_sub(1)?).copied()?;
    match axis {
        "x" => Some(probe.x),
        "y" => Some(probe.y),
        _ => None,
    }
}

/// The text of a String parameter in `scene`: the clamp or an obstacle's profile.
pub fn text_parameter<'s>(scene: &'s Scene, v: &Variable) -> Result<&'s str, Failure> {
    match v.name {
        "plate.clamp" => Ok(&scene.plate.clamp),
        "obstacle.lower_profile" => Ok(&scene.obstacle.lower_profile),
        "obstacle.upper_profile" => Ok(&scene.obstacle.upper_profile),
        _ => Err(Failure::refused(format!(
            "{} has no text binding (internal error)",
            v.name
        ))),
    }
}

/// Largest text a String parameter takes (bytes): a table profile of 201 × 201 values written
/// with 20 characters each fits.
pub const MAX_TEXT_BYTES: usize = 1 << 20;

/// `scene` with String parameter `v` set to `text`, after checking the text on its own: its
/// length, and its grammar ([`crate::scene::text`]) with every number finite. What depends on
/// other parameters (a stop on the plate, a clamp segment within its edge, the obstacle away from
/// the plate at rest) is [`Scene::validate`]'s, so the order of the sets does not matter.
pub fn with_text_parameter(scene: &Scene, v: &Variable, text: &str) -> Result<Scene, Failure> {
    if text.len() > MAX_TEXT_BYTES {
        return Err(crate::Error::invalid(
            v.name,
            format!("<{} bytes>", text.len()),
            &format!("must be at most {MAX_TEXT_BYTES} bytes long"),
        )
        .into());
    }
    // On an unbounded plate only the grammar and the numbers are checked.
    let unbounded = [f64::INFINITY; 2];
    match v.name {
        "plate.clamp" => drop(Clamp::parse(text, unbounded)?),
        _ => drop(Profile::parse(text, v.name, unbounded)?),
    }
    Ok(scene.with(v.name, serde_json::Value::from(text))?)
}

/// The value of a calculated parameter that follows from the parameters alone, without a set-up:
/// the Rayleigh α (`damping.alpha`) or β (`damping.beta`) in use
/// ([`Damping::rayleigh`](crate::scene::Damping::rayleigh)), refused while the damping settings
/// are inconsistent (the error names the parameters at fault); the free dofs of the plate
/// (`solver.free_dofs`, [`ProblemSize::of`], the count the set-up assembles), the linear backend
/// the set-up builds for them (`solver.backend`, [`backend_code`] of
/// [`backend_choice::resolve`]) and the clamped length on the mesh (`plate.clamped_length`). The
/// natural frequencies need the set-up ([`frequency_index`]).
pub fn calculated(scene: &Scene, v: &Variable) -> Result<Value, Failure> {
    let free_dofs = || ProblemSize::of(scene).map(|size| size.free_dofs);
    match v.vr {
        vr::DAMPING_ALPHA | vr::DAMPING_BETA => {
            scene.damping.validate()?;
            let (alpha, beta) = scene.damping.rayleigh();
            Ok(Value::Real(if v.vr == vr::DAMPING_ALPHA {
                alpha
            } else {
                beta
            }))
        }
        vr::SOLVER_FREE_DOFS => {
            let n = free_dofs()?;
            i32::try_from(n).map(Value::Integer).map_err(|_| {
                Failure::refused(format!(
                    "{} = {n} exceeds the Integer range (internal error: the mesh bounds keep it \
                     below)",
                    v.name
                ))
            })
        }
        vr::PLATE_CLAMPED_LENGTH => Ok(Value::Real(scene.clamped_edges()?.length())),
        vr::SOLVER_BACKEND => backend_code(backend_choice::resolve(scene, free_dofs()?))
            .map(Value::Integer)
            .ok_or_else(|| Failure::refused(format!("{} is unresolved (internal error)", v.name))),
        _ => Err(Failure::refused(format!(
            "{} has no binding (internal error)",
            v.name
        ))),
    }
}

/// The index k (from 0) of calculated parameter `v` among `mode1.frequency` …
/// `mode6.frequency`, if it is one of them: they are read from the set-up plate.
pub fn frequency_index(v: &Variable) -> Option<usize> {
    (vr::MODE1_FREQUENCY..vr::MODE1_FREQUENCY + FREQUENCIES as u32)
        .contains(&v.vr)
        .then(|| (v.vr - vr::MODE1_FREQUENCY) as usize)
}

/// The code `solver.backend` reports for a resolved linear backend (the description documents
/// them): 1 = modal, 2 = sparse; `None` for `auto`, which [`backend_choice::resolve`] never
/// returns.
pub fn backend_code(choice: LinearChoice) -> Option<i32> {
    match choice {
        LinearChoice::Modal => Some(1),
        LinearChoice::Sparse => Some(2),
        LinearChoice::Auto => None,
    }
}

/// Checks the FMI value of parameter `v` against its own range in [`BOUNDS`](crate::scene::BOUNDS)
/// (integers as `f64`, the element family by its code); the switches have no range.
fn check_own_range(v: &Variable, value: Value) -> Result<(), Failure> {
    let x = match value {
        Value::Real(x) => x,
        Value::Integer(i) => f64::from(i),
        Value::Boolean(_) | Value::UInt64(_) => return Ok(()),
    };
    match Bound::of(v.name) {
        Some(bound) => Ok(bound.check(x)?),
        None => Err(Failure::refused(format!(
            "{} has no range in the bounds table (internal error)",
            v.name
        ))),
    }
}

/// The scene's JSON value for an FMI value of parameter `v`, already within its range
/// ([`check_own_range`]).
fn json_value(v: &Variable, value: Value) -> Result<serde_json::Value, Failure> {
    Ok(match value {
        Value::Real(x) => serde_json::Value::from(x),
        Value::Boolean(b) => serde_json::Value::from(b),
        Value::Integer(code) if v.vr == vr::MESH_ELEMENT => {
            let kind = ElementKind::from_code(code).ok_or_else(|| {
                Failure::refused(format!("{} = {code} is no element family", v.name))
            })?;
            serde_json::to_value(kind).expect("an element kind serializes")
        }
        Value::Integer(i) => serde_json::Value::from(i),
        Value::UInt64(_) => {
            return Err(Failure::refused(format!(
                "{} cannot take the value {value:?}",
                v.name
            )))
        }
    })
}

/// `scene` with parameter `v` set to `value`, after checking the value against its own range in
/// [`BOUNDS`](crate::scene::BOUNDS). Limits that tie parameters together (thickness below the
/// shorter side, sine amplitude inside the gap, the damping pair) are left to [`Scene::validate`]
/// on the whole scene, so the order of the sets does not matter.
pub fn with_parameter(scene: &Scene, v: &Variable, value: Value) -> Result<Scene, Failure> {
    check_own_range(v, value)?;
    Ok(scene.with(v.name, json_value(v, value)?)?)
}

/// Checks the parameters of an untrusted `scene` as [`with_parameter`] checks each value set:
/// every FMU parameter within its own range (in the order of the variables), and no scene field
/// that is not an FMU variable away from its default. Each parameter is read from its field and
/// the scene rebuilt from them in one JSON tree, not one scene round-trip per parameter.
pub fn check_parameters(scene: &Scene) -> Result<(), Failure> {
    let mut rebuilt = serde_json::to_value(Scene::default()).expect("a scene always serializes");
    for v in FMI2
        .variables
        .iter()
        .filter(|v| v.causality == Causality::Parameter)
    {
        let json = if v.kind == Kind::String {
            let text = text_parameter(scene, v)?;
            with_text_parameter(&Scene::default(), v, text)?;
            serde_json::Value::from(text)
        } else {
            let value = parameter(scene, v)?;
            check_own_range(v, value)?;
            json_value(v, value)?
        };
        *Scene::slot(&mut rebuilt, v.name).expect("every parameter is a scene field") = json;
    }
    let rebuilt: Scene = serde_json::from_value(rebuilt)
        .map_err(|e| Failure::refused(format!("its parameters do not form a scene ({e})")))?;
    if rebuilt != *scene {
        return Err(Failure::refused(
            "its scene sets fields that are not FMU variables (stop_time, solver.qp or solver.linear)",
        ));
    }
    Ok(())
}

/// What the last communication step reports besides the outputs at its end.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LastStep {
    /// The contact over its internal steps.
    pub contact: ContactSummary,
    /// The mean of the force on the base over it (N,
    /// [`Simulation::base_mean_force`](crate::simulation::Simulation::base_mean_force)).
    pub base_mean_force: f64,
    /// d/dt of the probes' displacements at its end (m/s,
    /// [`Simulation::displacement_rates`](crate::simulation::Simulation::displacement_rates)).
    pub probe_velocities: [f64; PROBES],
}

/// How to read a Real output from the outputs at the communication time and what the last
/// communication step reports.
type RealOutput = fn(&Outputs, &LastStep) -> f64;

/// Every Real output, by value reference: the one table behind [`output`] and [`first_non_finite`].
const REAL_OUTPUTS: [(u32, RealOutput); 15] = [
    (vr::CORNER1_DISPLACEMENT, |o, _| o.corner1),
    (vr::CORNER2_DISPLACEMENT, |o, _| o.corner2),
    (vr::EDGE_MID_DISPLACEMENT, |o, _| o.edge_mid),
    (vr::ENERGY_KINETIC, |o, _| o.energy_kinetic),
    (vr::ENERGY_ELASTIC, |o, _| o.energy_elastic),
    (vr::ENERGY_TOTAL, |o, _| o.energy_total),
    (vr::CONTACT_FORCE, |o, _| o.contact_force),
    (vr::BASE_FORCE, |o, _| o.base_force),
    (vr::ENERGY_BASE_WORK, |o, _| o.base_work),
    (vr::ENERGY_LOAD_WORK, |o, _| o.load_work),
    (vr::ENERGY_CONTACT_LOSS, |o, _| o.contact_loss),
    (vr::ENERGY_DAMPING_LOSS, |o, _| o.damping_loss),
    (vr::CONTACT_IMPULSE, |_, s| s.contact.impulse),
    (vr::CONTACT_PEAK_FORCE, |_, s| s.contact.peak_force),
    (vr::BASE_MEAN_FORCE, |_, s| s.base_mean_force),
];

/// The Real output with value reference `vr` in `outputs` and `last`, if it is one: the table
/// [`REAL_OUTPUTS`], then the families of the probes and the stops.
fn real_output(vr: u32, outputs: &Outputs, last: &LastStep) -> Option<f64> {
    if let Some((_, read)) = REAL_OUTPUTS.iter().find(|(r, _)| *r == vr) {
        return Some(read(outputs, last));
    }
    let member = |first: u32, count: usize| {
        (first..first + count as u32)
            .contains(&vr)
            .then(|| (vr - first) as usize)
    };
    if let Some(k) = member(vr::PROBE1_DISPLACEMENT, PROBES) {
        return Some(outputs.probes()[k]);
    }
    if let Some(k) = member(vr::PROBE1_VELOCITY, PROBES) {
        return Some(last.probe_velocities[k]);
    }
    if let Some(k) = member(vr::STOP1_FORCE, STOP_OUTPUTS) {
        return Some(outputs.stop_forces[k]);
    }
    member(vr::STOP1_IMPULSE, STOP_OUTPUTS).map(|k| last.contact.stops[k].impulse)
}

/// The value of output `v` (by value reference) in `outputs` and `last`. Refused: an impact
/// count beyond the Integer range (more than 2³¹ − 1 impacts in one communication step).
pub fn output(outputs: &Outputs, last: &LastStep, v: &Variable) -> Result<Value, Failure> {
    if let Some(x) = real_output(v.vr, outputs, last) {
        return Ok(Value::Real(x));
    }
    let contact = &last.contact;
    let stop = (vr::STOP1_IMPACTS..vr::STOP1_IMPACTS + STOP_OUTPUTS as u32)
        .contains(&v.vr)
        .then(|| (v.vr - vr::STOP1_IMPACTS) as usize);
    let impacts = match (v.vr, stop) {
        (vr::CONTACT_ACTIVE_NODES, _) => {
            return Ok(Value::Integer(
                i32::try_from(outputs.active_nodes).expect("at most 401² vertices are in contact"),
            ))
        }
        (vr::CONTACT_IMPACTS, _) => contact.impacts,
        (_, Some(k)) => contact.stops[k].impacts,
        _ => {
            return Err(Failure::refused(format!(
                "{} has no output binding (internal error)",
                v.name
            )))
        }
    };
    Ok(Value::Integer(i32::try_from(impacts).map_err(|_| {
        Failure::refused(format!(
            "{} = {impacts} exceeds the Integer range of FMI 2.0 (2^31 - 1); take shorter communication steps",
            v.name
        ))
    })?))
}

/// The displacement outputs with a derivative, in the order of
/// [`Simulation::displacement_rates`](crate::simulation::Simulation::displacement_rates), and the
/// array output of every vertex.
pub const DISPLACEMENT_OUTPUTS: [&str; 8] = [
    "corner1.displacement",
    "corner2.displacement",
    "edge_mid.displacement",
    "probe1.displacement",
    "probe2.displacement",
    "probe3.displacement",
    "probe4.displacement",
    "plate.displacement",
];

/// The index of scalar displacement output `v` among the rates, if it is one.
pub fn displacement_point(v: &Variable) -> Option<usize> {
    [
        vr::CORNER1_DISPLACEMENT,
        vr::CORNER2_DISPLACEMENT,
        vr::EDGE_MID_DISPLACEMENT,
        vr::PROBE1_DISPLACEMENT,
        vr::PROBE2_DISPLACEMENT,
        vr::PROBE3_DISPLACEMENT,
        vr::PROBE4_DISPLACEMENT,
    ]
    .iter()
    .position(|&r| r == v.vr)
}

/// The first Real output of `outputs` and `last` that is not finite, as (variable name, value):
/// every Real output of the description, in its order.
pub fn first_non_finite(outputs: &Outputs, last: &LastStep) -> Option<(&'static str, f64)> {
    FMI2.variables
        .iter()
        .filter(|v| v.causality == Causality::Output && v.kind == Kind::Real)
        .find_map(|v| {
            let x = real_output(v.vr, outputs, last)?;
            (!x.is_finite()).then_some((v.name, x))
        })
}

/// The first corner output that is a contact point (the free corners of the paper's plate) and
/// lies past an enabled obstacle by more than [`bound_tolerance`] (a fraction of the gap), as
/// (variable name, value, obstacle level there); `heights` are the obstacles' heights over the
/// two corners ([`crate::scheme::Stepper::corner_heights`]). Every impact law keeps every level
/// within the obstacles, so the check holds for every restitution e.
pub fn first_past_obstacle(
    outputs: &Outputs,
    scene: &Scene,
    heights: [&[f64]; 2],
) -> Option<(&'static str, f64, f64)> {
    const CORNERS: [&str; 2] = ["corner1.displacement", "corner2.displacement"];
    scene
        .first_outside(
            &[outputs.corner1, outputs.corner2],
            heights,
            bound_tolerance(scene),
        )
        .map(|outside| (CORNERS[outside.index], outside.value, outside.level))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fmi::variables::Kind;
    use crate::fmi::variables::{Causality, Start, FMI3};

    fn by_name(name: &str) -> Option<&'static Variable> {
        FMI2.by_name(name)
    }

    /// The description's start values are the scene defaults: the two cannot drift.
    #[test]
    fn start_values_equal_scene_defaults() {
        let scene = Scene::default();
        let mut parameters = 0;
        for v in FMI2
            .variables
            .iter()
            .filter(|v| v.causality == Causality::Parameter)
        {
            parameters += 1;
            if let Some(Start::String(text)) = v.start.clone() {
                assert_eq!(text_parameter(&scene, v).unwrap(), text, "{}", v.name);
                continue;
            }
            let expected = match v.start.clone() {
                Some(Start::Real(x)) => Value::Real(x),
                Some(Start::Integer(i)) => Value::Integer(i32::try_from(i).unwrap()),
                Some(Start::Boolean(b)) => Value::Boolean(b),
                other => panic!("{}: unexpected start {other:?}", v.name),
            };
            assert_eq!(parameter(&scene, v).unwrap(), expected, "{}", v.name);
        }
        assert_eq!(parameters, 37, "docs/fmu.md lists 37 parameters");
    }

    /// `solver.free_dofs` and `solver.backend` are what a set-up builds: on meshes of both
    /// elements, modal and sparse (Argyris 21 × 10 has 2048 free dofs, just above the modal limit;
    /// its sparse set-up is cheap), they equal the built stepper's dimension and backend.
    #[test]
    fn free_dofs_and_backend_are_those_of_the_set_up() {
        use crate::scheme::Stepper;
        let free = by_name("solver.free_dofs").unwrap();
        let backend = by_name("solver.backend").unwrap();
        for (element, nx, ny) in [
            (ElementKind::Argyris, 2, 1),
            (ElementKind::Argyris, 10, 7),
            (ElementKind::Fvs, 5, 3),
            (ElementKind::Argyris, 21, 10),
        ] {
            let mut scene = Scene::default();
            (scene.mesh.element, scene.mesh.nx, scene.mesh.ny) = (element, nx, ny);
            let stepper = Stepper::new(&scene, 0.0).unwrap();
            let n = i32::try_from(stepper.free_dof_count()).unwrap();
            assert_eq!(calculated(&scene, free).unwrap(), Value::Integer(n));
            let code = backend_code(stepper.linear_backend()).unwrap();
            assert_eq!(calculated(&scene, backend).unwrap(), Value::Integer(code));
        }
        assert_eq!(backend_code(LinearChoice::Modal), Some(1));
        assert_eq!(backend_code(LinearChoice::Sparse), Some(2));
    }

    /// FMI 3.0 sizes plate.displacement by its structural parameters: their starts are the vertex
    /// rows and columns of the default mesh, so that the declared shape fits without configuring.
    #[test]
    fn the_field_sizes_start_at_the_default_mesh() {
        let scene = Scene::default();
        let start = |name| match FMI3.by_name(name).and_then(|v| v.start.clone()) {
            Some(Start::Integer(n)) => n,
            other => panic!("{name}: unexpected start {other:?}"),
        };
        assert_eq!(start("mesh.vertex_rows"), scene.mesh.ny as i64 + 1);
        assert_eq!(start("mesh.vertex_columns"), scene.mesh.nx as i64 + 1);
    }

    /// Every output variable has a binding, and the finiteness guard covers every Real output.
    #[test]
    fn every_output_is_bound_and_guarded() {
        let mut outputs = Outputs::default();
        let mut last = LastStep::default();
        for v in FMI2
            .variables
            .iter()
            .filter(|v| v.causality == Causality::Output)
        {
            output(&outputs, &last, v).unwrap();
        }
        let real_outputs = FMI2
            .variables
            .iter()
            .filter(|v| v.causality == Causality::Output && v.kind == Kind::Real)
            .count();
        assert_eq!(first_non_finite(&outputs, &last), None);
        last.base_mean_force = f64::NEG_INFINITY;
        assert_eq!(
            first_non_finite(&outputs, &last),
            Some(("base.mean_force", f64::NEG_INFINITY))
        );
        last.contact.impulse = f64::NAN;
        assert!(matches!(
            first_non_finite(&outputs, &last),
            Some(("contact.impulse", x)) if x.is_nan()
        ));
        outputs.energy_elastic = f64::INFINITY;
        assert_eq!(
            first_non_finite(&outputs, &last),
            Some(("energy.elastic", f64::INFINITY))
        );
        // 15 of the paper's model, 4 probes' displacements and velocities, 8 stops' forces and
        // impulses.
        assert_eq!(real_outputs, 15 + 2 * 4 + 2 * 8);
        for (name, kind) in [
            ("corner1.displacement", Kind::Real),
            ("energy.total", Kind::Real),
            ("contact.force", Kind::Real),
            ("base.force", Kind::Real),
            ("energy.damping_loss", Kind::Real),
            ("contact.impacts", Kind::Integer),
            ("contact.peak_force", Kind::Real),
            ("base.mean_force", Kind::Real),
        ] {
            assert_eq!(by_name(name).unwrap().kind, kind, "{name}");
        }
        last.contact.impacts = 1 << 31;
        let impacts = by_name("contact.impacts").unwrap();
        let err = output(&outputs, &last, impacts).unwrap_err();
        assert!(
            err.message.contains("contact.impacts = 2147483648"),
            "{}",
            err.message
        );
    }

    #[test]
    fn element_is_an_integer_naming_its_values() {
        let v = by_name("mesh.element").unwrap();
        assert_eq!(v.kind, Kind::Integer);
        let scene = with_parameter(&Scene::default(), v, Value::Integer(2)).unwrap();
        assert_eq!(scene.mesh.element, ElementKind::Fvs);
        let err = with_parameter(&scene, v, Value::Integer(3)).unwrap_err();
        assert!(
            err.message.contains("mesh.element = 3") && err.message.contains("2 = FVS"),
            "{}",
            err.message
        );
    }

    #[test]
    fn own_ranges_are_checked_cross_limits_are_not() {
        let thickness = by_name("plate.thickness").unwrap();
        let scene = with_parameter(&Scene::default(), thickness, Value::Real(0.3)).unwrap();
        assert!(
            scene.validate().is_err(),
            "thicker than the width: for later"
        );
        let ratio = by_name("material.poisson_ratio").unwrap();
        let err = with_parameter(&scene, ratio, Value::Real(0.5)).unwrap_err();
        assert!(err.message.contains("material.poisson_ratio"));
        let nx = by_name("mesh.nx").unwrap();
        assert!(with_parameter(&scene, nx, Value::Integer(-3)).is_err());
        assert!(with_parameter(&scene, nx, Value::Integer(401)).is_err());
    }

    /// Every FMU parameter reads from its field as through the scene's JSON ([`Scene::get`]),
    /// on the defaults and on a scene whose every parameter differs from them.
    #[test]
    fn every_parameter_reads_its_field_as_the_json_does() {
        let mut changed = Scene::default();
        changed.mesh.element = ElementKind::Fvs;
        (changed.mesh.nx, changed.mesh.ny) = (13, 9);
        changed.obstacle.lower_enabled = !changed.obstacle.lower_enabled;
        changed.obstacle.upper_enabled = !changed.obstacle.upper_enabled;
        let parameters = || {
            FMI2.variables
                .iter()
                .filter(|v| v.causality == Causality::Parameter)
        };
        for v in parameters().filter(|v| v.kind == Kind::Real) {
            let x = match parameter(&changed, v).unwrap() {
                Value::Real(x) => x,
                other => panic!("{} reads {other:?}", v.name),
            };
            let json = serde_json::Value::from(x * 1.5 + 0.25);
            changed = changed.with(v.name, json).unwrap();
        }
        changed.plate.clamp = "all".to_string();
        changed.obstacle.lower_profile = "point(x=0.1, y=0.1)".to_string();
        changed.obstacle.upper_profile = "plane(slope_x=0.01)".to_string();
        let mut read = 0;
        for scene in [Scene::default(), changed] {
            for v in parameters() {
                let json = scene.get(v.name).unwrap();
                if v.kind == Kind::String {
                    let text = text_parameter(&scene, v).unwrap();
                    assert_eq!(Some(text), json.as_str(), "{}", v.name);
                } else {
                    assert_eq!(parameter(&scene, v).unwrap(), typed(v, &json), "{}", v.name);
                }
                read += 1;
            }
        }
        assert_eq!(read, 2 * 37, "the 37 FMU parameters");
    }

    /// The FMI value of parameter `v` from its JSON value in a scene: the reference the direct
    /// field read is checked against.
    fn typed(v: &Variable, json: &serde_json::Value) -> Value {
        match v.kind {
            Kind::Real => Value::Real(json.as_f64().unwrap()),
            Kind::Boolean => Value::Boolean(json.as_bool().unwrap()),
            Kind::Integer | Kind::Enumeration if v.vr == vr::MESH_ELEMENT => Value::Integer(
                serde_json::from_value::<ElementKind>(json.clone())
                    .unwrap()
                    .code(),
            ),
            Kind::Integer | Kind::Enumeration => {
                Value::Integer(i32::try_from(json.as_i64().unwrap()).unwrap())
            }
            Kind::String | Kind::UInt64 => panic!("{} is no parameter kind", v.name),
        }
    }
}
