#include "session/session_scene.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "common/check.h"
#include "scene/toml_bounds.h"

namespace viscera::session {
namespace {

// The text of NAME in `dir`, opened without following a link (a link to a file outside, or to
// /dev/zero, was loaded) and without blocking (a FIFO hung the build and the shutdown), read
// only when it is a regular file and at most one byte past the scene size limit.
std::string ReadSceneFile(const std::string& dir, const std::string& name,
                          const std::string& scene_name) {
  const int dir_fd = open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  ThrowUnless(dir_fd >= 0, "the server's scene directory '", dir, "' cannot be opened");
  const int fd = openat(dir_fd, name.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  const int error = errno;
  close(dir_fd);
  if (fd < 0) {
    ThrowUnless(
        error != ELOOP, "scene '", scene_name, "': ", name,
        " is a symbolic link in the scene directory (refused: scenes are regular files there)");
    Fail("unknown scene '", scene_name, "' (no ", name, " in the scene directory)");
  }
  struct stat st {};
  if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    close(fd);
    Fail("scene '", scene_name, "': ", name,
         " is not a regular file (devices, FIFOs, sockets and directories are refused)");
  }
  std::string text(scene::kSceneTomlBounds.max_bytes + 1, '\0');
  size_t got = 0;
  for (ssize_t n; got < text.size() && (n = read(fd, text.data() + got, text.size() - got)) != 0;) {
    if (n < 0) {
      if (errno == EINTR) continue;
      close(fd);
      Fail("scene '", scene_name, "': ", name, " cannot be read");
    }
    got += static_cast<size_t>(n);
  }
  close(fd);
  text.resize(got);
  return text;  // ParseScene refuses it if it is over the limit
}

}  // namespace

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
  ThrowUnless(
      rate_hz == 0.0 || (std::isfinite(rate_hz) && rate_hz >= 1.0 && rate_hz <= max_rate_hz),
      "rate ", rate_hz, " Hz: must be 0 (the scene's) or within [1, ", max_rate_hz, "]");
  SessionScene out;
  if (!scene_name.empty()) {
    ThrowUnless(ValidSceneName(scene_name), "scene name '", scene_name,
                "': use letters, digits, '_', '-', '.' only");
    std::string name = scene_name;
    if (name.size() < 5 || name.substr(name.size() - 5) != ".toml") name += ".toml";
    const std::string path = scene_dir + "/" + name;
    out.toml = ReadSceneFile(scene_dir, name, scene_name);
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
