"""Lower bounds that certify a plan beyond its own solve: over the plane, the cover LP priced over every position
(:mod:`planner.bounds.plane`, on the arrangement of coverage regions) and, for connected plans, the ring walk over
patches (:mod:`planner.bounds.plane_ring`, :mod:`planner.bounds.plane_patches`) and the connected cover over patches
refined where its optimum sits (:mod:`planner.bounds.plane_refine`); over a large site's pool, the Lagrangian bound over
its tiles (:mod:`planner.bounds.lagrange`).

The MILP's own bounds inside a block (the ring bound of a zone-side and the tree bound) stay with the solver that uses
them (:mod:`planner.solve.ring`, :mod:`planner.solve.treebound`): the solver imports them, and these modules import the
solver, so one package for both would be an import cycle.
"""
