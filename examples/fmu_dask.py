"""Running the packaged PlateImpact FMU as Dask tasks: shared by the frequency sweep
(examples/studies/frequency_sweep.py) and the convergence study (examples/converge.py, scripts/converge).

A task is a function called as function(fmu_blob, digest, *args) on a worker, returning
(result, seconds). The FMU's bytes are scattered to the workers once (`run_tasks`) and unpacked
once per machine (`fmu_dir`), so workers on other machines need nothing but fmpy and this file,
which `run_tasks` uploads to them with the modules of the task functions.
"""

import contextlib
import hashlib
import io
import os
import pathlib
import shutil
import sys
import tempfile
import time
import zipfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
DEFAULT_FMU = ROOT / "target" / "fmu" / "PlateImpact.fmu"
ELEMENT = {"argyris": 1, "fvs": 2}

_EXTRACTED = {}


def fmu_dir(fmu_blob, digest):
    """The FMU unpacked once per machine, keyed by its content digest (workers may be remote)."""
    if digest in _EXTRACTED:
        return _EXTRACTED[digest]
    target = pathlib.Path(tempfile.gettempdir()) / f"plateimpact-fmu-{digest[:16]}"
    if not (target / "modelDescription.xml").exists():
        staging = pathlib.Path(tempfile.mkdtemp(prefix="plateimpact-fmu-"))
        with zipfile.ZipFile(io.BytesIO(fmu_blob)) as archive:
            archive.extractall(staging)
        try:
            os.rename(staging, target)  # atomic; another process may have won the race
        except OSError:
            shutil.rmtree(staging, ignore_errors=True)
    _EXTRACTED[digest] = str(target)
    return str(target)


def run_tasks(fmu_path, tasks, client, describe=None):
    """Calls function(fmu_blob, digest, *args) for each task (key, function, args), serially when
    client is None, else as Dask tasks (the FMU scattered to the workers once). Returns
    {key: result}; each function returns (result, seconds: wall or CPU time of the run). With
    `describe`, prints describe(key, result) and the seconds as each task finishes, and the total
    at the end."""
    fmu_blob = pathlib.Path(fmu_path).read_bytes()
    digest = hashlib.sha256(fmu_blob).hexdigest()
    done = {}
    started = time.perf_counter()

    def report(key, result, seconds):
        done[key] = result
        if describe:
            print(f"[{len(done):>{len(str(len(tasks)))}}/{len(tasks)}] {describe(key, result)} "
                  f"({seconds:.2f} s)", file=sys.stderr, flush=True)

    if client is None:
        for key, function, args in tasks:
            report(key, *function(fmu_blob, digest, *args))
    else:
        from distributed import as_completed
        ship_modules(client, [function for _, function, _ in tasks])
        # A unique key per call: under the default key, a hash of the content, every call
        # scatters the same FMU under the same key, and the release of the previous call's future
        # can reach the scheduler after the new scatter and drop the data under the new tasks
        # (Dask then cancels them for "lost dependencies"; tests/fmu/test_fmu_dask.py).
        blob = client.scatter(fmu_blob, broadcast=True, hash=False)
        futures = {client.submit(function, blob, digest, *args, pure=False): key
                   for key, function, args in tasks}
        for future in as_completed(futures):
            report(futures[future], *future.result())
    if describe:
        print(f"{len(tasks)} tasks in {time.perf_counter() - started:.1f} s", file=sys.stderr)
    return done


def ship_modules(client, functions):
    """Lets workers, local or remote, run the tasks' functions. A function of a script run as
    __main__ is pickled by value, one of an imported module by reference to the module, which the
    workers then need; either may call into this module, pickled by reference too. upload_file
    sends each such file to every worker (and to the scheduler, which runs in this process on a
    LocalCluster); load=True would reload it in this process too."""
    files = {__file__}
    for function in functions:
        module = sys.modules[function.__module__]
        if module.__name__ != "__main__":
            files.add(module.__file__)
    for path in sorted(files, key=lambda p: p != __file__):  # this module first: others import it
        client.upload_file(path, load=False)


def local_cluster(workers):
    """A LocalCluster of single-threaded worker processes (one FMU run each at a time).

    The workers' statistical profiler is off: it samples the task thread's Python stack every
    10 ms, and fmpy's per-step loop is Python, so with it on 2 workers on 2 cores were no faster
    than one serial process (measured: 8.5 s against 7.8 s; 5.1 s with it off)."""
    import dask
    from distributed import LocalCluster
    with dask.config.set({"distributed.worker.profile.enabled": False}):
        return LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                            dashboard_address=None)


@contextlib.contextmanager
def dask_client(scheduler=None, workers=None, serial=False):
    """A Dask client of the scheduler at `scheduler`, or of a LocalCluster of `workers` processes
    (default: the cores), or None with `serial`; closed (with the cluster) on exit."""
    if serial:
        yield None
        return
    from distributed import Client
    if scheduler:
        with Client(scheduler) as client:
            yield client
        return
    with local_cluster(workers or os.cpu_count()) as cluster, Client(cluster) as client:
        yield client


def parse_value(name, text, variables):
    """The start value `text` of the FMU variable `name` as its type wants it (`variables`: name
    -> fmpy ScalarVariable); `mesh.element` also takes the element's name."""
    kind = variables[name].type if name in variables else None
    if kind is None:
        raise SystemExit(f"{name} is not a variable of the FMU")
    if kind == "Boolean":
        if str(text).lower() not in ("true", "false", "1", "0"):
            raise SystemExit(f"{name} is Boolean: true or false, not {text}")
        return str(text).lower() in ("true", "1")
    if kind == "Enumeration" or name == "mesh.element":
        return ELEMENT[text] if text in ELEMENT else int(text)
    if kind == "Integer":
        return int(text)
    return float(text)
