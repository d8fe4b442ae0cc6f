#include "render/palette.h"

#include <algorithm>
#include <cctype>

namespace viscera::render {
namespace {

Material Make(Eigen::Vector3f albedo, float ambient, float specular, float shininess,
              float sheen = 0.0f, float sheen_shininess = 6.0f, float metallic = 0.0f) {
  Material m;
  m.albedo = albedo;
  m.ambient = ambient;
  m.specular = specular;
  m.shininess = shininess;
  m.sheen = sheen;
  m.sheen_shininess = sheen_shininess;
  m.metallic = metallic;
  return m;
}

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

}  // namespace

const Material& Palette::Organ(const std::string& name, int* unnamed_index) const {
  const std::string lower = Lower(name);
  for (const auto& [key, material] : named_organs) {
    if (lower.find(key) != std::string::npos) return material;
  }
  const Material& m = organs[static_cast<size_t>(*unnamed_index) % organs.size()];
  ++*unnamed_index;
  return m;
}

Palette DefaultPalette() {
  Palette p;
  // wet tissue: a strong narrow highlight (the moist film) over a broad faint sheen
  p.intestine = Make({0.92f, 0.52f, 0.52f}, 0.12f, 0.60f, 80.0f, 0.12f, 5.0f);
  p.intestine.pattern = Pattern::kSerosa;
  p.intestine.vessel = {0.70f, 0.20f, 0.22f};
  // parietal peritoneum: pale, pinkish cream (paler and yellower than the bowel), thin vessels
  p.cavity_wall = Make({0.84f, 0.62f, 0.54f}, 0.10f, 0.35f, 50.0f, 0.05f, 4.0f);
  p.cavity_wall.pattern = Pattern::kPeritoneum;
  p.cavity_wall.vessel = {0.68f, 0.20f, 0.18f};
  p.mesentery = Make({0.95f, 0.80f, 0.62f}, 0.25f, 0.35f, 40.0f, 0.05f, 4.0f);
  p.mesentery.opacity = 0.35f;
  p.mesentery.pattern = Pattern::kMesentery;
  p.mesentery.vessel = {0.62f, 0.12f, 0.14f};
  p.tool = Make({0.62f, 0.64f, 0.68f}, 0.12f, 0.90f, 40.0f, 0.15f, 3.0f, 0.8f);
  p.target = Make({0.10f, 0.95f, 0.25f}, 0.60f, 0.0f, 1.0f);
  p.damage = Make({0.30f, 0.10f, 0.95f}, 0.60f, 0.0f, 1.0f);
  p.named_organs = {
      {"liver", Make({0.40f, 0.13f, 0.18f}, 0.10f, 0.50f, 60.0f, 0.06f, 5.0f)},
      {"spleen", Make({0.40f, 0.12f, 0.20f}, 0.10f, 0.40f, 60.0f, 0.05f, 5.0f)},
      {"kidney", Make({0.50f, 0.18f, 0.12f}, 0.10f, 0.40f, 60.0f, 0.05f, 5.0f)},
      {"spine", Make({0.86f, 0.80f, 0.66f}, 0.12f, 0.20f, 20.0f)},
      {"bladder", Make({0.88f, 0.78f, 0.50f}, 0.12f, 0.55f, 70.0f, 0.08f, 5.0f)},
      {"stomach", Make({0.88f, 0.60f, 0.45f}, 0.12f, 0.50f, 60.0f, 0.08f, 5.0f)},
      {"colon", Make({0.80f, 0.55f, 0.40f}, 0.12f, 0.50f, 60.0f, 0.08f, 5.0f)},
      {"gall", Make({0.35f, 0.55f, 0.30f}, 0.10f, 0.60f, 70.0f, 0.08f, 5.0f)},
      {"vessel", Make({0.45f, 0.30f, 0.65f}, 0.10f, 0.50f, 60.0f, 0.05f, 5.0f)},
  };
  p.organs = {
      Make({0.88f, 0.78f, 0.50f}, 0.12f, 0.50f, 60.0f, 0.06f, 5.0f),  // yellowish
      Make({0.45f, 0.30f, 0.65f}, 0.10f, 0.50f, 60.0f, 0.05f, 5.0f),  // bluish purple
      Make({0.35f, 0.55f, 0.30f}, 0.10f, 0.50f, 60.0f, 0.05f, 5.0f),  // green
      Make({0.45f, 0.13f, 0.09f}, 0.10f, 0.45f, 60.0f, 0.05f, 5.0f),  // dark red-brown
  };
  return p;
}

void DropTextures(Palette* palette) {
  for (Material* m : {&palette->intestine, &palette->cavity_wall, &palette->mesentery,
                      &palette->tool, &palette->target, &palette->damage}) {
    m->pattern = Pattern::kPlain;
  }
  for (auto& named : palette->named_organs) named.second.pattern = Pattern::kPlain;
  for (Material& m : palette->organs) m.pattern = Pattern::kPlain;
}

}  // namespace viscera::render
