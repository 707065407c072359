"""Several instances in one process, and instances stepped from several threads."""

from concurrent.futures import ThreadPoolExecutor

import numpy as np

CASES = [
    {"base.amplitude": 0.009, "base.frequency": 10.0},
    {"base.amplitude": 0.005, "base.frequency": 30.0, "solver.restitution": 0.5},
    {"load.pressure": 2e5, "obstacle.lower": -0.004},
    {"initial.preload_pressure": 1e5, "obstacle.upper_enabled": False},
]


def trajectory(plate, steps=150):
    rows = []
    for _ in range(steps):
        plate.step(1e-3)
        rows.append(plate.outputs())
    return np.array(rows)


def test_instances_with_different_parameters_do_not_interfere(new_plate):
    alone = [trajectory(new_plate(f"alone{i}").initialize(c)) for i, c in enumerate(CASES)]
    together = [new_plate(f"together{i}").initialize(c) for i, c in enumerate(CASES)]
    rows = [[] for _ in CASES]
    for _ in range(150):  # interleaved steps
        for i, p in enumerate(together):
            p.step(1e-3)
            rows[i].append(p.outputs())
    for a, r in zip(alone, rows):
        assert a.tobytes() == np.array(r).tobytes()
    assert not np.array_equal(alone[0], alone[1])


def test_instances_on_threads_match_one_instance_alone(new_plate):
    alone = [trajectory(new_plate(f"seq{i}").initialize(c)) for i, c in enumerate(CASES)]
    plates = [new_plate(f"thread{i}") for i in range(len(CASES))]

    def work(i):
        return trajectory(plates[i].initialize(CASES[i]))

    with ThreadPoolExecutor(max_workers=len(CASES)) as pool:
        threaded = list(pool.map(work, range(len(CASES))))
    for a, t in zip(alone, threaded):
        assert a.tobytes() == t.tobytes()
