//! fmi2DeSerializeFMUstate / fmi3DeserializeFMUState of untrusted bytes, then, when a state was
//! made, its restore and steps of 1, 3 and 10 internal steps, under the oracles of
//! `plate_impact_host_check` (the random call-sequence test's), which after every call
//! also take the FMU state, serialize it and set it again.
//!
//! Input: one flags byte, then the bytes. Flags bit 0: FMI 3.0 (else FMI 2.0); bit 1: the bytes
//! are a JSON payload, framed here with a valid header and checksum (so that mutations reach the
//! payload's validation instead of dying at the checksum); else they are passed as they are
//! (mutations of the framing). The seeds (`fuzz/seeds/serialized_state`) are real states of the
//! shipped scenes, written by `cargo run --release --example fuzz_seeds`.

#![no_main]

use libfuzzer_sys::fuzz_target;
use plate_impact_host_check::{fuzz_init, fuzz_sequence, Op};
use plate_impact::fmi::serialized;

/// The most mesh cells a state may ask for (the seeds have 6): larger meshes are legitimate
/// states whose set-up under ASan costs up to seconds and would pass for hangs, while the
/// parser's checks do not depend on the mesh size.
const MOST_CELLS: u64 = 24;

/// Whether the state asks for a mesh larger than [`MOST_CELLS`] (in its parameters or its
/// simulation's scene).
fn too_large(bytes: &[u8]) -> bool {
    let Ok(tree) = serialized::decode_json(bytes) else {
        return false;
    };
    let model = &tree["model"];
    let cells = |scene: &serde_json::Value| {
        let mesh = &scene["mesh"];
        let n = |k: &str| mesh[k].as_u64().unwrap_or(0);
        n("nx").saturating_mul(n("ny"))
    };
    cells(&model["parameters"]) > MOST_CELLS
        || cells(&model["simulation"]["stepper"]["scene"]) > MOST_CELLS
}

fuzz_target!(
    init: fuzz_init(),
    |data: &[u8]| {
    let Some((&flags, rest)) = data.split_first() else {
        return;
    };
    let bytes = if flags & 2 != 0 {
        serialized::encode_payload(rest)
    } else {
        rest.to_vec()
    };
    if too_large(&bytes) {
        return;
    }
    // After every call the oracles also take the FMU state, serialize it and set it again.
    let ops = [
        Op::Deserialize(0, bytes),
        Op::RestoreState(0),
        Op::DoStep(1.0, false),
        Op::DoStep(3.0, false),
        Op::DoStep(10.0, false),
    ];
    fuzz_sequence(flags & 1 != 0, false, &ops);
});
