"""The command line run in a child process, from the repository root."""

from __future__ import annotations

import subprocess
import sys

from tests.conftest import ROOT


def planner_cli(*args: str, env: dict[str, str] | None = None) -> subprocess.CompletedProcess[str]:
    """``python -m planner ARGS``, its output captured as text; ``env``: the child's environment (None: this one's)."""
    return subprocess.run([sys.executable, "-m", "planner", *args], capture_output=True, text=True, cwd=ROOT, env=env)
