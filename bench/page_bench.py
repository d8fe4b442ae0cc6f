"""The viewer page's drawing rate, run by bench/page_bench.sh (which starts viscerad and the live
session in a loopback-only namespace): `viscera view` on the session, then for each variant a
headless Chromium with those flags opens the page and, once it draws, is watched for SECONDS:
the frames the page drew per second, the page's JavaScript per frame (Viewer.Player.Frame: the
skin rebuilt and the GL calls issued, not the rasterization, which runs in Chromium's GPU
process), a frame drawn and finished (a pixel read back, median of 20, after the window) and
Chromium's CPU (cores: CPU seconds per second, by process).

Usage: page_bench.py VISCERA SESSION LCM_URL SCENE_DIR WORK SECONDS VARIANT...
  VARIANT: Chromium flags added to tests/e2e/devtools_pipe.py's, space-separated; "!FLAG" drops
  one of those; "" or "default": those alone. A leading "NAME:" labels the row; "|JS" at the end
  is JavaScript run in the page before it is watched (to profile: what a frame costs without a
  piece of it), e.g. 'no intestine:|viscera.renderer.intestine_drawn = false'.
"""
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "e2e"))
from devtools_pipe import FLAGS, Browser, Failure  # noqa: E402
from viewer_page import FRAME_COST, start_view, stop  # noqa: E402

HTTP = "127.0.0.1:18084"

# Times Player.Frame (the page's own work per frame) from now on.
INSTRUMENT = r"""(() => {
  const v = window.viscera, frame = v.Frame.bind(v);
  v.bench = {ms: 0, n: 0};
  v.Frame = (now) => { const t = performance.now(); frame(now); v.bench.ms += performance.now() - t; ++v.bench.n; };
  return true;
})()"""
COUNTS = ("[viscera.drawn, viscera.states, viscera.bench.ms, viscera.bench.n, devicePixelRatio, "
          "viscera.renderer.intestine.count / 3, viscera.renderer.tube.indices.length / 3]")


def flags_of(variant):
    """The row's label, Chromium's flags and the JavaScript to run first (or None)."""
    variant, _, script = variant.partition("|")
    label, _, spec = variant.partition(":") if "--" not in variant.split(":", 1)[0] else ("", "", variant)
    flags = list(FLAGS)
    for word in ("" if spec == "default" else spec).split():
        if word.startswith("!"):
            flags.remove(word[1:])
        else:
            flags.append(word)
    return label or spec or "default", flags, script or None


def measure(url, work, seconds, variant):
    label, flags, script = flags_of(variant)
    with Browser(work, flags=flags) as browser:
        try:
            page = browser.open(url)
            page.wait_for("window.viscera && viscera.states >= 10 && viscera.drawn >= 10", 90,
                          "the page drew no 10 frames of 10 skeleton states")
            renderer = page.evaluate("(() => { const gl = viscera.renderer.gl, d = gl.getExtension("
                                     "'WEBGL_debug_renderer_info'); return d ? gl.getParameter("
                                     "d.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER); })()")
            page.evaluate(INSTRUMENT)
            if script is not None and page.evaluate(f"(() => {{ {script}; return true; }})()") is None:
                print(f"{label}: the page threw on {script!r}", file=sys.stderr)
                return
            time.sleep(2)  # past the page's first frames
            c0, t0, a = browser.cpu_seconds(), time.monotonic(), page.evaluate(COUNTS)
            time.sleep(seconds)
            c1, t1, b = browser.cpu_seconds(), time.monotonic(), page.evaluate(COUNTS)
            cost = page.evaluate(FRAME_COST, timeout=120)
        except Failure as e:
            for line in browser.log_tail():
                print(f"  chromium: {line}", file=sys.stderr)
            print(f"{label}: {e}", file=sys.stderr)
            return
    wall = t1 - t0
    cores = {k: (c1[k] - c0.get(k, 0.0)) / wall for k in c1}
    order = ("gpu-process", "renderer", "browser")
    parts = ", ".join(f"{k.split('-')[0]} {cores.get(k, 0):.2f}" for k in order)
    rest = sum(v for k, v in cores.items() if k not in order)
    frames = b[0] - a[0]
    print(f"| {label} | {frames / wall:.1f} | {(b[1] - a[1]) / wall:.0f} | {b[5]:.0f} of {b[6]:.0f} | "
          f"{(b[2] - a[2]) / max(b[3] - a[3], 1):.1f} | "
          f"{cost['frame_ms']:.1f} ({cost['skin_ms']:.1f}) | {sum(cores.values()):.2f} ({parts}, other {rest:.2f}) | "
          f"{os.getloadavg()[0]:.1f} | {renderer}, dpr {b[4]} |", flush=True)


def main():
    viscera, session, url, scene_dir, work, seconds = sys.argv[1:7]
    variants = sys.argv[7:] or ["default"]
    view = start_view(viscera, session, HTTP, url, scene_dir, work)
    try:
        print("| Chromium | fps | states/s | skin triangles drawn | page JS ms/frame | finished frame ms (skin) | "
              "Chromium cores (GPU, renderer, browser, other) | load | WebGL |")
        print("|---|---:|---:|---:|---:|---:|---|---:|---|")
        for variant in variants:
            measure(f"http://{HTTP}/", work, float(seconds), variant)
    finally:
        stop([view])


main()
