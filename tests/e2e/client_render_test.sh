#!/usr/bin/env bash
# The viewer page drawing a session itself in headless Chromium (client_render_test.py), inside
# a private network namespace holding only loopback (in_netns.sh).
# Usage: client_render_test.sh VISCERAD VISCERA
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
if [[ "${VISCERA_IN_NETNS:-}" != 1 ]]; then
  exec sh "$here/in_netns.sh" bash "$0" "$@"
fi
exec python3 "$here/client_render_test.py" "$1" "$2" "$root/scenes"
