#!/bin/sh
# Bit-identity check for a change that must not move the simulation: the state digests
# (viscera-state-digest) of seven runs, written to OUT_DIR; with REF_DIR (the same script's output
# for the reference build), each compared with its reference ("same" or "DIFFERENT"; exit 1 on any
# difference). Runs: the cavity with scenes/clearing.csv at 100 Hz and 1 kHz, scenes/fall.toml,
# the peers' coil at 100 Hz and 1 kHz, the cavity with the press gesture at 1 kHz and the sweep at
# 100 Hz. Usage, from the repository's root:
#   sh tools/sim/state_digests.sh BUILD/tools/viscera-state-digest OUT_DIR [REF_DIR]
set -eu
bin=$1
out=$2
ref=${3:-}
mkdir -p "$out"
"$bin" scenes/cavity.toml --duration 5.5 --tool-script scenes/clearing.csv --every 50 > "$out/cav100.txt" &
"$bin" scenes/cavity.toml --duration 5.5 --tool-script scenes/clearing.csv --rate 1000 --every 500 > "$out/cav1k.txt"
wait
"$bin" scenes/fall.toml --duration 3 --every 20 > "$out/fall.txt" &
"$bin" bench/scenes/paper_coil.toml --duration 2 --every 20 > "$out/paper.txt"
wait
"$bin" scenes/cavity.toml --duration 3 --tool-script scenes/gestures/press.csv --rate 1000 --every 300 > "$out/press1k.txt" &
"$bin" scenes/cavity.toml --duration 3 --tool-script scenes/gestures/sweep.csv --every 30 > "$out/sweep100.txt"
wait
"$bin" bench/scenes/paper_coil.toml --duration 1 --rate 1000 --every 100 > "$out/paper1k.txt"
[ -n "$ref" ] || exit 0
status=0
for run in cav100 cav1k fall paper paper1k press1k sweep100; do
  if cmp -s "$ref/$run.txt" "$out/$run.txt"; then
    echo "$run same"
  else
    echo "$run DIFFERENT"
    status=1
  fi
done
exit $status
