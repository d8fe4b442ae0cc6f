#include "scene/mesentery_table.h"

#include <toml++/toml.h>

#include "scene/toml_reader.h"

namespace viscera::scene {
namespace {

double Number(const toml::node& node, const std::string& what) {
  ThrowUnless(node.is_number(), what, " = ", Describe(node), ": expected a number");
  return node.is_integer() ? static_cast<double>(node.as_integer()->get())
                           : node.as_floating_point()->get();
}

std::vector<std::pair<double, double>> ReadLengths(const TomlReader& r) {
  const toml::node* node = r.Node("lengths");
  if (!node) return DefaultMesenteryLengths();
  const toml::array* list = node->as_array();
  ThrowUnless(list != nullptr, r.Name("lengths"), " = ", Describe(*node),
              ": expected a list of [s, length]");
  std::vector<std::pair<double, double>> lengths;
  for (size_t i = 0; i < list->size(); ++i) {
    const std::string what = r.Name("lengths") + "[" + std::to_string(i) + "]";
    const toml::array* pair = list->get(i)->as_array();
    ThrowUnless(pair != nullptr && pair->size() == 2, what, " = ", Describe(*list->get(i)),
                ": expected [s, length]");
    lengths.emplace_back(Number(*pair->get(0), what), Number(*pair->get(1), what));
  }
  return lengths;
}

}  // namespace

std::vector<std::pair<double, double>> DefaultMesenteryLengths() {
  return {{0.0, 0.03}, {0.1, 0.15}, {0.5, 0.20}, {0.9, 0.15}, {1.0, 0.03}};
}

std::optional<mechanics::MesenteryParams> ReadMesentery(const toml::table& root) {
  const toml::node* node = root.get("mesentery");
  if (!node) return std::nullopt;
  ThrowUnless(node->is_table(), "mesentery: expected a table [mesentery]");
  const TomlReader r(*node->as_table(), "mesentery");
  mechanics::MesenteryParams m;
  m.root_start = r.Vector("root_start");
  m.root_end = r.Vector("root_end");
  m.lengths = ReadLengths(r);
  m.stiffness = r.Double("stiffness");
  m.damping = r.Double("damping", m.damping);
  m.onset = r.Double("onset", m.onset);
  m.tethers = r.Int("tethers", 0);
  r.Finish();
  return m;
}

}  // namespace viscera::scene
