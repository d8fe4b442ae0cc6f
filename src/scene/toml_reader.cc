#include "scene/toml_reader.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include <toml++/toml.h>

#include "common/check.h"

namespace viscera::scene {

std::string Describe(const toml::node& node) {
  if (node.is_table()) return "a table";
  if (node.is_array()) return "an array";
  std::ostringstream out;
  node.visit([&](auto&& v) { out << v; });
  return out.str();
}

TomlReader::TomlReader(const toml::table& table, std::string path)
    : table_(table), path_(std::move(path)) {}

bool TomlReader::Has(const std::string& key) const { return table_.contains(key); }

const toml::node* TomlReader::Node(const std::string& key) const {
  read_.insert(key);
  return table_.get(key);
}

const toml::node& TomlReader::Required(const std::string& key) const {
  const toml::node* node = Node(key);
  ThrowUnless(node != nullptr, Name(key), ": missing (required)");
  return *node;
}

namespace {

constexpr double kMaxMagnitude = 1e9;

double AsDouble(const toml::node& node, const std::string& name) {
  std::optional<double> v;
  if (node.is_floating_point()) v = node.as_floating_point()->get();
  if (node.is_integer()) v = static_cast<double>(node.as_integer()->get());
  ThrowUnless(v.has_value(), name, " = ", Describe(node), ": expected a number");
  ThrowUnless(std::isfinite(*v), name, " = ", *v, ": must be finite");
  // no scene quantity comes near this (SI units); 1e308 overflowed into infinite forces
  ThrowUnless(std::fabs(*v) <= kMaxMagnitude, name, " = ", *v, ": outside +-", kMaxMagnitude);
  return *v;
}

Vec3 AsVector(const toml::node& node, const std::string& name) {
  const toml::array* a = node.as_array();
  ThrowUnless(a != nullptr && a->size() == 3, name, " = ", Describe(node), ": expected [x, y, z]");
  Vec3 v;
  for (int i = 0; i < 3; ++i) v(i) = AsDouble(*a->get(i), name + "[" + std::to_string(i) + "]");
  return v;
}

}  // namespace

double TomlReader::Double(const std::string& key) const {
  return AsDouble(Required(key), Name(key));
}

double TomlReader::Double(const std::string& key, double fallback) const {
  return Has(key) ? Double(key) : (read_.insert(key), fallback);
}

int TomlReader::Int(const std::string& key) const {
  const toml::node& node = Required(key);
  ThrowUnless(node.is_integer(), Name(key), " = ", Describe(node), ": expected an integer");
  const int64_t v = node.as_integer()->get();
  ThrowUnless(v >= -(1LL << 30) && v <= (1LL << 30), Name(key), " = ", v, ": out of range");
  return static_cast<int>(v);
}

int TomlReader::Int(const std::string& key, int fallback) const {
  return Has(key) ? Int(key) : (read_.insert(key), fallback);
}

double TomlReader::Positive(const std::string& key) const {
  const double v = Double(key);
  ThrowUnless(v > 0.0, Name(key), " = ", v, ": must be > 0");
  return v;
}

double TomlReader::Positive(const std::string& key, double fallback) const {
  const double v = Double(key, fallback);
  ThrowUnless(v > 0.0, Name(key), " = ", v, ": must be > 0");
  return v;
}

double TomlReader::NonNegative(const std::string& key, double fallback) const {
  const double v = Double(key, fallback);
  ThrowUnless(v >= 0.0, Name(key), " = ", v, ": must be >= 0");
  return v;
}

int TomlReader::NonNegative(const std::string& key, int fallback) const {
  const int v = Int(key, fallback);
  ThrowUnless(v >= 0, Name(key), " = ", v, ": must be >= 0");
  return v;
}

bool TomlReader::Bool(const std::string& key, bool fallback) const {
  if (!Has(key)) return read_.insert(key), fallback;
  const toml::node& node = Required(key);
  ThrowUnless(node.is_boolean(), Name(key), " = ", Describe(node), ": expected true or false");
  return node.as_boolean()->get();
}

std::string TomlReader::String(const std::string& key) const {
  const toml::node& node = Required(key);
  ThrowUnless(node.is_string(), Name(key), " = ", Describe(node), ": expected a string");
  return node.as_string()->get();
}

std::string TomlReader::String(const std::string& key, const std::string& fallback) const {
  return Has(key) ? String(key) : (read_.insert(key), fallback);
}

Vec3 TomlReader::Vector(const std::string& key) const { return AsVector(Required(key), Name(key)); }

Vec3 TomlReader::Vector(const std::string& key, const Vec3& fallback) const {
  return Has(key) ? Vector(key) : (read_.insert(key), fallback);
}

Points TomlReader::PointList(const std::string& key) const {
  const toml::node& node = Required(key);
  const toml::array* a = node.as_array();
  ThrowUnless(a != nullptr, Name(key), " = ", Describe(node), ": expected a list of [x, y, z]");
  Points p(static_cast<Eigen::Index>(a->size()), 3);
  for (size_t i = 0; i < a->size(); ++i) {
    p.row(static_cast<Eigen::Index>(i)) =
        AsVector(*a->get(i), Name(key) + "[" + std::to_string(i) + "]").transpose();
  }
  return p;
}

namespace {

// Edits (insert, delete, replace) between two short keys.
size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

}  // namespace

void TomlReader::Finish() const {
  for (const auto& [key, node] : table_) {
    const std::string k(key.str());
    if (read_.count(k) > 0) continue;
    // the keys this table was asked for are the ones it knows: the nearest is the likely typo
    std::string nearest;
    size_t best = 3;  // at most two edits away
    for (const std::string& known : read_) {
      if (const size_t d = EditDistance(k, known); d < best) {
        best = d;
        nearest = known;
      }
    }
    const toml::source_position where = node.source().begin;
    Fail(Name(k), " = ", Describe(node),
         where.line > 0 ? Cat(" (line ", where.line, ")") : std::string(), ": unknown key",
         nearest.empty() ? std::string() : Cat("; did you mean \"", nearest, "\"?"));
  }
}

}  // namespace viscera::scene
