"""Set cover and connectivity: the MILP and its backends, the greedy, presolve, bounds and certificates."""
