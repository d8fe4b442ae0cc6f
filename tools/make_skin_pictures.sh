#!/bin/sh
# Docs tool: regenerates the skin pictures in docs/ (docs/skins.md). Needs a build
# (./build/bench/skin_gallery) and python3 with numpy and matplotlib (pip install numpy matplotlib).
set -eu
repo=$(cd "$(dirname "$0")/.." && pwd)
out=$(mktemp -d)
"$repo/build/bench/skin_gallery" "$out"
plot="python3 $repo/tools/plot_mesh.py"
cd "$out"
$plot "$repo/docs/skins_spiral.png" spiral_parametric.obj spiral_implicit.obj spiral_convolution.obj spiral_hybrid.obj \
  --titles "parametric (generalized cylinder)" "implicit point skeletons (blending graph)" \
           "convolution surface (local, D = 1.8 R)" "hybrid (blue: inside the focus sphere)" \
  --focus 0.12 0 0 0.06 --focus-panel 3 --cols 2 --elev 50 --azim -70
$plot "$repo/docs/skins_closeup.png" spiral_parametric.obj spiral_implicit.obj spiral_convolution.obj spiral_hybrid.obj \
  --titles "parametric" "implicit" "convolution" "hybrid (blue: focus)" \
  --focus 0.12 0 0 0.06 --focus-panel 3 --box 0.03 0.16 -0.08 0.08 --cols 2 --elev 35 --azim -30
$plot "$repo/docs/skins_blending.png" hairpin_implicit_graph.obj hairpin_implicit_nograph.obj \
  hairpin_convolution_local.obj hairpin_convolution_global.obj \
  --titles "implicit, blending graph" "implicit, no blending graph" "convolution, local (D = 1.8 R)" \
           "convolution, whole skeleton" --cols 2 --elev 60 --azim -80
$plot "$repo/docs/skins_parametric_bend.png" ubend_parametric_ok.obj ubend_parametric_fold.obj \
  --titles "parametric, bend radius 2 R (kappa Rmax < 1)" "parametric, bend radius 0.6 R: inner rings fold" \
  --cols 2 --elev 70 --azim -90
rm -rf "$out"
echo "pictures written to $repo/docs"
