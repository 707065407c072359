"""The Dask task runner shared by the frequency sweep and scripts/converge
(plateimpact_tools.fmu_dask)."""

import pytest

from plateimpact_tools.fmu_dask import local_cluster, run_tasks


def blob_length(blob, digest, offset):
    """A task in run_tasks' form: the scattered blob's length plus `offset`, and zero seconds."""
    return len(blob) + offset, 0.0


def test_back_to_back_calls_keep_the_scattered_blob(tmp_path):
    # scripts/converge calls run_tasks once per ladder rung, each scattering the same FMU. Under a
    # key derived from the content, the release of one call's future raced with the next call's
    # scatter and the scheduler dropped the data under the new tasks ("lost dependencies", seen in
    # CI). With the content-hashed key this test failed in each of 6 runs on a 2-core machine.
    distributed = pytest.importorskip("distributed")
    path = tmp_path / "blob.bin"
    path.write_bytes(b"\x00" * 4096)
    with local_cluster(2) as cluster, distributed.Client(cluster) as client:
        for call in range(300):
            done = run_tasks(path, [(k, blob_length, (k,)) for k in range(2)], client)
            assert done == {0: 4096, 1: 4097}, f"call {call}"
