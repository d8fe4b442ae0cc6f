#!/bin/sh
# Runs a command inside a private network namespace holding only loopback, with a
# multicast route on lo: nothing can leave this machine, and no
# other server on the host can answer. Usage: in_netns.sh COMMAND [ARGS...]
set -eu
if [ "${VISCERA_IN_NETNS:-}" != 1 ]; then
  exec unshare -rn env VISCERA_IN_NETNS=1 sh "$0" "$@"
fi
ip link set lo up
ip link set lo multicast on
ip route add 224.0.0.0/4 dev lo
if ip -o link show | grep -v ': lo:' | grep -q .; then
  echo "in_netns.sh: network namespace has interfaces besides lo" >&2; exit 1
fi
exec "$@"
