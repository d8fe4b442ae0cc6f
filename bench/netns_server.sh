# The common start of the scripts that drive the real viscerad and viscera (bench/frames_bench.sh,
# bench/frame_governor_bench.sh, bench/frame_lease_bench.sh, bench/server_bench.sh,
# bench/haptic_bench.sh). Sourced, not run: `. "$(dirname "$0")/netns_server.sh"` from a POSIX
# sh or bash script one directory below the source tree, right after its `set`, with the
# script's own arguments. It
#  - runs the script again, with the same shell and arguments, inside a private network
#    namespace holding only loopback (tests/e2e/in_netns.sh): nothing leaves this machine and no
#    other server answers. VISCERA_BENCH_NETNS=0 stays on the host's network (the namespace is
#    a user namespace, which refuses SCHED_FIFO); the URL's ttl=0 keeps the traffic here;
#  - sets `root` (the source tree), `url` (the LCM URL), `work` (a temporary directory, removed
#    on exit) and VISCERA_SESSIONS (the client's session file, in `work`);
#  - defines `v` (the viscera client on `url`), `start_server` and `stop_server` (viscerad on
#    `url` with the scenes of scenes/, its stderr in $work/viscerad.err; stopped on exit too)
#    and `new_session` (creates a session, prints its id).
# The script sets `build` (the build tree) before it calls them.
root=$(cd "$(dirname "$0")/.." && pwd)
if [ "${VISCERA_IN_NETNS:-}" != 1 ] && [ "${VISCERA_BENCH_NETNS:-1}" != 0 ]; then
  if [ -n "${BASH_VERSION:-}" ]; then
    exec "$root/tests/e2e/in_netns.sh" bash "$0" "$@"
  fi
  exec "$root/tests/e2e/in_netns.sh" sh "$0" "$@"
fi
url='udpm://239.255.76.67:7667?ttl=0'
work=$(mktemp -d)
export VISCERA_SESSIONS="$work/sessions.json"
server_pid=""
# the server, then whatever else the script left running (each ends by itself), then the files
trap 'stop_server; wait 2>/dev/null; rm -rf "$work"' EXIT

v() { "$build/client/viscera" "$@" --lcm-url "$url"; }

start_server() {  # viscerad arguments besides --lcm-url and --scene-dir
  "$build/server/viscerad" --lcm-url "$url" --scene-dir "$root/scenes" "$@" 2>"$work/viscerad.err" &
  server_pid=$!
}

stop_server() {
  if [ -n "$server_pid" ]; then
    kill -TERM "$server_pid" 2>/dev/null || true
    wait "$server_pid" 2>/dev/null || true
    server_pid=""
  fi
}

new_session() {  # viscera create arguments: prints the new session's id
  v create "$@" --json | python3 -c 'import json, sys; print(json.load(sys.stdin)["session"])'
}
