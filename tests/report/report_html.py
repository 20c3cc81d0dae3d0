#!/usr/bin/env python3
"""report.html in a real browser: headless Chromium, driven over its
DevTools pipe (--remote-debugging-pipe; no network, no extra package).

    report_html.py PATH/TO/usm SCREENSHOT.png

Builds the report (--quick) and opens report.html; checks that
 - the page loads (load event) and the browser reports no error: no
   exception, no console error, no log entry of level error (a missing
   resource would be one: the page must be self-contained);
 - every figure of report.md is an inline SVG drawn with a non-zero size,
   and the page fetches nothing (no <img>, <link>, <script src>);
and keeps a screenshot of the whole page as SCREENSHOT.png.
Exit 77 (ctest: skipped) when chromium or gnuplot is not installed.
"""
import base64
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

USM, SHOT = sys.argv[1], sys.argv[2]
CHROMIUM = os.environ.get("USM_CHROMIUM") or shutil.which("chromium") or "/usr/bin/chromium"
failures = []


def fail(msg):
    print("FAIL", msg)
    failures.append(msg)


def ok(msg):
    print("ok  ", msg)


class Browser:
    """Chromium with the DevTools protocol on fds 3 (to it) and 4 (from it)."""

    def __init__(self, profile):
        to_r, self.to_w = os.pipe()
        self.from_r, from_w = os.pipe()
        flags = ["--headless", "--disable-gpu", "--no-first-run", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync", "--remote-debugging-pipe",
                 f"--user-data-dir={profile}", "--window-size=1200,900"]
        if os.getuid() == 0:
            flags.append("--no-sandbox")

        def fds():
            os.dup2(to_r, 3)
            os.dup2(from_w, 4)
        # fds 3 and 4 are kept open in the child (they are set by fds() before
        # subprocess closes the others); the pipes' own numbers do not matter
        self.proc = subprocess.Popen([CHROMIUM, *flags, "about:blank"],
                                     pass_fds=tuple(sorted({3, 4, to_r, from_w})),
                                     preexec_fn=fds, stdout=subprocess.DEVNULL,
                                     stderr=subprocess.DEVNULL)
        # the child's copies are at 3 and 4; close ours of its ends
        os.close(to_r)
        os.close(from_w)
        self.buf = b""
        self.next_id = 0
        self.events = []

    def _read(self, deadline):
        while b"\0" not in self.buf:
            if time.time() > deadline:
                raise TimeoutError("no answer from chromium")
            chunk = os.read(self.from_r, 1 << 20)
            if not chunk:
                raise EOFError("chromium closed the pipe")
            self.buf += chunk
        msg, self.buf = self.buf.split(b"\0", 1)
        return json.loads(msg)

    def call(self, method, session=None, timeout=60, **params):
        self.next_id += 1
        msg = {"id": self.next_id, "method": method, "params": params}
        if session:
            msg["sessionId"] = session
        os.write(self.to_w, json.dumps(msg).encode() + b"\0")
        deadline = time.time() + timeout
        while True:
            m = self._read(deadline)
            if m.get("id") == self.next_id:
                if "error" in m:
                    raise RuntimeError(f"{method}: {m['error']}")
                return m["result"]
            self.events.append(m)

    def wait_event(self, name, timeout=60):
        deadline = time.time() + timeout
        for m in self.events:
            if m.get("method") == name:
                return m
        while True:
            m = self._read(deadline)
            self.events.append(m)
            if m.get("method") == name:
                return m

    def close(self):
        try:
            self.call("Browser.close", timeout=10)
        except Exception:
            pass
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()


def main():
    if not os.path.exists(CHROMIUM):
        print(f"SKIP: {CHROMIUM} not found (install chromium)")
        sys.exit(77)
    if not shutil.which(os.environ.get("USM_GNUPLOT") or "gnuplot"):
        print("SKIP: gnuplot not found (install gnuplot-nox)")
        sys.exit(77)
    tmp = tempfile.mkdtemp(prefix="usm-html-")
    try:
        out = os.path.join(tmp, "rep")
        r = subprocess.run([USM, "report", "--out", out, "--quick"], capture_output=True,
                           text=True)
        if r.returncode != 0:
            fail(f"usm report exited {r.returncode}: {r.stderr}")
            return
        with open(os.path.join(out, "report.md"), encoding="utf-8") as f:
            figures = len(set(re.findall(r"!\[[^\]]*\]\(([^)\s]+\.png)\)", f.read())))
        with open(os.path.join(out, "report.html"), encoding="utf-8") as f:
            html = f.read()
        # the design figures and the non-ideal motor's
        # are inlined like the others
        for cap in ("Motor datasheet: rotor speed, output power and efficiency",
                    "Elasticities of rotor speed and of the largest Floquet modulus",
                    "The non-ideal motor: rotor-speed ripple, smallest contact force",
                    "One periodic orbit of the non-ideal motor: the tilt vector"):
            if re.search(r"<figure><svg(?:(?!</figure>).)*</svg>\s*<figcaption><em>" + re.escape(cap),
                         html, re.S):
                ok(f"report.html inlines the figure {cap!r}")
            else:
                fail(f"report.html lacks the figure {cap!r}")
        # each caption once: the caption paragraph report.md puts
        # under each figure is the figure's <figcaption>, not repeated beside it
        with open(os.path.join(out, "report.md"), encoding="utf-8") as f:
            alts = re.findall(r"^!\[([^\]]*)\]\([^)\s]+\.png\)$", f.read(), re.M)
        captions = re.findall(r"<figcaption>(.*?)</figcaption>", html, re.S)
        twice = []
        for alt in alts:
            esc = alt.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;") \
                     .replace('"', "&quot;")
            in_caps = sum(c.count(esc) for c in captions)
            if in_caps != 1 or html.count(f"<em>{esc}.</em>") != 1:
                twice.append((alt, in_caps, html.count(f"<em>{esc}.</em>")))
        if not alts or len(captions) != len(alts) or twice:
            fail(f"captions: {len(captions)} for {len(alts)} figures; not once: {twice[:3]}")
        else:
            ok(f"each of the {len(alts)} captions appears once, as its figure's <figcaption>")
        fetching = re.findall(r"<(?:img|link|script)\b[^>]*>", html)
        if fetching:
            fail(f"report.html fetches other files: {fetching[:3]}")
        else:
            ok("report.html is self-contained (no img, link or script elements)")
        b = Browser(os.path.join(tmp, "profile"))
        try:
            target = b.call("Target.createTarget", url="about:blank")["targetId"]
            s = b.call("Target.attachToTarget", targetId=target, flatten=True)["sessionId"]
            for domain in ("Page", "Runtime", "Log"):
                b.call(f"{domain}.enable", session=s)
            b.call("Page.navigate", session=s, url="file://" + os.path.join(out, "report.html"))
            b.wait_event("Page.loadEventFired")
            ok("report.html loads")
            sizes = json.loads(b.call(
                "Runtime.evaluate", session=s, returnByValue=True,
                expression="JSON.stringify(Array.from(document.querySelectorAll('figure svg'))"
                           ".map(e => { const r = e.getBoundingClientRect();"
                           " return [r.width, r.height, e.querySelectorAll('path').length]; }))"
            )["result"]["value"])
            if len(sizes) != figures or figures < 11:
                fail(f"{len(sizes)} inline SVG figures, report.md has {figures}")
            else:
                ok(f"{len(sizes)} figures inline, as in report.md")
            for k, (w, h, paths) in enumerate(sizes):
                if w > 0 and h > 0 and paths > 0:
                    ok(f"figure {k + 1}: drawn {w:.0f} x {h:.0f} px, {paths} paths")
                else:
                    fail(f"figure {k + 1}: size {w} x {h}, {paths} paths")
            metrics = b.call("Page.getLayoutMetrics", session=s)["cssContentSize"]
            shot = b.call("Page.captureScreenshot", session=s, format="png",
                          captureBeyondViewport=True,
                          clip={"x": 0, "y": 0, "width": metrics["width"],
                                "height": min(metrics["height"], 16000), "scale": 1})
            with open(SHOT, "wb") as f:
                f.write(base64.b64decode(shot["data"]))
            ok(f"screenshot: {SHOT}")
            errors = []
            for m in b.events:
                p = m.get("params", {})
                if m.get("method") == "Runtime.exceptionThrown":
                    errors.append(p["exceptionDetails"].get("text"))
                elif m.get("method") == "Runtime.consoleAPICalled" and p.get("type") == "error":
                    errors.append(str(p.get("args")))
                elif m.get("method") == "Log.entryAdded" and p["entry"]["level"] == "error":
                    errors.append(p["entry"].get("text"))
            if errors:
                fail(f"the browser reports errors: {errors[:3]}")
            else:
                ok("no errors in the browser")
        finally:
            b.close()
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


main()
if failures:
    print(f"FAILED: {len(failures)} check(s)")
    sys.exit(1)
print("report.html: all checks passed")
