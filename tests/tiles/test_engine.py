"""The task runner: job order kept, serial = Dask, an existing cluster reached by its address."""

from __future__ import annotations

import pytest

from planner.core.errors import UsageError
from planner.tiles.engine import _scatter, dask_client, run_tasks


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


def _weighted_sum(items: list[int], weight: int, job: int) -> int:
    return weight * sum(items) + job


def test_a_shared_list_goes_to_the_workers_as_one_object() -> None:
    # scatter(list) would make one key per element (50,000 candidates on 64 ha swamped the scheduler): each
    # shared value is one key, so the cluster holds 2 keys for 2 shared values, whatever the list's length
    from dask.distributed import LocalCluster

    shared = {"items": list(range(1000)), "weight": 2}
    jobs = [0, 1, 2]
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=":0") as cluster:
        with dask_client(scheduler=cluster.scheduler_address) as client:
            scattered = _scatter(client, shared)
            assert len(client.who_has()) == 2 and set(scattered) == {"items", "weight"}
            # sum(0..999) = 499,500; 2 x 499,500 + job
            assert run_tasks(_weighted_sum, jobs, shared, client) == [999_000, 999_001, 999_002]
