"""Write a small two-storey IFC house with IfcOpenShell's API: instances/house2.ifc.

Ground floor (elevation 0, rooms 2.7 m high): an L-shaped living room with a 0.3 m square column,
a kitchen and a hall with a straight stair (1.0 m wide, 4.2 m long, against the hall's north wall, its body
a block extruded 3.0 m, up to the upper floor); upper floor (elevation 3.0 m, rooms 2.5 m high): a bedroom,
a study and a landing that runs round the stairwell (the stair's footprint), with doors into both rooms.
Walls 0.2 m thick, outer box 12 m x 8 m; seven doors (three between ground-floor rooms, the front
door, three upstairs). The file's length unit is the millimetre, so a reader that assumed metres
would be 1000 times off. Usage::

    python scripts/make/make_ifc_house.py [OUT.ifc] [--schema IFC4|IFC2X3]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

Ring = list[tuple[float, float]]

#: metres; (name, elevation, room height, rooms, walls, doors, columns)
GROUND: dict = {
    "name": "Ground floor",
    "elevation": 0.0,
    "height": 2.7,
    "rooms": {
        "Living": [(0.2, 0.2), (7.9, 0.2), (7.9, 4.0), (4.0, 4.0), (4.0, 7.8), (0.2, 7.8)],
        "Kitchen": [(8.1, 0.2), (11.8, 0.2), (11.8, 4.0), (8.1, 4.0)],
        "Hall": [(4.2, 4.2), (11.8, 4.2), (11.8, 7.8), (4.2, 7.8)],
    },
    "walls": [(7.9, 0.2, 8.1, 4.0), (4.0, 4.0, 12.0, 4.2), (4.0, 4.2, 4.2, 8.0)],
    "doors": {
        "D-living-kitchen": (7.9, 1.5, 8.1, 2.4),
        "D-kitchen-hall": (9.5, 4.0, 10.4, 4.2),
        "D-living-hall": (4.0, 5.5, 4.2, 6.4),
        "D-front": (11.8, 5.5, 12.0, 6.5),
    },
    "columns": {"C1": (2.0, 2.0, 2.3, 2.3)},
    # (x0, y0, x1, y1, rise m): the flight climbs east from x = 6.1 to its top at x = 10.3
    "stairs": {"S-hall-landing": (6.1, 6.8, 10.3, 7.8, 3.0)},
    "windows": {"W-kitchen": (9.5, 0.0, 10.7, 0.2)},  # written only with build_house(..., windows=True)
}
UPPER: dict = {
    "name": "Upper floor",
    "elevation": 3.0,
    "height": 2.5,
    "rooms": {
        "Bedroom": [(0.2, 0.2), (5.9, 0.2), (5.9, 7.8), (0.2, 7.8)],
        "Study": [(6.1, 0.2), (11.8, 0.2), (11.8, 5.0), (6.1, 5.0)],
        # round the stairwell 6.1..10.3 x 6.8..7.8 (the stair's footprint): the stair arrives at x = 10.3
        "Landing": [(6.1, 5.2), (11.8, 5.2), (11.8, 7.8), (10.3, 7.8), (10.3, 6.8), (6.1, 6.8)],
    },
    "walls": [(5.9, 0.0, 6.1, 8.0), (6.1, 5.0, 11.8, 5.2)],
    "doors": {
        "D-bedroom-study": (5.9, 3.0, 6.1, 3.9),
        "D-landing-study": (7.0, 5.0, 7.9, 5.2),
        "D-landing-bedroom": (5.9, 5.6, 6.1, 6.5),
    },
    "columns": {},
    "stairs": {},
}
OUTER_WALLS = [(0.0, 0.0, 12.0, 0.2), (11.8, 0.0, 12.0, 8.0), (0.0, 7.8, 12.0, 8.0), (0.0, 0.0, 0.2, 8.0)]
DOOR_HEIGHT_M = 2.1
WINDOW_SILL_M, WINDOW_HEIGHT_M = 0.9, 1.2
MM = 1000.0


def _box(x0: float, y0: float, x1: float, y1: float) -> Ring:
    return [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]


def build_house(
    path: Path | str,
    schema: str = "IFC4",
    *,
    spaces: bool = True,
    faceless_space: str | None = None,
    windows: bool = False,
) -> Path:
    """Write the house to ``path`` and return it.

    ``spaces=False`` leaves the rooms out (a model the planner must refuse); ``faceless_space``
    names a room written without geometry; ``windows=True`` adds the ground floor's ``WINDOWS`` (the
    bundled house2.ifc has none).
    """
    import ifcopenshell
    import ifcopenshell.api
    from ifcopenshell.util.shape_builder import ShapeBuilder

    f = ifcopenshell.api.run("project.create_file", version=schema)
    run = ifcopenshell.api.run
    if schema == "IFC2X3":
        _owner(f)
    project = run("root.create_entity", f, ifc_class="IfcProject", name="planner test house")
    length = run("unit.add_si_unit", f, unit_type="LENGTHUNIT", prefix="MILLI")
    run("unit.assign_unit", f, units=[length])
    model = run("context.add_context", f, context_type="Model")
    body = run(
        "context.add_context",
        f,
        context_type="Model",
        context_identifier="Body",
        target_view="MODEL_VIEW",
        parent=model,
    )
    site = run("root.create_entity", f, ifc_class="IfcSite", name="Site")
    building = run("root.create_entity", f, ifc_class="IfcBuilding", name="House")
    run("aggregate.assign_object", f, products=[site], relating_object=project)
    run("aggregate.assign_object", f, products=[building], relating_object=site)
    builder = ShapeBuilder(f)

    def solid(product: object, ring: Ring, height_m: float, z_m: float) -> None:
        curve = builder.polyline([(x * MM, y * MM) for x, y in ring], closed=True)
        rep = builder.get_representation(body, [builder.extrude(curve, height_m * MM)])
        run("geometry.assign_representation", f, product=product, representation=rep)
        matrix = np.eye(4)
        matrix[2, 3] = z_m
        run("geometry.edit_object_placement", f, product=product, matrix=matrix, is_si=True)

    for level in (GROUND, UPPER):
        storey = run("root.create_entity", f, ifc_class="IfcBuildingStorey", name=level["name"])
        storey.Elevation = level["elevation"] * MM
        run("aggregate.assign_object", f, products=[storey], relating_object=building)
        z, h = level["elevation"], level["height"]
        if spaces:
            for name, ring in level["rooms"].items():
                space = run("root.create_entity", f, ifc_class="IfcSpace", name=name[:3].upper())
                space.LongName = name
                run("aggregate.assign_object", f, products=[space], relating_object=storey)
                if name != faceless_space:
                    solid(space, ring, h, z)
        contained = []
        for k, w in enumerate(OUTER_WALLS + level["walls"], 1):
            wall = run("root.create_entity", f, ifc_class="IfcWall", name=f"W{k}")
            solid(wall, _box(*w), h, z)
            contained.append(wall)
        for name, d in level["doors"].items():
            door = run("root.create_entity", f, ifc_class="IfcDoor", name=name)
            solid(door, _box(*d), DOOR_HEIGHT_M, z)
            contained.append(door)
        for name, wbox in (level.get("windows", {}) if windows else {}).items():
            window = run("root.create_entity", f, ifc_class="IfcWindow", name=name)
            solid(window, _box(*wbox), WINDOW_HEIGHT_M, z + WINDOW_SILL_M)
            contained.append(window)
        for name, c in level["columns"].items():
            column = run("root.create_entity", f, ifc_class="IfcColumn", name=name)
            solid(column, _box(*c), h, z)
            contained.append(column)
        for name, (*box, rise) in level["stairs"].items():
            stair = run("root.create_entity", f, ifc_class="IfcStair", name=name)
            solid(stair, _box(*box), rise, z)
            contained.append(stair)
        run("spatial.assign_container", f, products=contained, relating_structure=storey)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    f.write(str(path))
    return path


def _owner(f: object) -> None:
    """IFC2X3 needs an owner history on every rooted entity: a person, an organisation, an application."""
    import ifcopenshell.api
    import ifcopenshell.api.owner.settings as owner

    run = ifcopenshell.api.run
    person = run("owner.add_person", f, identification="planner", family_name="Planner", given_name="Test")
    org = run("owner.add_organisation", f, identification="TLS", name="tls-planner")
    user = run("owner.add_person_and_organisation", f, person=person, organisation=org)
    app = run("owner.add_application", f)
    owner.get_user = lambda _f: user
    owner.get_application = lambda _f: app


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", nargs="?", default="instances/house2.ifc")
    ap.add_argument("--schema", default="IFC4", choices=("IFC4", "IFC2X3"))
    args = ap.parse_args()
    print(f"wrote {build_house(args.out, args.schema)}")


if __name__ == "__main__":
    main()
