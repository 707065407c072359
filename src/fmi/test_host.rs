//! What the tests of both FMI versions share: a plate instance whose log is recorded, reading one
//! Real, and the walk of the call-state table through the instance.

use super::call_state::{CallState, CallTable};
use super::instance::{Instance, StoredState, Version};
use super::logger::LogSink;
use super::plate::PlateModel;
use super::status::{Failure, Status};
use std::sync::{Arc, Mutex};

/// The messages an instance logged: (status, category, message).
pub type Messages = Arc<Mutex<Vec<(Status, String, String)>>>;

/// A plate instance of version `V` named "test" with the version's token, logging off, and the
/// messages it logs.
pub fn recorded_instance<V: Version>() -> (Instance<V, PlateModel>, Messages) {
    let messages: Messages = Arc::default();
    let m = messages.clone();
    let sink: LogSink =
        Box::new(move |s, c, msg| m.lock().unwrap().push((s, c.to_string(), msg.to_string())));
    let token = V::description::<PlateModel>().token;
    let inst = Instance::new("test", token, false, Some(sink)).unwrap();
    (inst, messages)
}

/// The Real variable `vr` of `inst`.
pub fn real<V: Version>(inst: &mut Instance<V, PlateModel>, vr: u32) -> f64 {
    let mut v = [0.0];
    inst.get_real(&[vr], &mut v).unwrap();
    v[0]
}

/// One harmless call of a function on an instance, given an FMU state and its bytes.
pub type Call<V> = fn(
    &mut Instance<V, PlateModel>,
    <V as Version>::Function,
    &StoredState<V, PlateModel>,
    &[u8],
) -> Result<(), Failure>;

/// Every function of `functions` in every state of `modes` (each reached by `in_mode`, the
/// first taken as the donor of an FMU state), called by `call`: refused as "not allowed" exactly
/// where the version's table forbids it, and never for that reason elsewhere.
pub fn assert_table_holds<V: Version>(
    modes: &[V::Mode],
    functions: &[V::Function],
    in_mode: fn(V::Mode) -> Instance<V, PlateModel>,
    call: Call<V>,
) {
    let mut donor = in_mode(modes[0]);
    let state = donor.get_state().unwrap();
    let bytes = donor
        .serialized(V::SERIALIZED_FMU_STATE_SIZE, &state)
        .unwrap()
        .to_vec();
    for &mode in modes {
        assert!(mode.reachable(), "{mode:?}");
        for &function in functions {
            let mut inst = in_mode(mode);
            let result = call(&mut inst, function, &state, &bytes);
            let refused_by_table = result
                .as_ref()
                .is_err_and(|f| f.message.starts_with("not allowed"));
            assert_eq!(
                refused_by_table,
                !function.allowed_in(mode),
                "{} in {mode:?}: {result:?}",
                function.name()
            );
        }
    }
}
