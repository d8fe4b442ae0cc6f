#!/bin/sh
# Docs tool: regenerates the renderer's pictures in docs/ (docs/rendering.md): each skin in the
# settled cavity scene through a laparoscope inside the cavity, the clearing gesture at t = 3 s
# from viscera-sim's default camera, and a close-up of the grasper's jaws at t = 0.9 s. Frames
# come from `viscera-sim --render` (OSMesa, JPEG quality 95) and are converted to PNG. Needs a
# build and python3 with Pillow.
set -eu
repo=$(cd "$(dirname "$0")/.." && pwd)
sim="$repo/build/tools/viscera-sim"
out=$(mktemp -d)
scope="--camera -0.02 -0.14 0.20 -0.01 0.01 0.05"
for skin in parametric convolution implicit hybrid; do
  # shellcheck disable=SC2086
  "$sim" "$repo/scenes/cavity.toml" --duration 0.01 --skin "$skin" --render "$out/$skin" $scope \
    --jpeg-quality 95 >/dev/null
  python3 -c "import sys; from PIL import Image; Image.open(sys.argv[1]).save(sys.argv[2])" \
    "$out/$skin/frame_000000.jpg" "$repo/docs/render_$skin.png"
done
"$sim" "$repo/scenes/cavity.toml" --duration 3 --tool-script "$repo/scenes/clearing.csv" --skin convolution \
  --render "$out/clearing" --render-every 300 --jpeg-quality 95 >/dev/null
python3 -c "import sys; from PIL import Image; Image.open(sys.argv[1]).save(sys.argv[2])" \
  "$out/clearing/frame_000001.jpg" "$repo/docs/render_clearing.png"
# close-up of the open jaws coming down on the loop they grasp at t = 1.5 s
"$sim" "$repo/scenes/cavity.toml" --duration 1 --tool-script "$repo/scenes/clearing.csv" --skin convolution \
  --render "$out/grasp" --render-every 90 --camera 0.05 -0.095 0.14 0.019 -0.036 0.1 --jpeg-quality 95 >/dev/null
python3 -c "import sys; from PIL import Image; Image.open(sys.argv[1]).save(sys.argv[2])" \
  "$out/grasp/frame_000001.jpg" "$repo/docs/render_grasp.png"
rm -rf "$out"
echo "pictures written to $repo/docs"
