#!/bin/sh
# Several "hosts" on one machine (docs/deployment.md): network namespaces joined by a bridge
# with veth pairs, multicast routed only inside. viscerad runs on hosts 1 and 2, the load
# tester on host 3; the test checks that the sessions spread over both servers and that poses
# and forces flow between the hosts. The bridge's namespace has no other interface, so
# nothing can leave this machine.
# Usage: lan_test.sh VISCERAD PYTHON SOURCE_DIR
set -eu
viscerad=$1 python=$2 root=$3

# the "switch": a private network namespace (and user namespace, so no privilege is needed)
if [ "${VISCERA_IN_LAN:-}" != 1 ]; then
  exec unshare -rn env VISCERA_IN_LAN=1 sh "$0" "$@"
fi

url='udpm://239.255.76.67:7667?ttl=1'  # ttl 1: across the bridge, never beyond a router
work=$(mktemp -d)
pids=""
cleanup() {
  for p in $pids; do kill -TERM "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT
trap "exit 1" INT TERM
fail() {
  echo "FAIL: $*" >&2
  for f in "$work"/*.err; do [ -s "$f" ] && sed "s|^|  $(basename "$f"): |" "$f" >&2; done
  exit 1
}

ip link set lo up
ip link add lan0 type bridge
# no IGMP querier on this LAN: flood multicast to every port instead of snooping
ip link set lan0 type bridge mcast_snooping 0
ip link set lan0 up

own_netns=$(readlink /proc/self/ns/net)
# host N: a process holding a network namespace of its own, linked to the bridge by a veth
add_host() {
  n=$1
  unshare -n sleep 100000 &
  holder=$!
  pids="$pids $holder"
  tries=0
  while [ "$(readlink /proc/$holder/ns/net 2>/dev/null)" = "$own_netns" ] ||
        [ -z "$(readlink /proc/$holder/ns/net 2>/dev/null)" ]; do
    tries=$((tries + 1)); [ $tries -lt 1000 ] || fail "host $n: no namespace"
    sleep 0.01  # polling for the namespace to exist, bounded above
  done
  ip link add "h$n" type veth peer name eth0 netns "$holder"
  ip link set "h$n" master lan0
  ip link set "h$n" up
  nsenter -t "$holder" -n sh -c "
    ip link set lo up
    ip addr add 10.213.0.$n/24 dev eth0
    ip link set eth0 up
    ip route add 224.0.0.0/4 dev eth0"
  eval "host$n=$holder"
}
on_host() { n=$1; shift; eval "nsenter -t \$host$n -n \"\$@\""; }

add_host 1
add_host 2
add_host 3
# isolation: the switch holds only lo, the bridge and the three veth ends; a host only lo and eth0
links=$(ip -o link show | awk -F': ' '{print $2}' | sed 's/@.*//' | sort | tr '\n' ' ')
[ "$links" = "h1 h2 h3 lan0 lo " ] || fail "switch namespace has unexpected links: $links"
hlinks=$(on_host 3 ip -o link show | awk -F': ' '{print $2}' | sed 's/@.*//' | sort | tr '\n' ' ')
[ "$hlinks" = "eth0 lo " ] || fail "host 3 has unexpected links: $hlinks"

# nsenter execs the server in place: $! is the server itself, so cleanup stops it (a
# subshell's pid would leave it running in the host's namespace)
# --insecure: these namespaces reach only each other (ttl 1 over their bridge), never off the machine
nsenter -t "$host1" -n "$viscerad" --server-id lan-a --insecure --max-sessions 3 --lcm-url "$url" \
  --scene-dir "$root/scenes" 2>"$work/lan-a.err" &
pids="$pids $!"
nsenter -t "$host2" -n "$viscerad" --server-id lan-b --insecure --max-sessions 3 --lcm-url "$url" \
  --scene-dir "$root/scenes" 2>"$work/lan-b.err" &
pids="$pids $!"

# host 3 hears both servers across the bridge (poll with a deadline)
on_host 3 "$python" - "$url" <<'PY' || fail "host 3 did not hear both servers"
import sys, time
from viscera_client import Client
c = Client(sys.argv[1])
deadline, heard = time.monotonic() + 30, set()
while time.monotonic() < deadline:
    heard |= {s.server_id for s in c.servers(0.5)}
    if heard >= {"lan-a", "lan-b"}:
        sys.exit(0)
sys.exit(1)
PY
# negative control: with ttl=0 a request never leaves host 3, so no server can answer it
on_host 3 "$python" - <<'PY' || fail "a ttl=0 client on host 3 reached a server on another host"
import sys
from viscera_client import Client, VisceraError
try:
    Client("udpm://239.255.76.67:7667?ttl=0").create(scene="hanging", server="lan-a", timeout_s=2, build_timeout_s=2)
except VisceraError as e:
    sys.exit(0 if e.result is None else 1)
sys.exit(1)
PY

# bytes the bridge delivered to host 3: what its veth end h3 transmitted (/proc/net/dev is
# this namespace's; /sys/class/net is the one sysfs was mounted in)
to_host3() { awk -F'[: ]+' '$2 == "h3" {print $11}' /proc/net/dev; }
before=$(to_host3)
status=0
on_host 3 "$python" "$root/tools/loadtest.py" --sessions 4 --seconds 4 --pose-rate 100 \
  --session-rate 100 --scene-file "$root/tests/e2e/scenes/push.toml" --lcm-url "$url" \
  --json "$work/report.json" --progress none >"$work/loadtest.out" 2>"$work/loadtest.err" ||
  status=$?
[ $status -le 1 ] || [ $status -eq 3 ] || fail "loadtest exited with $status"
after=$(to_host3)

"$python" - "$work/report.json" <<'PY' || fail "report: $(cat "$work/report.json")"
import json, sys
r = json.load(open(sys.argv[1]))
o = r["overall"]
# spread: two sessions on each host's server (least loaded first, counting its own)
assert o["servers"] == {"lan-a": 2, "lan-b": 2}, o["servers"]
assert sorted(s["server"] for s in r["sessions"]) == ["lan-a", "lan-a", "lan-b", "lan-b"]
for s in r["sessions"]:
    # traffic both ways between the hosts; how much UDP lost is a figure (docs/loadtest.md),
    # not a test: under load a receive buffer overflows now and then (1 pose of 370 once,
    # with a build beside ctest -j2)
    assert s["poses"]["accepted"] > 200, s["poses"]
    assert s["forces"]["received"] > 200, s["forces"]
    assert 0 < s["round_trip_us"]["p50"] <= s["round_trip_us"]["max"], s["round_trip_us"]
print("ok: 4 sessions, 2 on lan-a (host 1), 2 on lan-b (host 2), driven from host 3;",
      o["forces_received"], "forces,", o["round_trip_us"]["p50"], "us median round trip")
PY
# the forces reached host 3 through its veth: well over 1000 messages of ~300 bytes
[ $((after - before)) -gt 300000 ] || fail "only $((after - before)) bytes reached host 3"
echo "ok: $((after - before)) bytes into host 3 over the bridge"
