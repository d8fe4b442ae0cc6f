#!/bin/sh
# Docs tool: regenerates the renderer's pictures in docs/ (docs/rendering.md): each skin in the
# settled cavity scene through a laparoscope inside the cavity, the clearing gesture at t = 3 s
# from viscera-sim's default camera, and a close-up of the grasper's jaws at t = 0.9 s. Frames
# come from `viscera-sim --render` (OSMesa, JPEG quality 95) and are converted to PNG. Needs a
# build and python3 with Pillow. Then the laparoscope's view (docs/images/view_*.jpg, JPEG as
# rendered).
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
  --render "$out/grasp" --render-every 90 --camera 0.16 -0.07 0.15 0.12 -0.025 0.07 --jpeg-quality 95 >/dev/null
python3 -c "import sys; from PIL import Image; Image.open(sys.argv[1]).save(sys.argv[2])" \
  "$out/grasp/frame_000001.jpg" "$repo/docs/render_grasp.png"
# the laparoscope's view (docs/rendering.md): the cavity through its [camera] scope before and
# after the clearing gesture, with 30 degree optics, and the mesentery scene; JPEG as rendered
mkdir -p "$repo/docs/images"
"$sim" "$repo/scenes/cavity.toml" --duration 6 --tool-script "$repo/scenes/clearing.csv" --skin convolution \
  --render "$out/view" --render-every 600 --jpeg-quality 80 >/dev/null
cp "$out/view/frame_000000.jpg" "$repo/docs/images/view_before.jpg"
cp "$out/view/frame_000001.jpg" "$repo/docs/images/view_after.jpg"
cp "$repo/scenes/liver.obj" "$out/"
# 30 degree optics need the shaft more than 31 degrees from the image's up: the cavity's scope
# is 25 degrees from the vertical, so the oblique view shows the patient's right (+y) up
sed 's/^optics = 0 .*/optics = 30\nup = [0.0, 1.0, 0.0]/' "$repo/scenes/cavity.toml" >"$out/oblique.toml"
grep -q '^optics = 30' "$out/oblique.toml"
"$sim" "$out/oblique.toml" --duration 0.01 --skin convolution --render "$out/oblique" --jpeg-quality 80 >/dev/null
cp "$out/oblique/frame_000000.jpg" "$repo/docs/images/view_oblique.jpg"
"$sim" "$repo/scenes/cavity.toml" --duration 0.01 --skin convolution --render "$out/mesentery" \
  --camera 0.0 -0.13 0.06 0.0 0.02 0.03 --jpeg-quality 80 >/dev/null
cp "$out/mesentery/frame_000000.jpg" "$repo/docs/images/view_mesentery.jpg"
rm -rf "$out"
echo "pictures written to $repo/docs"
