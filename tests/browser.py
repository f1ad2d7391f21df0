"""Pages in headless Chromium, for the tests of report.html and field.html: find the browser, add a probe script
that records script and console errors and runs a test's own steps once the page has loaded, dump the DOM and read
back what the probe wrote on ``<body>``."""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path


def chromium() -> str | None:
    """The headless browser here (None: none; the tests that need it are skipped)."""
    return shutil.which("chromium") or shutil.which("chromium-browser") or shutil.which("google-chrome")


def probe(steps: str) -> str:
    """A ``<script>`` that records every script error and ``console.error`` in ``body[data-errors]`` (a JSON list)
    and, 50 ms after the page's load event, runs ``steps`` (JavaScript with ``b`` bound to ``document.body``; it
    writes its findings as attributes of ``b``)."""
    return (
        "<script>\n(function () {\n  var errors = [];\n"
        "  function note() { document.body.setAttribute('data-errors', JSON.stringify(errors)); }\n"
        "  window.onerror = function (m) { errors.push(String(m)); note(); };\n"
        "  var ce = console.error;\n"
        "  console.error = function () { errors.push(Array.prototype.join.call(arguments, ' ')); note();"
        " ce.apply(console, arguments); };\n"
        "  window.addEventListener('load', function () { setTimeout(function () {\n"
        "    var b = document.body;\n    note();\n"
        f"{steps}\n    note();\n  }}, 50); }});\n}})();\n</script>"
    )


def dump_dom(page: Path, width: int = 1200, height: int = 900) -> str:
    """The DOM of ``page`` after it loaded and its scripts ran (10 s of virtual time), in a window of the size."""
    cmd = [chromium() or "chromium", "--headless", "--no-sandbox", "--disable-gpu", f"--window-size={width},{height}"]
    cmd += ["--virtual-time-budget=10000", "--dump-dom", page.as_uri()]
    return subprocess.run(cmd, check=False, capture_output=True, text=True, timeout=120).stdout


def body_attributes(dom: str) -> dict[str, str]:
    """The attributes of the dumped page's ``<body>`` (what a probe wrote), unescaped."""
    tag = re.search(r"<body([^>]*)>", dom)
    assert tag, dom[:500]
    return {k: v.replace("&gt;", ">").replace("&quot;", '"') for k, v in re.findall(r'([\w-]+)="([^"]*)"', tag[1])}
