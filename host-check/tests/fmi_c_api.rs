//! The exported C functions, called as a host would call them: null pointers and garbage, then
//! random call sequences of both FMI versions: good and bad values, calls in every state, FMU
//! states saved, serialized, corrupted and restored. The host and its oracles are this crate's
//! (shared with the fuzz targets in `fuzz/`), after every call:
//! * no crash and no hang (small meshes, at most a few hundred internal steps per call);
//! * every FMU state taken can be set again, and setting it changes nothing observable;
//! * after OK, every output readable is finite, the free corners (obstacle-constrained
//!   vertices) lie within the obstacles to 1e-7 of the gap (e = 0), energies are ≥ 0;
//! * a call answered Error either changed nothing the host can observe (every variable value
//!   with its status, the call state, the serialized FMU state), or left the instance in the
//!   version's failed state as its rules say (FMI 2.0: a failed fmi2DoStep; FMI 3.0: every
//!   fmi3Error ends in Terminated, with every value as before but for a failed step).
//!
//! `PROPTEST_CASES=1000 cargo test --release -p plate_impact_host_check` runs a longer search.

use plate_impact::fmi::fmi2::exports::*;
use plate_impact::fmi::variables::{vr, Description, Kind, FMI2, FMI3};
use plate_impact_host_check::fmi2::{instantiate, Fmi2Host};
use plate_impact_host_check::fmi3::Fmi3Host;
use plate_impact_host_check::{
    check_call, check_sequence, value_references, Host, Op, INTEGERS, REALS, SIZES, SLOTS, STEPS,
    TEXTS, TIMES,
};
use proptest::prelude::*;

const OK: fmi2Status = 0;
const ERROR: fmi2Status = 3;

/// Calls of version `d`, weighted towards those that make a run go on, so that sequences get
/// deep into stepping.
fn op(d: &'static Description) -> impl Strategy<Value = Op> {
    let real = prop::sample::select(value_references(d, Kind::Real));
    let integer = prop::sample::select(value_references(d, Kind::Integer));
    let uint64 = prop::sample::select(value_references(d, Kind::UInt64));
    let boolean = prop::sample::select(value_references(d, Kind::Boolean));
    let string = prop::sample::select(value_references(d, Kind::String));
    let time = prop::sample::select(TIMES);
    let slot = 0..SLOTS;
    prop_oneof![
        1 => (time.clone(), prop::option::of(time)).prop_map(|(a, b)| Op::SetupExperiment(a, b)),
        2 => Just(Op::EnterInitialization),
        2 => Just(Op::ExitInitialization),
        1 => any::<bool>().prop_map(Op::Configuration),
        1 => Just(Op::Terminate),
        1 => Just(Op::Reset),
        4 => prop::collection::vec((real, prop::sample::select(REALS)), 1..4).prop_map(Op::SetReal),
        1 => prop::collection::vec((integer, prop::sample::select(INTEGERS)), 1..3)
            .prop_map(Op::SetInteger),
        1 => prop::collection::vec((uint64, prop::sample::select(SIZES)), 1..3)
            .prop_map(Op::SetUInt64),
        1 => prop::collection::vec((boolean, any::<bool>()), 1..3).prop_map(Op::SetBoolean),
        1 => prop::collection::vec((string, prop::sample::select(TEXTS)), 1..3).prop_map(|items| {
            Op::SetString(items.into_iter().map(|(r, t)| (r, t.to_string())).collect())
        }),
        8 => (
            prop::sample::select(STEPS),
            prop::bool::weighted(0.1)
        )
            .prop_map(|(k, wrong)| Op::DoStep(k, wrong)),
        1 => (0..4i32, prop::sample::select(REALS)).prop_map(|(o, x)| Op::Derivative(o, x)),
        2 => slot.clone().prop_map(Op::SaveState),
        2 => slot.clone().prop_map(Op::RestoreState),
        1 => slot.clone().prop_map(Op::SerializeRoundTrip),
        1 => (slot, any::<usize>(), 1..=255u8).prop_map(|(s, at, x)| Op::CorruptState(s, at, x)),
        1 => (any::<bool>(), any::<bool>()).prop_map(|(on, bad)| Op::Logging(on, bad)),
    ]
}

/// Runs one sequence (half of them start from a running simulation, where most of the state
/// lives) and fails the case with the oracle's message.
fn run<H: Host>(running: bool, ops: &[Op]) -> Result<(), TestCaseError> {
    let steps = check_sequence::<H>(running, ops).map_err(TestCaseError::fail)?;
    if std::env::var_os("CALL_SEQUENCES_VERBOSE").is_some() {
        eprintln!("{} calls, {steps} steps taken", ops.len());
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 256,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn random_fmi2_call_sequences_keep_the_oracles(
        running in any::<bool>(),
        ops in prop::collection::vec(op(&FMI2), 1..40),
    ) {
        run::<Fmi2Host>(running, &ops)?;
    }

    #[test]
    fn random_fmi3_call_sequences_keep_the_oracles(
        running in any::<bool>(),
        ops in prop::collection::vec(op(&FMI3), 1..40),
    ) {
        run::<Fmi3Host>(running, &ops)?;
    }
}

/// A plate the elements cannot mesh (Lx = 1e300 m: each parameter valid, the Argyris triangles
/// degenerate in floating point) is refused when initialization ends, through the panic that the
/// set-up catches, under every oracle and in both versions. Found by the call-sequence fuzz target,
/// whose harness aborted at that caught panic (it now keeps std's panic hook).
#[test]
fn a_plate_the_elements_cannot_mesh_is_refused_at_initialization() {
    fn statuses<H: Host>() -> Vec<Option<i32>> {
        let mut host = H::new();
        let ops = [
            Op::SetReal(vec![(vr::PLATE_LENGTH, 1e300)]),
            Op::SetupExperiment(0.0, None),
            Op::EnterInitialization,
            Op::ExitInitialization,
        ];
        ops.iter()
            .map(|op| check_call(&mut host, op).unwrap_or_else(|e| panic!("{e}")))
            .collect()
    }
    assert_eq!(
        statuses::<Fmi2Host>(),
        [Some(0), Some(0), Some(0), Some(ERROR)]
    );
    assert_eq!(
        statuses::<Fmi3Host>(),
        [Some(0), None, Some(0), Some(ERROR)]
    );
}

/// An FMI 2.0 instance on a 3 × 2 mesh.
fn instance() -> fmi2Component {
    let c = instantiate("garbage");
    let refs = [vr::MESH_NX, vr::MESH_NY];
    // SAFETY: arrays of two elements.
    assert_eq!(
        unsafe { fmi2SetInteger(c, refs.as_ptr(), 2, [3, 2].as_ptr()) },
        0
    );
    c
}

/// Null pointers and garbage are errors, not crashes.
#[test]
fn null_pointers_and_garbage_are_errors_not_crashes() {
    // SAFETY: every pointer passed is null, dangling-free, or a valid local.
    unsafe {
        assert!(fmi2Instantiate(
            std::ptr::null(),
            1,
            std::ptr::null(),
            std::ptr::null(),
            std::ptr::null(),
            0,
            0
        )
        .is_null());
        assert_eq!(fmi2DoStep(std::ptr::null_mut(), 0.0, 1e-3, 0), ERROR);
        let c = instance();
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), 0);
        assert_eq!(fmi2EnterInitializationMode(c), 0);
        // The default scene has obstacles and no damping of the high modes: its impact statistics
        // may not converge, which the FMU logs as a warning while the call succeeds
        // (docs/accuracy/damping.md, docs/fmu.md).
        assert_eq!(fmi2ExitInitializationMode(c), OK);
        assert_eq!(
            fmi2GetReal(c, std::ptr::null(), 1, std::ptr::null_mut()),
            ERROR
        );
        assert_eq!(fmi2GetReal(c, std::ptr::null(), 0, std::ptr::null_mut()), 0);
        let refs = [vr::CORNER1_DISPLACEMENT];
        let mut out = [f64::NAN];
        assert_eq!(fmi2GetReal(c, refs.as_ptr(), 1, out.as_mut_ptr()), 0);
        assert_eq!(out[0], 0.0);
        assert_eq!(fmi2GetFMUstate(c, std::ptr::null_mut()), ERROR);
        let garbage = [7u8; 64];
        let mut state: fmi2FMUstate = std::ptr::null_mut();
        assert_eq!(
            fmi2DeSerializeFMUstate(c, garbage.as_ptr() as *const fmi2Byte, 64, &mut state),
            ERROR
        );
        assert!(state.is_null());
        assert_eq!(
            fmi2DeSerializeFMUstate(c, std::ptr::null(), 10, &mut state),
            ERROR
        );
        assert_eq!(fmi2GetFMUstate(c, &mut state), 0);
        let mut size: usize = 0;
        assert_eq!(fmi2SerializedFMUstateSize(c, state, &mut size), 0);
        let mut bytes = vec![0 as fmi2Byte; size];
        assert_eq!(
            fmi2SerializeFMUstate(c, state, bytes.as_mut_ptr(), size - 1),
            ERROR
        );
        assert_eq!(fmi2SerializeFMUstate(c, state, bytes.as_mut_ptr(), size), 0);
        let mut copy: fmi2FMUstate = std::ptr::null_mut();
        assert_eq!(
            fmi2DeSerializeFMUstate(c, bytes.as_ptr(), size, &mut copy),
            0
        );
        assert_eq!(fmi2SetFMUstate(c, copy), 0);
        assert_eq!(fmi2SetFMUstate(c, std::ptr::null_mut()), ERROR);
        assert_eq!(fmi2FreeFMUstate(c, &mut state), 0);
        assert_eq!(fmi2FreeFMUstate(c, &mut copy), 0);
        assert!(state.is_null() && copy.is_null());
        assert_eq!(fmi2CancelStep(c), ERROR);
        let mut t = -1.0;
        assert_eq!(fmi2GetRealStatus(c, 2, &mut t), 0);
        assert_eq!(t, 0.0);
        assert_eq!(fmi2DoStep(c, 0.0, 1e-3, 0), 0);
        fmi2FreeInstance(std::ptr::null_mut());
        fmi2FreeInstance(c);
    }
}
