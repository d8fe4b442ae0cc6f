#include "session/session_scene.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "common/check.h"

namespace viscera::session {

bool ValidSceneName(const std::string& name) {
  if (name.empty() || name.size() > 64 || name[0] == '.') return false;
  for (const char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '-' || c == '.';
    if (!ok) return false;
  }
  return true;
}

SessionScene LoadSessionScene(const std::string& scene_dir, const std::string& scene_name,
                              const std::string& scene_toml, double rate_hz, double max_rate_hz,
                              const std::string& inline_source, const scene::SceneLimits& limits) {
  ThrowUnless(scene_name.empty() != scene_toml.empty(),
              "give either a scene name or an inline scene, not ",
              scene_name.empty() ? "neither" : "both");
  ThrowUnless(rate_hz == 0.0 || (std::isfinite(rate_hz) && rate_hz >= 1.0 && rate_hz <= max_rate_hz),
              "rate ", rate_hz, " Hz: must be 0 (the scene's) or within [1, ", max_rate_hz, "]");
  SessionScene out;
  if (!scene_name.empty()) {
    ThrowUnless(ValidSceneName(scene_name), "scene name '", scene_name,
                "': use letters, digits, '_', '-', '.' only");
    std::string name = scene_name;
    if (name.size() < 5 || name.substr(name.size() - 5) != ".toml") name += ".toml";
    const std::string path = scene_dir + "/" + name;
    std::ifstream in(path);
    ThrowUnless(in.good(), "unknown scene '", scene_name, "' (no ", name, " in the scene directory)");
    std::ostringstream text;
    text << in.rdbuf();
    out.toml = text.str();
    out.label = scene_name;
    char* absolute = realpath(path.c_str(), nullptr);
    out.source = absolute != nullptr ? absolute : path;
    std::free(absolute);
  } else {
    out.toml = scene_toml;
    out.label = "<inline>";
    out.source = inline_source;
  }
  scene::Scene scene = scene::ParseScene(out.toml, out.source, limits);
  out.warnings = scene.warnings;
  if (rate_hz != 0.0) scene::ChangeRate(&scene.model, rate_hz);
  ThrowUnless(scene.model.rate_hz <= max_rate_hz, "scene rate ", scene.model.rate_hz,
              " Hz is above the server's maximum ", max_rate_hz, " Hz");
  out.model = std::make_shared<const mechanics::Model>(std::move(scene.model));
  return out;
}

}  // namespace viscera::session
