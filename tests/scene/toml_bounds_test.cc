#include "scene/toml_bounds.h"

#include <gtest/gtest.h>

#include <dirent.h>

#include <fstream>
#include <sstream>
#include <string>

#include "common/check.h"
#include "scene/scene.h"

namespace viscera::scene {
namespace {

std::string Repeat(const std::string& part, int n) {
  std::string out;
  out.reserve(part.size() * static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) out += part;
  return out;
}

std::string ErrorOf(const std::string& text) {
  try {
    CheckTomlBounds(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// The attack: ~80 KB of key 40,000 levels deep, as a dotted key and as a table header. toml++
// recursed ~30,000 frames on it and overflowed the build thread's stack. With the bound, the
// parser never sees it. (Removing the CheckTomlBounds call in ParseScene makes this test crash
// or see the parser's own message instead of the limit.)
TEST(TomlBounds, ADeepDottedKeyOrHeaderIsRefusedBeforeTheParserWithTheLimit) {
  const std::string key = Repeat("x.", 40000) + "x";
  ASSERT_GT(key.size(), 80000u);
  const std::string tube =
      "[intestine]\nlength = 0.4\nradius = 0.0125\nmass = 0.1\ncontrol_points = 21\n";
  for (const std::string& text : {key + " = 1\n", "[" + key + "]\n", "[[" + key + "]]\n",
                                  "a = { " + key + " = 1 }\n", tube + key + " = 1\n"}) {
    try {
      ParseScene(text, "deep.toml");
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("deep.toml: line "), std::string::npos) << message;
      EXPECT_NE(
          message.find(": a dotted key or [table] header nests deeper than the limit of 16 levels"),
          std::string::npos)
          << message;
    }
  }
}

TEST(TomlBounds, TheLimitsAreExact) {
  EXPECT_EQ(ErrorOf(Repeat("k.", 15) + "k = 1\n"), "");  // 16 parts
  EXPECT_NE(ErrorOf(Repeat("k.", 16) + "k = 1\n").find("limit of 16"), std::string::npos);
  EXPECT_NE(ErrorOf(std::string("[") + Repeat("k . ", 16) + "k]\n").find("limit of 16"),
            std::string::npos);  // spaces are allowed
  EXPECT_NE(ErrorOf("a.\"b\".'c'." + Repeat("k.", 14) + "k = 1").find("limit of 16"),
            std::string::npos);
  EXPECT_EQ(ErrorOf("a = " + Repeat("[", 32) + Repeat("]", 32) + "\n"), "");
  EXPECT_NE(ErrorOf("a = " + Repeat("[", 33) + Repeat("]", 33) + "\n")
                .find("nest deeper than the limit of 32"),
            std::string::npos);
  EXPECT_NE(ErrorOf("a = " + Repeat("{b = ", 33) + "1" + Repeat("}", 33)).find("limit of 32"),
            std::string::npos);
  EXPECT_EQ(ErrorOf(std::string(kSceneTomlBounds.max_bytes, '#')), "");
  EXPECT_NE(ErrorOf(std::string(kSceneTomlBounds.max_bytes + 1, '#'))
                .find("above the limit of 1048576 bytes"),
            std::string::npos);
}

// Dots in strings, comments and values are not keys: nothing a real scene holds is refused.
TEST(TomlBounds, DotsInStringsCommentsAndValuesAreNotCounted) {
  const std::string many = Repeat("a.", 100);
  EXPECT_EQ(ErrorOf("name = \"" + many + "\"\n"), "");
  EXPECT_EQ(ErrorOf("name = '" + many + "'\n"), "");
  EXPECT_EQ(ErrorOf("# " + many + "\n"), "");
  EXPECT_EQ(ErrorOf("text = \"\"\"\n" + many + "\n\"\"\"\n"), "");
  EXPECT_EQ(ErrorOf("text = '''\n" + many + "\n'''\n"), "");
  EXPECT_EQ(ErrorOf("text = \"a \\\" " + many + "\"\n"), "");  // an escaped quote does not end it
  EXPECT_EQ(ErrorOf("\"" + many + "\" = 1\n"), "");            // one quoted part
  EXPECT_EQ(ErrorOf("v = [" + Repeat("1.5, ", 100) + "2.5e-3]\nt = 1979-05-27T07:32:00.999999Z\n"),
            "");
}

// The scanner must end a string where the parser does: a multi-line string's closing quotes
// may be followed by two more that belong to it, and what follows is outside the string.
TEST(TomlBounds, StringEndsAreWhereTheParserSeesThem) {
  const std::string deep = Repeat("k.", 40) + "k = 1";
  EXPECT_NE(ErrorOf("a = [{s = \"\"\"x\"\"\"\"\", " + deep + "}]\n").find("limit of 16"),
            std::string::npos);
  EXPECT_NE(ErrorOf("a = [{s = '''x''''', " + deep + "}]\n").find("limit of 16"),
            std::string::npos);
  EXPECT_NE(ErrorOf("s = \"x\\\\\"\n" + deep + "\n").find("line 2"),
            std::string::npos);  // "x\\" ends there
  EXPECT_NE(ErrorOf("s = \"unterminated\n" + deep + "\n").find("line 2"), std::string::npos);
}

TEST(TomlBounds, EveryShippedSceneIsWithinTheBounds) {
  const std::string dir = std::string(VISCERA_SOURCE_DIR) + "/scenes";
  DIR* d = opendir(dir.c_str());
  ASSERT_NE(d, nullptr);
  int scenes = 0;
  for (dirent* e = readdir(d); e != nullptr; e = readdir(d)) {
    const std::string name = e->d_name;
    if (name.size() < 5 || name.substr(name.size() - 5) != ".toml") continue;
    std::ifstream in(dir + "/" + name);
    std::ostringstream text;
    text << in.rdbuf();
    EXPECT_EQ(ErrorOf(text.str()), "") << name;
    ++scenes;
  }
  closedir(d);
  EXPECT_GE(scenes, 5);
}

// A scene file is read only up to the limit: a larger one is refused, not read whole.
TEST(TomlBounds, ALargeSceneFileIsRefusedWithTheLimit) {
  const std::string path = ::testing::TempDir() + "/large_scene.toml";
  std::ofstream(path) << std::string(kSceneTomlBounds.max_bytes + 4096, '#');
  try {
    LoadSceneFile(path);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("above the limit of 1048576 bytes"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace viscera::scene
