"""The task runner: job order kept, serial = Dask, an existing cluster reached by its address."""

from __future__ import annotations

import pytest

from planner.errors import UsageError
from planner.tiles.engine import dask_client, run_tasks


def _square_plus(offset: int, job: int) -> int:
    return job * job + offset


def test_serial_and_existing_cluster_give_the_same_results_in_job_order() -> None:
    from dask.distributed import LocalCluster

    jobs = [5, 1, 4, 2, 3]
    serial = run_tasks(_square_plus, jobs, {"offset": 10})
    assert serial == [35, 11, 26, 14, 19]  # j*j + 10 in the order given
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=":0") as cluster:
        with dask_client(scheduler=cluster.scheduler_address) as client:
            assert run_tasks(_square_plus, jobs, {"offset": 10}, client) == serial


def test_zero_workers_is_a_usage_error() -> None:
    with pytest.raises(UsageError):
        with dask_client(workers=0):
            pass
