//! The restitution study through the FMU: the `energy` scene run by the FMU's FMI 2.0 instance
//! (the code its exported functions run), its parameters set from a scene.

use plate_impact::fmi::fmi2::instance::Fmi2;
use plate_impact::fmi::instance::{Instance, Version};
use plate_impact::fmi::model::StepOptions;
use plate_impact::fmi::plate::PlateModel;
use plate_impact::fmi::variables::{vr, Causality, Kind};
use plate_impact::scene::Scene;

/// Sets every FMU parameter of `scene` on `inst` (the variable names are the scene's paths).
fn set_parameters<V: Version>(
    inst: &mut Instance<V, PlateModel>,
    scene: &Scene,
) -> Result<(), String> {
    let tree = serde_json::to_value(scene).map_err(|e| e.to_string())?;
    for v in V::description::<PlateModel>()
        .variables
        .iter()
        .filter(|v| v.causality == Causality::Parameter)
    {
        let field = v.name.split('.').fold(&tree, |t, k| &t[k]);
        let done = match v.kind {
            Kind::Real => inst.set_real(&[v.vr], &[field.as_f64().unwrap_or(f64::NAN)]),
            Kind::Boolean => inst.set_boolean(&[v.vr], &[field.as_bool() == Some(true)]),
            Kind::Integer if v.vr == vr::MESH_ELEMENT => {
                let code = if field.as_str() == Some("argyris") {
                    1
                } else {
                    2
                };
                inst.set_integer(&[v.vr], &[code])
            }
            Kind::Integer => {
                let value = field.as_i64().and_then(|x| i32::try_from(x).ok());
                inst.set_integer(&[v.vr], &[value.unwrap_or(-1)])
            }
            _ => continue,
        };
        done.map_err(|f| format!("{}: {}", v.name, f.message))?;
    }
    Ok(())
}

/// The `energy` scene at e = 1 with time step Δt through the FMU's FMI 2.0 instance (the code
/// its exported functions run): E after a first communication step of Δt, E and the contact
/// loss after communication steps of 1 ms up to the scene's stop time (J).
pub fn through_the_fmu(scene: &Scene) -> Result<[f64; 3], String> {
    let failed = |f: plate_impact::fmi::status::Failure| f.message;
    let token = Fmi2::description::<PlateModel>().token;
    let mut inst = Instance::<Fmi2, PlateModel>::new("restitution", token, false, None)?;
    set_parameters(&mut inst, scene)?;
    inst.begin_initialization(Some((0.0, None)))
        .map_err(failed)?;
    inst.exit_initialization_mode().map_err(failed)?;
    let options = StepOptions {
        early_return: false,
    };
    let mut energy = [0.0];
    let dt = scene.solver.time_step;
    inst.step(0.0, dt, options).map_err(failed)?;
    inst.get_real(&[vr::ENERGY_TOTAL], &mut energy)
        .map_err(failed)?;
    let first = energy[0];
    let (mut t, points) = (dt, (scene.stop_time / 1e-3).round() as u32);
    for k in 1..=points {
        let next = f64::from(k) * 1e-3;
        inst.step(t, next - t, options).map_err(failed)?;
        t = next;
    }
    let mut last = [0.0; 2];
    inst.get_real(&[vr::ENERGY_TOTAL, vr::ENERGY_CONTACT_LOSS], &mut last)
        .map_err(failed)?;
    Ok([first, last[0], last[1]])
}
