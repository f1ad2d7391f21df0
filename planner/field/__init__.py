"""The field sheet of a plan: walking distances inside the accessible area, the visiting order
(shortest or registration order) with a lower bound, the field time, registration targets, and the sheet
(field.html, field.csv, field.geojson, field.json, field.pdf).

Modules: :mod:`~planner.instrument.field_table` (an instrument's field properties), :mod:`~planner.field.walking`
(walkable area, visibility graph, walking distances), :mod:`~planner.field.order` (OR-Tools routing),
:mod:`~planner.field.bound` (Held-Karp 1-tree bound, exact DP), :mod:`~planner.field.timing` (field time,
sessions), :mod:`~planner.field.crossing` (legs through walls where the model has no opening),
:mod:`~planner.field.targets` (registration targets), :mod:`~planner.field.spread` (three targets spread apart),
:mod:`~planner.field.sheet` (the files: :mod:`~planner.field.tables`, :mod:`~planner.field.figure`,
:mod:`~planner.field.page` with its site map :mod:`~planner.field.site_map`, :mod:`~planner.field.record`
(field.json), :mod:`~planner.field.pdf`).
This package file imports nothing, so :mod:`planner.instrument.models` can read field properties cheaply.
"""
