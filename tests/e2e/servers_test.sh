#!/bin/sh
# End-to-end test of viscerad + `viscera servers` over real UDP multicast, inside a
# private network namespace that holds only loopback: nothing
# can leave this machine, and no other viscerad on the host can answer.
# Usage: servers_test.sh found|none VISCERAD VISCERA
set -eu
mode=$1 viscerad=$2 viscera=$3

# A private network namespace holding only loopback, with a multicast route (in_netns.sh).
if [ "${VISCERA_IN_NETNS:-}" != 1 ]; then
  exec sh "$(dirname "$0")/in_netns.sh" sh "$0" "$@"
fi

url='udpm://239.255.76.67:7667?ttl=0'
work=$(mktemp -d)
pids=""
# whatever happens, leave no daemon behind (they would outlive the namespace's shell)
cleanup() {
  for p in $pids; do kill -TERM "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

fail() { echo "FAIL: $*" >&2; [ -f "$work/viscerad.err" ] && sed 's/^/  viscerad: /' "$work/viscerad.err" >&2; exit 1; }

case "$mode" in
none)
  # no server: a clear message and a non-zero exit, within the timeout
  if "$viscera" servers --timeout 1 --lcm-url "$url" >"$work/out" 2>"$work/err"; then
    fail "viscera servers succeeded with no server running"
  fi
  grep -q "no server answered" "$work/err" || fail "unclear message: $(cat "$work/err")"
  [ ! -s "$work/out" ] || fail "printed servers with none running: $(cat "$work/out")"
  echo "ok: no server -> $(cat "$work/err")"
  ;;
found)
  id="e2e-$$"
  "$viscerad" --server-id "$id" --max-sessions 3 --lcm-url "$url" 2>"$work/viscerad.err" &
  pid=$!
  pids="$pid"
  # a second server on the same group and port: both must be heard
  "$viscerad" --server-id "$id-b" --lcm-url "$url" 2>"$work/viscerad-b.err" &
  pid_b=$!
  pids="$pid $pid_b"
  "$viscera" servers --json --timeout 2 --lcm-url "$url" >"$work/servers.json" 2>"$work/err" \
    || { fail "viscera servers exited non-zero: $(cat "$work/err")"; }
  python3 - "$work/servers.json" "$id" <<'PY' || { fail "bad JSON: $(cat "$work/servers.json")"; }
import json, sys
servers = json.load(open(sys.argv[1]))
assert isinstance(servers, list), servers
mine = [s for s in servers if s["server_id"] == sys.argv[2]]
assert len(mine) == 1, servers
assert [x["server_id"] for x in servers] == sorted([sys.argv[2], sys.argv[2] + "-b"]), servers
s = mine[0]
assert s["sessions"] == 0 and s["max_sessions"] == 3, s
assert 0.0 <= s["load"] <= 2.0, s
assert s["heartbeats"] >= 1, s
PY
  # the readable table names the server too
  "$viscera" servers --timeout 1.2 --lcm-url "$url" | grep -q "^$id " \
    || { fail "table does not list $id"; }

  kill -TERM "$pid"
  kill -INT "$pid_b"
  pids=""
  status=0
  wait "$pid" || status=$?
  [ "$status" -eq 0 ] || fail "viscerad exited with $status after SIGTERM"
  grep -q "SIGTERM received, stopping" "$work/viscerad.err" || fail "no stop message"
  grep -q "stopped cleanly" "$work/viscerad.err" || fail "no clean-stop message"
  status=0
  wait "$pid_b" || status=$?
  [ "$status" -eq 0 ] || fail "second viscerad exited with $status after SIGINT"
  grep -q "SIGINT received, stopping" "$work/viscerad-b.err" || fail "no stop message on SIGINT"
  echo "ok: found $id and $id-b, clean exits on SIGTERM and SIGINT"
  ;;
*)
  echo "usage: $0 found|none VISCERAD VISCERA" >&2; exit 2 ;;
esac
