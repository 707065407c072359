//! The exported C functions, called as a host would call them: null pointers and garbage, then
//! random FMI 2.0 call sequences:
//! good and bad values, calls in every state, FMU states saved, serialized, corrupted and
//! restored. Oracles, after every call:
//! * no crash and no hang (small meshes, at most a few hundred internal steps per call);
//! * after fmi2OK, every output readable is finite, the free corners (obstacle-constrained
//!   vertices) lie within the obstacles to 1e-7 of the gap (e = 0), energies are ≥ 0;
//! * a call answered fmi2Error either changed nothing the host can observe (every variable value
//!   with its status, the call state, the serialized FMU state), or was a failed fmi2DoStep that
//!   put the instance in the Error state.
//!
//! `PROPTEST_CASES=1000 cargo test --release --test fmi_c_api` runs a longer search.

use plate_impact::fmi::fmi2::exports::*;
use plate_impact::fmi::variables::{vr, Kind, FMI2};
use proptest::prelude::*;
use std::ffi::CString;

const OK: fmi2Status = 0;
const WARNING: fmi2Status = 1;
const ERROR: fmi2Status = 3;

#[derive(Clone, Debug)]
enum Op {
    SetupExperiment(f64, Option<f64>),
    EnterInitialization,
    ExitInitialization,
    Terminate,
    Reset,
    SetReal(Vec<(u32, f64)>),
    SetInteger(Vec<(u32, i32)>),
    SetBoolean(Vec<(u32, bool)>),
    /// k internal steps of the current Δt, optionally off the grid or with a wrong time.
    DoStep(f64, bool),
    Derivative(i32, f64),
    SaveState(usize),
    RestoreState(usize),
    SerializeRoundTrip(usize),
    CorruptState(usize, usize, u8),
    Logging(bool, bool),
}

const REALS: &[f64] = &[
    0.0,
    1e-3,
    -1e-3,
    0.005,
    -0.004,
    0.02,
    -0.02,
    0.3,
    0.5,
    1e-4,
    5e-5,
    1e5,
    -2e5,
    1e308,
    -1e308,
    2.1e11,
    7770.0,
    35.0,
    f64::NAN,
    f64::INFINITY,
];
const INTEGERS: &[i32] = &[1, 2, 3, 0, -1, 401];

fn vrs_of(kind: Kind) -> Vec<u32> {
    let mut v: Vec<u32> = FMI2
        .variables
        .iter()
        .filter(|v| v.kind == kind)
        .map(|v| v.vr)
        .collect();
    v.push(9999); // not a value reference
    v
}

fn op() -> impl Strategy<Value = Op> {
    let real = prop::sample::select(vrs_of(Kind::Real));
    let integer = prop::sample::select(vrs_of(Kind::Integer));
    let boolean = prop::sample::select(vrs_of(Kind::Boolean));
    let time = prop::sample::select(vec![0.0, 0.5, -2.0, 1e9, -1e308, f64::NAN]);
    // Weighted towards the calls that make a run go on, so that sequences get deep into stepping.
    prop_oneof![
        1 => (time.clone(), prop::option::of(time)).prop_map(|(a, b)| Op::SetupExperiment(a, b)),
        2 => Just(Op::EnterInitialization),
        2 => Just(Op::ExitInitialization),
        1 => Just(Op::Terminate),
        1 => Just(Op::Reset),
        4 => prop::collection::vec((real, prop::sample::select(REALS)), 1..4).prop_map(Op::SetReal),
        1 => prop::collection::vec((integer, prop::sample::select(INTEGERS)), 1..3)
            .prop_map(Op::SetInteger),
        1 => prop::collection::vec((boolean, any::<bool>()), 1..3).prop_map(Op::SetBoolean),
        8 => (
            prop::sample::select(vec![1.0, 3.0, 10.0, 30.0, 0.5, 1.5, -1.0, 1e300]),
            prop::bool::weighted(0.1)
        )
            .prop_map(|(k, wrong)| Op::DoStep(k, wrong)),
        1 => (0..4i32, prop::sample::select(REALS)).prop_map(|(o, x)| Op::Derivative(o, x)),
        2 => (0..3usize).prop_map(Op::SaveState),
        2 => (0..3usize).prop_map(Op::RestoreState),
        1 => (0..3usize).prop_map(Op::SerializeRoundTrip),
        1 => (0..3usize, any::<usize>(), 1..=255u8).prop_map(|(s, at, x)| Op::CorruptState(s, at, x)),
        1 => (any::<bool>(), any::<bool>()).prop_map(|(on, bad)| Op::Logging(on, bad)),
    ]
}

/// One instance and the FMU states the host keeps for it.
struct Host {
    c: fmi2Component,
    states: [fmi2FMUstate; 3],
}

impl Drop for Host {
    fn drop(&mut self) {
        // SAFETY: the states and the instance were created by the library and are freed once.
        unsafe {
            for s in &mut self.states {
                fmi2FreeFMUstate(self.c, s);
            }
            fmi2FreeInstance(self.c);
        }
    }
}

/// Everything the host can observe without changing anything.
#[derive(Debug, PartialEq)]
struct Observation {
    /// Status of an empty set, an empty get and fmi2GetRealStatus: together they tell the state.
    probe: [fmi2Status; 3],
    values: Vec<(fmi2Status, u64)>,
    state: Option<Vec<u8>>,
}

impl Host {
    fn new() -> Host {
        let callbacks = fmi2CallbackFunctions {
            logger: None,
            allocate_memory: None,
            free_memory: None,
            step_finished: None,
            component_environment: std::ptr::null_mut(),
        };
        let name = CString::new("random").unwrap();
        let guid = CString::new(FMI2.token).unwrap();
        // SAFETY: valid strings and callbacks for the call.
        let c = unsafe {
            fmi2Instantiate(
                name.as_ptr(),
                1,
                guid.as_ptr(),
                std::ptr::null(),
                &callbacks,
                0,
                0,
            )
        };
        assert!(!c.is_null());
        let host = Host {
            c,
            states: [std::ptr::null_mut(); 3],
        };
        host.small_mesh();
        host
    }

    /// A 3 × 2 mesh keeps every set-up to a millisecond (random values cannot grow it: the
    /// integers drawn are at most 3 or refused).
    fn small_mesh(&self) {
        let refs = [vr::MESH_NX, vr::MESH_NY];
        // SAFETY: arrays of two elements.
        assert_eq!(
            unsafe { fmi2SetInteger(self.c, refs.as_ptr(), 2, [3, 2].as_ptr()) },
            OK
        );
    }

    fn time_step(&self) -> f64 {
        let mut x = 1e-4;
        // SAFETY: one value reference, one value.
        unsafe { fmi2GetReal(self.c, &vr::SOLVER_TIME_STEP, 1, &mut x) };
        x
    }

    fn time(&self) -> f64 {
        let mut t = 0.0;
        // SAFETY: a valid pointer to an fmi2Real.
        unsafe { fmi2GetRealStatus(self.c, 2, &mut t) };
        t
    }

    fn serialize(&self, state: fmi2FMUstate) -> Option<Vec<u8>> {
        let mut size = 0;
        // SAFETY: `state` is null or a live state of this instance; the buffer has `size` bytes.
        unsafe {
            if fmi2SerializedFMUstateSize(self.c, state, &mut size) != OK {
                return None;
            }
            let mut bytes = vec![0 as fmi2Byte; size];
            assert_eq!(
                fmi2SerializeFMUstate(self.c, state, bytes.as_mut_ptr(), size),
                OK
            );
            Some(bytes.iter().map(|&b| b as u8).collect())
        }
    }

    fn observe(&self) -> Observation {
        let c = self.c;
        let mut values = Vec::new();
        // SAFETY: every array passed has the length passed with it; empty calls pass null.
        unsafe {
            let mut t = 0.0;
            let probe = [
                fmi2SetReal(c, std::ptr::null(), 0, std::ptr::null()),
                fmi2GetReal(c, std::ptr::null(), 0, std::ptr::null_mut()),
                fmi2GetRealStatus(c, 2, &mut t),
            ];
            for v in FMI2.variables {
                let (status, bits) = match v.kind {
                    Kind::Real => {
                        let mut x = 0.0;
                        (fmi2GetReal(c, &v.vr, 1, &mut x), x.to_bits())
                    }
                    Kind::Integer | Kind::Enumeration => {
                        let mut i = 0;
                        (fmi2GetInteger(c, &v.vr, 1, &mut i), i as u64)
                    }
                    Kind::Boolean => {
                        let mut b = 0;
                        (fmi2GetBoolean(c, &v.vr, 1, &mut b), b as u64)
                    }
                    Kind::String | Kind::UInt64 => unreachable!("not in FMI 2.0"),
                };
                values.push((status, if status == OK { bits } else { 0 }));
            }
            let mut s: fmi2FMUstate = std::ptr::null_mut();
            let state = if fmi2GetFMUstate(c, &mut s) == OK {
                let bytes = self.serialize(s);
                fmi2FreeFMUstate(c, &mut s);
                bytes
            } else {
                None
            };
            Observation {
                probe,
                values,
                state,
            }
        }
    }

    /// Takes the FMU state and sets it again: the status of fmi2SetFMUstate, or None when no
    /// state can be taken.
    fn restore_own_state(&self) -> Option<fmi2Status> {
        let c = self.c;
        let mut s: fmi2FMUstate = std::ptr::null_mut();
        // SAFETY: `s` is null or a live state of this instance, freed once.
        unsafe {
            if fmi2GetFMUstate(c, &mut s) != OK {
                return None;
            }
            let status = fmi2SetFMUstate(c, s);
            fmi2FreeFMUstate(c, &mut s);
            Some(status)
        }
    }

    /// Runs one operation; returns its status.
    fn run(&mut self, op: &Op) -> fmi2Status {
        let c = self.c;
        // SAFETY: every array passed has the length passed with it; states are live or null.
        unsafe {
            match op {
                Op::SetupExperiment(start, stop) => fmi2SetupExperiment(
                    c,
                    0,
                    0.0,
                    *start,
                    i32::from(stop.is_some()),
                    stop.unwrap_or(0.0),
                ),
                Op::EnterInitialization => fmi2EnterInitializationMode(c),
                Op::ExitInitialization => fmi2ExitInitializationMode(c),
                Op::Terminate => fmi2Terminate(c),
                Op::Reset => {
                    let status = fmi2Reset(c);
                    if status == OK {
                        self.small_mesh();
                    }
                    status
                }
                Op::SetReal(items) => {
                    let (r, v): (Vec<u32>, Vec<f64>) = items.iter().copied().unzip();
                    fmi2SetReal(c, r.as_ptr(), r.len(), v.as_ptr())
                }
                Op::SetInteger(items) => {
                    let (r, v): (Vec<u32>, Vec<i32>) = items.iter().copied().unzip();
                    fmi2SetInteger(c, r.as_ptr(), r.len(), v.as_ptr())
                }
                Op::SetBoolean(items) => {
                    let r: Vec<u32> = items.iter().map(|x| x.0).collect();
                    let v: Vec<i32> = items.iter().map(|x| i32::from(x.1)).collect();
                    fmi2SetBoolean(c, r.as_ptr(), r.len(), v.as_ptr())
                }
                Op::DoStep(k, wrong_time) => {
                    let t = self.time() + if *wrong_time { 0.25 } else { 0.0 };
                    fmi2DoStep(c, t, k * self.time_step(), 1)
                }
                Op::Derivative(order, x) => {
                    fmi2SetRealInputDerivatives(c, &vr::BASE_DISPLACEMENT, 1, order, x)
                }
                Op::SaveState(i) => fmi2GetFMUstate(c, &mut self.states[*i]),
                Op::RestoreState(i) => fmi2SetFMUstate(c, self.states[*i]),
                Op::SerializeRoundTrip(i) => match self.serialize(self.states[*i]) {
                    Some(bytes) => fmi2DeSerializeFMUstate(
                        c,
                        bytes.as_ptr() as *const fmi2Byte,
                        bytes.len(),
                        &mut self.states[*i],
                    ),
                    None => ERROR,
                },
                Op::CorruptState(i, at, x) => match self.serialize(self.states[*i]) {
                    Some(mut bytes) => {
                        let n = bytes.len();
                        bytes[at % n] ^= x;
                        let mut s: fmi2FMUstate = std::ptr::null_mut();
                        let status = fmi2DeSerializeFMUstate(
                            c,
                            bytes.as_ptr() as *const fmi2Byte,
                            n,
                            &mut s,
                        );
                        assert!(s.is_null() || status == OK);
                        fmi2FreeFMUstate(c, &mut s);
                        status
                    }
                    None => ERROR,
                },
                Op::Logging(on, bad) => {
                    let names = [
                        CString::new("logContact").unwrap(),
                        CString::new(if *bad { "logNothing" } else { "logAll" }).unwrap(),
                    ];
                    let pointers: Vec<fmi2String> = names.iter().map(|n| n.as_ptr()).collect();
                    fmi2SetDebugLogging(c, i32::from(*on), 2, pointers.as_ptr())
                }
            }
        }
    }
}

/// The physical oracle on the outputs after an fmi2OK.
fn outputs_are_sound(
    obs: &Observation,
    bounds: (Option<f64>, Option<f64>, f64),
) -> Result<(), String> {
    let value = |name: &str| {
        let i = FMI2.variables.iter().position(|v| v.name == name).unwrap();
        let (status, bits) = obs.values[i];
        (status == OK).then(|| f64::from_bits(bits))
    };
    for v in FMI2.variables.iter().filter(|v| v.kind == Kind::Real) {
        if let Some(x) = value(v.name) {
            if !x.is_finite() {
                return Err(format!("{} = {x} reported with fmi2OK", v.name));
            }
        }
    }
    let (lower, upper, restitution) = bounds;
    if restitution == 0.0 {
        for name in ["corner1.displacement", "corner2.displacement"] {
            if let Some(u) = value(name) {
                // 1e-7 of the gap: the static preload problem is solved by clarabel alone (the
                // dynamic steps are exact to round-off); with a plate of E = 1e-4 Pa its answer
                // lies up to 9e-9 of the gap past an obstacle.
                let gap = upper.unwrap_or(1.0) - lower.unwrap_or(-1.0);
                let tol = 1e-7 * gap;
                if lower.is_some_and(|g| u < g - tol) || upper.is_some_and(|g| u > g + tol) {
                    return Err(format!("{name} = {u} outside {bounds:?}"));
                }
            }
        }
    }
    for name in ["energy.kinetic", "energy.elastic"] {
        if let Some(e) = value(name) {
            if e < 0.0 {
                return Err(format!("{name} = {e} < 0"));
            }
        }
    }
    Ok(())
}

/// The obstacle levels and restitution in force, read back through the API.
fn bounds(host: &Host) -> (Option<f64>, Option<f64>, f64) {
    let c = host.c;
    let (mut lower, mut upper, mut e) = (0.0, 0.0, 0.0);
    let (mut lower_on, mut upper_on) = (0, 0);
    // SAFETY: one value reference and one value per call.
    unsafe {
        fmi2GetReal(c, &vr::OBSTACLE_LOWER, 1, &mut lower);
        fmi2GetReal(c, &vr::OBSTACLE_UPPER, 1, &mut upper);
        fmi2GetReal(c, &vr::SOLVER_RESTITUTION, 1, &mut e);
        fmi2GetBoolean(c, &vr::OBSTACLE_LOWER_ENABLED, 1, &mut lower_on);
        fmi2GetBoolean(c, &vr::OBSTACLE_UPPER_ENABLED, 1, &mut upper_on);
    }
    (
        (lower_on != 0).then_some(lower),
        (upper_on != 0).then_some(upper),
        e,
    )
}

const ERROR_STATE: [fmi2Status; 3] = [ERROR, OK, ERROR];

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 256,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn random_call_sequences_keep_the_oracles(
        initialized in any::<bool>(),
        ops in prop::collection::vec(op(), 1..40),
    ) {
        let mut host = Host::new();
        // Half the sequences start from a running simulation, where most of the state lives.
        let start = [Op::SetupExperiment(0.0, None), Op::EnterInitialization, Op::ExitInitialization];
        let prefix = if initialized { &start[..] } else { &[] };
        let mut steps = 0;
        for (i, op) in prefix.iter().chain(&ops).enumerate() {
            let before = host.observe();
            let status = host.run(op);
            let after = host.observe();
            let context = format!("call {i}: {op:?} -> {status}");
            // Every state the FMU gives can be set again, and setting it changes nothing.
            if let Some(restored) = host.restore_own_state() {
                prop_assert_eq!(restored, OK, "{}: its own FMU state was refused", context);
                prop_assert_eq!(&host.observe(), &after, "{}: setting its own FMU state", context);
            }
            steps += usize::from(matches!(op, Op::DoStep(..)) && status == OK);
            match status {
                OK | 1 => outputs_are_sound(&after, bounds(&host))
                    .map_err(|e| TestCaseError::fail(format!("{context}: {e}")))?,
                ERROR => {
                    let failed_step = matches!(op, Op::DoStep(..)) && after.probe == ERROR_STATE;
                    prop_assert!(failed_step || after == before, "{}: a refused call changed {:?} into {:?}", context, before, after);
                }
                2 => prop_assert_eq!(&after, &before, "{}", context),
                other => prop_assert!(false, "{}: unexpected status {}", context, other),
            }
        }
        if std::env::var_os("CALL_SEQUENCES_VERBOSE").is_some() {
            eprintln!("{} calls, {steps} steps taken", prefix.len() + ops.len());
        }
    }
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
        let host = Host::new();
        let c = host.c;
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), 0);
        assert_eq!(fmi2EnterInitializationMode(c), 0);
        // The default scene has obstacles and no damping of the high modes: its impact statistics
        // may not converge, which the FMU says with a warning (docs/accuracy/damping.md).
        assert_eq!(fmi2ExitInitializationMode(c), WARNING);
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
    }
}
