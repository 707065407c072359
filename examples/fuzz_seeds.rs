//! Writes the seed corpus of the fuzz targets (`fuzz/seeds/`, docs/fuzzing.md): real FMU states
//! of the shipped scenes for `serialized_state`, and a few fixed pseudo-random call sequences for
//! `call_sequences`.
//!
//! `cargo run --release --example fuzz_seeds [-- OUT_DIR]` (default `fuzz/seeds`).
//!
//! Each scene runs on a 3 × 2 mesh of its element (the fuzzer's executions stay fast; the
//! parser's checks do not depend on the mesh size) through the FMU's instance of each FMI version:
//! its state when stepping after 40 communication steps of 10 Δt, and for `forced-35hz` also
//! when instantiated, in initialization and terminated. A seed is a flags byte (bit 0: FMI 3.0;
//! bit 1: the payload alone, framed by the fuzz target) and the bytes; the stepping states of
//! `forced-35hz` are also written whole (bit 1 clear), for the framing checks.

use plate_impact::fmi::fmi2::instance::Fmi2;
use plate_impact::fmi::fmi3::instance::Fmi3;
use plate_impact::fmi::instance::{Instance, Version};
use plate_impact::fmi::model::StepOptions;
use plate_impact::fmi::plate::PlateModel;
use plate_impact::fmi::serialized;
use plate_impact::fmi::variables::{vr, Causality, Kind};
use plate_impact::scene::Scene;
use std::path::{Path, PathBuf};

const SCENES: [&str; 4] = ["forced-35hz", "forced-30hz", "forced", "energy"];

/// Sets every parameter of `scene` on `inst` (the variable names are the scene's field paths),
/// then the 3 × 2 mesh.
fn set_scene<V: Version>(inst: &mut Instance<V, PlateModel>, scene: &Scene) {
    let tree = serde_json::to_value(scene).unwrap();
    let d = V::description::<PlateModel>();
    for v in d
        .variables
        .iter()
        .filter(|v| v.causality == Causality::Parameter)
    {
        let field = v.name.split('.').fold(&tree, |t, k| &t[k]);
        let done = match v.kind {
            Kind::Real => inst.set_real(&[v.vr], &[field.as_f64().unwrap()]),
            Kind::Boolean => inst.set_boolean(&[v.vr], &[field.as_bool().unwrap()]),
            Kind::Integer if v.vr == vr::MESH_ELEMENT => {
                let code = if field.as_str() == Some("argyris") {
                    1
                } else {
                    2
                };
                inst.set_integer(&[v.vr], &[code])
            }
            Kind::Integer => inst.set_integer(&[v.vr], &[field.as_i64().unwrap() as i32]),
            other => panic!("{}: a parameter of kind {other:?}", v.name),
        };
        done.unwrap_or_else(|f| panic!("{}: {}", v.name, f.message));
    }
    inst.set_integer(&[vr::MESH_NX, vr::MESH_NY], &[3, 2])
        .unwrap();
}

/// The serialized current state of `inst`.
fn state<V: Version>(inst: &mut Instance<V, PlateModel>) -> Vec<u8> {
    let s = inst.get_state().unwrap();
    inst.serialized(V::SERIALIZED_FMU_STATE_SIZE, &s)
        .unwrap()
        .to_vec()
}

/// The seeds of one scene and version: (name, bytes with the flags byte).
fn seeds<V: Version>(
    version: u8,
    scene_name: &str,
    configure: fn(&mut Instance<V, PlateModel>),
) -> Vec<(String, Vec<u8>)> {
    let scene = Scene::named(scene_name).unwrap();
    let token = V::description::<PlateModel>().token;
    let mut inst = Instance::<V, PlateModel>::new("seed", token, false, None).unwrap();
    set_scene(&mut inst, &scene);
    configure(&mut inst);
    let all = scene_name == "forced-35hz";
    let mut states = Vec::new();
    if all {
        states.push(("instantiated", state(&mut inst)));
    }
    inst.begin_initialization(Some((0.0, None))).unwrap();
    if all {
        states.push(("initialization", state(&mut inst)));
    }
    inst.exit_initialization_mode().unwrap();
    let h = 10.0 * scene.solver.time_step;
    for _ in 0..40 {
        let t = inst.time();
        let options = StepOptions {
            early_return: false,
        };
        inst.step(t, h, options).unwrap();
    }
    states.push(("stepping", state(&mut inst)));
    if all {
        inst.terminate().unwrap();
        states.push(("terminated", state(&mut inst)));
    }
    let mut out = Vec::new();
    for (mode, bytes) in states {
        let name = format!("fmi{}-{scene_name}-{mode}", version + 2);
        let payload = serde_json::to_vec(&serialized::decode_json(&bytes).unwrap()).unwrap();
        out.push((
            format!("{name}.json"),
            [&[version | 2][..], &payload].concat(),
        ));
        if all && mode == "stepping" {
            out.push((format!("{name}.bin"), [&[version][..], &bytes].concat()));
        }
    }
    out
}

/// FMI 3.0's structural sizes for the 3 × 2 mesh.
fn fmi3_sizes(inst: &mut Instance<Fmi3, PlateModel>) {
    inst.enter_configuration_mode().unwrap();
    let refs = [vr::MESH_VERTEX_ROWS, vr::MESH_VERTEX_COLUMNS];
    inst.set_uint64(&refs, &[3, 4]).unwrap();
    inst.exit_configuration_mode().unwrap();
}

/// Eight call sequences of 255 pseudo-random bytes (xorshift), with every flags value.
fn call_sequences() -> Vec<(String, Vec<u8>)> {
    let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
    (0..8u8)
        .map(|i| {
            let bytes = (0..255).map(|_| {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                (x >> 32) as u8
            });
            let seed = std::iter::once(i % 4).chain(bytes).collect();
            (format!("random-{i}"), seed)
        })
        .collect()
}

fn write(dir: &Path, seeds: &[(String, Vec<u8>)]) {
    std::fs::create_dir_all(dir).unwrap();
    for (name, bytes) in seeds {
        std::fs::write(dir.join(name), bytes).unwrap();
    }
    println!("{}: {} seeds", dir.display(), seeds.len());
}

fn main() {
    let out = PathBuf::from(std::env::args().nth(1).unwrap_or("fuzz/seeds".into()));
    let mut states = Vec::new();
    for scene in SCENES {
        states.extend(seeds::<Fmi2>(0, scene, |_| {}));
        states.extend(seeds::<Fmi3>(1, scene, fmi3_sizes));
    }
    write(&out.join("serialized_state"), &states);
    write(&out.join("call_sequences"), &call_sequences());
}
