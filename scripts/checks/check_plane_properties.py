"""The plane property tests (tests/bounds/test_plane_properties.py, and the refined connected bound's in
tests/bounds/test_plane_refine.py) at a larger scale: more examples
(derandomised as in CI, so a run is repeatable) and corridors up to 300 m long.

    python scripts/checks/check_plane_properties.py [--scale 10] [--corridor-m 300]

Exit status: pytest's (0: every property held on every example).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scale", type=float, default=10.0, help="examples per property, times the CI counts (default 10)")
    ap.add_argument("--corridor-m", type=float, default=300.0, help="longest corridor (m, default 300)")
    a = ap.parse_args()
    env = dict(os.environ, PLANNER_PROPERTY_SCALE=str(a.scale), PLANNER_PROPERTY_CORRIDOR_M=str(a.corridor_m))
    tests = ["tests/bounds/test_plane_properties.py", "tests/bounds/test_plane_refine.py"]
    cmd = [sys.executable, "-m", "pytest", "-q", *tests]
    return subprocess.call(cmd, cwd=ROOT, env=env)


if __name__ == "__main__":
    sys.exit(main())
