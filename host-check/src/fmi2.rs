//! The FMI 2.0 host: one instance and its FMU-state slots, through the exported fmi2 functions.

use crate::{text_hash, Host, Observation, Op, StateCalls, ERROR, OK, SLOTS};
use plate_impact::fmi::fmi2::exports::*;
use plate_impact::fmi::variables::{vr, Description, Kind, FMI2};
use std::ffi::{c_char, CString};

/// One FMI 2.0 instance and the FMU states the host keeps for it.
pub struct Fmi2Host {
    c: fmi2Component,
    states: [fmi2FMUstate; SLOTS],
}

impl Drop for Fmi2Host {
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

/// fmi2GetRealStatus's status and time.
fn real_status(c: fmi2Component) -> (fmi2Status, f64) {
    let mut t = 0.0;
    // SAFETY: a valid pointer to an fmi2Real.
    let status = unsafe { fmi2GetRealStatus(c, 2, &mut t) };
    (status, t)
}

impl Fmi2Host {
    /// A 3 × 2 mesh (random values cannot grow it: the integers a caller passes are at most 3 or
    /// refused).
    fn small_mesh(&self) {
        let refs = [vr::MESH_NX, vr::MESH_NY];
        // SAFETY: arrays of two elements.
        let status = unsafe { fmi2SetInteger(self.c, refs.as_ptr(), 2, [3, 2].as_ptr()) };
        assert_eq!(status, OK, "the 3 x 2 mesh was refused");
    }

    fn time_step(&self) -> f64 {
        let mut x = 1e-4;
        // SAFETY: one value reference, one value.
        unsafe { fmi2GetReal(self.c, &vr::SOLVER_TIME_STEP, 1, &mut x) };
        x
    }

    /// The serialized bytes of `state`, or `None` when the size is refused.
    fn serialize(&self, state: fmi2FMUstate) -> Option<Vec<u8>> {
        let mut size = 0;
        // SAFETY: `state` is null or a live state of this instance; the buffer has `size` bytes.
        unsafe {
            if fmi2SerializedFMUstateSize(self.c, state, &mut size) != OK {
                return None;
            }
            let mut bytes = vec![0 as fmi2Byte; size];
            let status = fmi2SerializeFMUstate(self.c, state, bytes.as_mut_ptr(), size);
            assert_eq!(
                status, OK,
                "a state whose size was given cannot be serialized"
            );
            Some(bytes.iter().map(|&b| b as u8).collect())
        }
    }

    /// Deserializes `bytes` into `slot`.
    fn deserialize(&mut self, bytes: &[u8], slot: usize) -> fmi2Status {
        // SAFETY: the buffer holds `bytes.len()` bytes; the slot is null or a live state.
        unsafe {
            fmi2DeSerializeFMUstate(
                self.c,
                bytes.as_ptr() as *const fmi2Byte,
                bytes.len(),
                &mut self.states[slot],
            )
        }
    }
}

/// A new FMI 2.0 instance named `name`, without callbacks, on the default mesh; panics when the
/// library refuses it. The caller frees it (`fmi2FreeInstance`).
pub fn instantiate(name: &str) -> fmi2Component {
    let callbacks = fmi2CallbackFunctions {
        logger: None,
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: std::ptr::null_mut(),
    };
    let name = CString::new(name).expect("an instance name without NUL");
    let guid = CString::new(FMI2.token).expect("the token has no NUL");
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
    assert!(!c.is_null(), "fmi2Instantiate failed");
    c
}

impl Host for Fmi2Host {
    const DESCRIPTION: &'static Description = &FMI2;
    const EVERY_ERROR_FAILS: bool = false;

    fn new() -> Fmi2Host {
        let host = Fmi2Host {
            c: instantiate("random"),
            states: [std::ptr::null_mut(); SLOTS],
        };
        host.small_mesh();
        host
    }

    fn run(&mut self, op: &Op) -> Option<fmi2Status> {
        let c = self.c;
        // SAFETY: every array passed has the length passed with it; states are live or null.
        let status = unsafe {
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
                Op::Configuration(_) | Op::SetUInt64(_) => return None,
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
                Op::SetString(items) => {
                    let r: Vec<u32> = items.iter().map(|x| x.0).collect();
                    let texts: Vec<CString> = items
                        .iter()
                        .map(|x| CString::new(x.1.clone()).unwrap())
                        .collect();
                    let v: Vec<*const c_char> = texts.iter().map(|t| t.as_ptr()).collect();
                    fmi2SetString(c, r.as_ptr(), r.len(), v.as_ptr())
                }
                Op::DoStep(k, wrong_time) => {
                    let t = real_status(c).1 + if *wrong_time { 0.25 } else { 0.0 };
                    fmi2DoStep(c, t, k * self.time_step(), 1)
                }
                Op::Derivative(order, x) => {
                    fmi2SetRealInputDerivatives(c, &vr::BASE_DISPLACEMENT, 1, order, x)
                }
                Op::SaveState(i) => fmi2GetFMUstate(c, &mut self.states[*i]),
                Op::RestoreState(i) => fmi2SetFMUstate(c, self.states[*i]),
                Op::SerializeRoundTrip(i) => match self.serialize(self.states[*i]) {
                    Some(bytes) => self.deserialize(&bytes, *i),
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
                        assert!(s.is_null() || status == OK, "a refused state was stored");
                        fmi2FreeFMUstate(c, &mut s);
                        status
                    }
                    None => ERROR,
                },
                Op::Deserialize(i, bytes) => self.deserialize(bytes, *i),
                Op::Logging(on, bad) => {
                    let names = [
                        CString::new("logContact").unwrap(),
                        CString::new(if *bad { "logNothing" } else { "logAll" }).unwrap(),
                    ];
                    let pointers: Vec<fmi2String> = names.iter().map(|n| n.as_ptr()).collect();
                    fmi2SetDebugLogging(c, i32::from(*on), 2, pointers.as_ptr())
                }
            }
        };
        Some(status)
    }

    fn observe(&mut self) -> Observation {
        let c = self.c;
        let mut values = Vec::new();
        // SAFETY: every array passed has the length passed with it; empty calls pass null.
        unsafe {
            // An empty set, an empty get and fmi2GetRealStatus: together they tell the state.
            let probe = vec![
                fmi2SetReal(c, std::ptr::null(), 0, std::ptr::null()),
                fmi2GetReal(c, std::ptr::null(), 0, std::ptr::null_mut()),
                real_status(c).0,
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
                    Kind::String => {
                        let mut p: *const c_char = std::ptr::null();
                        let status = fmi2GetString(c, &v.vr, 1, &mut p);
                        let text = if status == OK {
                            // SAFETY: the FMU returned a NUL-terminated text it keeps until
                            // its next String get.
                            text_hash(std::ffi::CStr::from_ptr(p).to_bytes())
                        } else {
                            0
                        };
                        (status, text)
                    }
                    Kind::UInt64 => unreachable!("not in FMI 2.0"),
                };
                values.push((status, if status == OK { vec![bits] } else { vec![] }));
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

    fn restore_own_state(&mut self) -> Option<fmi2Status> {
        let calls = StateCalls {
            get: fmi2GetFMUstate,
            set: fmi2SetFMUstate,
            free: fmi2FreeFMUstate,
        };
        // SAFETY: `self.c` is a live instance (it is, from `new` to `drop`).
        unsafe { calls.take_and_set(self.c) }
    }

    fn failed(obs: &Observation) -> bool {
        obs.probe == [ERROR, OK, ERROR]
    }
}
