// Scenes by name come from the server's scene directory: regular files only, opened without
// following links or blocking (docs/security.md, "Files and disks").
#include "session/session_scene.h"

#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include "common/check.h"

namespace viscera::session {
namespace {

const char kScene[] =
    "[intestine]\nlength = 0.4\nradius = 0.0125\nmass = 0.1\ncontrol_points = 21\n"
    "[intestine.shape]\nkind = \"straight\"\n";

std::string ErrorOf(const std::string& dir, const std::string& name) {
  try {
    LoadSessionScene(dir, name, "", 0.0, 1000.0);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(SessionScene, NamesResolveToRegularFilesInsideTheSceneDirectoryOnly) {
  const std::string root = ::testing::TempDir() + "/scene_dir_" + std::to_string(getpid());
  const std::string dir = root + "/scenes";
  std::system(("rm -rf '" + root + "' && mkdir -p '" + dir + "'").c_str());
  std::ofstream(dir + "/good.toml") << kScene;
  std::ofstream(root + "/outside.toml") << kScene;
  ASSERT_EQ(symlink((root + "/outside.toml").c_str(), (dir + "/out.toml").c_str()), 0);
  ASSERT_EQ(symlink("/dev/zero", (dir + "/zero.toml").c_str()), 0);
  ASSERT_EQ(symlink("good.toml", (dir + "/alias.toml").c_str()), 0);
  ASSERT_EQ(mkfifo((dir + "/fifo.toml").c_str(), 0600), 0);
  ASSERT_EQ(mkdir((dir + "/folder.toml").c_str(), 0700), 0);
  std::ofstream(dir + "/huge.toml") << std::string(2 << 20, '#');

  EXPECT_EQ(ErrorOf(dir, "good"), "");
  for (const char* link : {"out", "zero", "alias"}) {
    EXPECT_NE(ErrorOf(dir, link).find("is a symbolic link in the scene directory"),
              std::string::npos)
        << link;
  }
  // a FIFO is opened without blocking and refused (it hung the build and the shutdown)
  EXPECT_NE(ErrorOf(dir, "fifo").find("fifo.toml is not a regular file"), std::string::npos)
      << ErrorOf(dir, "fifo");
  EXPECT_NE(ErrorOf(dir, "folder").find("not a regular file"), std::string::npos);
  EXPECT_NE(ErrorOf(dir, "huge").find("above the limit of 1048576 bytes"), std::string::npos)
      << ErrorOf(dir, "huge");
  EXPECT_NE(ErrorOf(dir, "missing").find("unknown scene 'missing'"), std::string::npos);
  std::system(("rm -rf '" + root + "'").c_str());
}

}  // namespace
}  // namespace viscera::session
