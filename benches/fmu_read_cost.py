"""What reading the outputs costs against a 1 ms communication step, through fmpy.

    cargo run --release --bin package-fmu
    .venv/bin/python benches/fmu_read_cost.py [--steps 2000] [--batches 200] [--fmu target/fmu/PlateImpact.fmu]

Runs the paper's forced scene at 35 Hz (10 x 7 Argyris mesh, internal step 0.1 ms, ten internal
steps per doStep) and times, after every doStep: the doStep itself, reading the Real outputs one
value reference per fmi2GetReal call (as some hosts do), reading every output (Real and Integer)
in two calls through fmpy's wrappers, the same two calls straight through ctypes with arrays made
once, and two empty calls (nvr = 0: the FMU checks the call and returns) as the floor of what
Python pays per call. Prints the medians (microseconds) and each read's ratio to the step. The FMU
computes its outputs once per step and serves reads from that cache; its own cost of reading
every output is the raw calls minus the empty ones, and the target is under 10 % of a step.

Then, after the last step, a parameter read: fmi2GetReal of `plate.thickness` (one value per raw
ctypes call) and, interleaved with it, the empty call, each in batches of 1000 calls; prints the
median over --batches batches of the time per call. The exit status looks only at the outputs.
"""

import argparse
import ctypes
import pathlib
import statistics
import sys
import time

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

ROOT = pathlib.Path(__file__).resolve().parents[1]


def main():
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--fmu", default=str(ROOT / "target" / "fmu" / "PlateImpact.fmu"))
    parser.add_argument("--steps", type=int, default=2000)
    parser.add_argument("--batches", type=int, default=200, help="batches of 1000 parameter reads")
    args = parser.parse_args()
    md = read_model_description(args.fmu)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    reals = [
        v.valueReference for v in md.modelVariables if v.causality == "output" and v.type == "Real"
    ]
    integers = [
        v.valueReference
        for v in md.modelVariables
        if v.causality == "output" and v.type == "Integer"
    ]
    fmu = FMU2Slave(
        guid=md.guid,
        unzipDirectory=extract(args.fmu),
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="cost",
    )
    fmu.instantiate()
    fmu.setupExperiment(startTime=0.0)
    fmu.setReal([vr["base.amplitude"], vr["base.frequency"]], [0.009, 35.0])
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    real_refs = (ctypes.c_uint * len(reals))(*reals)
    real_values = (ctypes.c_double * len(reals))()
    int_refs = (ctypes.c_uint * len(integers))(*integers)
    int_values = (ctypes.c_int * len(integers))()
    step, one_by_one, all_at_once, raw, empty = [], [], [], [], []
    t, h = 0.0, 1e-3
    clock = time.perf_counter
    for _ in range(args.steps):
        a = clock()
        fmu.doStep(t, h)
        b = clock()
        for r in reals:
            fmu.getReal([r])
        c = clock()
        fmu.getReal(reals)
        fmu.getInteger(integers)
        d = clock()
        assert fmu.fmi2GetReal(fmu.component, real_refs, len(reals), real_values) == 0
        assert fmu.fmi2GetInteger(fmu.component, int_refs, len(integers), int_values) == 0
        e = clock()
        fmu.fmi2GetReal(fmu.component, real_refs, 0, real_values)
        fmu.fmi2GetInteger(fmu.component, int_refs, 0, int_values)
        f = clock()
        t += h
        step.append(b - a)
        one_by_one.append(c - b)
        all_at_once.append(d - c)
        raw.append(e - d)
        empty.append(f - e)
    param_ref = (ctypes.c_uint * 1)(vr["plate.thickness"])
    param_value = (ctypes.c_double * 1)()
    assert fmu.fmi2GetReal(fmu.component, param_ref, 1, param_value) == 0
    assert param_value[0] == 0.01, param_value[0]  # the default: a read of the parameter itself
    batch, param, param_empty = 1000, [], []
    for _ in range(args.batches):
        a = clock()
        for _ in range(batch):
            fmu.fmi2GetReal(fmu.component, param_ref, 1, param_value)
        b = clock()
        for _ in range(batch):
            fmu.fmi2GetReal(fmu.component, param_ref, 0, param_value)
        c = clock()
        param.append((b - a) / batch)
        param_empty.append((c - b) / batch)
    fmu.terminate()
    fmu.freeInstance()
    median = {
        name: 1e6 * statistics.median(x)
        for name, x in [
            ("doStep", step),
            ("one by one", one_by_one),
            ("2 reads", all_at_once),
            ("2 raw", raw),
            ("2 empty", empty),
        ]
    }
    labels = {
        "doStep": "doStep (1 ms, 10 internal steps)",
        "one by one": f"{len(reals)} Real outputs, one fmpy getReal each",
        "2 reads": "every output, fmpy getReal + getInteger",
        "2 raw": "every output, 2 raw ctypes calls",
        "2 empty": "2 empty raw ctypes calls (call overhead)",
    }
    print(f"forced-35hz through fmpy, medians over {args.steps} communication steps:")
    for name, us in median.items():
        ratio = "" if name == "doStep" else f"  {100 * us / median['doStep']:5.1f} % of a step"
        print(f"  {labels[name]:42s} {us:7.2f} us{ratio}")
    own = median["2 raw"] - median["2 empty"]
    ratio = own / median["doStep"]
    print(
        f"the FMU's own cost of reading every output: {own:.2f} us, {100 * ratio:.1f} % of a 1 ms step (target < 10 %)"
    )
    read, call = 1e6 * statistics.median(param), 1e6 * statistics.median(param_empty)
    print(
        f"parameter read (plate.thickness, one raw fmi2GetReal per call), medians over {args.batches} batches "
        f"of {batch} calls: {read:.2f} us per call, {call:.2f} us for the empty call, the FMU's own {read - call:.2f} us"
    )
    sys.exit(0 if ratio < 0.10 else 1)


if __name__ == "__main__":
    main()
