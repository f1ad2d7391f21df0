"""Figures drawn on two cores (:mod:`planner.figures.forked`, :func:`planner.figures.plan_fig.plan_pngs`): the same
images in the same order whether the later half is drawn in a forked process or here, and a failed process leaves
its half to this one."""

from __future__ import annotations

import os

import pytest

import planner.figures.forked as forked
from planner.figures.base import png_bytes
from planner.figures.plan_fig import plan_figures, plan_pngs


@pytest.mark.parametrize("n", [0, 1, 2, 5])
def test_drawn_keeps_the_order_with_or_without_a_second_core(n: int, monkeypatch: pytest.MonkeyPatch) -> None:
    items = list(range(n))
    monkeypatch.setattr(forked, "thread_count", lambda: 2)
    two = forked.drawn(lambda x: bytes([x, os.getpid() % 256]), items)
    assert [b[0] for b in two] == items
    monkeypatch.setattr(forked, "thread_count", lambda: 1)
    assert forked.drawn(lambda x: bytes([x]), items) == [bytes([x]) for x in items]


def test_a_failed_process_leaves_its_half_here(monkeypatch: pytest.MonkeyPatch) -> None:
    parent = os.getpid()

    def draw(x: int) -> bytes:
        if os.getpid() != parent:
            raise RuntimeError("broken in the forked process")
        return bytes([x])

    monkeypatch.setattr(forked, "thread_count", lambda: 2)
    assert forked.drawn(draw, [1, 2, 3, 4]) == [bytes([1]), bytes([2]), bytes([3]), bytes([4])]


@pytest.mark.slow  # eight plan figures drawn three times
def test_plan_pngs_are_the_same_images_on_one_core_or_two(house_plain, monkeypatch: pytest.MonkeyPatch) -> None:  # type: ignore[no-untyped-def]
    monkeypatch.setattr(forked, "thread_count", lambda: 1)
    one = plan_pngs(house_plain)
    monkeypatch.setattr(forked, "thread_count", lambda: 2)
    two = plan_pngs(house_plain)
    assert len(one) == sum(len(z.scan_side.sides) for z in house_plain.site.zones) >= 3
    assert one == two
    # the figures share one make-up: each takes the first one's layout, as the figures drawn in turn do
    assert [png for _, png in one] == [png_bytes(f) for _, f in plan_figures(house_plain)]
