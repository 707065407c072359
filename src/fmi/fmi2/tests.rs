//! The FMI 2.0 instance driving the plate, through its safe API: the call-state table walked in
//! every state the FMU can be in, and one regression test per defect the FMU had (rejected sets
//! half-applied, OK with non-finite outputs, crafted FMU states accepted, unbounded steps, set-ups
//! repeated in Initialization mode, results depending on ulp jitter of the step size, an element
//! choice engines could not set).

use super::call_state::{Function, Mode};
use super::instance::{Instance, StoredState};
use crate::fmi::call_state::CallState;
use crate::fmi::logger::{LOG_ALL, LOG_ERROR};
use crate::fmi::plate::{PlateModel, LOG_CONTACT};
use crate::fmi::serialized;
use crate::fmi::status::{Failure, Status};
use crate::fmi::test_host::{assert_table_holds, real, recorded_instance, Messages};
use crate::fmi::variables::{vr, Causality, Kind, Start, FMI2};
use crate::simulation::{input::InputSample, Outputs, Simulation};

type Plate = Instance<PlateModel>;

fn instance() -> (Plate, Messages) {
    recorded_instance()
}

/// A small mesh keeps each set-up to a millisecond.
fn small() -> (Plate, Messages) {
    let (mut inst, m) = instance();
    inst.set_integer(&[vr::MESH_NX, vr::MESH_NY], &[3, 2])
        .unwrap();
    (inst, m)
}

fn initialized() -> (Plate, Messages) {
    let (mut inst, m) = small();
    inst.setup_experiment(0.0, None).unwrap();
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    (inst, m)
}

/// Everything the host can observe: every variable readable now, and the serialized state.
fn observe(inst: &mut Plate) -> (Vec<String>, Vec<u8>) {
    let mut values = Vec::new();
    for v in FMI2.variables {
        let text = match v.kind {
            Kind::Real => {
                let mut x = [0.0];
                inst.get_real(&[v.vr], &mut x)
                    .map(|()| x[0].to_bits().to_string())
            }
            Kind::Integer | Kind::Enumeration => {
                let mut i = [0];
                inst.get_integer(&[v.vr], &mut i).map(|()| i[0].to_string())
            }
            Kind::Boolean => {
                let mut b = [false];
                inst.get_boolean(&[v.vr], &mut b).map(|()| b[0].to_string())
            }
            Kind::String => inst
                .get_string(&[v.vr])
                .map(|texts| texts[0].to_string_lossy().into_owned()),
            Kind::UInt64 => unreachable!("not in FMI 2.0"),
        };
        values.push(text.unwrap_or_else(|f| f.message));
    }
    let state = inst.get_state().unwrap();
    let bytes = inst
        .serialized(Function::SerializeFMUstate, &state)
        .unwrap()
        .to_vec();
    (values, bytes)
}

#[test]
fn wrong_guid_is_refused() {
    assert!(Plate::new("x", "{nope}", false, None).is_err());
}

#[test]
fn every_variable_can_be_read_after_initialization() {
    let (mut inst, _) = initialized();
    let (values, _) = observe(&mut inst);
    for (v, text) in FMI2.variables.iter().zip(values) {
        let read = match v.start.clone() {
            // A text parameter reads as its start value.
            Some(Start::String(start)) => text == start,
            _ => text.parse::<f64>().is_ok() || text.parse::<bool>().is_ok(),
        };
        assert!(read, "{}: {text}", v.name);
    }
}

/// An instance in `mode` (one of those this FMU can be in).
fn in_mode(mode: Mode) -> Plate {
    let (mut inst, _) = small();
    match mode {
        Mode::Instantiated => {}
        Mode::InitializationMode => inst.enter_initialization_mode().unwrap(),
        Mode::StepComplete | Mode::Terminated | Mode::Error => {
            inst.enter_initialization_mode().unwrap();
            inst.exit_initialization_mode().unwrap();
            if mode == Mode::Terminated {
                inst.terminate().unwrap();
            }
            if mode == Mode::Error {
                inst.set_real(&[vr::BASE_DISPLACEMENT], &[0.02]).unwrap();
                let result = inst.do_step(0.0, 1e-3);
                assert_eq!(inst.finish(Function::DoStep, result), Status::Error);
            }
        }
        _ => unreachable!("{mode:?} is never entered"),
    }
    assert_eq!(inst.mode(), mode);
    inst
}

/// One harmless call of `function`.
fn call(
    inst: &mut Plate,
    function: Function,
    state: &StoredState<PlateModel>,
    bytes: &[u8],
) -> Result<(), Failure> {
    use Function::*;
    let t = inst.time();
    match function {
        SetDebugLogging => inst.set_debug_logging(true, &[]),
        SetupExperiment => inst.setup_experiment(0.0, None),
        EnterInitializationMode => inst.enter_initialization_mode(),
        ExitInitializationMode => inst.exit_initialization_mode().map(|_| ()),
        Terminate => inst.terminate(),
        Reset => inst.reset(),
        GetReal => inst.get_real(&[vr::PLATE_LENGTH], &mut [0.0]),
        GetInteger => inst.get_integer(&[vr::MESH_NX], &mut [0]),
        GetBoolean => inst.get_boolean(&[vr::OBSTACLE_LOWER_ENABLED], &mut [false]),
        GetString => inst.get_string(&[vr::PLATE_CLAMP]).map(|_| ()),
        SetString => inst.set_string(&[], &[]),
        SetReal => inst.set_real(&[vr::BASE_DISPLACEMENT], &[0.0]),
        SetInteger => inst.set_integer(&[], &[]),
        SetBoolean => inst.set_boolean(&[], &[]),
        GetFMUstate => inst.get_state().map(|_| ()),
        SetFMUstate => inst.set_state(state),
        FreeFMUstate => inst.free_state(),
        SerializedFMUstateSize | SerializeFMUstate => inst.serialized(function, state).map(|_| ()),
        DeSerializeFMUstate => inst.deserialize_state(bytes).map(|_| ()),
        GetDirectionalDerivative => inst.get_directional_derivative(),
        SetRealInputDerivatives => {
            inst.set_real_input_derivatives(&[vr::BASE_DISPLACEMENT], &[1], &[0.0])
        }
        GetRealOutputDerivatives => {
            inst.output_derivatives(&[vr::CORNER1_DISPLACEMENT], &[1], &mut [0.0])
        }
        DoStep => inst.do_step(t, 1e-4).map(|_| ()),
        CancelStep => inst.cancel_step(),
        GetRealStatus => inst.last_successful_time().map(|_| ()),
        GetBooleanStatus => inst.terminated_early().map(|_| ()),
        GetStatus | GetIntegerStatus | GetStringStatus => inst.status_not_available(function, "it"),
    }
}

/// Every function in every state the FMU can be in: refused as "not allowed" exactly where the
/// standard's table (`call_state.rs`) forbids it, and never for that reason elsewhere.
#[test]
fn the_standards_table_holds_through_the_instance() {
    let modes: Vec<Mode> = Mode::ALL
        .iter()
        .copied()
        .filter(|m| m.reachable())
        .collect();
    assert_table_holds(&modes, Function::ALL, in_mode, call);
}

/// Regression: a rejected multi-value set was half-applied.
#[test]
fn a_refused_set_changes_nothing() {
    let (mut inst, _) = small();
    inst.enter_initialization_mode().unwrap();
    let before = observe(&mut inst);
    let err = inst
        .set_real(&[vr::LOAD_PRESSURE, vr::ENERGY_KINETIC], &[7770.0, 1.0])
        .unwrap_err();
    assert!(err.message.contains("energy.kinetic"), "{}", err.message);
    assert!(inst
        .set_real(
            &[vr::BASE_DISPLACEMENT, vr::PLATE_LENGTH],
            &[1e-3, f64::NAN]
        )
        .is_err());
    assert!(inst
        .set_integer(&[vr::MESH_NX, vr::MESH_ELEMENT], &[5, 3])
        .is_err());
    assert!(inst.set_integer(&[vr::MESH_NX, 9999], &[5, 1]).is_err());
    assert!(inst
        .set_boolean(
            &[vr::OBSTACLE_LOWER_ENABLED, vr::PLATE_LENGTH],
            &[false, true]
        )
        .is_err());
    assert!(inst
        .set_real_input_derivatives(&[vr::BASE_DISPLACEMENT; 2], &[1, 3], &[0.5, 1.0])
        .is_err());
    assert_eq!(observe(&mut inst), before);

    inst.exit_initialization_mode().unwrap();
    // Bend the plate up, past 1 mm at the free corners.
    inst.set_real(&[vr::LOAD_PRESSURE], &[3e5]).unwrap();
    for _ in 0..5 {
        inst.do_step(inst.time(), 1e-3).unwrap();
    }
    assert!(real(&mut inst, vr::CORNER1_DISPLACEMENT) > 1e-3);
    let before = observe(&mut inst);
    // While stepping: a legal obstacle move with an illegal value, and a legal input with a fixed
    // parameter.
    assert!(inst
        .set_real(
            &[vr::OBSTACLE_UPPER, vr::LOAD_PRESSURE],
            &[1e308, f64::INFINITY]
        )
        .is_err());
    assert!(inst
        .set_real(&[vr::BASE_DISPLACEMENT, vr::PLATE_WIDTH], &[1e-3, 0.3])
        .is_err());
    assert!(inst
        .set_real(&[vr::LOAD_PRESSURE, vr::OBSTACLE_UPPER], &[100.0, 1e-6])
        .is_err());
    assert_eq!(observe(&mut inst), before);
    // The same sets without the bad value go through whole.
    inst.set_real(&[vr::OBSTACLE_UPPER, vr::LOAD_PRESSURE], &[0.02, 100.0])
        .unwrap();
    assert_eq!(real(&mut inst, vr::OBSTACLE_UPPER), 0.02);
    assert_eq!(real(&mut inst, vr::LOAD_PRESSURE), 100.0);
}

/// Regression: fmi2DoStep returned OK with non-finite outputs.
#[test]
fn a_step_that_overflows_is_an_error_naming_the_output() {
    let (mut inst, messages) = small();
    inst.set_boolean(
        &[vr::OBSTACLE_LOWER_ENABLED, vr::OBSTACLE_UPPER_ENABLED],
        &[false, false],
    )
    .unwrap();
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    inst.set_real(&[vr::BASE_DISPLACEMENT], &[1e308]).unwrap();
    let result = inst.do_step(0.0, 1e-3);
    assert_eq!(inst.finish(Function::DoStep, result), Status::Error);
    assert_eq!(inst.mode(), Mode::Error);
    let log = messages.lock().unwrap().clone();
    let (_, category, message) = log.last().unwrap();
    assert_eq!(category, LOG_ERROR);
    assert!(
        message.contains("not finite") || message.contains("non-finite"),
        "{message}"
    );
    // Nothing non-finite is ever reported with OK.
    for v in FMI2
        .variables
        .iter()
        .filter(|v| v.causality == Causality::Output && v.kind == Kind::Real)
    {
        let mut x = [0.0];
        if inst.get_real(&[v.vr], &mut x).is_ok() {
            assert!(x[0].is_finite(), "{} = {}", v.name, x[0]);
        }
    }
}

/// A contact problem that was not solved is an error, never garbage with OK: under huge loads
/// (1e20, 1e30 Pa), for the paper's law (e = 0) and Newton's law (e = 0.5, which also keeps every
/// level within the obstacles), every step either returns OK with the displacement outputs
/// within the obstacles or fails naming the cause; and under 1e308 Pa the step fails.
#[test]
fn a_free_corner_past_an_obstacle_is_an_error() {
    // The FMU's own tolerance: 1e-7 of the 0.02 m gap.
    let tolerance = 1e-7 * 0.02;
    let outputs = [
        vr::CORNER1_DISPLACEMENT,
        vr::CORNER2_DISPLACEMENT,
        vr::EDGE_MID_DISPLACEMENT,
    ];
    for restitution in [0.0, 0.5] {
        for pressure in [1e20, 1e30, 1e308] {
            let (mut inst, _) = small();
            inst.set_real(&[vr::SOLVER_RESTITUTION], &[restitution])
                .unwrap();
            inst.setup_experiment(0.0, None).unwrap();
            inst.enter_initialization_mode().unwrap();
            inst.exit_initialization_mode().unwrap();
            inst.set_real(&[vr::LOAD_PRESSURE], &[pressure]).unwrap();
            let case = format!("e = {restitution}, {pressure} Pa");
            let mut failed = false;
            for k in 0..20 {
                match inst.do_step(k as f64 * 1e-4, 1e-4) {
                    Ok(_) => {
                        for &r in &outputs {
                            let u = real(&mut inst, r);
                            assert!(
                                u.abs() <= 0.01 + tolerance,
                                "{case}, step {k}: OK with vr {r} = {u} m, past an obstacle"
                            );
                        }
                    }
                    Err(err) => {
                        assert!(
                            ["past the obstacle", "not finite", "non-finite", "contact"]
                                .iter()
                                .any(|words| err.message.contains(words)),
                            "{case}: {}",
                            err.message
                        );
                        assert_eq!(inst.finish(Function::DoStep, Err(err)), Status::Error);
                        failed = true;
                        break;
                    }
                }
            }
            assert!(failed || pressure < 1e308, "{case}: no step failed");
            // What can still be read (FMI allows fmi2GetReal in the Error state) is the state
            // before the failed step, finite and inside the obstacles.
            let mut corner = [f64::NAN];
            if inst
                .get_real(&[vr::CORNER1_DISPLACEMENT], &mut corner)
                .is_ok()
            {
                assert!(
                    corner[0].is_finite() && corner[0].abs() <= 0.01 + tolerance,
                    "{case}: {}",
                    corner[0]
                );
            }
        }
    }
}

/// A step may end past the stop time by the time tolerance (1e-9 of the experiment's scale); the
/// state it reaches can be set again, by the same rule, and a step beyond it is refused.
#[test]
fn a_state_at_the_stop_time_tolerance_can_be_set() {
    // The stop time 3e-13 s before the grid point t = 0: a step of 1 s from t = -1 s ends on
    // that grid point, within 1e-9 × 1 s of the stop time.
    let stop = -3e-13;
    let experiment = || {
        let (mut inst, _) = small();
        inst.setup_experiment(-1.0, Some(stop)).unwrap();
        inst.enter_initialization_mode().unwrap();
        inst.exit_initialization_mode().unwrap();
        inst
    };
    let mut inst = experiment();
    inst.do_step(-1.0, 1.0).unwrap();
    let state = inst.get_state().unwrap();
    inst.set_state(&state).unwrap();
    // 2e-9 s past the grid point: beyond the tolerance.
    let err = experiment().do_step(-1.0, 1.0 + 2e-9).unwrap_err();
    assert!(err.message.contains("beyond stopTime"), "{}", err.message);
}

/// The bytes of `inst`'s state with the JSON field at `path` replaced by the JSON text `value`
/// and a fresh checksum: a buffer that passes every framing check.
fn crafted(inst: &mut Plate, path: &[&str], value: &str) -> Vec<u8> {
    let state = inst.get_state().unwrap();
    let bytes = inst
        .serialized(Function::SerializeFMUstate, &state)
        .unwrap();
    let original = serialized::decode_json(bytes).unwrap();
    let mut tree = original.clone();
    let mut slot = &mut tree;
    for part in path {
        slot = match part.parse::<usize>() {
            Ok(i) => &mut slot[i],
            Err(_) => &mut slot[*part],
        };
    }
    *slot = serde_json::Value::String("@raw@".into());
    let text = serde_json::to_string(&tree)
        .unwrap()
        .replace("\"@raw@\"", value);
    assert_ne!(
        text,
        serde_json::to_string(&original).unwrap(),
        "{path:?} changed nothing"
    );
    serialized::encode_payload(text.as_bytes())
}

/// Regression: a crafted FMU state with a matching checksum was accepted.
///
/// Long (~105 lines) because most of it is the table of crafted fields, one row per check of
/// the snapshot validation, with the words each refusal must contain.
#[test]
fn crafted_fmu_states_are_refused_naming_the_field() {
    let (mut inst, _) = initialized();
    for _ in 0..5 {
        let t = inst.time();
        inst.do_step(t, 1e-3).unwrap();
    }
    let cases: Vec<(Vec<&str>, &str, &str)> = vec![
        (vec!["model", "start_time"], "-1e308", "too coarse"),
        (vec!["model", "stop_time"], "1e-4", "beyond stopTime"),
        (
            vec!["model", "parameters", "material", "poisson_ratio"],
            "0.7",
            "material.poisson_ratio",
        ),
        (
            vec!["model", "parameters", "stop_time"],
            "5.0",
            "not FMU variables",
        ),
        (
            vec!["model", "parameters", "load", "pressure"],
            "-1e308",
            "differs from the parameters",
        ),
        (
            vec!["model", "simulation", "stepper", "step_index"],
            "1125899906842624",
            "too coarse",
        ),
        (
            vec!["model", "simulation", "stepper", "step_index"],
            "-9223372036854775809",
            "invalid payload",
        ),
        (
            vec!["model", "simulation", "start_time"],
            "0.5",
            "starts at",
        ),
        (
            vec!["model", "simulation", "input", "last_sample"],
            "[7.0, 0.0]",
            "outside",
        ),
        (
            vec!["model", "simulation", "stepper", "current", "0"],
            "-1e308",
            "current[contact point",
        ),
        (
            vec!["model", "simulation", "point"],
            r#"{"Between":{"elapsed":0.1,"previous":{"corner1":0.0,"corner2":0.0,"edge_mid":0.0,"energy_kinetic":0.0,"energy_elastic":0.0,"energy_total":0.0,"active_nodes":0,"contact_force":0.0,"base_force":0.0,"base_impulse":0.0,"base_work":0.0,"load_work":0.0,"contact_loss":0.0,"damping_loss":0.0}}}"#,
            "not strictly between",
        ),
        (
            vec!["model", "simulation", "step_start"],
            r#"{"elapsed":1e9,"impulse":0.0}"#,
            "last communication step started",
        ),
        (
            vec!["model", "simulation", "contact", "impacts"],
            "1000",
            "1000 impacts",
        ),
        (
            vec!["model", "simulation", "contact_ahead", "peak_force"],
            "5.0",
            "covers no step",
        ),
        (vec!["model", "simulation"], "null", "holds no simulation"),
        (vec!["mode"], "\"StepFailed\"", "never enters"),
        (
            vec!["mode"],
            "\"Instantiated\"",
            "holds a running simulation",
        ),
        (vec!["model", "input_derivatives", "0"], "1e308", ""),
    ];
    let before = observe(&mut inst);
    for (path, value, words) in cases {
        let bytes = crafted(&mut inst, &path, value);
        let outcome = inst
            .deserialize_state(&bytes)
            .and_then(|state| inst.set_state(&state));
        if words.is_empty() {
            // A finite derivative is a legal state: accepted.
            outcome.unwrap();
            let state = inst.deserialize_state(&before.1).unwrap();
            inst.set_state(&state).unwrap();
        } else {
            let err = outcome.expect_err(&format!("{path:?} = {value} accepted"));
            assert!(
                err.message.contains(words),
                "{path:?} = {value}: {}",
                err.message
            );
        }
        assert_eq!(
            observe(&mut inst),
            before,
            "{path:?} = {value} changed the instance"
        );
    }
}

/// Regression: a huge communication step ran for ever; a start time whose grid cannot advance was
/// accepted.
#[test]
fn unbounded_steps_and_frozen_grids_are_refused_at_once() {
    let (mut inst, _) = initialized();
    for h in [1e300, 1e12] {
        let err = inst.do_step(0.0, h).unwrap_err();
        assert!(err.message.contains("internal steps"), "{}", err.message);
    }
    assert_eq!(inst.mode(), Mode::StepComplete);
    let (mut inst, _) = small();
    let err = inst.setup_experiment(-1e308, None).unwrap_err();
    assert!(err.message.contains("startTime"), "{}", err.message);
    // A start time fine for the default Δt but too coarse for a shorter one is refused at the
    // end of initialization.
    inst.setup_experiment(1e8, None).unwrap();
    inst.set_real(&[vr::SOLVER_TIME_STEP], &[1e-7]).unwrap();
    inst.enter_initialization_mode().unwrap();
    let err = inst.exit_initialization_mode().unwrap_err();
    assert!(
        err.message.contains("startTime = 100000000"),
        "{}",
        err.message
    );
}

/// Regression: every set in Initialization mode rebuilt the model, every read recomputed outputs.
#[test]
fn initialization_sets_do_not_rebuild_the_plate() {
    let (mut inst, _) = small();
    inst.enter_initialization_mode().unwrap();
    for k in 0..20 {
        let z = 1e-4 * f64::from(k);
        inst.set_real(
            &[vr::BASE_DISPLACEMENT, vr::LOAD_PRESSURE, vr::OBSTACLE_LOWER],
            &[z, 10.0 * z, -0.01 - z],
        )
        .unwrap();
        assert_eq!(
            real(&mut inst, vr::CORNER1_DISPLACEMENT),
            z,
            "the plate follows its base"
        );
    }
    assert_eq!(inst.model().full_set_ups(), 1);
    inst.exit_initialization_mode().unwrap();
    assert_eq!(inst.model().full_set_ups(), 1);
    // Reset, same fixed parameters: the assembled plate is reused.
    inst.reset().unwrap();
    inst.set_integer(&[vr::MESH_NX, vr::MESH_NY], &[3, 2])
        .unwrap();
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    assert_eq!(inst.model().full_set_ups(), 1);
    // A fixed parameter changed: one new set-up.
    inst.reset().unwrap();
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    assert_eq!(inst.model().full_set_ups(), 2);
}

/// Regression (found by the call-sequence fuzzer): a scene whose set-up is refused was set up
/// again for every value reference a host read, so reading all outputs cost a set-up each.
#[test]
fn a_refused_set_up_is_tried_once_per_scene() {
    let (mut inst, _) = small();
    // Accepted by the parameter checks (thickness > 0), refused by the set-up.
    inst.set_real(&[vr::PLATE_THICKNESS], &[1e-300]).unwrap();
    inst.enter_initialization_mode().unwrap();
    let first = real_result(&mut inst, vr::CORNER1_DISPLACEMENT).unwrap_err();
    for _ in 0..5 {
        let again = real_result(&mut inst, vr::CORNER1_DISPLACEMENT).unwrap_err();
        assert_eq!(again.message, first.message);
    }
    assert_eq!(inst.model().full_set_ups(), 1, "{}", first.message);
    // Another thickness is another scene: tried again, and set up.
    inst.set_real(&[vr::PLATE_THICKNESS], &[0.01]).unwrap();
    real_result(&mut inst, vr::CORNER1_DISPLACEMENT).unwrap();
    assert_eq!(inst.model().full_set_ups(), 2);
}

/// Regression: the input plan used the host's raw h, so ulp jitter of h changed the results.
#[test]
fn ulp_jitter_of_the_step_size_changes_nothing() {
    let run = |jitter: bool| {
        let (mut inst, _) = initialized();
        let mut out = Vec::new();
        for k in 0..200u32 {
            let t = f64::from(k) * 1e-3;
            let h = if jitter {
                f64::from(k + 1) * 1e-3 - t
            } else {
                1e-3
            };
            inst.set_real(&[vr::BASE_DISPLACEMENT], &[2e-3 * (60.0 * t).sin()])
                .unwrap();
            inst.do_step(inst.time(), h).unwrap();
            out.push(real(&mut inst, vr::CORNER1_DISPLACEMENT).to_bits());
        }
        out
    };
    assert_eq!(run(true), run(false));
}

/// Regression: mesh.element was an enumeration that some engines cannot set.
#[test]
fn the_element_is_an_integer_parameter() {
    let (mut inst, _) = small();
    inst.set_integer(&[vr::MESH_ELEMENT], &[2]).unwrap();
    let err = inst.set_integer(&[vr::MESH_ELEMENT], &[3]).unwrap_err();
    assert!(
        err.message.contains("1 = Argyris") && err.message.contains("2 = FVS"),
        "{}",
        err.message
    );
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    let mut code = [0];
    inst.get_integer(&[vr::MESH_ELEMENT], &mut code).unwrap();
    assert_eq!(code, [2]);
}

#[test]
fn state_round_trip_is_bit_identical() {
    let (mut inst, _) = small();
    inst.set_real(&[vr::BASE_AMPLITUDE], &[0.005]).unwrap();
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    for k in 0..20 {
        inst.set_real(&[vr::BASE_DISPLACEMENT], &[1e-3 * (k as f64 * 0.3).sin()])
            .unwrap();
        inst.do_step(inst.time(), 1e-3).unwrap();
    }
    let state = inst.get_state().unwrap();
    let bytes = inst
        .serialized(Function::SerializeFMUstate, &state)
        .unwrap()
        .to_vec();
    let run = |inst: &mut Plate| {
        (0..30)
            .map(|k| {
                inst.set_real(&[vr::BASE_DISPLACEMENT], &[2e-3 * (k as f64 * 0.7).cos()])
                    .unwrap();
                inst.do_step(inst.time(), 1e-3).unwrap();
                real(inst, vr::CORNER1_DISPLACEMENT).to_bits()
            })
            .collect::<Vec<_>>()
    };
    let first = run(&mut inst);
    inst.set_state(&state).unwrap();
    assert_eq!(run(&mut inst), first);
    let (mut fresh, _) = instance();
    let copy = fresh.deserialize_state(&bytes).unwrap();
    fresh.set_state(&copy).unwrap();
    assert_eq!(fresh.mode(), Mode::StepComplete);
    assert_eq!(run(&mut fresh), first);
}

/// A pseudo-random communication step: 1 ms × a factor in [0.2, 1.5].
fn random_h(k: u32) -> f64 {
    1e-3 * (0.2 + 1.3 * (f64::from(k) * 0.618_034).fract())
}

/// Communication steps off the grid: a state saved between two grid points, restored in place
/// or serialized into a fresh instance, repeats the run bit for bit.
#[test]
fn random_steps_round_trip_through_a_serialized_state() {
    let (mut inst, _) = small();
    inst.set_real(&[vr::BASE_AMPLITUDE], &[0.005]).unwrap();
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    let run = |inst: &mut Plate, from: u32| {
        (from..from + 30)
            .map(|k| {
                inst.set_real(
                    &[vr::BASE_DISPLACEMENT],
                    &[1e-3 * (f64::from(k) * 0.3).sin()],
                )
                .unwrap();
                inst.do_step(inst.time(), random_h(k)).unwrap();
                [
                    inst.time(),
                    real(inst, vr::CORNER1_DISPLACEMENT),
                    real(inst, vr::ENERGY_TOTAL),
                ]
                .map(f64::to_bits)
            })
            .collect::<Vec<_>>()
    };
    run(&mut inst, 0);
    let t = inst.time();
    assert!(
        ((t / 1e-4).round() * 1e-4 - t).abs() > 1e-9,
        "t = {t}: the state must be saved between grid points"
    );
    let state = inst.get_state().unwrap();
    let bytes = inst
        .serialized(Function::SerializeFMUstate, &state)
        .unwrap()
        .to_vec();
    let first = run(&mut inst, 30);
    inst.set_state(&state).unwrap();
    assert_eq!(inst.time(), t);
    assert_eq!(run(&mut inst, 30), first);
    let (mut fresh, _) = instance();
    let copy = fresh.deserialize_state(&bytes).unwrap();
    fresh.set_state(&copy).unwrap();
    assert_eq!(run(&mut fresh, 30), first);
}

/// Steps of Δt/2, 3Δt/2 or 1e-9 s: the FMU time is t + h, and whenever it lands on a grid point
/// the outputs are those of whole steps, bit for bit (the built-in sine: the grid does not depend
/// on the communication steps).
#[test]
fn steps_off_the_grid_report_at_t_plus_h() {
    let start = || {
        let (mut inst, _) = small();
        inst.set_real(&[vr::BASE_AMPLITUDE], &[0.005]).unwrap();
        inst.set_real(&[vr::BASE_FREQUENCY], &[35.0]).unwrap();
        inst.enter_initialization_mode().unwrap();
        inst.exit_initialization_mode().unwrap();
        inst
    };
    let mut whole = start();
    let mut grid = vec![real(&mut whole, vr::CORNER1_DISPLACEMENT)];
    for _ in 0..30 {
        whole.do_step(whole.time(), 1e-4).unwrap();
        grid.push(real(&mut whole, vr::CORNER1_DISPLACEMENT));
    }
    for h in [0.5e-4, 1.5e-4] {
        let mut inst = start();
        for k in 1..=20 {
            inst.do_step(inst.time(), h).unwrap();
            let t = inst.time();
            assert!((t - f64::from(k) * h).abs() < 1e-15, "t = {t}");
            let corner = real(&mut inst, vr::CORNER1_DISPLACEMENT);
            let n = t / 1e-4;
            if (n - n.round()).abs() < 1e-9 {
                assert_eq!(
                    corner.to_bits(),
                    grid[n.round() as usize].to_bits(),
                    "t = {t}"
                );
            } else {
                let (a, b) = (grid[n.floor() as usize], grid[n.ceil() as usize]);
                assert!(corner >= a.min(b) && corner <= a.max(b), "t = {t}");
            }
        }
    }
    let mut tiny = start();
    for k in 1..=5 {
        tiny.do_step(tiny.time(), 1e-9).unwrap();
        assert!((tiny.time() - f64::from(k) * 1e-9).abs() < 1e-20);
    }
    // 5e-9 s of a step of 1e-4 s: 5e-5 of the way from t_0 to t_1.
    let corner = real(&mut tiny, vr::CORNER1_DISPLACEMENT);
    let expected = grid[0] + 5e-5 * (grid[1] - grid[0]);
    assert!(
        (corner - expected).abs() <= 1e-15 * grid[1].abs(),
        "{corner} vs {expected}"
    );
    tiny.do_step(tiny.time(), 1e-4 - 5e-9).unwrap();
    assert_eq!(real(&mut tiny, vr::CORNER1_DISPLACEMENT), grid[1]);
}

/// A stop time off the grid (fmpy's `-s 0.99995`): the last step ends on it, the grid may run one
/// internal step beyond it, and no step may end after it.
#[test]
fn a_stop_time_off_the_grid_is_reached() {
    let (mut inst, _) = small();
    inst.setup_experiment(0.0, Some(0.00995)).unwrap();
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    for _ in 0..9 {
        inst.do_step(inst.time(), 1e-3).unwrap();
    }
    inst.do_step(inst.time(), 0.00995 - 0.009).unwrap();
    assert!((inst.time() - 0.00995).abs() < 1e-15);
    let err = inst.do_step(inst.time(), 1e-5).unwrap_err();
    assert!(err.message.contains("stopTime"), "{}", err.message);
    let state = inst.get_state().unwrap();
    inst.set_state(&state).unwrap();
}

/// The Rayleigh damping parameters reach the scheme: the FMU's run equals the library's for the
/// same damped scene, bit for bit, and differs from the undamped one; a negative value is refused
/// by name.
#[test]
fn damping_parameters_reach_the_scheme() {
    use crate::scene::Scene;
    let (mut inst, _) = small();
    let err = inst
        .set_real(&[vr::DAMPING_MASS_PROPORTIONAL], &[-1.0])
        .unwrap_err();
    assert!(
        err.message.contains("damping.mass_proportional"),
        "{}",
        err.message
    );
    inst.set_real(
        &[
            vr::DAMPING_MASS_PROPORTIONAL,
            vr::DAMPING_STIFFNESS_PROPORTIONAL,
            vr::BASE_AMPLITUDE,
        ],
        &[6.0, 2e-5, 0.005],
    )
    .unwrap();
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    let mut scene = Scene::default();
    scene.mesh.nx = 3;
    scene.mesh.ny = 2;
    scene.base.amplitude = 0.005;
    let undamped = library_outputs(&scene, 50);
    scene.damping.mass_proportional = 6.0;
    scene.damping.stiffness_proportional = 2e-5;
    let library = library_outputs(&scene, 50);
    for _ in 0..50 {
        inst.do_step(inst.time(), 1e-3).unwrap();
    }
    let corner = real(&mut inst, vr::CORNER1_DISPLACEMENT);
    assert_eq!(corner.to_bits(), library.corner1.to_bits());
    assert_ne!(corner, undamped.corner1);
}

/// The engineers' damping parameters: the `damping.ratio` pair reaches the scheme (the FMU's run
/// equals the library's, bit for bit), its α and β are readable as calculated parameters and equal
/// the pair's formula, and setting it with a non-zero α is refused at the end of initialization
/// naming both parameters.
#[test]
fn the_damping_ratio_pair_reaches_the_scheme_and_its_coefficients_are_readable() {
    use crate::scene::Scene;
    let (mut inst, _) = small();
    // The ratio first: the frequencies it needs come later, in the same initialization.
    inst.set_real(
        &[
            vr::DAMPING_RATIO,
            vr::DAMPING_FREQUENCY_LOW,
            vr::DAMPING_FREQUENCY_HIGH,
            vr::BASE_AMPLITUDE,
        ],
        &[0.01, 53.83, 5000.0, 0.005],
    )
    .unwrap();
    inst.enter_initialization_mode().unwrap();
    let (w1, w2) = (
        2.0 * std::f64::consts::PI * 53.83,
        2.0 * std::f64::consts::PI * 5000.0,
    );
    let (alpha, beta) = (
        real(&mut inst, vr::DAMPING_ALPHA),
        real(&mut inst, vr::DAMPING_BETA),
    );
    assert!((alpha / (2.0 * 0.01 * w1 * w2 / (w1 + w2)) - 1.0).abs() < 1e-14);
    assert!((beta / (2.0 * 0.01 / (w1 + w2)) - 1.0).abs() < 1e-14);
    for w in [w1, w2] {
        assert!((alpha / (2.0 * w) + beta * w / 2.0 - 0.01).abs() < 1e-15);
    }
    let err = inst.set_real(&[vr::DAMPING_ALPHA], &[1.0]).unwrap_err();
    assert!(err.message.contains("damping.alpha"), "{}", err.message);
    inst.exit_initialization_mode().unwrap();
    let mut scene = Scene::default();
    (scene.mesh.nx, scene.mesh.ny) = (3, 2);
    scene.base.amplitude = 0.005;
    scene.damping.mass_proportional = alpha;
    scene.damping.stiffness_proportional = beta;
    let library = library_outputs(&scene, 50);
    for _ in 0..50 {
        inst.do_step(inst.time(), 1e-3).unwrap();
    }
    let corner = real(&mut inst, vr::CORNER1_DISPLACEMENT);
    assert_eq!(corner.to_bits(), library.corner1.to_bits());
    let loss = real(&mut inst, vr::ENERGY_DAMPING_LOSS);
    assert!(loss > 0.0 && loss == library.damping_loss);

    let (mut inst, messages) = small();
    inst.set_real(
        &[
            vr::DAMPING_RATIO,
            vr::DAMPING_FREQUENCY_LOW,
            vr::DAMPING_FREQUENCY_HIGH,
            vr::DAMPING_MASS_PROPORTIONAL,
        ],
        &[0.01, 50.0, 5000.0, 3.0],
    )
    .unwrap();
    inst.enter_initialization_mode().unwrap();
    let err = real_result(&mut inst, vr::DAMPING_BETA).unwrap_err();
    assert!(
        err.message.contains("damping.mass_proportional"),
        "{}",
        err.message
    );
    let err = inst.exit_initialization_mode().unwrap_err();
    for name in ["damping.ratio", "damping.mass_proportional"] {
        assert!(err.message.contains(name), "{}", err.message);
    }
    let status = inst.finish(Function::ExitInitializationMode, Err(err));
    assert_eq!(status, Status::Error);
    assert!(messages
        .lock()
        .unwrap()
        .iter()
        .any(|(_, c, m)| c == LOG_ERROR
            && m.contains("damping.ratio")
            && m.contains("damping.mass_proportional")));
}

/// The library's outputs after `steps` communication steps of 1 ms of `scene` from t = 0 with no
/// external base displacement: what an FMU instance of the same scene, stepped alike, must give
/// bit for bit.
fn library_outputs(scene: &crate::scene::Scene, steps: usize) -> Outputs {
    let mut library = Simulation::new(scene, 0.0, 0.0).unwrap();
    for _ in 0..steps {
        let end = library.step_end(1e-3).unwrap();
        library
            .advance(&end, &InputSample::default(), false, &mut |_| {})
            .unwrap();
    }
    library.outputs().clone()
}

/// The Real variable `vr` of `inst`, or the refusal.
fn real_result(inst: &mut Plate, vr: u32) -> Result<f64, Failure> {
    let mut x = [0.0];
    inst.get_real(&[vr], &mut x).map(|()| x[0])
}

/// A modal damping ratio reaches the modal backend (the FMU's run equals the library's, bit for
/// bit, and damps more than without it); it has no effect on α and β.
#[test]
fn the_modal_ratio_reaches_the_scheme() {
    use crate::scene::Scene;
    let (mut inst, _) = small();
    inst.set_real(
        &[vr::DAMPING_MODAL_RATIO, vr::BASE_AMPLITUDE],
        &[0.02, 0.005],
    )
    .unwrap();
    inst.enter_initialization_mode().unwrap();
    assert_eq!(real(&mut inst, vr::DAMPING_ALPHA), 0.0);
    inst.exit_initialization_mode().unwrap();
    let mut scene = Scene::default();
    (scene.mesh.nx, scene.mesh.ny) = (3, 2);
    scene.base.amplitude = 0.005;
    scene.damping.modal_ratio = 0.02;
    let library = library_outputs(&scene, 50);
    for _ in 0..50 {
        inst.do_step(inst.time(), 1e-3).unwrap();
    }
    let corner = real(&mut inst, vr::CORNER1_DISPLACEMENT);
    assert_eq!(corner.to_bits(), library.corner1.to_bits());
    assert!(real(&mut inst, vr::ENERGY_DAMPING_LOSS) > 0.0);
}

/// The warning at the end of initialization (docs/accuracy/damping.md): the paper's forced scene
/// (undamped, obstacles) warns, naming the documentation section, in a message of status Warning
/// while the call returns fmi2OK (strict importers stop at a returned Warning); the damped
/// preset `forced-35hz-damped` (β = 2ζ₁/ω₁, ζ₁ = 1 %, Δt = 1e-4 s) and a plate without obstacles
/// do not. The warning changes no result: the warned run equals the library's bit for bit.
#[test]
fn unconverged_statistics_settings_warn_at_initialization() {
    use crate::advice::DOCS_SECTION;
    use crate::scene::Scene;
    let run = |scene: &Scene| {
        let (mut inst, messages) = instance();
        let mut reals = Vec::new();
        let mut values = Vec::new();
        for v in FMI2
            .variables
            .iter()
            .filter(|v| v.causality == Causality::Parameter)
        {
            match v.kind {
                Kind::Real => {
                    reals.push(v.vr);
                    values.push(scene.get(v.name).unwrap().as_f64().unwrap());
                }
                Kind::Integer if v.vr == vr::MESH_ELEMENT => {}
                Kind::Integer => inst
                    .set_integer(
                        &[v.vr],
                        &[scene.get(v.name).unwrap().as_i64().unwrap() as i32],
                    )
                    .unwrap(),
                Kind::Boolean => inst
                    .set_boolean(&[v.vr], &[scene.get(v.name).unwrap().as_bool().unwrap()])
                    .unwrap(),
                Kind::String => inst
                    .set_string(&[v.vr], &[scene.get(v.name).unwrap().as_str().unwrap()])
                    .unwrap(),
                _ => unreachable!(),
            }
        }
        inst.set_real(&reals, &values).unwrap();
        inst.enter_initialization_mode().unwrap();
        let status = inst.exit_initialization_mode().unwrap();
        let status = inst.finish(Function::ExitInitializationMode, Ok(status));
        let warnings: Vec<String> = messages
            .lock()
            .unwrap()
            .iter()
            .filter(|(s, c, _)| *s == Status::Warning && c == "logStatusWarning")
            .map(|(_, _, m)| m.clone())
            .collect();
        (inst, status, warnings)
    };
    let mut forced = Scene::named("forced-35hz").unwrap();
    (forced.mesh.nx, forced.mesh.ny) = (3, 2);
    let (mut inst, status, warnings) = run(&forced);
    assert_eq!(status, Status::Ok);
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0].contains(DOCS_SECTION), "{}", warnings[0]);
    let library = library_outputs(&forced, 100);
    for _ in 0..100 {
        assert_eq!(inst.do_step(inst.time(), 1e-3).unwrap(), Status::Ok);
    }
    for (r, expected) in [
        (vr::CORNER1_DISPLACEMENT, library.corner1),
        (vr::ENERGY_TOTAL, library.energy_total),
        (vr::ENERGY_CONTACT_LOSS, library.contact_loss),
    ] {
        assert_eq!(real(&mut inst, r).to_bits(), expected.to_bits());
    }
    assert!(library.contact_loss > 0.0, "the run impacts");

    let mut damped = Scene::named("forced-35hz-damped").unwrap();
    (damped.mesh.nx, damped.mesh.ny) = (3, 2);
    let (_, status, warnings) = run(&damped);
    assert_eq!((status, warnings.len()), (Status::Ok, 0), "{warnings:?}");
    forced.obstacle.lower_enabled = false;
    forced.obstacle.upper_enabled = false;
    let (_, status, warnings) = run(&forced);
    assert_eq!((status, warnings.len()), (Status::Ok, 0), "{warnings:?}");
}

/// fmpy asks for the size, then for the bytes: the state is encoded once.
#[test]
fn a_state_is_encoded_once_per_save() {
    let (mut inst, _) = initialized();
    let state = inst.get_state().unwrap();
    let size = inst
        .serialized(Function::SerializedFMUstateSize, &state)
        .unwrap();
    let bytes = inst
        .serialized(Function::SerializeFMUstate, &state)
        .unwrap();
    assert!(
        std::ptr::eq(size, bytes),
        "the second call re-encoded the state"
    );
    let again = inst.get_state().unwrap();
    let fresh = inst
        .serialized(Function::SerializeFMUstate, &again)
        .unwrap();
    assert_eq!(fresh, bytes, "encoding is deterministic");
}

#[test]
fn base_outside_the_gap_is_an_error_then_reset_recovers() {
    let (mut inst, messages) = initialized();
    inst.set_real(&[vr::BASE_DISPLACEMENT], &[0.02]).unwrap();
    let result = inst.do_step(0.0, 1e-3);
    assert_eq!(inst.finish(Function::DoStep, result), Status::Error);
    assert_eq!(inst.mode(), Mode::Error);
    assert!(messages
        .lock()
        .unwrap()
        .iter()
        .any(|(s, c, m)| *s == Status::Error && c == LOG_ERROR && m.contains("base displacement")));
    assert!(inst.do_step(inst.time(), 1e-3).is_err());
    inst.reset().unwrap();
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    inst.do_step(0.0, 1e-3).unwrap();
}

#[test]
fn derivatives_sent_during_initialization_reach_the_first_step() {
    let first_corner = |during_initialization: bool, send: bool| {
        let (mut inst, _) = small();
        inst.enter_initialization_mode().unwrap();
        let derivative = |inst: &mut Plate| {
            inst.set_real_input_derivatives(&[vr::BASE_DISPLACEMENT], &[1], &[0.5])
                .unwrap()
        };
        if send && during_initialization {
            derivative(&mut inst);
        }
        inst.exit_initialization_mode().unwrap();
        if send && !during_initialization {
            derivative(&mut inst);
        }
        inst.do_step(0.0, 1e-3).unwrap();
        real(&mut inst, vr::CORNER1_DISPLACEMENT).to_bits()
    };
    assert_eq!(first_corner(true, true), first_corner(false, true));
    assert_ne!(first_corner(true, true), first_corner(true, false));
}

#[test]
fn logging_categories() {
    let (mut inst, messages) = initialized();
    assert!(inst.set_debug_logging(true, &["logNothing"]).is_err());
    inst.set_debug_logging(true, &[LOG_CONTACT]).unwrap();
    inst.set_real(&[vr::LOAD_PRESSURE], &[2e5]).unwrap();
    for _ in 0..200 {
        let result = inst.do_step(inst.time(), 1e-3);
        assert_eq!(inst.finish(Function::DoStep, result), Status::Ok);
    }
    let log = messages.lock().unwrap();
    assert!(
        log.iter().any(|(_, c, _)| c == LOG_CONTACT),
        "no contact event logged"
    );
    assert!(!log.iter().any(|(_, c, _)| c == LOG_ALL));
}
