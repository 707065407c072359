"""Running the packaged PlateImpact FMU as Dask tasks: shared by the frequency sweep
(`plateimpact_tools.studies.frequency_sweep`) and the convergence study (`plateimpact_tools.converge`,
scripts/converge).

A task is a function called as function(fmu_blob, digest, *args) on a worker, returning
(result, seconds). The FMU's bytes are scattered to the workers once (`run_tasks`) and unpacked
once per machine (`fmu_dir`), so workers on other machines need nothing but fmpy, numpy and this
package, which `run_tasks` uploads to them (`ship_package`).
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

# digest of an FMU -> the directory it was unpacked to, once per process.
_EXTRACTED: dict[str, str] = {}
_SHIPPED: set[str] = set()  # the ids of the clients whose workers have the package (`ship_package`)


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
            print(
                f"[{len(done):>{len(str(len(tasks)))}}/{len(tasks)}] {describe(key, result)} "
                f"({seconds:.2f} s)",
                file=sys.stderr,
                flush=True,
            )

    if client is None:
        for key, function, args in tasks:
            report(key, *function(fmu_blob, digest, *args))
    else:
        from distributed import as_completed

        ship_package(client)
        # A unique key per call: under the default key, a hash of the content, every call
        # scatters the same FMU under the same key, and the release of the previous call's future
        # can reach the scheduler after the new scatter and drop the data under the new tasks
        # (Dask then cancels them for "lost dependencies"; tests/fmu/test_fmu_dask.py).
        blob = client.scatter(fmu_blob, broadcast=True, hash=False)
        futures = {
            client.submit(function, blob, digest, *args, pure=False): key
            for key, function, args in tasks
        }
        for future in as_completed(futures):
            report(futures[future], *future.result())
    if describe:
        print(f"{len(tasks)} tasks in {time.perf_counter() - started:.1f} s", file=sys.stderr)
    return done


def ship_package(client):
    """Lets the workers of `client` import this package, wherever they run. A local cluster's
    workers are processes of this Python, which has the package installed: nothing to do. Else
    the package's modules go to the scheduler and every worker as one zip (Dask's upload_file puts
    it first on their sys.path and imports it), so a remote worker needs only fmpy and numpy."""
    if getattr(client, "cluster", None) is not None or client.id in _SHIPPED:
        return  # a cluster this client started (a LocalCluster of this environment), or done
    package = pathlib.Path(__file__).resolve().parent
    with tempfile.TemporaryDirectory(prefix="plateimpact-tools-") as tmp:
        archive = pathlib.Path(tmp) / "plateimpact_tools.zip"
        with zipfile.ZipFile(archive, "w") as z:
            for path in sorted(package.rglob("*.py")):
                z.write(path, path.relative_to(package.parent).as_posix())
        client.upload_file(str(archive), load=True)
    _SHIPPED.add(client.id)


def local_cluster(workers):
    """A LocalCluster of single-threaded worker processes (one FMU run each at a time).

    The workers' statistical profiler is off: it samples the task thread's Python stack every
    10 ms, and fmpy's per-step loop is Python, so with it on 2 workers on 2 cores were no faster
    than one serial process (measured: 8.5 s against 7.8 s; 5.1 s with it off)."""
    import dask
    from distributed import LocalCluster

    with dask.config.set({"distributed.worker.profile.enabled": False}):
        return LocalCluster(
            n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None
        )


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
