"""Children of the benchmark scripts, run under ``/usr/bin/time -v`` for their peak resident memory."""

from __future__ import annotations

import csv
import json
import re
import subprocess
import sys
import tempfile
from pathlib import Path


def peak_rss_mb(stderr: str) -> int | None:
    """The "Maximum resident set size" that ``/usr/bin/time -v`` wrote, in MB (None when absent)."""
    m = re.search(r"Maximum resident set size \(kbytes\): (\d+)", stderr)
    return round(int(m.group(1)) / 1024) if m else None


def json_child(script: str, args: list[str], what: str) -> dict:
    """Run ``python script *args --json FILE`` under ``/usr/bin/time -v``; the row it wrote, with
    ``peak_rss_mb``. Exits with the child's standard error when it fails (``what`` names the run)."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "row.json"
        cmd = ["/usr/bin/time", "-v", sys.executable, script, *args, "--json", str(out)]
        proc = subprocess.run(cmd, capture_output=True, text=True)
        if proc.returncode != 0 or not out.exists():
            raise SystemExit(f"{what} failed:\n{proc.stderr[-3000:]}")
        row = json.loads(out.read_text())
    row["peak_rss_mb"] = peak_rss_mb(proc.stderr)
    return row


def append_csv(path: Path, fields: list[str], rows: list[dict]) -> None:
    """Append ``rows`` (only ``fields``, missing ones empty) to the CSV at ``path``, with a header when new."""
    new = not path.exists()
    with path.open("a", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields)
        if new:
            w.writeheader()
        w.writerows({k: r.get(k, "") for k in fields} for r in rows)
