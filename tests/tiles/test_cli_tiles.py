"""``planner plan --tiles``: the plan, its summary and plan.json; usage errors exit 2 in one line."""

from __future__ import annotations

import json
from collections.abc import Iterator
from contextlib import contextmanager

import pytest

from planner.cli import main
from tests.conftest import INSTANCES

PLANT = str(INSTANCES / "plant_1ha.json")


@pytest.mark.slow
def test_plan_by_tiles_from_the_command_line(capsys, tmp_path) -> None:
    code = main(
        [
            "plan",
            PLANT,
            "--tiles",
            "50",
            "--set",
            "tile-budget=140",
            "--set",
            "moves-per-piece=0.1",
            "--out",
            str(tmp_path),
            "--quiet",
        ]
    )
    out = capsys.readouterr().out
    assert code == 0
    assert "4 tiles of 50 m, margin 60.0 m" in out  # plant_1ha: anchors span ~66 m -> 2 x 2 tiles; S_max 60 m
    assert "registration: every registration group connected" in out
    assert "verification at 0.1 m: 100.000 % covered" in out
    data = json.loads((tmp_path / "plan.json").read_text())
    assert len(data["stations"]) >= data["bound"] >= 1  # never below the proven bound (over the pool)
    search = data["solver"]["local_search"]  # the local search on the kept plan, as asked
    assert 0 < search["moves_budget"] and search["moves"] <= search["moves_budget"]  # 0.1 move per wall piece
    # the windows come after the search and may take more off (with the axis candidates in the pool: 10 -> 9)
    assert len(data["stations"]) <= search["after"] == search["before"] - search["removed"]


def test_workers_without_tiles_is_a_usage_error(capsys) -> None:
    assert main(["plan", PLANT, "--workers", "2"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--tiles" in err and "--workers = 2" in err
    # the flag given is the one named
    assert main(["plan", PLANT, "--scheduler", "tcp://127.0.0.1:1"]) == 2
    assert "--scheduler = 'tcp://127.0.0.1:1'" in capsys.readouterr().err


def test_tiles_with_greedy_is_a_usage_error(capsys) -> None:
    assert main(["plan", PLANT, "--tiles", "50", "--method", "greedy"]) == 2
    assert "MILP" in capsys.readouterr().err


def test_negative_tile_budget_is_a_usage_error(capsys) -> None:
    assert main(["plan", PLANT, "--tiles", "50", "--set", "tile-budget=-1"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--set tile-budget" in err


def test_bad_window_options_are_usage_errors(capsys) -> None:
    for key, value in (("tile-budget", "-1"), ("tile-budget", "0")):
        assert main(["plan", PLANT, "--tiles", "50", "--set", f"{key}={value}"]) == 2
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and f"--set {key}" in err and value in err


def test_bad_search_options_name_their_key(capsys) -> None:
    # the key's type checks them (and TileOptions again for the library); the one-line error names the key
    for key, value in (("moves-per-piece", "-1"),):
        assert main(["plan", PLANT, "--tiles", "50", "--set", f"{key}={value}"]) == 2
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and f"--set {key}: must be" in err and f"'{value}'" in err


def test_a_scheduler_address_that_is_malformed_or_silent_is_named(capsys, monkeypatch) -> None:
    """A malformed --scheduler address is a usage error (2); one where nothing answers is 'unreachable' (5),
    after CONNECT_TIMEOUT_S (shortened here); both one line quoting the address."""
    import socket

    from planner.tiles import engine

    assert main(["plan", PLANT, "--tiles", "50", "--scheduler", "nonsense"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "'nonsense'" in err and "tcp://HOST:PORT" in err
    monkeypatch.setattr(engine, "CONNECT_TIMEOUT_S", 1.0)
    with socket.socket() as s:  # bound, not listening, and held: no scheduler (nor another test's server) is there
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
        assert main(["plan", PLANT, "--tiles", "50", "--scheduler", f"tcp://127.0.0.1:{port}"]) == 5
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and f"'tcp://127.0.0.1:{port}'" in err and "within 1 s" in err


def test_a_server_that_is_no_dask_scheduler_is_named(capsys, monkeypatch) -> None:
    """Another server on the scheduler's address (the port taken by something else): exit 5, one line, not an
    internal error (Dask reads the server's bytes as a frame length, or asserts on its reply)."""
    from planner.tiles import engine

    monkeypatch.setattr(engine, "CONNECT_TIMEOUT_S", 1.0)
    with _server(b"HTTP/1.1 400 Bad Request\r\n\r\n" * 10) as port:
        assert main(["plan", PLANT, "--tiles", "50", "--scheduler", f"tcp://127.0.0.1:{port}"]) == 5
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and f"'tcp://127.0.0.1:{port}'" in err and "not as a Dask scheduler" in err


@pytest.mark.slow  # 3 s: the wait it tests
def test_a_server_that_accepts_and_never_replies_is_named_and_does_not_hang(capsys, monkeypatch) -> None:
    """Dask's client waits without end for the handshake of a server that accepts and stays silent: the plan gives
    up after HANDSHAKE_WAITS x CONNECT_TIMEOUT_S (3 s here) with exit 5, one line."""
    from planner.tiles import engine

    monkeypatch.setattr(engine, "CONNECT_TIMEOUT_S", 1.0)
    with _server(b"") as port:
        assert main(["plan", PLANT, "--tiles", "50", "--scheduler", f"tcp://127.0.0.1:{port}"]) == 5
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and f"'tcp://127.0.0.1:{port}'" in err and "no Dask scheduler replies" in err


@contextmanager
def _server(reply: bytes) -> Iterator[int]:
    """A local server that answers every connection with ``reply`` (nothing: silent) and holds it open; its port."""
    import socket
    import threading

    with socket.socket() as srv:
        srv.bind(("127.0.0.1", 0))
        srv.listen(8)
        port = srv.getsockname()[1]

        def hold(conn: socket.socket) -> None:
            with conn:
                if reply:
                    conn.sendall(reply)
                try:
                    while conn.recv(1 << 16):  # read and never reply, until the client closes
                        pass
                except OSError:
                    pass

        def answer() -> None:
            while True:
                try:
                    conn, _ = srv.accept()
                except OSError:  # closed: the test is over
                    return
                threading.Thread(target=hold, args=(conn,), daemon=True).start()

        threading.Thread(target=answer, daemon=True).start()
        yield port


def test_a_bad_worker_memory_is_a_usage_error(capsys) -> None:
    for size, why in (("lots", "not a memory size"), ("0", "must be > 0")):
        assert main(["plan", PLANT, "--tiles", "50", "--workers", "1", "--set", f"worker-memory={size}"]) == 2
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and f"'{size}'" in err and why in err
