"""``planner network`` on a plan across storeys (issue 46, step 3): instances/house2.ifc read with ``--storey all``
gives one connected survey network, the two storeys joined by the registration links through the stair
(:mod:`planner.coverage.stair_links`: a Hall station and a Landing station that see the stair's edge), with its
accuracy check; the control traverse stays within each storey."""

from __future__ import annotations

import json

import pytest

from planner.cli import main
from tests.conftest import INSTANCES


@pytest.mark.slow
def test_house2_all_storeys_is_one_network(tmp_path, capsys):
    site = str(INSTANCES / "house2.ifc")
    assert main(["plan", site, "--storey", "all", "--out", str(tmp_path)]) == 0
    assert main(["network", site, str(tmp_path / "plan.json"), "--storey", "all", "--out", str(tmp_path)]) == 0
    text = capsys.readouterr().out
    assert "accuracy check at 10 mm (single precision): PASS" in text
    assert "survey network: 1 registration part(s)" in text
    d = json.loads((tmp_path / "network.json").read_text())
    frame = {n["id"]: n.get("frame") for n in d["nodes"]}
    zone = {n["id"]: n.get("zone") for n in d["nodes"]}
    assert len(d["diagnostics"]["components"]) == 1
    across = [e for e in d["edges"] if frame[e["from"]] != frame[e["to"]]]
    assert across and all(e["kinds"] == ["registration"] for e in across)  # only registration crosses storeys
    assert {frozenset((zone[e["from"]], zone[e["to"]])) for e in across} == {
        frozenset(("Ground floor/Hall", "Upper floor/Landing"))  # the stair's lower and upper zone
    }
    assert len(d["survey"]["parts"]) == 1
