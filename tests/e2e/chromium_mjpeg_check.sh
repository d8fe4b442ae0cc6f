#!/usr/bin/env bash
# Opens URL (an MjpegServer's page "/") in Debian's headless Chromium and succeeds once the
# page's <span id="shown"> counts at least MIN_FRAMES different pictures; prints the count.
# Usage: chromium_mjpeg_check.sh URL MIN_FRAMES [MAX_SECONDS (default 20)]
#
# Why DevTools over a pipe and not --dump-dom: the page's load event fires with the first
# part of the never-ending MJPEG stream, before any timer ran, so --dump-dom (with or without
# --timeout) dumps "0"; and --virtual-time-budget never ends, since virtual time stands still
# while a fetch is pending. A pipe (--remote-debugging-pipe) opens no port and needs no
# network, so the check also runs in a loopback-only namespace.
set -euo pipefail
if (($# < 2 || $# > 3)); then
  echo "usage: $0 URL MIN_FRAMES [MAX_SECONDS]" >&2; exit 2
fi
url=$1 min_frames=$2 max_seconds=${3:-20}

# The real binary, not Debian's /usr/bin/chromium wrapper: the wrapper adds flags of its own
# (extensions, GPU rasterization) and prints shell errors on some machines.
browser=/usr/lib/chromium/chromium
[[ -x $browser ]] || browser=$(command -v chromium || true)
[[ -n $browser ]] || { echo "chromium_mjpeg_check: chromium not installed (tools/setup.sh)" >&2; exit 2; }

work=$(mktemp -d)
driver_pid=""
# Chromium runs in its own session (process group) named in $work/pgid: whatever happens, kill
# the whole group (browser, zygotes, renderer, GPU) and the driver, and remove the profile.
# Killed outright (SIGKILL), this script cannot clean up, but Chromium still exits once the
# driver holding its DevTools pipe is gone (within MAX_SECONDS + 5).
cleanup() {
  if [[ -s $work/pgid ]]; then kill -KILL -- "-$(cat "$work/pgid")" 2>/dev/null || true; fi
  if [[ -n $driver_pid ]]; then
    # the redirection also silences bash's "Killed" report of the job
    { kill -KILL "$driver_pid"; wait "$driver_pid"; } 2>/dev/null || true
  fi
  # a process just killed may still be finishing a write into the profile: retry once
  rm -rf "$work" 2>/dev/null || { sleep 0.5; rm -rf "$work"; }
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# The driver runs in the background and the shell waits for it: a signal interrupts `wait`
# at once (a foreground child would delay the trap until it ended).
python3 - "$browser" "$url" "$min_frames" "$max_seconds" "$work" <<'PY' &
import json, os, select, signal, subprocess, sys, time

browser, url, min_frames, max_seconds, work = sys.argv[1:]
min_frames, max_seconds = int(min_frames), float(max_seconds)
flags = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--no-first-run", "--no-default-browser-check", "--disable-extensions", "--mute-audio",
         "--no-proxy-server", "--remote-debugging-pipe", f"--user-data-dir={work}/profile",
         "about:blank"]

# DevTools pipe: Chromium reads commands on fd 3 and writes replies on fd 4, NUL-terminated.
to_browser_r, to_browser_w = os.pipe()
from_browser_r, from_browser_w = os.pipe()
def plumb():
    # through high numbers first, so that no pipe end is overwritten before it is copied
    os.dup2(to_browser_r, 100); os.dup2(from_browser_w, 101)
    os.dup2(100, 3); os.dup2(101, 4)
    os.close(100); os.close(101)
log = open(f"{work}/chromium.log", "wb")
proc = subprocess.Popen([browser] + flags, stdin=subprocess.DEVNULL, stdout=log, stderr=log,
                        preexec_fn=plumb, close_fds=False, start_new_session=True)
with open(f"{work}/pgid", "w") as f:
    f.write(str(proc.pid))
os.close(to_browser_r); os.close(from_browser_w)

start = time.monotonic()
deadline = start + max_seconds
buffer, next_id = b"", 0

def fail(message):
    log.flush()
    lines = open(f"{work}/chromium.log", "rb").read().decode(errors="replace").splitlines()
    # without a D-Bus (containers, namespaces) Chromium complains at length: not the cause
    tail = [line for line in lines if "dbus" not in line][-15:]
    print(f"chromium_mjpeg_check: FAIL: {message}", file=sys.stderr)
    for line in tail:
        print(f"  chromium: {line}", file=sys.stderr)
    sys.exit(1)

def call(method, params=None, session=None, errors_fail=True):
    """Sends one DevTools command and returns its result (events in between are skipped),
    or None on an error reply when not errors_fail."""
    global buffer, next_id
    next_id += 1
    message = {"id": next_id, "method": method, "params": params or {}}
    if session:
        message["sessionId"] = session
    os.write(to_browser_w, json.dumps(message).encode() + b"\0")
    while True:
        while b"\0" not in buffer:
            remaining = deadline + 5 - time.monotonic()
            ready, _, _ = select.select([from_browser_r], [], [], max(remaining, 0))
            if not ready:
                fail(f"no DevTools answer to {method}")
            chunk = os.read(from_browser_r, 1 << 16)
            if not chunk:
                fail(f"chromium exited (status {proc.wait()}) during {method}")
            buffer += chunk
        raw, buffer = buffer.split(b"\0", 1)
        reply = json.loads(raw)
        if reply.get("id") == next_id:
            if "error" not in reply:
                return reply["result"]
            if errors_fail:
                fail(f"{method}: {reply['error']}")
            return None

def evaluate(session, expression):
    """The value of a JavaScript expression in the page; None while the page has no
    JavaScript context yet (during navigation) or on any error."""
    result = call("Runtime.evaluate", {"expression": expression, "returnByValue": True},
                  session, errors_fail=False)
    return None if result is None else result.get("result", {}).get("value")

def check():
    target = call("Target.createTarget", {"url": url})["targetId"]
    session = call("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
    while True:
        # null until the page has loaded, or if URL is not an MjpegServer page
        value = evaluate(session, "(document.getElementById('shown') || {}).textContent")
        shown = int(value) if isinstance(value, str) and value.isdigit() else 0
        elapsed = time.monotonic() - start
        if shown >= min_frames:
            print(f"ok: chromium saw {shown} frames in {elapsed:.1f} s ({url})")
            return
        if time.monotonic() > deadline:
            title = evaluate(session, "document.title")
            fail(f"saw {shown} frames in {elapsed:.1f} s, wanted {min_frames} "
                 f"(page title: {title!r}, #shown: {value!r})")
        time.sleep(0.25)

try:
    check()
finally:
    # Close politely, so that Chromium reaps its own children; else kill them all.
    try:
        deadline = time.monotonic()  # no more waiting for answers than the 5 s grace
        call("Browser.close")
        proc.wait(timeout=5)
    except (OSError, SystemExit, subprocess.TimeoutExpired):
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
PY
driver_pid=$!
status=0
wait "$driver_pid" || status=$?
driver_pid=""
exit "$status"
