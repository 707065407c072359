//! A hostile host and its oracles, shared by the random call-sequence test
//! (`tests/fmi_c_api.rs`, proptest) and the coverage-guided fuzz targets (`fuzz/`, libFuzzer):
//! both drive the exported C functions of one FMI version through [`Host`] and judge every call
//! with [`check_call`]. A crate of its own that depends on the library, so that the library is
//! built one way for every test, example and the packager, and the FMU binary carries none of
//! it.
//!
//! The oracles, after every call:
//! * no crash and no hang (the caller's business: small meshes, bounded steps, a time limit);
//! * every FMU state the instance gives can be set again, and setting it changes nothing the host
//!   can observe;
//! * after OK or Warning, every Real the host can read is finite, the free corners
//!   (obstacle-constrained vertices) lie within the obstacles to 1e-7 of the gap when e = 0, and
//!   the kinetic and elastic energies are ≥ 0;
//! * a call answered Error changed nothing the host can observe (every variable value with its
//!   status, the call state, the serialized FMU state), except that the version's rules may
//!   leave the instance in its failed state: FMI 2.0 after a failed fmi2DoStep (which may have
//!   failed part-way: its values are then undefined), FMI 3.0 after every fmi3Error (Terminated,
//!   with every value as before, but for a failed fmi3DoStep);
//! * a call answered Discard changed nothing.

// The host calls the exported C functions through raw pointers, as a C host would.
#![allow(unsafe_code)]

pub mod fmi2;
pub mod fmi3;

use plate_impact::fmi::serialized;
use plate_impact::fmi::variables::{Description, Kind};
use std::ffi::c_void;

/// The status codes, the same numbers in FMI 2.0 and FMI 3.0.
pub const OK: i32 = 0;

/// The FMU-state calls of one FMI version: get, set and free share one C signature in FMI 2.0
/// and 3.0 (an instance pointer, a state or a pointer to one, a status).
struct StateCalls {
    get: unsafe extern "C" fn(*mut c_void, *mut *mut c_void) -> i32,
    set: unsafe extern "C" fn(*mut c_void, *mut c_void) -> i32,
    free: unsafe extern "C" fn(*mut c_void, *mut *mut c_void) -> i32,
}

impl StateCalls {
    /// Takes the FMU state of instance `c` and sets it again: the status of the set, or `None`
    /// when no state can be taken.
    ///
    /// # Safety
    /// `c` is a live instance of this library's version of the calls.
    unsafe fn take_and_set(&self, c: *mut c_void) -> Option<i32> {
        let mut s: *mut c_void = std::ptr::null_mut();
        // SAFETY: `s` is null or a live state of this instance, freed once.
        unsafe {
            if (self.get)(c, &mut s) != OK {
                return None;
            }
            let status = (self.set)(c, s);
            (self.free)(c, &mut s);
            Some(status)
        }
    }
}
/// Warning.
pub const WARNING: i32 = 1;
/// Discard.
pub const DISCARD: i32 = 2;
/// Error.
pub const ERROR: i32 = 3;
/// Stands for a value the host did not read (it would have failed the instance).
pub const NOT_READ: i32 = -1;

/// One call of the host (the values are what the host passes; which C function is called
/// depends on the version, and a version without the call skips it).
#[derive(Clone, Debug)]
pub enum Op {
    /// fmi2SetupExperiment(start, stop); FMI 3.0 passes them to the next
    /// fmi3EnterInitializationMode (no call).
    SetupExperiment(f64, Option<f64>),
    /// Enter Initialization Mode.
    EnterInitialization,
    /// Exit Initialization Mode.
    ExitInitialization,
    /// Enter (true) or exit (false) Configuration Mode, FMI 3.0 only.
    Configuration(bool),
    /// Terminate.
    Terminate,
    /// Reset, then the small mesh again when it succeeded.
    Reset,
    /// Set Real / Float64 values (value reference, value).
    SetReal(Vec<(u32, f64)>),
    /// Set Integer / Int32 values.
    SetInteger(Vec<(u32, i32)>),
    /// Set UInt64 values, FMI 3.0 only (the structural parameters).
    SetUInt64(Vec<(u32, u64)>),
    /// Set Boolean values.
    SetBoolean(Vec<(u32, bool)>),
    /// Set String values (the clamp and the obstacles' profiles).
    SetString(Vec<(u32, String)>),
    /// A step of k times the current internal Δt from the current time, or from 0.25 s past it
    /// when the flag is set.
    DoStep(f64, bool),
    /// FMI 2.0: fmi2SetRealInputDerivatives of the base displacement (order, value); FMI 3.0:
    /// fmi3GetOutputDerivatives of corner1.displacement (order; the value is unused).
    Derivative(i32, f64),
    /// Get the FMU state into host slot i.
    SaveState(usize),
    /// Set the FMU state of slot i (null if none was saved).
    RestoreState(usize),
    /// Serialize the state of slot i and deserialize it into the same slot.
    SerializeRoundTrip(usize),
    /// Serialize the state of slot i, xor one byte (at a position modulo the length) with a
    /// non-zero mask, and deserialize it into a fresh state, freed at once.
    CorruptState(usize, usize, u8),
    /// Deserialize these bytes into slot i (the serialized-state fuzz target's call).
    Deserialize(usize, Vec<u8>),
    /// Set debug logging (on or off) for logContact and logAll, or an unknown category.
    Logging(bool, bool),
}

/// Reals a host tries: in range, at the edges, absurd and not finite.
pub const REALS: &[f64] = &[
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
/// Integers a host tries: at most 3 (a mesh of at most 3 × 3 cells keeps every set-up to a
/// millisecond) or refused.
pub const INTEGERS: &[i32] = &[1, 2, 3, 0, -1, 401];
/// Texts a host tries for the String parameters: clamps and profiles that the small plate
/// takes, ones it refuses (a stop or segment off the plate, an obstacle touching the plate at
/// rest), and ones no plate takes (bad grammar, numbers that are not finite, nothing).
pub const TEXTS: &[&str] = &[
    "flat",
    "xmin",
    "all",
    "xmin, ymax",
    "ymin(0, 0.2)",
    "plane(slope_x = 0.01, slope_y = -0.02)",
    "table(0, 0.001; 0.002, 0.003)",
    "point(x = 0.39, y = 0.01)",
    "disc(x = 0.2, y = 0.1, radius = 0.01, offset = 0.005); point(x = 0.1, y = 0.05)",
    "rectangle(x0 = 0.3, y0 = 0, x1 = 0.4, y1 = 0.05, offset = -0.002)",
    "point(x = 0.39, y = 0.01, offset = 0.02)",
    "point(x = 5, y = 0)",
    "ymin(0.1, 0.11)",
    "disc(x = 0.2, y = 0.1, radius = NaN)",
    "table(1, inf; 2, 3)",
    "plane(slope_x = 0.01",
    "left",
    "",
];

/// A text's 64-bit FNV-1a hash: how an observation records a String value.
pub fn text_hash(text: &[u8]) -> u64 {
    text.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// Structural sizes a host tries: the small mesh's (3 rows, 4 columns), others, out of range.
pub const SIZES: &[u64] = &[3, 4, 2, 8, 11, 0, 402];
/// Step sizes a host tries, in internal steps Δt: on and off the grid, negative, absurd.
pub const STEPS: &[f64] = &[1.0, 3.0, 10.0, 30.0, 0.5, 1.5, -1.0, 1e300];
/// Start and stop times a host tries.
pub const TIMES: &[f64] = &[0.0, 0.5, -2.0, 1e9, -1e308, f64::NAN];

/// The value references of `kind` in `d`, and one that is none.
pub fn value_references(d: &Description, kind: Kind) -> Vec<u32> {
    let mut v: Vec<u32> = d
        .variables
        .iter()
        .filter(|v| v.kind == kind)
        .map(|v| v.vr)
        .collect();
    v.push(9999);
    v
}

/// The number of FMU-state slots a host keeps.
pub const SLOTS: usize = 3;

/// Everything the host can observe without changing anything.
#[derive(Clone, Debug, PartialEq)]
pub struct Observation {
    /// Statuses of calls that change nothing and together tell the call state.
    pub probe: Vec<i32>,
    /// The status and bits of every variable of the version's description, in its order (an
    /// array's every element; a String's [`text_hash`]; `NOT_READ` and none where reading would
    /// fail the instance).
    pub values: Vec<(i32, Vec<u64>)>,
    /// The serialized FMU state, if one can be taken.
    pub state: Option<Vec<u8>>,
}

/// A host of one FMI version: one instance on a small mesh and its FMU-state slots, driven
/// through the exported C functions.
pub trait Host {
    /// The version's model description.
    const DESCRIPTION: &'static Description;
    /// Whether every Error leaves the instance in the failed state (FMI 3.0), or only a failed
    /// step (FMI 2.0).
    const EVERY_ERROR_FAILS: bool;

    /// A fresh instance on a 3 × 2 mesh (every set-up about a millisecond).
    fn new() -> Self;
    /// Runs one call: its status, or `None` when the version has no such call.
    fn run(&mut self, op: &Op) -> Option<i32>;
    /// What the host can observe, by calls that change nothing.
    fn observe(&mut self) -> Observation;
    /// Takes the FMU state and sets it again: the status of the set, or `None` when no state
    /// can be taken.
    fn restore_own_state(&mut self) -> Option<i32>;
    /// Whether `obs` shows the instance in the version's failed state.
    fn failed(obs: &Observation) -> bool;
}

/// The Real value `name` of `obs`, if it was read with OK.
fn real(obs: &Observation, d: &Description, name: &str) -> Option<f64> {
    let i = d.variables.iter().position(|v| v.name == name)?;
    let (status, bits) = &obs.values[i];
    (*status == OK && bits.len() == 1).then(|| f64::from_bits(bits[0]))
}

/// The Boolean value `name` of `obs`, if it was read with OK.
fn boolean(obs: &Observation, d: &Description, name: &str) -> Option<bool> {
    let i = d.variables.iter().position(|v| v.name == name)?;
    let (status, bits) = &obs.values[i];
    (*status == OK && bits.len() == 1).then(|| bits[0] != 0)
}

/// The hash of String value `name` of `obs` ([`text_hash`]), if it was read with OK.
fn text(obs: &Observation, d: &Description, name: &str) -> Option<u64> {
    let i = d.variables.iter().position(|v| v.name == name)?;
    let (status, bits) = &obs.values[i];
    (*status == OK && bits.len() == 1).then(|| bits[0])
}

/// The physical oracle on the outputs of `obs` after an OK.
pub fn outputs_are_sound(obs: &Observation, d: &Description) -> Result<(), String> {
    for (v, (status, bits)) in d.variables.iter().zip(&obs.values) {
        if v.kind == Kind::Real && *status == OK {
            if let Some(x) = bits
                .iter()
                .map(|&b| f64::from_bits(b))
                .find(|x| !x.is_finite())
            {
                return Err(format!("{} = {x} reported with OK", v.name));
            }
        }
    }
    let restitution = real(obs, d, "solver.restitution");
    let on = |name| boolean(obs, d, name).unwrap_or(false);
    let lower = real(obs, d, "obstacle.lower").filter(|_| on("obstacle.lower_enabled"));
    let upper = real(obs, d, "obstacle.upper").filter(|_| on("obstacle.upper_enabled"));
    // The corners lie within the levels where both obstacles are flat (and the corners are then
    // contact points off the clamp x = 0 of the default clamp).
    let flat = ["obstacle.lower_profile", "obstacle.upper_profile"]
        .iter()
        .all(|name| text(obs, d, name) == Some(text_hash(b"flat")))
        && text(obs, d, "plate.clamp") == Some(text_hash(b"xmin"));
    if restitution == Some(0.0) && flat {
        for name in ["corner1.displacement", "corner2.displacement"] {
            if let Some(u) = real(obs, d, name) {
                // 1e-7 of the gap: the static preload problem is solved by clarabel alone (the
                // dynamic steps are exact to round-off); with a plate of E = 1e-4 Pa its answer
                // lies up to 9e-9 of the gap past an obstacle.
                let gap = upper.unwrap_or(1.0) - lower.unwrap_or(-1.0);
                let tol = 1e-7 * gap;
                if lower.is_some_and(|g| u < g - tol) || upper.is_some_and(|g| u > g + tol) {
                    return Err(format!("{name} = {u} outside [{lower:?}, {upper:?}]"));
                }
            }
        }
    }
    for name in ["energy.kinetic", "energy.elastic"] {
        if let Some(e) = real(obs, d, name).filter(|&e| e < 0.0) {
            return Err(format!("{name} = {e} < 0"));
        }
    }
    Ok(())
}

/// Whether every variable read in both observations has the same status and value.
fn same_where_read(a: &Observation, b: &Observation) -> bool {
    a.values
        .iter()
        .zip(&b.values)
        .all(|(x, y)| x.0 == NOT_READ || y.0 == NOT_READ || x == y)
}

/// What differs between two observations of version `d`, for messages.
pub fn difference(a: &Observation, b: &Observation, d: &Description) -> String {
    let mut out = Vec::new();
    if a.probe != b.probe {
        out.push(format!("probe {:?} -> {:?}", a.probe, b.probe));
    }
    for (v, (x, y)) in d.variables.iter().zip(a.values.iter().zip(&b.values)) {
        if x != y {
            let show = |(s, bits): &(i32, Vec<u64>)| match v.kind {
                Kind::Real => format!(
                    "{s} {:?}",
                    bits.iter().map(|&b| f64::from_bits(b)).collect::<Vec<_>>()
                ),
                _ => format!("{s} {bits:?}"),
            };
            out.push(format!("{}: {} -> {}", v.name, show(x), show(y)));
        }
    }
    if a.state != b.state {
        let payload = |s: &Option<Vec<u8>>| {
            s.as_deref()
                .and_then(|b| serialized::decode_json(b).ok())
                .map(|t| t.to_string())
        };
        let (x, y) = (payload(&a.state), payload(&b.state));
        let common = match (&x, &y) {
            (Some(x), Some(y)) => x.bytes().zip(y.bytes()).take_while(|(p, q)| p == q).count(),
            _ => 0,
        };
        let from = common.saturating_sub(40);
        let cut = |s: &Option<String>| {
            s.as_ref()
                .map(|s| s.chars().skip(from).take(160).collect::<String>())
        };
        out.push(format!(
            "FMU state (payload from character {from}): {:?} -> {:?}",
            cut(&x),
            cut(&y)
        ));
    }
    out.join("; ")
}

/// Runs `op` on `host` under every oracle: its status (`None` when the version has no such
/// call), or what went wrong.
pub fn check_call<H: Host>(host: &mut H, op: &Op) -> Result<Option<i32>, String> {
    let before = host.observe();
    let Some(status) = host.run(op) else {
        return Ok(None);
    };
    let after = host.observe();
    let context = format!("{op:?} -> {status}");
    // Every state the FMU gives can be set again, and setting it changes nothing.
    if let Some(restored) = host.restore_own_state() {
        if restored != OK {
            return Err(format!(
                "{context}: its own FMU state was refused ({restored})"
            ));
        }
        let again = host.observe();
        if again != after {
            let what = difference(&after, &again, H::DESCRIPTION);
            return Err(format!(
                "{context}: setting its own FMU state changed {what}"
            ));
        }
    }
    match status {
        OK | WARNING => {
            outputs_are_sound(&after, H::DESCRIPTION).map_err(|e| format!("{context}: {e}"))?
        }
        ERROR => {
            let failed = H::failed(&after);
            let failed_step = matches!(op, Op::DoStep(..)) && failed;
            let failed_unchanged =
                H::EVERY_ERROR_FAILS && failed && same_where_read(&before, &after);
            if !(after == before || failed_step || failed_unchanged) {
                let what = difference(&before, &after, H::DESCRIPTION);
                return Err(format!("{context}: a refused call changed {what}"));
            }
        }
        DISCARD => {
            if after != before {
                return Err(format!(
                    "{context}: a discarded call changed {before:?} into {after:?}"
                ));
            }
        }
        other => return Err(format!("{context}: unexpected status {other}")),
    }
    Ok(Some(status))
}

/// The calls that start a simulation at t = 0 (FMI 3.0 takes the experiment at the second).
pub const START: [Op; 3] = [
    Op::SetupExperiment(0.0, None),
    Op::EnterInitialization,
    Op::ExitInitialization,
];

/// Runs `ops` on a fresh host of version `H`, after [`START`] when `running`, under every oracle:
/// the number of steps taken with OK, or the first call that went wrong and how.
pub fn check_sequence<H: Host>(running: bool, ops: &[Op]) -> Result<usize, String> {
    let mut host = H::new();
    let prefix = if running { &START[..] } else { &[] };
    let mut steps = 0;
    for (i, op) in prefix.iter().chain(ops).enumerate() {
        let status = check_call(&mut host, op).map_err(|e| format!("call {i}: {e}"))?;
        steps += usize::from(matches!(op, Op::DoStep(..)) && status == Some(OK));
    }
    Ok(steps)
}

/// The fuzz targets' check: runs `ops` as [`check_sequence`] does, on FMI 3.0 when `fmi3`, else
/// on FMI 2.0, and panics with the first call that went wrong and how (a finding of the fuzzer).
pub fn fuzz_sequence(fmi3: bool, running: bool, ops: &[Op]) {
    let result = if fmi3 {
        check_sequence::<fmi3::Fmi3Host>(running, ops)
    } else {
        check_sequence::<fmi2::Fmi2Host>(running, ops)
    };
    if let Err(e) = result {
        panic!("{e}");
    }
}

/// The fuzz targets' `init`: std's default panic hook instead of libfuzzer-sys's, which aborts at
/// every panic, also one the FMU's C boundary catches (by design, such as the set-up's panic for
/// a geometry the elements cannot mesh, refused with Error). With std's hook, a panic that
/// escapes the exported functions, or an oracle's, still aborts (libfuzzer-sys catches it around
/// the target's closure).
pub fn fuzz_init() {
    drop(std::panic::take_hook());
}
