"""Set cover and connectivity over a candidate pool: the MILP and its backends, the greedy, presolve and pool bounds.
Pure set cover: no site geometry (the plane certificates are in :mod:`planner.bounds`)."""
