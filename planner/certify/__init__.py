"""Certificates over the plane: the cover LP priced over every position (:mod:`planner.certify.plane`, on the
arrangement of coverage regions) and the ring walk over patches for connected plans
(:mod:`planner.certify.plane_ring`, :mod:`planner.certify.plane_patches`)."""
