"""Certificates over the plane: the cover LP priced over every position (:mod:`planner.certify.plane`, on the
arrangement of coverage regions) and, for connected plans, the ring walk over patches
(:mod:`planner.certify.plane_ring`, :mod:`planner.certify.plane_patches`) and the connected cover over patches refined
where its optimum sits (:mod:`planner.certify.plane_refine`)."""
