//! The FMI 3.0 instance driving the plate, through its safe API: the call-state table walked in
//! every state the FMU can be in, the same numbers as FMI 2.0, early return at impacts, the
//! displacement field sized by structural parameters, output derivatives, errors that end in
//! Terminated, and the FMU state.

use super::call_state::{Function, Mode};
use super::instance::{Instance, StoredState};
use crate::fmi::call_state::CallState;
use crate::fmi::fmi2;
use crate::fmi::plate::PlateModel;
use crate::fmi::status::{Failure, Status};
use crate::fmi::test_host::{assert_table_holds, real, recorded_instance, Messages};
use crate::fmi::variables::{vr, Causality, Kind, FMI2};

type Plate = Instance<PlateModel>;

fn instance() -> (Plate, Messages) {
    recorded_instance()
}

/// A 3 × 2 mesh (each set-up about a millisecond), with plate.displacement sized for it.
fn small() -> Plate {
    let (mut inst, _) = instance();
    inst.set_integer(&[vr::MESH_NX, vr::MESH_NY], &[3, 2])
        .unwrap();
    inst.enter_configuration_mode().unwrap();
    inst.set_uint64(&[vr::MESH_VERTEX_ROWS, vr::MESH_VERTEX_COLUMNS], &[3, 4])
        .unwrap();
    inst.exit_configuration_mode().unwrap();
    inst
}

/// `small()` in Step Mode at t = 0, with the base sine of `amplitude` (m) at 35 Hz.
fn stepping(amplitude: f64) -> Plate {
    let mut inst = small();
    inst.set_real(
        &[vr::BASE_AMPLITUDE, vr::BASE_FREQUENCY],
        &[amplitude, 35.0],
    )
    .unwrap();
    inst.begin_initialization(Some((0.0, None))).unwrap();
    inst.exit_initialization_mode().unwrap();
    inst
}

/// An instance in `mode` (one this FMU can be in outside a step).
fn in_mode(mode: Mode) -> Plate {
    let mut inst = small();
    match mode {
        Mode::Instantiated => {}
        Mode::ConfigurationMode => inst.enter_configuration_mode().unwrap(),
        Mode::InitializationMode => inst.begin_initialization(Some((0.0, None))).unwrap(),
        Mode::StepMode | Mode::Terminated => {
            inst.begin_initialization(Some((0.0, None))).unwrap();
            inst.exit_initialization_mode().unwrap();
            if mode == Mode::Terminated {
                inst.terminate().unwrap();
            }
        }
        _ => unreachable!("{mode:?} is not entered outside a step"),
    }
    assert_eq!(inst.mode(), mode);
    inst
}

/// One harmless call of `function`: the instance method the export calls.
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
        EnterInitializationMode => inst.begin_initialization(Some((0.0, None))),
        ExitInitializationMode => inst.exit_initialization_mode().map(|_| ()),
        Terminate => inst.terminate(),
        Reset => inst.reset(),
        GetFloat64 => inst.get_real(&[vr::PLATE_LENGTH], &mut [0.0]),
        GetInt32 => inst.get_integer(&[vr::MESH_NX], &mut [0]),
        GetUInt64 => inst.get_uint64(&[vr::MESH_VERTEX_ROWS], &mut [0]),
        GetBoolean => inst.get_boolean(&[vr::OBSTACLE_LOWER_ENABLED], &mut [false]),
        SetFloat64 => inst.set_real(&[], &[]),
        SetInt32 => inst.set_integer(&[], &[]),
        SetUInt64 => inst.set_uint64(&[], &[]),
        SetBoolean => inst.set_boolean(&[], &[]),
        GetFloat32 | GetInt8 | GetUInt8 | GetInt16 | GetUInt16 | GetUInt32 | GetInt64
        | GetString | GetBinary | GetClock | SetFloat32 | SetInt8 | SetUInt8 | SetInt16
        | SetUInt16 | SetUInt32 | SetInt64 | SetString | SetBinary | SetClock => {
            inst.check_absent_kind(function, &[], &[])
        }
        GetFMUState => inst.get_state().map(|_| ()),
        SetFMUState => inst.set_state(state),
        FreeFMUState => inst.free_state(),
        SerializedFMUStateSize | SerializeFMUState => inst.serialized(function, state).map(|_| ()),
        DeserializeFMUState => inst.deserialize_state(bytes).map(|_| ()),
        EnterConfigurationMode => inst.enter_configuration_mode(),
        ExitConfigurationMode => inst.exit_configuration_mode(),
        GetOutputDerivatives => {
            inst.output_derivatives(&[vr::CORNER1_DISPLACEMENT], &[1], &mut [0.0])
        }
        DoStep => inst.do_step(t, 1e-4, false).map(|_| ()),
        _ => inst.not_provided(function, "not provided"),
    }
}

/// Every function in every state the FMU can be in outside a step: refused as "not allowed"
/// exactly where the table (`call_state.rs`) forbids it, and never for that reason elsewhere.
#[test]
fn the_table_holds_through_the_instance() {
    let modes: Vec<Mode> = Mode::ALL
        .iter()
        .copied()
        .filter(|m| m.reachable() && *m != Mode::IntermediateUpdateMode)
        .collect();
    assert_table_holds(&modes, Function::ALL, in_mode, call);
}

/// Every output, read after the same calls on an FMI 2.0 and an FMI 3.0 instance: the same bits.
/// Early return off, an external input, steps on and off the grid, a tunable set half-way.
#[test]
fn the_same_calls_give_fmi2s_numbers_bit_for_bit() {
    let mut fmi3 = stepping(0.009);
    let mut fmi2 = fmi2::instance::Instance::<PlateModel>::new("two", FMI2.token, false, None)
        .ok()
        .unwrap();
    fmi2.set_integer(&[vr::MESH_NX, vr::MESH_NY], &[3, 2])
        .unwrap();
    fmi2.set_real(&[vr::BASE_AMPLITUDE, vr::BASE_FREQUENCY], &[0.009, 35.0])
        .unwrap();
    fmi2.setup_experiment(0.0, None).unwrap();
    fmi2.enter_initialization_mode().unwrap();
    fmi2.exit_initialization_mode().unwrap();
    let outputs: Vec<u32> = FMI2
        .variables
        .iter()
        .filter(|v| v.causality == Causality::Output && v.kind == Kind::Real)
        .map(|v| v.vr)
        .collect();
    for k in 0..300u32 {
        let h = 1e-4 * (1.0 + f64::from(k % 7) * 0.37);
        let z = [5e-4 * (f64::from(k) * 0.2).sin()];
        if k == 150 {
            fmi3.set_real(&[vr::LOAD_PRESSURE], &[2e4]).unwrap();
            fmi2.set_real(&[vr::LOAD_PRESSURE], &[2e4]).unwrap();
        }
        fmi3.set_real(&[vr::BASE_DISPLACEMENT], &z).unwrap();
        fmi2.set_real(&[vr::BASE_DISPLACEMENT], &z).unwrap();
        let outcome = fmi3.do_step(fmi3.time(), h, false).unwrap();
        assert!(!outcome.early_return);
        fmi2.do_step(fmi2.time(), h).unwrap();
        let (mut a, mut b) = (vec![0.0; outputs.len()], vec![0.0; outputs.len()]);
        fmi3.get_real(&outputs, &mut a).unwrap();
        fmi2.get_real(&outputs, &mut b).unwrap();
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&a), bits(&b), "step {k}");
        assert_eq!(fmi3.time().to_bits(), fmi2.time().to_bits());
    }
}

/// Early return: allowed, fmi3DoStep ends at the grid point of each impact before t + h, and the
/// importer continuing from there with its regular points sees the same trajectory there; not
/// allowed, it never does.
#[test]
fn do_step_returns_early_at_impacts_only_when_allowed() {
    let regular = |allowed: bool| {
        let mut inst = stepping(0.009);
        let (mut points, mut early) = (Vec::new(), 0);
        let mut next = 0;
        while next < 300 {
            next += 1;
            let target = f64::from(next) * 1e-3;
            loop {
                let outcome = inst
                    .do_step(inst.time(), target - inst.time(), allowed)
                    .unwrap();
                if !outcome.early_return {
                    break;
                }
                early += 1;
                let t = inst.time();
                assert!(t < target, "an early return ends before t + h");
                assert_eq!(t, (t / 1e-4).round() * 1e-4, "on the internal grid");
                let mut counts = [0; 2];
                inst.get_integer(
                    &[vr::CONTACT_IMPACTS, vr::CONTACT_ACTIVE_NODES],
                    &mut counts,
                )
                .unwrap();
                assert!(
                    counts[0] >= 1 && counts[1] > 0,
                    "an early return is at an impact: {counts:?}"
                );
            }
            points.push(real(&mut inst, vr::CORNER1_DISPLACEMENT).to_bits());
        }
        (points, early)
    };
    let (with, early) = regular(true);
    let (without, none) = regular(false);
    assert!(early > 3, "only {early} early returns in 0.3 s of impacts");
    assert_eq!(none, 0);
    assert_eq!(with, without, "the same trajectory at the regular points");
}

/// plate.displacement has the shape its structural parameters declare: read with the matching
/// mesh it is every vertex (the free corners are the corner outputs, the clamp column the base);
/// with another mesh it is refused, naming the structural parameters, until they are set in
/// Configuration Mode, and they can be set nowhere else.
#[test]
fn the_field_is_sized_by_its_structural_parameters() {
    let mut inst = stepping(0.004);
    for _ in 0..7 {
        inst.do_step(inst.time(), 2.5e-4, false).unwrap();
    }
    let mut field = vec![0.0; 12];
    inst.get_real(&[vr::PLATE_DISPLACEMENT], &mut field)
        .unwrap();
    let corners = [
        real(&mut inst, vr::CORNER1_DISPLACEMENT),
        real(&mut inst, vr::CORNER2_DISPLACEMENT),
    ];
    // Row-major, 3 rows (y) × 4 columns (x): corner1 (Lx, 0) is [0][3], corner2 (Lx, Ly) [2][3].
    // Two functionals of the same field: equal to round-off of the 4 mm amplitude.
    assert!(
        (field[3] - corners[0]).abs() < 4e-15,
        "{field:?} {corners:?}"
    );
    assert!(
        (field[11] - corners[1]).abs() < 4e-15,
        "{field:?} {corners:?}"
    );
    assert!(
        field[0] == field[4] && field[4] == field[8],
        "the clamp column: {field:?}"
    );
    // A scalar and the array in one call: nValues counts the elements.
    let mut both = vec![0.0; 13];
    inst.get_real(&[vr::TIME, vr::PLATE_DISPLACEMENT], &mut both)
        .unwrap();
    assert_eq!((both[0], &both[1..]), (inst.time(), &field[..]));
    let err = inst
        .get_real(&[vr::PLATE_DISPLACEMENT], &mut [0.0; 11])
        .unwrap_err();
    assert!(err.message.contains("nValues = 11"), "{}", err.message);

    // The default sizes (8 × 11) with a 3 × 2 mesh: refused, naming what to set.
    let (mut inst, _) = instance();
    inst.set_integer(&[vr::MESH_NX, vr::MESH_NY], &[3, 2])
        .unwrap();
    inst.begin_initialization(Some((0.0, None))).unwrap();
    let result = inst.get_real(&[vr::PLATE_DISPLACEMENT], &mut [0.0; 88]);
    let err = result.clone().unwrap_err();
    for words in ["mesh.vertex_rows = 8", "mesh.vertex_columns = 11", "[3, 4]"] {
        assert!(err.message.contains(words), "{words}: {}", err.message);
    }
    let status = inst.finish(Function::GetFloat64, result.map(|()| Status::Ok));
    assert_eq!(status, Status::Error);
    assert_eq!(
        inst.mode(),
        Mode::Terminated,
        "every fmi3Error ends in Terminated"
    );

    // Structural parameters only in Configuration Mode, within their range.
    let (mut inst, _) = instance();
    let err = inst.set_uint64(&[vr::MESH_VERTEX_ROWS], &[3]).unwrap_err();
    assert!(
        err.message.contains("Configuration Mode"),
        "{}",
        err.message
    );
    let (mut inst, _) = instance();
    inst.enter_configuration_mode().unwrap();
    let err = inst.set_real(&[vr::PLATE_LENGTH], &[0.5]).unwrap_err();
    assert!(err.message.contains("plate.length"), "{}", err.message);
    let (mut inst, _) = instance();
    inst.enter_configuration_mode().unwrap();
    let err = inst
        .set_uint64(&[vr::MESH_VERTEX_COLUMNS], &[402])
        .unwrap_err();
    assert!(err.message.contains("[2, 401]"), "{}", err.message);
}

/// d/dt of the displacement outputs (order 1): the slope of the interpolation, so that between
/// grid points extrapolating with it lands on the next grid point; the field's rates match the
/// corners'; other outputs and higher orders are refused.
#[test]
fn output_derivatives_are_the_slope_of_the_interpolation() {
    let mut inst = stepping(0.004);
    let mut at_rest = [1.0; 3];
    inst.output_derivatives(
        &[
            vr::CORNER1_DISPLACEMENT,
            vr::CORNER2_DISPLACEMENT,
            vr::EDGE_MID_DISPLACEMENT,
        ],
        &[1, 1, 1],
        &mut at_rest,
    )
    .unwrap();
    assert_eq!(at_rest, [0.0; 3], "released at rest");
    inst.do_step(0.0, 2.25e-3, false).unwrap();
    let (u, t) = (real(&mut inst, vr::CORNER1_DISPLACEMENT), inst.time());
    let mut rates = vec![0.0; 13];
    inst.output_derivatives(
        &[vr::CORNER1_DISPLACEMENT, vr::PLATE_DISPLACEMENT],
        &[1, 1],
        &mut rates,
    )
    .unwrap();
    // corner1 is entry [0][3] of the field: the same rate to round-off (4e-15 m over 1e-4 s).
    assert!((rates[0] - rates[1 + 3]).abs() < 8e-11, "{rates:?}");
    let ahead = 2.3e-3 - t;
    inst.do_step(t, ahead, false).unwrap();
    let landed = real(&mut inst, vr::CORNER1_DISPLACEMENT);
    assert!(
        (u + rates[0] * ahead - landed).abs() < 4e-15,
        "{u} + {} × {ahead} is not {landed}",
        rates[0]
    );
    for (vrs, orders, words) in [
        (vr::ENERGY_TOTAL, 1, "energy.total has no derivative"),
        (vr::CORNER1_DISPLACEMENT, 2, "order 2"),
    ] {
        let mut inst = stepping(0.004);
        let err = inst
            .output_derivatives(&[vrs], &[orders], &mut [0.0])
            .unwrap_err();
        assert!(err.message.contains(words), "{}", err.message);
    }
}

/// Every fmi3Error ends in Terminated (FMI 3.0 has no Error state), also a refused call, which
/// still changes no value; an FMU state restores the instance, in this or a fresh one, bit for
/// bit, with the structural parameters it was saved with. An FMI 2.0 state is not an FMI 3.0
/// one.
#[test]
fn errors_end_in_terminated_and_an_fmu_state_continues() {
    let mut inst = stepping(0.009);
    for _ in 0..20 {
        inst.do_step(inst.time(), 1e-3, false).unwrap();
    }
    let saved = inst.get_state().unwrap();
    let bytes = inst
        .serialized(Function::SerializeFMUState, &saved)
        .unwrap()
        .to_vec();
    let run = |inst: &mut Plate| -> Vec<u64> {
        (0..30)
            .map(|_| {
                inst.do_step(inst.time(), 1e-3, true).unwrap();
                real(inst, vr::CORNER2_DISPLACEMENT).to_bits()
            })
            .collect()
    };
    let expected = run(&mut inst);
    inst.set_state(&saved).unwrap();
    let before = real(&mut inst, vr::OBSTACLE_LOWER);
    let result = inst.set_real(&[vr::OBSTACLE_LOWER], &[0.5]);
    assert_eq!(
        inst.finish(Function::SetFloat64, result.map(|()| Status::Ok)),
        Status::Error
    );
    assert_eq!(inst.mode(), Mode::Terminated);
    assert_eq!(
        real(&mut inst, vr::OBSTACLE_LOWER),
        before,
        "nothing changed"
    );
    let result = inst.do_step(inst.time(), 1e-3, false);
    assert!(result
        .unwrap_err()
        .message
        .starts_with("not allowed in the Terminated"));
    inst.set_state(&saved).unwrap();
    assert_eq!(inst.mode(), Mode::StepMode);
    assert_eq!(run(&mut inst), expected);

    let (mut fresh, _) = instance();
    let restored = fresh.deserialize_state(&bytes).unwrap();
    fresh.set_state(&restored).unwrap();
    let mut sizes = [0; 2];
    fresh
        .get_uint64(&[vr::MESH_VERTEX_ROWS, vr::MESH_VERTEX_COLUMNS], &mut sizes)
        .unwrap();
    assert_eq!(sizes, [3, 4]);
    assert_eq!(run(&mut fresh), expected);

    let mut fmi2 = fmi2::instance::Instance::<PlateModel>::new("two", FMI2.token, false, None)
        .ok()
        .unwrap();
    let err = fmi2.deserialize_state(&bytes).err().unwrap();
    assert!(err.message.contains("invalid payload"), "{}", err.message);
}

/// An fmi3Error after fmi3Reset ends in Terminated without bringing back the run before the
/// reset (the model keeps its simulation to reuse the assembled plate): the time is the new
/// start time, the outputs are not available, and the FMU state taken there can be set again.
/// Found by the random FMI 3.0 call sequences (`host-check/tests/fmi_c_api.rs`).
#[test]
fn an_error_after_a_reset_does_not_bring_back_the_run_before_it() {
    let mut inst = stepping(0.005);
    for _ in 0..3 {
        inst.do_step(inst.time(), 1e-3, false).unwrap();
    }
    inst.reset().unwrap();
    inst.set_real(&[vr::PLATE_LENGTH], &[0.3]).unwrap();
    let refused = inst.set_real(&[vr::TIME], &[0.0]);
    let status = inst.finish(Function::SetFloat64, refused.map(|()| Status::Ok));
    assert_eq!((status, inst.mode()), (Status::Error, Mode::Terminated));
    assert_eq!(real(&mut inst, vr::TIME), 0.0);
    let output = inst.get_real(&[vr::CORNER1_DISPLACEMENT], &mut [0.0]);
    assert!(output.is_err(), "an output of the run before the reset");
    let state = inst.get_state().unwrap();
    inst.set_state(&state).unwrap();
}

/// An fmi3Error before initialization ends in Terminated with parameters that are each valid
/// but not yet together (here a base amplitude beyond the gap, which initialization would
/// refuse): the FMU state taken there can be set again. Found by the random FMI 3.0 call
/// sequences (`host-check/tests/fmi_c_api.rs`).
#[test]
fn an_fmu_state_taken_after_an_error_before_initialization_can_be_set() {
    let mut inst = small();
    inst.set_real(&[vr::BASE_AMPLITUDE], &[0.02]).unwrap();
    let refused = inst.set_real(&[vr::CORNER1_DISPLACEMENT], &[0.0]);
    let status = inst.finish(Function::SetFloat64, refused.map(|()| Status::Ok));
    assert_eq!((status, inst.mode()), (Status::Error, Mode::Terminated));
    let state = inst.get_state().unwrap();
    inst.set_state(&state).unwrap();
    assert_eq!(real(&mut inst, vr::BASE_AMPLITUDE), 0.02);
}
