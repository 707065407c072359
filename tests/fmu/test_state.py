"""FMU state: get/set, serialize into a fresh instance, reset; corrupt bytes are refused."""

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException

FORCED = {"base.amplitude": 0.009, "base.frequency": 10.0}
H = 1e-3


def run(plate, steps, load=None):
    rows = []
    for k in range(steps):
        plate.set("base.displacement", 5e-4 * np.sin(0.37 * k))
        if load is not None:
            plate.set("load.pressure", load * k)
        plate.step(H)
        rows.append(plate.outputs() + [plate.get("contact.active_nodes")])
    return np.array(rows)


def test_get_set_state_continues_bit_identically(new_plate):
    p = new_plate().initialize(FORCED)
    run(p, 50)
    t0 = p.time
    state = p.fmu.getFMUstate()
    first = run(p, 60, load=10.0)
    p.fmu.setFMUstate(state)
    p.time = t0
    again = run(p, 60, load=10.0)
    assert first.tobytes() == again.tobytes()
    p.fmu.freeFMUstate(state)


def test_serialized_state_continues_bit_identically_in_a_fresh_instance(new_plate):
    p = new_plate("a").initialize(FORCED)
    run(p, 40)
    t0 = p.time
    state = p.fmu.getFMUstate()
    data = p.fmu.serializeFMUstate(state)
    expected = run(p, 60)

    q = new_plate("b").initialize()  # default parameters: the state brings its own
    restored = q.fmu.deSerializeFMUstate(data)
    q.fmu.setFMUstate(restored)
    q.time = t0
    assert q.get("base.amplitude") == 0.009
    assert run(q, 60).tobytes() == expected.tobytes()

    r = new_plate("c")  # not even initialized
    r.fmu.setFMUstate(r.fmu.deSerializeFMUstate(data))
    r.time = t0
    assert run(r, 60).tobytes() == expected.tobytes()


def test_reset_returns_to_the_start_values(new_plate):
    p = new_plate().initialize(FORCED)
    run(p, 20)
    p.fmu.reset()
    p.initialize()
    assert p.get("base.amplitude") == 0.0
    assert p.get("corner1.displacement") == 0.0
    fresh = new_plate("fresh").initialize()
    assert run(p, 20).tobytes() == run(fresh, 20).tobytes()


@pytest.mark.parametrize(
    "corrupt",
    [
        lambda b: b[:-1],
        lambda b: b[:10],
        lambda b: b"",
        lambda b: b + b"\0",
        lambda b: bytes([b[0] ^ 1]) + b[1:],
        lambda b: b[:8] + bytes([99]) + b[9:],
        lambda b: b[: len(b) // 2] + bytes([b[len(b) // 2] ^ 0x20]) + b[len(b) // 2 + 1 :],
        lambda b: b"\xff" * 200,
    ],
    ids=["truncated", "header-only", "empty", "trailing", "magic", "version", "payload", "garbage"],
)
def test_corrupt_serialized_state_is_an_error(new_plate, corrupt):
    p = new_plate().initialize(FORCED)
    run(p, 5)
    data = p.fmu.serializeFMUstate(p.fmu.getFMUstate())
    with pytest.raises(FMICallException) as e:
        p.fmu.deSerializeFMUstate(corrupt(bytes(data)))
    assert e.value.status == 3
    assert any("serialized FMU state" in m for m in p.errors()), p.messages
    run(p, 5)  # the instance is untouched
