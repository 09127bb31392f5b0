"""Scale-out from Python: a parameter sweep with signorini.run as the task
of a dask.distributed LocalCluster (worker processes) gives the same
numbers as the same runs in this process (skipped without dask)."""

import pickle

import numpy as np
import pytest

import signorini

distributed = pytest.importorskip("dask.distributed")


def scene(omega):
    return {
        "oscillator": {"mass": 1.0, "stiffness": 1.0, "damping_ratio": 0.05, "stop": 0.2, "restitution": 0.8, "dt": 1e-3, "t_end": 60.0},
        "forcing": {"amplitude": 1.0, "omega": omega},
    }


def impacts(omega):
    """The task: one run, reduced to what a sweep keeps."""
    r = signorini.run(scene(omega))
    return omega, r.contact_steps, float(np.abs(r.tip).max()), r


def test_result_pickles():
    r = signorini.run(scene(1.8))
    back = pickle.loads(pickle.dumps(r))
    assert np.array_equal(back.tip, r.tip) and back.status == r.status and back.contact_dofs == r.contact_dofs


def test_a_sweep_through_a_local_cluster_gives_the_local_numbers():
    omegas = [1.6, 1.8, 2.0, 2.2]
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        got = client.gather(client.map(impacts, omegas))
    for (w, n, amp, r), w0 in zip(got, omegas):
        _, n0, amp0, r0 = impacts(w0)
        assert w == w0 and n == n0 and amp == amp0 and np.array_equal(r.tip, r0.tip)
    # The sweep saw impacts (the gap is inside the response).
    assert all(n > 0 for _, n, _, _ in got)
