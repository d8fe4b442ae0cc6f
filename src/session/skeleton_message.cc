#include "session/skeleton_message.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "bus/header.h"

namespace viscera::session {

const viscera_proto::skeleton_state_t& SkeletonMessage::Fill(const mechanics::Model& model,
                                                             const mechanics::State& s) {
  viscera_proto::skeleton_state_t& k = message_;
  k.header = bus::MakeHeader(session_id_, seq_++);
  k.step = s.steps;
  k.sim_time = s.t;
  k.num_points = static_cast<int32_t>(s.q.rows());
  k.points.resize(static_cast<size_t>(s.q.rows()), std::vector<double>(3));
  for (int i = 0; i < s.q.rows(); ++i) {
    for (int a = 0; a < 3; ++a) k.points[static_cast<size_t>(i)][a] = s.q(i, a);
  }
  // collision spheres: equal spheres spread uniformly by arc length (docs/contacts.md, "Sphere
  // chain")
  const double radius = model.params().radius;
  arc_table_.Build(model.curve(), s.q);
  const double length = arc_table_.total_length();
  const int n = std::max(2, static_cast<int>(std::floor(length / (2.0 * radius))) + 1);
  k.num_spheres = n;
  k.spheres.resize(static_cast<size_t>(n), std::vector<double>(3));
  for (int j = 0; j < n; ++j) {
    const double u = arc_table_.ParameterAt(length * j / (n - 1));
    const Vec3 c = model.curve().Position(s.q, u);
    for (int a = 0; a < 3; ++a) k.spheres[static_cast<size_t>(j)][a] = c(a);
  }
  k.sphere_radius = radius;
  k.environment_contacts = s.contacts.environment;
  k.self_contacts = s.contacts.self;
  k.tool_contacts = s.contacts.tool;
  return k;
}

}  // namespace viscera::session
