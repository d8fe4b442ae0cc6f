"""End to end, the page drawing a session itself: viscerad -> LCM skeleton states -> `viscera view`
-> WebSocket -> headless Chromium's WebGL2 (software). Run inside a loopback-only network
namespace (client_render_test.sh does).

Checks: the page connects, receives skeleton states and draws the intestine, and the server
draws no frame for it (its frame lease is not renewed while the page draws itself); with the session
paused, the page's canvas and the server's JPEG of the same step and camera agree (the
intestine's pixel mask overlaps by >= 80 % (intersection over union), the lesion visible or hidden in
both), once settled (the lesion hidden) and once after the clearing gesture (the tools in view,
the lesion uncovered), and through a camera a client set; the control: the page drawn without the intestine loses > 90 % of that mask, so the
mask is the intestine's; the page keeps drawing when the stream stops (the server stopped) and
says so. Prints the page's drawing rate (a figure, not asserted).

Usage: client_render_test.py VISCERAD VISCERA SCENE_DIR
"""
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from devtools_pipe import Browser, Failure  # noqa: E402
from viewer_page import FRAME_COST, start_view, stop  # noqa: E402

viscerad, viscera, scene_dir = sys.argv[1:4]
URL = "udpm://239.255.76.67:7667?ttl=0"
HTTP = "http://127.0.0.1:18082"
work = tempfile.mkdtemp()
os.environ["VISCERA_SESSIONS"] = f"{work}/sessions.json"
procs = []

# The masks, computed in the page from the canvas (read back right after a draw) and the
# server's /frame.jpg decoded by the browser. Intestine: the bowel's pink, (r - g) / r in
# 0.33..0.6 and g within 0.04 r of b (albedo 0.92 0.52 0.52; the wall's cream is 0.26 and g - b
# 0.1 r, its vessels and the serosa's 0.7); lesion: the target's green.
COMPARE = r"""(async () => {
  const v = window.viscera, gl = v.renderer.gl, w = v.renderer.scene.width, h = v.renderer.scene.height;
  const page = (intestine) => {
    v.renderer.intestine_drawn = intestine;
    v.Frame(performance.now() + 1e6);  // the latest state itself, not between two
    v.renderer.intestine_drawn = true;
    const px = new Uint8Array(w * h * 4);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
    const flipped = new Uint8Array(w * h * 4);  // GL's rows start at the bottom
    for (let y = 0; y < h; ++y) flipped.set(px.subarray((h - 1 - y) * w * 4, (h - y) * w * 4), y * w * 4);
    return flipped;
  };
  const img = new Image();
  img.src = 'frame.jpg?' + Date.now();
  await img.decode();
  const c = document.createElement('canvas');
  c.width = w; c.height = h;
  const ctx = c.getContext('2d');
  ctx.drawImage(img, 0, 0, w, h);
  const server = ctx.getImageData(0, 0, w, h).data;
  const bowel = (p, i) => { const r = p[i], g = p[i + 1], b = p[i + 2];
    return r > 50 && (r - g) > 0.33 * r && (r - g) < 0.6 * r && Math.abs(g - b) < 0.04 * r; };
  const green = (p, i) => p[i + 1] > 150 && p[i + 1] > p[i] + 60 && p[i + 1] > p[i + 2] + 40;
  const drawn = page(true), without = page(false);
  let a = 0, b = 0, both = 0, either = 0, control = 0, ga = 0, gb = 0;
  for (let i = 0; i < w * h * 4; i += 4) {
    const x = bowel(drawn, i), y = bowel(server, i);
    a += x; b += y; both += x && y; either += x || y; control += bowel(without, i) && x;
    ga += green(drawn, i); gb += green(server, i);
  }
  return {page: a, server: b, iou: both / Math.max(either, 1), control: control / Math.max(a, 1),
          lesion_page: ga, lesion_server: gb, step: v.latest.step, image: [img.naturalWidth, img.naturalHeight]};
})()"""


def fail(message):
    print(f"FAIL: {message}", file=sys.stderr)
    for name in ("viscerad.err", "view.err"):
        path = f"{work}/{name}"
        if os.path.exists(path):
            for line in open(path).read().splitlines()[-10:]:
                print(f"  {name}: {line}", file=sys.stderr)
    sys.exit(1)


def cli(*args):
    return subprocess.run([viscera, *args, "--lcm-url", URL], capture_output=True, text=True, timeout=120)


def stats():
    opener = urllib.request.build_opener(urllib.request.ProxyHandler({}))
    return json.load(opener.open(HTTP + "/stats.json", timeout=10))


def frame_jpg():
    """GET /frame.jpg (503 before the first frame); the bytes or None."""
    opener = urllib.request.build_opener(urllib.request.ProxyHandler({}))
    try:
        return opener.open(HTTP + "/frame.jpg", timeout=10).read()
    except urllib.error.HTTPError:
        return None


def compare(page, session, label):
    """Pauses the session, waits until the page and the server's frame show the same step, and
    checks that they agree; resumes the session. The masks."""
    paused = cli("pause", session)
    if paused.returncode != 0:
        fail(f"pause: {paused.stderr}")
    deadline = time.monotonic() + 30
    while True:
        step = page.evaluate("viscera.latest.step")
        frame_jpg()  # the viewer renews the frame lease for it: the server draws again
        time.sleep(1.0)
        if step is not None and step == page.evaluate("viscera.latest.step") == stats()["frame_step"]:
            break
        if time.monotonic() > deadline:
            fail(f"{label}: the page's step {step} and the server frame's {stats()['frame_step']} never met")
    m = page.evaluate(COMPARE, timeout=60)
    print(f"{label}:", json.dumps(m))
    if m is None or m["image"] != [640, 480]:
        fail(f"{label}: no comparison: {m}")
    if m["iou"] < 0.8:
        fail(f"{label}: the intestine's masks overlap by {m['iou']:.3f} (< 0.8)")
    if m["control"] > 0.1:
        fail(f"{label}: without the intestine the page keeps {m['control']:.2f} of its mask: not the intestine's")
    if (m["lesion_page"] > 20) != (m["lesion_server"] > 20):
        fail(f"{label}: the lesion shows in one picture only: page {m['lesion_page']}, "
             f"server {m['lesion_server']} px")
    cli("resume", session)
    return m


def main():
    # frames of the size asked for, whatever the load: they are compared with the page's
    procs.append(subprocess.Popen([viscerad, "--server-id", "render-test", "--lcm-url", URL, "--scene-dir", scene_dir,
                                   "--adaptive-frames", "off"], stderr=open(f"{work}/viscerad.err", "w")))
    server = procs[-1]
    created = cli("create", "cavity", "--skin", "parametric", "--width", "640", "--height", "480",
                  "--frame-rate", "25", "--json", "--timeout", "120")
    if created.returncode != 0:
        fail(f"create: {created.stderr}")
    session = str(json.loads(created.stdout)["session"])
    try:
        procs.append(start_view(viscera, session, HTTP[7:], URL, scene_dir, work))
    except RuntimeError as e:
        fail(str(e))

    with Browser(work) as browser:
        try:
            page = browser.open(HTTP + "/")
            page.wait_for("window.viscera && viscera.states >= 10 && viscera.drawn >= 10", 90,
                          "the page drew no 10 frames of 10 skeleton states")
            mode = page.evaluate("document.getElementById('mode').textContent")
            if "drawn here" not in mode:
                fail(f"the page is not drawing the session itself: mode {mode!r}")
            if stats()["frame_step"] != -1:
                fail("the server drew frames that nobody watched")

            settled = compare(page, session, "settled")
            if settled["page"] < 0.02 * 640 * 480:
                fail(f"the page shows hardly any intestine: {settled['page']} pixels")

            # the stream stops (the server stopped): the page keeps drawing and says so
            server.send_signal(signal.SIGSTOP)
            try:
                time.sleep(1.5)
                before = page.evaluate("viscera.drawn")
                time.sleep(2.0)
                after = page.evaluate("viscera.drawn")
                note = page.evaluate("document.getElementById('state').textContent")
            finally:
                server.send_signal(signal.SIGCONT)
            print(f"stream stopped: {after - before} frames drawn in 2 s; the page said {note!r}")
            if after <= before:
                fail("the page stopped drawing when the stream stopped")
            if "stream paused" not in note:
                fail(f"the page did not say the stream paused: {note!r}")

            page.wait_for("viscera.Rates(performance.now()).states_hz > 5", 30, "the stream never came back")
            # the clearing gesture uncovers the lesion: the tools in the picture, the lesion in both
            driven = cli("drive", session, "--gesture", "clearing")
            if driven.returncode != 0:
                fail(f"drive: {driven.stderr}")
            cleared = compare(page, session, "cleared")
            print(f"lesion pixels: hidden at the start (page {settled['lesion_page']}, server "
                  f"{settled['lesion_server']}), after the clearing page {cleared['lesion_page']}, "
                  f"server {cleared['lesion_server']}")
            # a camera a client sets (a plain look-at camera from inside the cavity): both follow it
            moved = cli("camera", session, "--eye", "-0.02", "-0.14", "0.20", "--target", "-0.01", "0.01", "0.05")
            if moved.returncode != 0:
                fail(f"camera: {moved.stderr}")
            time.sleep(2.0)
            compare(page, session, "client camera")
            start, drawn = time.monotonic(), page.evaluate("viscera.drawn")
            time.sleep(3.0)
            fps = (page.evaluate("viscera.drawn") - drawn) / (time.monotonic() - start)
            print(f"the page drew {fps:.1f} fps (headless Chromium, software WebGL, 640x480, load "
                  f"{os.getloadavg()[0]:.1f})")
            cost = page.evaluate(FRAME_COST, timeout=120)
            print(f"a page frame costs {cost['frame_ms']:.1f} ms of wall time (the intestine's skin "
                  f"{cost['skin_ms']:.1f} ms of it), median of 20 drawn back to back and finished")
        except Failure as e:
            for line in browser.log_tail():
                print(f"  chromium: {line}", file=sys.stderr)
            fail(str(e))
    cli("destroy", session)
    print("ok: the page draws the session from its skeleton, as the server's frames show it")


try:
    main()
finally:
    stop(procs)
    subprocess.run(["rm", "-rf", work])
