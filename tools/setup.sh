#!/usr/bin/env bash
# Installs every Debian package that viscera's build, tests and tools need, and the Python
# virtual environment of the Python client and the load tester (.venv, or $VISCERA_VENV).
# Idempotent: when everything is present it installs nothing and touches no network.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libsuitesparse-dev
  liblcm-dev liblcm-bin libglib2.0-dev
  libopencv-dev libosmesa6-dev libjpeg-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libtomlplusplus-dev nlohmann-json3-dev
  libsodium-dev libcli11-dev libboost-dev
  iproute2 util-linux python3 python3-venv
  chromium
  clang libclang-rt-14-dev llvm ccache clang-format
)

missing=()
for p in "${packages[@]}"; do
  # dpkg-query prints "install ok installed" only for a fully installed package.
  if [[ "$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null)" != "install ok installed" ]]; then
    missing+=("$p")
  fi
done

if ((${#missing[@]} > 0)); then
  echo "setup: installing ${missing[*]}" >&2
  sudo_cmd=()
  if [[ $(id -u) -ne 0 ]]; then sudo_cmd=(sudo); fi
  export DEBIAN_FRONTEND=noninteractive
  # A fresh machine has no package lists yet; refresh them once before installing.
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  echo "setup: done" >&2
fi

# Python: a virtual environment (Debian 12's system pip refuses to install: PEP 668) with
# PyPI's lcm, matplotlib and numpy (and wheel, to build the client), pinned, and the viscera client built from python/ and
# proto/ (its build runs lcm-gen). Reinstalled only when those sources change.
venv="${VISCERA_VENV:-$root/.venv}"
python_packages=(lcm==1.5.3 matplotlib==3.11.2 numpy==2.4.6 wheel==0.48.0)
stamp="$venv/.viscera-client-stamp"
sources_hash=$(cd "$root" && cat python/pyproject.toml python/setup.py python/viscera_client/*.py \
  python/viscera_client/load/*.py proto/*.lcm | sha256sum | cut -d' ' -f1)
if [[ ! -x "$venv/bin/python" ]]; then
  echo "setup: making the Python environment $venv" >&2
  /usr/bin/python3 -m venv "$venv"
fi
if ! "$venv/bin/python" - "${python_packages[@]}" <<'PY' 2>/dev/null; then
import sys
from importlib.metadata import version
for spec in sys.argv[1:]:
    name, wanted = spec.split("==")
    assert version(name) == wanted, spec
PY
  echo "setup: installing ${python_packages[*]} into $venv" >&2
  "$venv/bin/python" -m pip install -q --disable-pip-version-check "${python_packages[@]}"
fi
if [[ "$(cat "$stamp" 2>/dev/null)" != "$sources_hash" ]]; then
  echo "setup: installing the viscera client (python/) into $venv" >&2
  "$venv/bin/python" -m pip install -q --disable-pip-version-check --no-build-isolation \
    --force-reinstall --no-deps "$root/python"
  rm -rf "$root/python/build" "$root/python/"*.egg-info
  echo "$sources_hash" >"$stamp"
fi
