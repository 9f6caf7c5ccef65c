"""Headless Chromium driven over the Chrome DevTools Protocol, for the dashboard's browser tests
and ``web.pages``' load times: the system's ``chromium`` (Debian's package), nothing else.

Why the protocol itself and not Playwright or Selenium: Playwright drives only the browser
builds it downloads (no network here, and none on a greenhouse's CI), and Selenium needs a
chromedriver of the browser's exact version plus a dozen packages; the protocol is the browser's
own, spoken over one WebSocket with ``websockets`` (already a test dependency), so whatever
``chromium`` the machine has is driven as it is. One connection to the browser, the page
attached in flat mode (``sessionId`` on each message); every event is kept, so a test reads the
network log (each request's URL) and downloads from them.
"""
from __future__ import annotations

import base64
import contextlib
import itertools
import json
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

BINARIES = ("chromium", "chromium-browser", "google-chrome")
FLAGS = ("--headless=new", "--no-sandbox", "--disable-gpu", "--no-first-run", "--no-default-browser-check",
         "--disable-extensions", "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--disable-default-apps", "--metrics-recording-only", "--password-store=basic", "--hide-scrollbars")
"""Headless, as root (no sandbox), and quiet: no update checks, sync or safe-browsing lists, so the
browser itself asks no host either (the network log is the pages' alone)."""


class BrowserMissing(RuntimeError):
    """No Chromium on this machine (the message says what to install)."""


class BrowserError(RuntimeError):
    """The browser answered a command with an error, or not in time."""


def find_chromium() -> str:
    for name in BINARIES:
        if path := shutil.which(name):
            return path
    raise BrowserMissing("no chromium on PATH: install Debian's chromium package (apt-get install chromium)")


class Chromium:
    """One headless browser with one page (a tab). Use as a context manager."""

    def __init__(self, width: int = 1280, height: int = 900, timeout: float = 30.0, mobile: bool = False):
        """``mobile``: a phone's screen (the page's viewport meta applies, as on a phone)."""
        from websockets.sync.client import connect

        self.timeout = timeout
        self._open = contextlib.ExitStack()
        self.profile = Path(tempfile.mkdtemp(prefix="lupin-chromium-"))
        self.proc = subprocess.Popen([find_chromium(), *FLAGS, "--remote-debugging-port=0",
                                      f"--user-data-dir={self.profile}", f"--window-size={width},{height}",
                                      "about:blank"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            port, path = self._devtools_port()
            self.ws = self._open.enter_context(connect(f"ws://127.0.0.1:{port}{path}", max_size=64 * 2 ** 20,
                                                       open_timeout=timeout))
            self._ids = itertools.count(1)
            self.events: list[dict] = []
            target = self.call("Target.createTarget", url="about:blank", session=False)["targetId"]
            self.session = self.call("Target.attachToTarget", targetId=target, flatten=True,
                                     session=False)["sessionId"]
            for domain in ("Page", "Network", "Runtime"):
                self.call(f"{domain}.enable")
            self.call("Emulation.setDeviceMetricsOverride", width=width, height=height, deviceScaleFactor=1,
                      mobile=mobile)
        except BaseException:
            self.close()
            raise

    def _devtools_port(self) -> tuple[int, str]:
        """The browser writes its port and WebSocket path to ``DevToolsActivePort`` once it listens."""
        marker, until = self.profile / "DevToolsActivePort", time.monotonic() + self.timeout
        while time.monotonic() < until:
            if self.proc.poll() is not None:
                raise BrowserError(f"chromium exited ({self.proc.returncode}) before it listened")
            lines = marker.read_text().split() if marker.exists() else []
            if len(lines) >= 2:
                return int(lines[0]), lines[1]
            time.sleep(0.05)
        raise BrowserError("chromium did not open its DevTools port in time")

    # --- the protocol ------------------------------------------------------------------------
    def call(self, method: str, session: bool = True, **params) -> dict:
        """Send one command (to the page's session unless ``session`` is false) and wait for its
        answer; events that arrive meanwhile are kept in :attr:`events`."""
        msg_id = next(self._ids)
        msg = {"id": msg_id, "method": method, "params": params}
        if session:
            msg["sessionId"] = self.session
        self.ws.send(json.dumps(msg))
        while True:
            reply = self._receive()
            if reply.get("id") == msg_id:
                if "error" in reply:
                    raise BrowserError(f"{method}: {reply['error'].get('message')}")
                return reply.get("result", {})

    def _receive(self, timeout: float | None = None) -> dict:
        try:
            reply = json.loads(self.ws.recv(timeout=self.timeout if timeout is None else timeout))
        except TimeoutError:
            raise BrowserError("chromium did not answer in time") from None
        if "method" in reply:
            self.events.append(reply)
        return reply

    def wait_for(self, method: str, since: int, test=lambda params: True) -> dict:
        """The first event ``method`` after ``self.events[since:]`` began, waiting for it."""
        until = time.monotonic() + self.timeout
        seen = since
        while True:
            for e in self.events[seen:]:
                if e["method"] == method and test(e.get("params", {})):
                    return e["params"]
            seen = len(self.events)
            left = until - time.monotonic()
            if left <= 0:
                raise BrowserError(f"no {method} within {self.timeout:g} s")
            self._receive(timeout=left)

    # --- what a test does --------------------------------------------------------------------
    def goto(self, url: str) -> float:
        """Open ``url`` and wait for its load event; the browser's own time from navigation to
        the end of the load event, ms (``PerformanceNavigationTiming.loadEventEnd``)."""
        mark = len(self.events)
        self.call("Page.navigate", url=url)
        self.wait_for("Page.loadEventFired", mark)
        return self.load_ms()

    def load_ms(self) -> float:
        return float(self.eval("performance.getEntriesByType('navigation')[0].loadEventEnd"))

    def eval(self, expression: str):
        """A JavaScript expression's value in the page (JSON-able)."""
        got = self.call("Runtime.evaluate", expression=expression, returnByValue=True, awaitPromise=True)
        if "exceptionDetails" in got:
            raise BrowserError(f"{expression[:80]}: {got['exceptionDetails'].get('text')}")
        return got["result"].get("value")

    def click(self, selector: str, navigates: bool = True) -> None:
        """Click the first element ``selector`` matches (as a person would: a real mouse event at
        its centre); with ``navigates``, wait for the page it opens to load."""
        box = self.eval(f"(() => {{ const e = document.querySelector({json.dumps(selector)});"
                        f" if (!e) return null; e.scrollIntoView({{block: 'center'}});"
                        f" const r = e.getBoundingClientRect(); return [r.x + r.width / 2, r.y + r.height / 2]; }})()")
        if box is None:
            raise BrowserError(f"nothing on {self.eval('location.pathname')} matches {selector}")
        mark = len(self.events)
        for kind in ("mousePressed", "mouseReleased"):
            self.call("Input.dispatchMouseEvent", type=kind, x=box[0], y=box[1], button="left", clickCount=1)
        if navigates:
            self.wait_for("Page.loadEventFired", mark)

    def type_into(self, selector: str, text: str) -> None:
        self.eval(f"document.querySelector({json.dumps(selector)}).focus()")
        self.call("Input.insertText", text=text)

    def requested(self) -> list[str]:
        """Every URL the page asked for so far (the network log)."""
        return [e["params"]["request"]["url"] for e in self.events if e["method"] == "Network.requestWillBeSent"]

    def download(self, selector: str, directory: Path) -> Path:
        """Click a download link and wait for the file to be written into ``directory``."""
        directory.mkdir(parents=True, exist_ok=True)
        self.call("Browser.setDownloadBehavior", session=False, behavior="allowAndName",
                  downloadPath=str(directory), eventsEnabled=True)
        mark = len(self.events)
        self.click(selector, navigates=False)
        begin = self.wait_for("Browser.downloadWillBegin", mark)
        self.wait_for("Browser.downloadProgress", mark,
                      lambda p: p.get("guid") == begin["guid"] and p.get("state") == "completed")
        return directory / begin["guid"]

    def screenshot(self, path: Path, full_page: bool = True) -> None:
        params = {"format": "png", "captureBeyondViewport": full_page}
        if full_page:
            w, h = self.eval("[document.documentElement.scrollWidth, document.documentElement.scrollHeight]")
            params["clip"] = {"x": 0, "y": 0, "width": w, "height": h, "scale": 1}
        Path(path).write_bytes(base64.b64decode(self.call("Page.captureScreenshot", **params)["data"]))

    def close(self) -> None:
        self._open.close()
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        shutil.rmtree(self.profile, ignore_errors=True)

    def __enter__(self) -> "Chromium":
        return self

    def __exit__(self, *exc) -> None:
        self.close()
