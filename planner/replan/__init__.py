"""Re-planning on site: a plan repaired after its edits (stations done, blocked or moved, obstacles, closed areas
and zones, the crew's position and the time left today), from the plan's stored pool, in seconds
(:func:`planner.replan.run.replan`, also ``planner.replan``; ``planner replan PLAN.json EDITS.json --out DIR``;
docs/field.md, "Re-planning on site").

This ``__init__`` loads nothing: ``planner.replan`` is the function (as ``planner.solve`` is), and the package is
bound first so that loading its modules never rebinds the name."""
