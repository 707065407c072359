//! The FMI 3.0 host: one Co-Simulation instance and its FMU-state slots, through the exported
//! fmi3 functions.
//!
//! FMI 3.0 ends every fmi3Error in Terminated, so the host observes with calls that cannot fail
//! where it believes the instance is: in Configuration Mode (which it tracks: entered and left
//! by its own calls, ended by any error) an empty set only; elsewhere the FMU state, whose
//! serialized payload names the call state, then every variable readable in that state
//! (outputs and calculated parameters from Step Mode on; the displacement field only when its
//! structural sizes match the mesh).

use crate::{text_hash, Host, Observation, Op, StateCalls, ERROR, NOT_READ, OK, SLOTS};
use plate_impact::fmi::fmi3::exports::*;
use plate_impact::fmi::serialized;
use plate_impact::fmi::variables::{vr, Causality, Description, Kind, FMI3};
use std::ffi::{c_char, CString};

/// One FMI 3.0 instance, the FMU states the host keeps for it, and what the host tracks.
pub struct Fmi3Host {
    c: fmi3Instance,
    states: [fmi3FMUState; SLOTS],
    /// Whether the instance is in Configuration Mode (by the host's own calls).
    configuring: bool,
    /// The start and stop times the next fmi3EnterInitializationMode passes.
    experiment: (f64, Option<f64>),
}

impl Drop for Fmi3Host {
    fn drop(&mut self) {
        // SAFETY: the states and the instance were created by the library and are freed once.
        unsafe {
            for s in &mut self.states {
                fmi3FreeFMUState(self.c, s);
            }
            fmi3FreeInstance(self.c);
        }
    }
}

/// The call states a serialized payload names, numbered for the probe.
const MODES: [&str; 4] = [
    "Instantiated",
    "InitializationMode",
    "StepMode",
    "Terminated",
];

impl Fmi3Host {
    /// A 3 × 2 mesh with plate.displacement sized for it (random values cannot grow it: the
    /// integers a caller passes are at most 3 or refused).
    fn small_mesh(&self) {
        let c = self.c;
        // SAFETY: arrays of two elements.
        unsafe {
            let refs = [vr::MESH_NX, vr::MESH_NY];
            let mut ok = fmi3SetInt32(c, refs.as_ptr(), 2, [3, 2].as_ptr(), 2) == OK;
            ok &= fmi3EnterConfigurationMode(c) == OK;
            let refs = [vr::MESH_VERTEX_ROWS, vr::MESH_VERTEX_COLUMNS];
            ok &= fmi3SetUInt64(c, refs.as_ptr(), 2, [3, 4].as_ptr(), 2) == OK;
            ok &= fmi3ExitConfigurationMode(c) == OK;
            assert!(ok, "the 3 x 2 mesh was refused");
        }
    }

    /// The Float64 scalar `vr` (not in Configuration Mode), or `fallback` if refused.
    fn float64(&self, vr: u32, fallback: f64) -> f64 {
        let mut x = fallback;
        // SAFETY: one value reference, one value.
        let status = unsafe { fmi3GetFloat64(self.c, &vr, 1, &mut x, 1) };
        if status == OK {
            x
        } else {
            fallback
        }
    }

    /// The serialized bytes of `state`, or `None` when the size is refused.
    fn serialize(&self, state: fmi3FMUState) -> Option<Vec<u8>> {
        let mut size = 0;
        // SAFETY: `state` is null or a live state of this instance; the buffer has `size` bytes.
        unsafe {
            if fmi3SerializedFMUStateSize(self.c, state, &mut size) != OK {
                return None;
            }
            let mut bytes = vec![0u8; size];
            let status = fmi3SerializeFMUState(self.c, state, bytes.as_mut_ptr(), size);
            assert_eq!(
                status, OK,
                "a state whose size was given cannot be serialized"
            );
            Some(bytes)
        }
    }

    /// Deserializes `bytes` into `slot`.
    fn deserialize(&mut self, bytes: &[u8], slot: usize) -> fmi3Status {
        // SAFETY: the buffer holds `bytes.len()` bytes; the slot is null or a live state.
        unsafe {
            fmi3DeserializeFMUState(self.c, bytes.as_ptr(), bytes.len(), &mut self.states[slot])
        }
    }

    /// The call, as [`Host::run`]: one `match` arm per [`Op`], each a single FMI call (the longer
    /// ones in a method of their own), side by side with the FMI 2.0 host's.
    ///
    /// # Safety
    /// `self.c` is a live instance (it is, from `new` to `drop`).
    unsafe fn call(&mut self, op: &Op) -> Option<fmi3Status> {
        let c = self.c;
        // SAFETY: every array passed has the length passed with it; states are live or null.
        let status = unsafe {
            match op {
                Op::SetupExperiment(start, stop) => {
                    self.experiment = (*start, *stop);
                    return None;
                }
                Op::EnterInitialization => {
                    let (start, stop) = self.experiment;
                    fmi3EnterInitializationMode(
                        c,
                        false,
                        0.0,
                        start,
                        stop.is_some(),
                        stop.unwrap_or(0.0),
                    )
                }
                Op::ExitInitialization => fmi3ExitInitializationMode(c),
                Op::Configuration(true) => {
                    let status = fmi3EnterConfigurationMode(c);
                    self.configuring |= status == OK;
                    status
                }
                Op::Configuration(false) => {
                    let status = fmi3ExitConfigurationMode(c);
                    self.configuring &= status != OK;
                    status
                }
                Op::Terminate => fmi3Terminate(c),
                Op::Reset => {
                    let status = fmi3Reset(c);
                    if status == OK {
                        self.small_mesh();
                    }
                    status
                }
                Op::SetReal(items) => {
                    let (r, v): (Vec<u32>, Vec<f64>) = items.iter().copied().unzip();
                    fmi3SetFloat64(c, r.as_ptr(), r.len(), v.as_ptr(), v.len())
                }
                Op::SetInteger(items) => {
                    let (r, v): (Vec<u32>, Vec<i32>) = items.iter().copied().unzip();
                    fmi3SetInt32(c, r.as_ptr(), r.len(), v.as_ptr(), v.len())
                }
                Op::SetUInt64(items) => {
                    let (r, v): (Vec<u32>, Vec<u64>) = items.iter().copied().unzip();
                    fmi3SetUInt64(c, r.as_ptr(), r.len(), v.as_ptr(), v.len())
                }
                Op::SetBoolean(items) => {
                    let (r, v): (Vec<u32>, Vec<bool>) = items.iter().copied().unzip();
                    fmi3SetBoolean(c, r.as_ptr(), r.len(), v.as_ptr(), v.len())
                }
                Op::SetString(items) => {
                    let r: Vec<u32> = items.iter().map(|x| x.0).collect();
                    let texts: Vec<CString> = items
                        .iter()
                        .map(|x| CString::new(x.1.clone()).unwrap())
                        .collect();
                    let v: Vec<*const c_char> = texts.iter().map(|t| t.as_ptr()).collect();
                    fmi3SetString(c, r.as_ptr(), r.len(), v.as_ptr(), v.len())
                }
                Op::DoStep(k, wrong_time) => self.do_step(*k, *wrong_time),
                Op::Derivative(order, _) => {
                    let mut x = f64::NAN;
                    let status =
                        fmi3GetOutputDerivatives(c, &vr::CORNER1_DISPLACEMENT, 1, order, &mut x, 1);
                    assert!(
                        status != OK || x.is_finite(),
                        "derivative of order {order} = {x} with fmi3OK"
                    );
                    status
                }
                Op::SaveState(i) => fmi3GetFMUState(c, &mut self.states[*i]),
                Op::RestoreState(i) => fmi3SetFMUState(c, self.states[*i]),
                Op::SerializeRoundTrip(i) => match self.serialize(self.states[*i]) {
                    Some(bytes) => self.deserialize(&bytes, *i),
                    None => ERROR,
                },
                Op::CorruptState(i, at, x) => self.deserialize_corrupted(*i, *at, *x),
                Op::Deserialize(i, bytes) => self.deserialize(bytes, *i),
                Op::Logging(on, bad) => {
                    let names = [
                        CString::new("logContact").unwrap(),
                        CString::new(if *bad { "logNothing" } else { "logAll" }).unwrap(),
                    ];
                    let pointers: Vec<fmi3String> = names.iter().map(|n| n.as_ptr()).collect();
                    fmi3SetDebugLogging(c, *on, 2, pointers.as_ptr())
                }
            }
        };
        Some(status)
    }

    /// fmi3DoStep over `k` internal steps from the instance's time (shifted by 0.25 s when
    /// `wrong_time`, which the FMU must refuse); an OK step must report a finite last time and
    /// neither an event nor termination.
    ///
    /// # Safety
    /// As [`Fmi3Host::call`].
    unsafe fn do_step(&self, k: f64, wrong_time: bool) -> fmi3Status {
        let (t, dt) = if self.configuring {
            (self.experiment.0, 1e-4)
        } else {
            (
                self.float64(vr::TIME, 0.0),
                self.float64(vr::SOLVER_TIME_STEP, 1e-4),
            )
        };
        let t = t + if wrong_time { 0.25 } else { 0.0 };
        let (mut event, mut terminate, mut early) = (true, true, true);
        let mut last = f64::NAN;
        // SAFETY: every out-pointer is a live local.
        let status = unsafe {
            fmi3DoStep(
                self.c,
                t,
                k * dt,
                false,
                &mut event,
                &mut terminate,
                &mut early,
                &mut last,
            )
        };
        if status == OK {
            assert!(
                last.is_finite() && !event && !terminate,
                "fmi3DoStep OK with lastSuccessfulTime = {last}, \
                 eventHandlingNeeded = {event}, terminateSimulation = {terminate}"
            );
        }
        status
    }

    /// Serializes the state of slot `i`, flips the bits `x` of its byte `at` (modulo its length)
    /// and deserializes it into a fresh state, which is freed: a refused payload must store
    /// nothing.
    ///
    /// # Safety
    /// As [`Fmi3Host::call`].
    unsafe fn deserialize_corrupted(&self, i: usize, at: usize, x: u8) -> fmi3Status {
        let Some(mut bytes) = self.serialize(self.states[i]) else {
            return ERROR;
        };
        let n = bytes.len();
        bytes[at % n] ^= x;
        let mut s: fmi3FMUState = std::ptr::null_mut();
        // SAFETY: the buffer holds `n` bytes; `s` is a null state that the call may fill.
        unsafe {
            let status = fmi3DeserializeFMUState(self.c, bytes.as_ptr(), n, &mut s);
            assert!(s.is_null() || status == OK, "a refused state was stored");
            fmi3FreeFMUState(self.c, &mut s);
            status
        }
    }

    /// The value of the scalar `v` (status and bits).
    ///
    /// # Safety
    /// As [`Fmi3Host::call`].
    unsafe fn scalar(&self, vr: u32, kind: Kind) -> (fmi3Status, u64) {
        let c = self.c;
        // SAFETY: one value reference and one value per call.
        unsafe {
            match kind {
                Kind::Real => {
                    let mut x = 0.0;
                    (fmi3GetFloat64(c, &vr, 1, &mut x, 1), x.to_bits())
                }
                Kind::Integer | Kind::Enumeration => {
                    let mut i = 0;
                    (fmi3GetInt32(c, &vr, 1, &mut i, 1), i as u64)
                }
                Kind::UInt64 => {
                    let mut i = 0;
                    (fmi3GetUInt64(c, &vr, 1, &mut i, 1), i)
                }
                Kind::Boolean => {
                    let mut b = false;
                    (fmi3GetBoolean(c, &vr, 1, &mut b, 1), u64::from(b))
                }
                Kind::String => {
                    let mut p: *const c_char = std::ptr::null();
                    let status = fmi3GetString(c, &vr, 1, &mut p, 1);
                    let text = if status == OK {
                        // SAFETY: the FMU returned a NUL-terminated text it keeps until its next
                        // String get.
                        text_hash(std::ffi::CStr::from_ptr(p).to_bytes())
                    } else {
                        0
                    };
                    (status, text)
                }
            }
        }
    }
}

impl Host for Fmi3Host {
    const DESCRIPTION: &'static Description = &FMI3;
    const EVERY_ERROR_FAILS: bool = true;

    fn new() -> Fmi3Host {
        let name = CString::new("random").unwrap();
        let token = CString::new(FMI3.token).unwrap();
        // SAFETY: valid strings; no callbacks and no required intermediate variables.
        let c = unsafe {
            fmi3InstantiateCoSimulation(
                name.as_ptr(),
                token.as_ptr(),
                std::ptr::null(),
                false,
                false,
                false,
                true,
                std::ptr::null(),
                0,
                std::ptr::null_mut(),
                None,
                None,
            )
        };
        assert!(!c.is_null(), "fmi3InstantiateCoSimulation failed");
        let host = Fmi3Host {
            c,
            states: [std::ptr::null_mut(); SLOTS],
            configuring: false,
            experiment: (0.0, None),
        };
        host.small_mesh();
        host
    }

    fn run(&mut self, op: &Op) -> Option<fmi3Status> {
        // SAFETY: `self.c` is live from `new` to `drop`.
        let status = unsafe { self.call(op) };
        // Every fmi3Error ends Configuration Mode (in Terminated).
        self.configuring &= status != Some(ERROR);
        status
    }

    fn observe(&mut self) -> Observation {
        let c = self.c;
        let n = FMI3.variables.len();
        // SAFETY: every array passed has the length passed with it; empty calls pass null.
        unsafe {
            // Refused in Terminated only, where it changes nothing.
            let set = fmi3SetFloat64(c, std::ptr::null(), 0, std::ptr::null(), 0);
            if self.configuring {
                return Observation {
                    probe: vec![set],
                    values: vec![(NOT_READ, vec![]); n],
                    state: None,
                };
            }
            let mut s: fmi3FMUState = std::ptr::null_mut();
            let state = if fmi3GetFMUState(c, &mut s) == OK {
                let bytes = self.serialize(s);
                fmi3FreeFMUState(c, &mut s);
                bytes
            } else {
                None
            };
            let mode = state
                .as_deref()
                .and_then(|b| serialized::decode_json(b).ok())
                .and_then(|tree| {
                    let name = tree["mode"].as_str()?.to_string();
                    MODES.iter().position(|&m| m == name)
                });
            // In Initialization Mode the first output read sets the simulation up, and a set-up
            // that fails is an fmi3Error, as is a calculated parameter that the parameters do not
            // determine yet: those are read from Step Mode on.
            let outputs_readable = mode.is_some_and(|m| m > 1);
            let size = |vr| self.scalar(vr, Kind::Integer);
            let sized = size(vr::MESH_NY).1 + 1
                == self.scalar(vr::MESH_VERTEX_ROWS, Kind::UInt64).1
                && size(vr::MESH_NX).1 + 1 == self.scalar(vr::MESH_VERTEX_COLUMNS, Kind::UInt64).1;
            let mut values = Vec::with_capacity(n);
            for v in FMI3.variables {
                // Outputs and calculated parameters are computed, and may fail to be.
                let computed = matches!(
                    v.causality,
                    Causality::Output | Causality::CalculatedParameter
                );
                let value = if computed && !outputs_readable {
                    (NOT_READ, vec![])
                } else if v.is_array() {
                    if sized {
                        let rows = self.scalar(vr::MESH_VERTEX_ROWS, Kind::UInt64).1;
                        let columns = self.scalar(vr::MESH_VERTEX_COLUMNS, Kind::UInt64).1;
                        let mut x = vec![0.0; (rows * columns) as usize];
                        let status = fmi3GetFloat64(c, &v.vr, 1, x.as_mut_ptr(), x.len());
                        let bits = x.iter().map(|x| x.to_bits());
                        (status, if status == OK { bits.collect() } else { vec![] })
                    } else {
                        (NOT_READ, vec![])
                    }
                } else {
                    let (status, bits) = self.scalar(v.vr, v.kind);
                    (status, if status == OK { vec![bits] } else { vec![] })
                };
                values.push(value);
            }
            let probe = vec![set, mode.map_or(NOT_READ, |m| m as i32)];
            Observation {
                probe,
                values,
                state,
            }
        }
    }

    fn restore_own_state(&mut self) -> Option<fmi3Status> {
        if self.configuring {
            return None;
        }
        let calls = StateCalls {
            get: fmi3GetFMUState,
            set: fmi3SetFMUState,
            free: fmi3FreeFMUState,
        };
        // SAFETY: `self.c` is a live instance (it is, from `new` to `drop`).
        unsafe { calls.take_and_set(self.c) }
    }

    fn failed(obs: &Observation) -> bool {
        obs.probe[0] == ERROR
    }
}
