"""The viewer page drawing a session itself, as tests/e2e/client_render_test.py and
bench/page_bench.py drive it: `viscera view` started on a session, and the page's cost per frame
measured in the page.

    view = start_view(viscera, session, "127.0.0.1:18082", url, scene_dir, work)
    ...
    stop([view])
"""
import signal
import subprocess
import time

# Wall time of one frame drawn and finished, and of the skin alone, median of 20. Finished: one
# pixel read back, which waits for the GPU process to draw it (Chromium's gl.finish does not).
FRAME_COST = r"""(() => {
  const v = window.viscera, r = v.renderer, q = v.latest.points, frames = [], skins = [];
  const pixel = new Uint8Array(4);
  for (let i = 0; i < 20; ++i) {
    const t0 = performance.now();
    r.tube.Build(q);
    const t1 = performance.now();
    v.Frame(performance.now() + 1e6);
    r.gl.readPixels(0, 0, 1, 1, r.gl.RGBA, r.gl.UNSIGNED_BYTE, pixel);
    frames.push(performance.now() - t1);
    skins.push(t1 - t0);
  }
  const median = (x) => x.sort((a, b) => a - b)[x.length >> 1];
  return {frame_ms: median(frames), skin_ms: median(skins)};
})()"""


def start_view(viscera, session, http, url, scene_dir, work, seconds=30):
    """`viscera view SESSION --http HTTP` (host:port), its stderr in WORK/view.err; returns the
    process once it listens. RuntimeError if it does not within `seconds`."""
    err = f"{work}/view.err"
    view = subprocess.Popen([viscera, "view", session, "--http", http, "--lcm-url", url, "--scene-dir", scene_dir],
                            stderr=open(err, "w"))
    deadline = time.monotonic() + seconds
    while f"http://{http}/" not in open(err).read():
        if view.poll() is not None or time.monotonic() > deadline:
            view.kill()
            raise RuntimeError(f"viscera view never listened ({seconds} s)")
        time.sleep(0.1)
    return view


def stop(procs):
    """Ends the processes started (the last first), stopped ones too."""
    for p in reversed(procs):
        if p.poll() is None:
            p.send_signal(signal.SIGCONT)
            p.terminate()
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                p.kill()
