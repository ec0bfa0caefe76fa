# SPDX-License-Identifier: GPL-3.0-or-later
"""The compare report's viewer in headless Chromium, driven through the DevTools protocol.

A small `translucent compare` (the cube at 40x30, two techniques, small photon and sample counts,
no budget), then Chromium opens DIR/index.html from file:// and the test checks that
  - the summary is the first table of the page, at the top, with report.json's numbers in the
    order of its "summary" rows;
  - the viewer picks a technique, and the readout under the mouse at a known pixel gives the
    linear RGB of both images as the report's EXR files hold them (read here by a small EXR
    reader of its own, not through the viewer's data files), and the relative error there;
  - a click flips the shown image, the wheel zooms about the cursor (the readout still names the
    same pixel, and one pixel to the right is the next one), key 3 shows the error map.

Chromium is driven over --remote-debugging-pipe (fds 3 and 4, NUL-separated JSON messages), so
nothing beyond Python's standard library and Debian's chromium is needed.

Usage: viewer_chromium.py TRANSLUCENT_BINARY CUBE_SCENE WORK_DIR
"""
import fcntl
import json
import math
import os
import shutil
import struct
import subprocess
import sys
import time
import zlib

WIDTH, HEIGHT = 40, 30
# The technique that the test selects (not the default: the default is the best of the summary
# or the first); its name holds ':' and '=', which the report's file names replace.
TECHNIQUES = ["pointcloud:points=2000", "empirical"]


def fail(message):
    print("viewer_chromium: FAIL: " + message, file=sys.stderr)
    sys.exit(1)


# ---- EXR (scanline; no, ZIPS or ZIP compression; HALF or FLOAT channels) ---------------------

def read_exr(path):
    """Returns (width, height, {channel: list of floats, rows from the top})."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:4] != b"\x76\x2f\x31\x01":
        fail(f"{path}: not an OpenEXR file")
    flags = struct.unpack_from("<I", data, 4)[0]
    if flags & 0x200 or flags & 0x1000:
        fail(f"{path}: tiled or multi-part EXR: this reader reads scanline files only")
    pos = 8
    header = {}
    while data[pos] != 0:
        end = data.index(b"\0", pos)
        name = data[pos:end].decode()
        pos = end + 1
        end = data.index(b"\0", pos)
        kind = data[pos:end].decode()
        pos = end + 1
        size = struct.unpack_from("<i", data, pos)[0]
        pos += 4
        header[name] = (kind, data[pos:pos + size])
        pos += size
    pos += 1
    channels = []
    raw = header["channels"][1]
    p = 0
    while raw[p] != 0:
        end = raw.index(b"\0", p)
        name = raw[p:end].decode()
        pixel_type = struct.unpack_from("<i", raw, end + 1)[0]
        channels.append((name, pixel_type))
        p = end + 1 + 16
    compression = header["compression"][1][0]
    xmin, ymin, xmax, ymax = struct.unpack("<4i", header["dataWindow"][1])
    width, height = xmax - xmin + 1, ymax - ymin + 1
    lines = {0: 1, 2: 1, 3: 16}.get(compression)
    if lines is None:
        fail(f"{path}: compression {compression}: this reader reads none, ZIPS and ZIP only")
    chunks = (height + lines - 1) // lines
    offsets = struct.unpack_from(f"<{chunks}Q", data, pos)
    out = {name: [0.0] * (width * height) for name, _ in channels}
    for offset in offsets:
        y, size = struct.unpack_from("<ii", data, offset)
        block = data[offset + 8:offset + 8 + size]
        n = min(lines, ymax - y + 1)
        expected = sum(width * (2 if t == 1 else 4) for _, t in channels) * n
        if compression != 0 and size < expected:
            t = bytearray(zlib.decompress(block))
            for i in range(1, len(t)):  # undo the predictor
                t[i] = (t[i - 1] + t[i] - 128) & 0xFF
            half = (len(t) + 1) // 2  # undo the interleaving of the two halves
            block = bytearray(len(t))
            block[0::2] = t[:half]
            block[1::2] = t[half:]
        q = 0
        for row in range(y - ymin, y - ymin + n):
            for name, pixel_type in channels:
                fmt_, step = ("<e", 2) if pixel_type == 1 else ("<f", 4)
                if pixel_type == 0:
                    fail(f"{path}: UINT channel {name}")
                values = struct.unpack_from(f"<{width}{fmt_[1]}", block, q)
                out[name][row * width:(row + 1) * width] = values
                q += width * step
    return width, height, out


def rgb_at(exr, layer, x, y):
    width, _, ch = exr
    prefix = layer + "." if layer else ""
    return [ch[prefix + c][y * width + x] for c in "RGB"]


# ---- Chromium over the DevTools pipe ------------------------------------------------------------

class Browser:
    def __init__(self, work):
        exe = shutil.which("chromium") or shutil.which("chromium-browser")
        if not exe:
            fail("no chromium (run scripts/install-deps)")
        to_chrome_r, self.to_chrome = os.pipe()
        self.from_chrome, from_chrome_w = os.pipe()
        # Above the fds the child's dup2 onto 3 and 4 could overwrite.
        high_r = fcntl.fcntl(to_chrome_r, fcntl.F_DUPFD, 10)
        high_w = fcntl.fcntl(from_chrome_w, fcntl.F_DUPFD, 10)

        def child_fds():
            os.dup2(high_r, 3)
            os.dup2(high_w, 4)

        self.log = open(os.path.join(work, "chromium.log"), "wb")
        self.proc = subprocess.Popen(
            [exe, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
             "--no-first-run", "--mute-audio", "--remote-debugging-pipe",
             "--user-data-dir=" + os.path.join(work, "chromium-profile"),
             "--window-size=1400,1000", "about:blank"],
            stdout=self.log, stderr=subprocess.STDOUT, close_fds=False, preexec_fn=child_fds)
        for fd in (to_chrome_r, from_chrome_w, high_r, high_w):
            os.close(fd)
        self.buffer = b""
        self.next_id = 0
        self.events = []
        self.session = None

    def send(self, method, params=None, session=True, timeout=60):
        self.next_id += 1
        message = {"id": self.next_id, "method": method, "params": params or {}}
        if session and self.session:
            message["sessionId"] = self.session
        os.write(self.to_chrome, json.dumps(message).encode() + b"\0")
        deadline = time.time() + timeout
        while True:
            reply = self.receive(deadline)
            if reply.get("id") == self.next_id:
                if "error" in reply:
                    fail(f"{method}: {reply['error']}")
                return reply.get("result", {})
            self.events.append(reply)

    def receive(self, deadline):
        while b"\0" not in self.buffer:
            if time.time() > deadline:
                fail("no answer from Chromium in time (log: chromium.log)")
            chunk = os.read(self.from_chrome, 1 << 16)
            if not chunk:
                fail("Chromium closed the pipe (log: chromium.log)")
            self.buffer += chunk
        message, self.buffer = self.buffer.split(b"\0", 1)
        return json.loads(message)

    def attach(self):
        targets = self.send("Target.getTargets", session=False)["targetInfos"]
        page = next((t for t in targets if t["type"] == "page"), None)
        if not page:
            page = {"targetId": self.send("Target.createTarget", {"url": "about:blank"},
                                          session=False)["targetId"]}
        self.session = self.send("Target.attachToTarget",
                                 {"targetId": page["targetId"], "flatten": True},
                                 session=False)["sessionId"]

    def evaluate(self, expression):
        result = self.send("Runtime.evaluate", {"expression": expression, "returnByValue": True,
                                                "awaitPromise": True})
        if "exceptionDetails" in result:
            fail(f"JavaScript error in {expression!r}: {result['exceptionDetails']}")
        return result["result"].get("value")

    def wait_for(self, expression, what, timeout=30):
        deadline = time.time() + timeout
        while time.time() < deadline:
            value = self.evaluate(expression)
            if value:
                return value
            time.sleep(0.1)
        fail(f"timed out waiting for {what} ({expression})")

    def mouse(self, kind, x, y, **extra):
        params = {"type": kind, "x": x, "y": y}
        params.update(extra)
        self.send("Input.dispatchMouseEvent", params)

    def close(self):
        try:
            self.send("Browser.close", session=False, timeout=10)
        except SystemExit:
            pass
        try:
            self.proc.wait(timeout=20)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        self.log.close()


def close_enough(a, b, rel=1e-6):
    return abs(a - b) <= rel * max(abs(a), abs(b)) + 1e-30


def main():
    if len(sys.argv) != 4:
        fail("usage: viewer_chromium.py TRANSLUCENT_BINARY CUBE_SCENE WORK_DIR")
    exe, scene, work = sys.argv[1], sys.argv[2], os.path.join(sys.argv[3], "compare_viewer")
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    out = os.path.join(work, "report")
    log = os.path.join(work, "compare.log")
    with open(log, "wb") as f:
        rc = subprocess.call(
            [exe, "compare", scene, "--techniques", ",".join(TECHNIQUES), "--width", str(WIDTH),
             "--height", str(HEIGHT), "--photons", "20000", "--samples", "2000", "--frames", "1",
             "--warmup", "0", "--threads", "2", "--budget", "0", "--no-cache", "--out", out],
            stdout=f, stderr=subprocess.STDOUT,
            env=dict(os.environ, TRANSLUCENT_CACHE_DIR=os.path.join(work, "cache")))  # not ~/.cache
    if rc != 0:
        fail(f"translucent compare exited {rc}:\n" + open(log).read())
    report = json.load(open(os.path.join(out, "report.json")))
    size = sum(os.path.getsize(os.path.join(out, n)) for n in os.listdir(out))
    viewer_size = sum(os.path.getsize(os.path.join(out, n)) for n in os.listdir(out)
                      if n.startswith("px-") or n.startswith("viewer"))
    print(f"report folder: {size} bytes, of which the viewer's files {viewer_size} bytes "
          f"({WIDTH}x{HEIGHT}, {len(TECHNIQUES)} techniques)")

    # The pair the test shows: the second technique of the summary (not the viewer's default)
    # against the physical reference's true radiance (cone): the technique's EXR holds its L as
    # the base RGB, physical.exr the cone radiance as a layer; neither depends on the radiance
    # convention.
    rows = report["summary"]["rows"]
    done = [r["technique"] for r in rows if r["status"] == "done"]
    if sorted(done) != sorted(TECHNIQUES):
        fail(f"summary rows {rows}: expected both techniques done")
    technique = done[1]
    technique_exr = next(t["exr"] for t in report["techniques"] if t["name"] == technique)
    tech = read_exr(os.path.join(out, technique_exr))
    phys = read_exr(os.path.join(out, "physical.exr"))
    if tech[:2] != (WIDTH, HEIGHT) or phys[:2] != (WIDTH, HEIGHT):
        fail(f"EXR sizes {tech[:2]} {phys[:2]}, expected {WIDTH}x{HEIGHT}")
    # A pixel near the middle (on the cube) where both images are lit.
    target = None
    for radius in range(0, 10):
        for y in range(HEIGHT // 2 - radius, HEIGHT // 2 + radius + 1):
            for x in range(WIDTH // 2 - radius, WIDTH // 2 + radius + 1):
                if target is None and min(rgb_at(tech, "", x, y)) > 0 and \
                        min(rgb_at(phys, "cone_radiance", x, y)) > 0:
                    target = (x, y)
    if target is None:
        fail("no lit pixel near the middle of the image")
    expected_left = rgb_at(tech, "", *target)
    expected_right = rgb_at(phys, "cone_radiance", *target)

    browser = Browser(work)
    try:
        browser.attach()
        browser.send("Page.enable")
        browser.send("Runtime.enable")
        browser.send("Page.navigate", {"url": "file://" + os.path.abspath(os.path.join(out, "index.html"))})
        browser.wait_for("document.readyState === 'complete' && !!window.translucentViewer",
                         "the page and viewer.js")

        # The summary: the first table, at the top of the page, report.json's rows in order.
        first = browser.evaluate("""(() => { const t = document.querySelector('table');
            return {id: t.id, top: t.getBoundingClientRect().top + window.scrollY,
                    rows: Array.from(t.querySelectorAll('tr[data-technique]')).map(r =>
                      [r.dataset.technique, Array.from(r.cells).map(c => c.textContent)])}; })()""")
        if first["id"] != "summary":
            fail(f"the first table is {first['id']!r}, expected the summary")
        if first["top"] > 400:
            fail(f"the summary starts {first['top']} px down the page")
        if [r[0] for r in first["rows"]] != [r["technique"] for r in rows]:
            fail(f"summary order {first['rows']} is not report.json's {rows}")
        for (name, cells), row in zip(first["rows"], rows):
            if row["status"] != "done":
                continue
            for column, key in ((2, "vs_model_rel_rmse"), (3, "vs_physical_rel_rmse")):
                want = "–" if row.get(key) is None else f"{100 * row[key]:.2f}%"
                if cells[column] != want:
                    fail(f"summary {name} column {column}: {cells[column]!r}, report.json {want!r}")

        # Pick the technique, the physical reference and the cone radiance.
        browser.evaluate(f"""(() => {{
            const pick = (id, v) => {{ const s = document.getElementById(id); s.value = v;
              s.dispatchEvent(new Event('change')); return s.value; }};
            pick('v-test', {json.dumps(technique)});
            pick('v-reference', 'physical');
            const q = Array.from(document.getElementById('v-quantity').options)
              .find(o => o.value.startsWith('cone_radiance/'));
            pick('v-quantity', q ? q.value : '');
            document.getElementById('v-canvas').scrollIntoView({{block: 'center'}});
            return true; }})()""")
        state = browser.evaluate("window.translucentViewer.state()")
        if state["test"] != technique or state["reference"] != "physical" or \
                state["pair"]["quantity"] != "cone_radiance":
            fail(f"the viewer shows {state}, expected {technique} against the physical cone radiance")
        browser.wait_for("document.getElementById('viewer').dataset.ready === " +
                         json.dumps(state["pair"]["left"] + "|" + state["pair"]["right"]),
                         "the two images' pixels")

        # The mouse over the centre of the target pixel: the canvas shows the image fitted and
        # centred (computed here from the canvas's box, not asked of the viewer).
        rect = browser.evaluate("""(() => { const r = document.getElementById('v-canvas')
            .getBoundingClientRect(); return {left: r.left, top: r.top, width: r.width,
            height: r.height}; })()""")
        scale = min(rect["width"] / WIDTH, rect["height"] / HEIGHT)
        ox = rect["left"] + (rect["width"] - WIDTH * scale) / 2
        oy = rect["top"] + (rect["height"] - HEIGHT * scale) / 2
        cx, cy = ox + (target[0] + 0.5) * scale, oy + (target[1] + 0.5) * scale
        browser.mouse("mouseMoved", cx, cy)
        # A click flips to the reference (flip mode), and the readout stays on the pixel.
        if browser.evaluate("document.getElementById('viewer').dataset.showing") != "left":
            fail("the viewer does not start on the left image")
        browser.mouse("mousePressed", cx, cy, button="left", clickCount=1)
        browser.mouse("mouseReleased", cx, cy, button="left", clickCount=1)
        if browser.evaluate("document.getElementById('viewer').dataset.showing") != "right":
            fail("a click on the image did not flip to the reference")

        def readout():
            return browser.evaluate("""(() => { const r = document.getElementById('v-readout');
                const cells = id => Array.from(document.querySelectorAll('#' + id + ' td'))
                  .map(c => c.textContent);
                return {values: r.dataset.values ? JSON.parse(r.dataset.values) : null,
                        pixel: (document.getElementById('v-pixel') || {}).textContent,
                        left: cells('v-left'), right: cells('v-right'), rel: cells('v-rel')}; })()""")

        shown = readout()
        values = shown["values"]
        if not values:
            fail(f"no readout under the cursor: {shown}")
        if (values["x"], values["y"]) != target or shown["pixel"] != f"({target[0]}, {target[1]})":
            fail(f"the readout names pixel {shown['pixel']}, the mouse is over {target}")
        for side, want in (("left", expected_left), ("right", expected_right)):
            text = [float(v) for v in shown[side]]  # what the page shows (7 digits)
            for c in range(3):
                if not close_enough(values[side][c], want[c], 1e-7):
                    fail(f"{side} {'RGB'[c]} at {target}: viewer {values[side][c]}, EXR {want[c]}")
                if not close_enough(text[c], want[c], 1e-6):
                    fail(f"{side} {'RGB'[c]} at {target}: shown {text[c]}, EXR {want[c]}")
        for c in range(3):
            rel = (expected_left[c] - expected_right[c]) / expected_right[c]
            shown_rel = float(shown["rel"][c].rstrip("%")) / 100
            if abs(shown_rel - rel) > 5e-5 or not close_enough(values["relative"][c], rel, 1e-5):
                fail(f"relative error {'RGB'[c]}: shown {shown['rel'][c]}, expected {rel}")
        print(f"readout at {target}: left {values['left']} right {values['right']} "
              f"relative {shown['rel']}: matches the EXR files")

        # The wheel zooms about the cursor: the same pixel stays under it, and a step of one
        # zoomed pixel to the right reads the next pixel.
        before = browser.evaluate("window.translucentViewer.view()")
        browser.mouse("mouseWheel", cx, cy, deltaX=0, deltaY=-500)
        after = browser.evaluate("window.translucentViewer.view()")
        if not after["scale"] > 2 * before["scale"]:
            fail(f"the wheel did not zoom in: {before} -> {after}")
        if (readout()["values"]["x"], readout()["values"]["y"]) != target:
            fail(f"after zooming the readout left pixel {target}: {readout()['values']}")
        step = after["scale"]  # CSS pixels per image pixel (the canvas is not scaled by CSS)
        if target[0] + 1 < WIDTH:
            browser.mouse("mouseMoved", cx + step, cy)
            v = readout()["values"]
            if (v["x"], v["y"]) != (target[0] + 1, target[1]):
                fail(f"one zoomed pixel right of {target} reads {(v['x'], v['y'])}")
            if not all(close_enough(v["left"][c], rgb_at(tech, "", target[0] + 1, target[1])[c], 1e-7)
                       for c in range(3)):
                fail(f"zoomed readout {v['left']} differs from the EXR")
        # Key 3: the error map of the pair.
        browser.send("Input.dispatchKeyEvent", {"type": "keyDown", "key": "3", "text": "3",
                                                "code": "Digit3", "windowsVirtualKeyCode": 51})
        browser.send("Input.dispatchKeyEvent", {"type": "keyUp", "key": "3", "code": "Digit3",
                                                "windowsVirtualKeyCode": 51})
        if browser.evaluate("document.getElementById('viewer').dataset.showing") != "error":
            fail("key 3 did not show the error map")
        problems = [e for e in browser.events
                    if e.get("method") == "Runtime.exceptionThrown"]
        if problems:
            fail(f"the page threw: {problems[0]['params']}")
    finally:
        browser.close()
    print("ok: summary first, viewer readout matches the EXR files")


if __name__ == "__main__":
    main()
