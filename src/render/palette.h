#pragma once
/// Palette: the materials of a laparoscopic scene. Colours are RGB in [0, 1], written to
/// the frame as they are (no gamma step), chosen to look right on an sRGB screen.
#include <string>
#include <utility>
#include <vector>

#include "render/mesh_renderer.h"

namespace viscera::render {

struct Palette {
  /// Pink serosa with vessels around the tube (Pattern::kSerosa), a sharp wet highlight and a
  /// broad sheen.
  Material intestine;
  /// The abdominal wall (`inside = true` obstacles) and planes: the parietal peritoneum, pale
  /// with fine vessels (Pattern::kPeritoneum).
  Material cavity_wall;
  /// The mesentery ([mesentery] scenes): a thin translucent film, pale (fat) pink, its vessels
  /// darker and more opaque (Pattern::kMesentery).
  Material mesentery;
  /// Laparoscopic instruments: metallic grey, highlights tinted by the metal.
  Material tool;
  /// The training task's targets ([[target]]): a saturated green nothing else in the abdomen
  /// has, lit mostly by its ambient term, so a frame shows (and a test finds) every visible bit.
  Material target;
  /// Bowel the handling damaged (running the bowel's damage events): a saturated blue-violet
  /// bruise no tissue has, lit mostly by its ambient term, so the trainee (and a test) sees it.
  Material damage;
  /// Organs by obstacle name (case-insensitive substring: "liver", "spine", ...).
  std::vector<std::pair<std::string, Material>> named_organs;
  /// Organs whose name matches none of the above, cycled in scene order.
  std::vector<Material> organs;
  /// What the scope sees where nothing is: near black, like an unlit abdomen.
  Eigen::Vector3f background{0.02f, 0.01f, 0.01f};

  /// The material of an organ obstacle named `name`, `index`-th unnamed organ so far.
  const Material& Organ(const std::string& name, int* unnamed_index) const;
};

/// The palette the renderer uses unless told otherwise.
Palette DefaultPalette();

/// Every material of `palette` plain (no procedural texture): the flat look, for comparisons.
void DropTextures(Palette* palette);

}  // namespace viscera::render
