#!/usr/bin/env bash
# End to end: headless Chromium shows the MJPEG viewer's stream (a moving disc from
# mjpeg_feeder), inside a private network namespace holding only loopback (in_netns.sh).
# Usage: viewer_chromium_test.sh MJPEG_FEEDER
set -euo pipefail
feeder=$1
here=$(cd "$(dirname "$0")" && pwd)
if [[ "${VISCERA_IN_NETNS:-}" != 1 ]]; then
  exec sh "$here/in_netns.sh" bash "$0" "$@"
fi

work=$(mktemp -d)
feeder_pid=""
# whatever happens, leave no feeder behind
cleanup() {
  if [[ -n $feeder_pid ]]; then kill -TERM "$feeder_pid" 2>/dev/null || true; fi
  wait 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT
fail() {
  echo "FAIL: $*" >&2
  [[ -s $work/feeder.err ]] && sed 's/^/  mjpeg_feeder: /' "$work/feeder.err" >&2
  exit 1
}

# long enough for a slow Chromium start; the trap ends it sooner
"$feeder" --seconds 100 >"$work/feeder.out" 2>"$work/feeder.err" &
feeder_pid=$!
for _ in $(seq 300); do
  grep -q '^port ' "$work/feeder.out" && break
  kill -0 "$feeder_pid" 2>/dev/null || fail "mjpeg_feeder exited"
  sleep 0.1
done
port=$(sed -n 's/^port //p' "$work/feeder.out")
[[ -n $port ]] || fail "mjpeg_feeder printed no port (30 s)"
url="http://127.0.0.1:$port"

"$here/chromium_mjpeg_check.sh" "$url/" 5 || fail "Chromium did not show the stream"

# the server saw it too; no proxy, whatever the environment says
python3 - "$url/stats.json" <<'PY' || fail "bad stats"
import json, sys, urllib.request
opener = urllib.request.build_opener(urllib.request.ProxyHandler({}))
stats = json.load(opener.open(sys.argv[1], timeout=10))
print("stats:", json.dumps(stats))
assert stats["parts_sent"] > 0, stats
assert stats["streams_opened"] >= 1, stats
assert stats["frames_posted"] > 0, stats
PY
echo "ok: viewer shown by Chromium inside a loopback-only namespace"
