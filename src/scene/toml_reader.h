#pragma once
/// Typed, strict reading of one TOML table: every error names the key (with its table path),
/// the value and the reason; Finish() rejects keys nobody asked for.
#include <initializer_list>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "common/check.h"
#include "common/types.h"
#include "scene/toml_fwd.h"

namespace viscera::scene {

class TomlReader {
 public:
  /// @param path dotted path of the table, for messages ("intestine.shape").
  TomlReader(const toml::table& table, std::string path);

  bool Has(const std::string& key) const;
  /// @throws InputError when missing (required) or of the wrong type, or not finite.
  double Double(const std::string& key) const;
  double Double(const std::string& key, double fallback) const;
  int Int(const std::string& key) const;
  int Int(const std::string& key, int fallback) const;
  /// The same, refused (InputError naming the key and the value) when not > 0 or not >= 0.
  double Positive(const std::string& key) const;
  double Positive(const std::string& key, double fallback) const;
  double NonNegative(const std::string& key, double fallback) const;
  int NonNegative(const std::string& key, int fallback) const;
  bool Bool(const std::string& key, bool fallback) const;
  std::string String(const std::string& key) const;
  std::string String(const std::string& key, const std::string& fallback) const;
  Vec3 Vector(const std::string& key) const;
  Vec3 Vector(const std::string& key, const Vec3& fallback) const;
  Points PointList(const std::string& key) const;
  /// A string key naming one of `choices` (the first is the default).
  /// @throws InputError naming the key, the value and the accepted names.
  template <typename E>
  E Choice(const std::string& key, std::initializer_list<std::pair<const char*, E>> choices) const {
    return Choice(key, choices, choices.begin()->second);
  }
  /// The same, with `fallback` when the key is absent: a default kept in the params themselves,
  /// not in the list's order. @pre fallback is one of the choices.
  template <typename E>
  E Choice(const std::string& key, std::initializer_list<std::pair<const char*, E>> choices,
           E fallback) const {
    const char* fallback_name = choices.begin()->first;
    for (const auto& [name, e] : choices) {
      if (e == fallback) {
        fallback_name = name;
        break;
      }
    }
    const std::string value = String(key, fallback_name);
    std::string accepted;
    for (const auto& [name, e] : choices) {
      if (value == name) return e;
      accepted += (accepted.empty() ? "\"" : ", \"") + std::string(name) + "\"";
    }
    Fail(Name(key), " = \"", value, "\": expected ", accepted);
  }
  /// The raw node (for keys with several accepted types); nullptr when absent.
  const toml::node* Node(const std::string& key) const;
  std::string Name(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

  /// @throws InputError naming the first key that was never read.
  void Finish() const;

 private:
  const toml::node& Required(const std::string& key) const;

  const toml::table& table_;
  std::string path_;
  mutable std::set<std::string> read_;
};

/// Describes a TOML value for messages: `"abc"`, `1.5`, `[...]`, `{...}`.
std::string Describe(const toml::node& node);

}  // namespace viscera::scene
