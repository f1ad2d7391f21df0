"""Re-planning on site: a plan repaired after its edits (stations done, blocked or moved, obstacles, closed areas
and zones, the crew's position and the time left today), from the plan's stored pool, in seconds
(:func:`planner.replanning.run.replan`, public as ``planner.replan``; ``planner replan PLAN.json EDITS.json --out
DIR``; docs/field.md, "Re-planning on site"). The stage sits between the command line and the engine: it reads
plans and edits (:mod:`planner.io`), solves (:mod:`planner.solve`), verifies (:mod:`planner.plan`) and walks
(:mod:`planner.field`)."""
