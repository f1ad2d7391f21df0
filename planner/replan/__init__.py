"""Re-planning on site: a plan repaired after its edits (stations done, blocked or moved, obstacles, closed areas
and zones, the crew's position and the time left today), from the plan's stored pool, in seconds
(:func:`replan`; ``planner replan PLAN.json EDITS.json --out DIR``; docs/field.md, "Re-planning on site")."""

from planner.replan.run import Replan, replan

__all__ = ["Replan", "replan"]
