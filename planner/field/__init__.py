"""The field sheet of a plan: walking distances inside the accessible area (:mod:`~planner.field.walking`,
across storeys :mod:`~planner.field.storeys`, legs through walls :mod:`~planner.field.crossing`), the visiting
order with its lower bound (:mod:`~planner.field.order`, :mod:`~planner.field.bound`,
:mod:`~planner.field.scip_order`, :mod:`~planner.field.certify`), the field time (:mod:`~planner.field.timing`),
registration targets (:mod:`~planner.field.targets`, :mod:`~planner.field.spread`), all made by
:mod:`~planner.field.run`, and the files (:mod:`~planner.field.sheet`).

Planning, not the sheet: :mod:`~planner.field.tradeoff` (the field-time trade-off of plans) and
:mod:`~planner.field.route_search` (stations moved to shorten the walk) time whole plans by the sheet's walk, so
they stand above it; the plan stage lies below the sheet and may not import it.
"""
