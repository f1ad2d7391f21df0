"""Pages in headless Chromium, for the tests of report.html and field.html: find the browser, add a probe script
that records script and console errors and runs a test's own steps once the page has loaded, dump the DOM and read
back what the probe wrote on ``<body>``."""

from __future__ import annotations

import base64
import json
import re
import shutil
import socket
import subprocess
import time
import urllib.error
import urllib.request
from pathlib import Path
from typing import Any


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


# A phone in Chromium through chromedriver: a tiny W3C WebDriver client over HTTP (urllib only, no selenium), for
# the tests that need what --dump-dom cannot give: a phone's viewport (390 x 844 CSS px, 3 device px per CSS px,
# a touch screen), touch taps at screen points and a screenshot.

PHONE_UA = (
    "Mozilla/5.0 (Linux; Android 14; Pixel 8) AppleWebKit/537.36 (KHTML, like Gecko) "
    "Chrome/126.0.0.0 Mobile Safari/537.36"
)


def chromedriver() -> str | None:
    """The chromedriver here, with a browser for it to drive (None: either is missing; the tests skip)."""
    driver = shutil.which("chromedriver")
    return driver if driver and chromium() else None


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


class Phone:
    """One Chromium session emulating a phone of ``width`` x ``height`` CSS px with touch, driven over W3C
    WebDriver; use as a context manager (the driver starts on enter and stops on exit, the session is deleted)."""

    def __init__(
        self, width: int = 390, height: int = 844, pixel_ratio: float = 3.0, downloads: Path | None = None
    ) -> None:
        self.metrics = {"width": width, "height": height, "pixelRatio": pixel_ratio, "touch": True}
        self.downloads = downloads  # where the browser saves a download without asking (None: its default)
        self.proc: subprocess.Popen[bytes] | None = None
        self.base = ""
        self.sid = ""

    def _call(self, method: str, path: str, body: dict[str, Any] | None = None) -> Any:
        """One WebDriver command; its ``value`` (an error answer raises with the driver's message)."""
        data = None if body is None else json.dumps(body).encode()
        req = urllib.request.Request(self.base + path, data=data, method=method)
        req.add_header("Content-Type", "application/json")
        try:
            with urllib.request.urlopen(req, timeout=120) as r:
                return json.loads(r.read() or b"{}").get("value")
        except urllib.error.HTTPError as e:
            raise RuntimeError(f"webdriver {method} {path}: {e.read()[:500]!r}") from None

    def __enter__(self) -> Phone:
        port = _free_port()
        self.base = f"http://127.0.0.1:{port}"
        cmd = [chromedriver() or "chromedriver", f"--port={port}"]
        self.proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        for _ in range(200):
            try:
                if self._call("GET", "/status").get("ready"):
                    break
            except (OSError, RuntimeError):
                pass
            time.sleep(0.05)
        try:
            opts = {
                "args": ["--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage"],
                "mobileEmulation": {"deviceMetrics": self.metrics, "userAgent": PHONE_UA},
            }
            if self.downloads is not None:
                opts["prefs"] = {
                    "download.default_directory": str(self.downloads),
                    "download.prompt_for_download": False,
                }
            caps = {"capabilities": {"alwaysMatch": {"browserName": "chrome", "goog:chromeOptions": opts}}}
            self.sid = self._call("POST", "/session", caps)["sessionId"]
        except BaseException:
            self._stop()
            raise
        return self

    def __exit__(self, *exc: object) -> None:
        try:
            if self.sid:
                self._call("DELETE", f"/session/{self.sid}")
        finally:
            self._stop()

    def _stop(self) -> None:
        if self.proc is not None:
            self.proc.terminate()
            try:
                self.proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
            self.proc = None

    def get(self, page: Path) -> None:
        """Open a page (a file here) and wait for its load event (WebDriver's default page-load strategy)."""
        self._call("POST", f"/session/{self.sid}/url", {"url": page.as_uri()})

    def run(self, script: str, *args: Any) -> Any:
        """Run ``script`` (a function body: ``arguments`` are ``args``; what it returns comes back as JSON)."""
        return self._call("POST", f"/session/{self.sid}/execute/sync", {"script": script, "args": list(args)})

    def tap(self, x: float, y: float) -> None:
        """A finger's tap at the viewport point (``x``, ``y``) in CSS px: down, 60 ms, up (touch events, the
        pointer events of type touch and then the click a browser makes of a tap)."""
        finger = {
            "type": "pointer",
            "id": "finger",
            "parameters": {"pointerType": "touch"},
            "actions": [
                {"type": "pointerMove", "duration": 0, "origin": "viewport", "x": round(x), "y": round(y)},
                {"type": "pointerDown", "button": 0},
                {"type": "pause", "duration": 60},
                {"type": "pointerUp", "button": 0},
            ],
        }
        self._call("POST", f"/session/{self.sid}/actions", {"actions": [finger]})
        self._call("DELETE", f"/session/{self.sid}/actions")

    def screenshot(self) -> bytes:
        """The viewport as a PNG."""
        return base64.b64decode(self._call("GET", f"/session/{self.sid}/screenshot"))

    def tap_element(self, selector: str) -> tuple[float, float]:
        """Scroll the first element matching the CSS ``selector`` to the middle of the screen and tap its centre as a
        finger would (:meth:`tap`); the point tapped. An element missing or not displayed raises."""
        at = self.run(
            "var e = document.querySelector(arguments[0]); if (!e) return null;"
            "e.scrollIntoView({block: 'center'}); var r = e.getBoundingClientRect();"
            "return r.width && r.height ? [r.left + r.width / 2, r.top + r.height / 2] : null;",
            selector,
        )
        if at is None:
            raise AssertionError(f"{selector}: no such element on screen")
        self.tap(*at)
        return at[0], at[1]

    def wait_for(self, script: str, timeout_s: float = 10.0) -> Any:
        """Run ``script`` (as :meth:`run`) until it returns something other than null; that value (None: it kept
        returning null for ``timeout_s``)."""
        end = time.monotonic() + timeout_s
        while True:
            value = self.run(script)
            if value is not None or time.monotonic() > end:
                return value
            time.sleep(0.05)
