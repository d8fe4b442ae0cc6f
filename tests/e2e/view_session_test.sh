#!/usr/bin/env bash
# End to end: a session's frames from the real viscerad, through `viscera view --http`, shown
# by headless Chromium; inside a private network namespace holding only loopback (in_netns.sh).
# Usage: view_session_test.sh VISCERAD VISCERA
set -euo pipefail
viscerad=$1 viscera=$2
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
if [[ "${VISCERA_IN_NETNS:-}" != 1 ]]; then
  exec sh "$here/in_netns.sh" bash "$0" "$@"
fi

work=$(mktemp -d)
url='udpm://239.255.76.67:7667?ttl=0'
export VISCERA_SESSIONS="$work/sessions.json"
server_pid="" view_pid=""
cleanup() {
  [[ -n $view_pid ]] && kill -TERM "$view_pid" 2>/dev/null || true
  [[ -n $server_pid ]] && kill -TERM "$server_pid" 2>/dev/null || true
  wait 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT
fail() {
  echo "FAIL: $*" >&2
  for f in viscerad.err view.err; do [[ -s $work/$f ]] && sed "s/^/  $f: /" "$work/$f" >&2; done
  exit 1
}
v() { "$viscera" "$@" --lcm-url "$url"; }

"$viscerad" --server-id view-test --lcm-url "$url" --scene-dir "$root/scenes" 2>"$work/viscerad.err" &
server_pid=$!
id=$(v create hanging --width 320 --height 240 --frame-rate 25 --json --timeout 10 |
  python3 -c 'import json, sys; print(json.load(sys.stdin)["session"])') || fail "create"

# a fixed port is safe: this namespace is ours alone; the binary itself in the background
# (not through v, whose subshell would take the SIGTERM meant for it)
"$viscera" view "$id" --http 127.0.0.1:18080 --lcm-url "$url" 2>"$work/view.err" &
view_pid=$!
for _ in $(seq 300); do
  grep -q 'http://127.0.0.1:18080/' "$work/view.err" && break
  kill -0 "$view_pid" 2>/dev/null || fail "viscera view exited"
  sleep 0.1
done
grep -q 'http://127.0.0.1:18080/' "$work/view.err" || fail "viscera view never listened (30 s)"

# the server's frames (the page's default is to draw the session itself: client_render_test.py)
"$here/chromium_mjpeg_check.sh" "http://127.0.0.1:18080/?video=server" 5 || fail "Chromium did not show the session"

python3 - "http://127.0.0.1:18080" <<'PY' || fail "stats or still frame"
import json, sys, urllib.request
opener = urllib.request.build_opener(urllib.request.ProxyHandler({}))
stats = json.load(opener.open(sys.argv[1] + "/stats.json", timeout=10))
print("stats:", json.dumps(stats))
assert stats["frames_posted"] >= 10 and stats["parts_sent"] > 0 and stats["streams_opened"] >= 1, stats
jpeg = opener.open(sys.argv[1] + "/frame.jpg", timeout=10).read()
assert jpeg[:2] == b"\xff\xd8" and jpeg[-2:] == b"\xff\xd9", "not a JPEG"
PY

kill -TERM "$view_pid"
wait "$view_pid" || fail "viscera view did not end cleanly on SIGTERM"
view_pid=""
grep -q 'served' "$work/view.err" || fail "viscera view printed no summary"
v destroy "$id" >/dev/null || fail "destroy"
echo "ok: a live session shown by Chromium through viscera view"
