#include "sim/trace_writer.h"

#include <cerrno>
#include <cmath>
#include <cstring>

#include "common/check.h"

namespace viscera::tools {
namespace {

// Appends a number with 10 significant digits (round-trips float32 and is plenty for m).
void Number(std::string* out, double v) {
  char buf[32];
  const int n = std::snprintf(buf, sizeof buf, "%.10g", v);
  out->append(buf, n);
}

}  // namespace

TraceWriter::TraceWriter(const std::string& path) : file_(std::fopen(path.c_str(), "w")) {
  ThrowUnless(file_ != nullptr, path, ": cannot write trace: ", std::strerror(errno));
}

TraceWriter::~TraceWriter() {
  if (file_) std::fclose(file_);
}

void TraceWriter::Points(const char* key, const viscera::Points& p) {
  line_ += ",\"";
  line_ += key;
  line_ += "\":[";
  for (Eigen::Index i = 0; i < p.rows(); ++i) {
    if (i) line_ += ',';
    line_ += '[';
    Number(&line_, p(i, 0));
    line_ += ',';
    Number(&line_, p(i, 1));
    line_ += ',';
    Number(&line_, p(i, 2));
    line_ += ']';
  }
  line_ += ']';
}

void TraceWriter::Write(const mechanics::Model& model, const mechanics::State& state,
                        const mechanics::Interactions* interactions, double length,
                        const mechanics::Energies& e, double step_us) {
  line_.clear();
  line_ += "{\"t\":";
  Number(&line_, state.t);
  Points("q", state.q);
  Points("qd", state.qd);
  line_ += ",\"length\":";
  Number(&line_, length);
  const Vec3 momentum = model.Momentum(state.qd);
  line_ += ",\"momentum\":[";
  for (int a = 0; a < 3; ++a) {
    if (a) line_ += ',';
    Number(&line_, momentum(a));
  }
  line_ += ']';
  line_ += ",\"energy\":{";
  const std::pair<const char*, double> terms[] = {
      {"kinetic", e.kinetic}, {"gravity", e.gravity},       {"stretch", e.stretch},
      {"bend", e.bend},       {"continuous", e.continuous}, {"attachment", e.attachment},
      {"contact", e.contact}, {"total", e.total()}};
  bool first = true;
  for (const auto& [name, value] : terms) {
    if (!first) line_ += ',';
    first = false;
    line_ += '"';
    line_ += name;
    line_ += "\":";
    Number(&line_, value);
  }
  line_ += "},\"step_us\":";
  Number(&line_, step_us);
  line_ += ",\"substeps\":" + std::to_string(state.substeps);
  line_ += ",\"unconverged_solves\":" + std::to_string(state.unconverged_solves);
  if (interactions) {
    const auto& spheres = interactions->chain().spheres();
    centres_.resize(static_cast<Eigen::Index>(spheres.size()), 3);
    for (size_t k = 0; k < spheres.size(); ++k)
      centres_.row(static_cast<Eigen::Index>(k)) = spheres[k].centre.transpose();
    Points("spheres", centres_);
    line_ += ",\"sphere_radius\":";
    Number(&line_, interactions->chain().radius());
    const mechanics::ContactStats& c = state.contacts;
    line_ += ",\"contacts\":{\"self\":" + std::to_string(c.self) +
             ",\"environment\":" + std::to_string(c.environment) +
             ",\"tool\":" + std::to_string(c.tool) + "},\"min_clearance\":";
    if (std::isnan(c.min_clearance)) {
      line_ += "null";
    } else {
      Number(&line_, c.min_clearance);
    }
    line_ += ",\"deepest\":\"" + std::string(c.deepest) + '"';
    // per tool: the force on the hand, where its tip is, which part of the bowel it holds (-1:
    // none)
    const auto per_tool = [&](const char* key, const auto& write) {
      line_ += ",\"" + std::string(key) + "\":{";
      for (size_t t = 0; t < state.tools.size(); ++t) {
        if (t) line_ += ',';
        line_ += '"' + model.params().tools[t].name + "\":";
        write(state.tools[t]);
      }
      line_ += '}';
    };
    const auto vector = [&](const Vec3& v) {
      line_ += '[';
      for (int a = 0; a < 3; ++a) {
        if (a) line_ += ',';
        Number(&line_, v(a));
      }
      line_ += ']';
    };
    per_tool("tool_force", [&](const mechanics::ToolState& ts) { vector(ts.force); });
    per_tool("tool_tip", [&](const mechanics::ToolState& ts) { vector(ts.tip); });
    per_tool("tool_tip_velocity", [&](const mechanics::ToolState& ts) { vector(ts.tip_velocity); });
    per_tool("grasp_s", [&](const mechanics::ToolState& ts) {
      Number(&line_, ts.grasping ? ts.grasp_s : -1.0);
    });
    per_tool("grip", [&](const mechanics::ToolState& ts) { Number(&line_, ts.grip_force); });
    per_tool("slips", [&](const mechanics::ToolState& ts) {
      Number(&line_, static_cast<double>(ts.slips));
    });
  }
  line_ += "}\n";
  std::fwrite(line_.data(), 1, line_.size(), file_);
  ++frames_;
}

}  // namespace viscera::tools
