#pragma once
/// The last check before a message leaves the server: a force, skeleton or status with a
/// NaN or an infinity in it is never sent (a haptic device would render it; a client would
/// draw or average it). The stepper already restores the last good state when the
/// mechanics blow up; this catches what slips past it.
#include <cmath>

#include <viscera_proto/force_feedback_t.hpp>
#include <viscera_proto/session_status_t.hpp>
#include <viscera_proto/skeleton_state_t.hpp>
#include <viscera_proto/step_record_t.hpp>

namespace viscera::session {

inline bool AllFinite(const viscera_proto::force_feedback_t& f) {
  bool ok = std::isfinite(f.sim_time);
  for (int a = 0; a < 3; ++a) {
    ok = ok && std::isfinite(f.force[a]) && std::isfinite(f.torque[a]) && std::isfinite(f.tip[a]);
    for (int b = 0; b < 3; ++b) ok = ok && std::isfinite(f.stiffness[a][b]);
  }
  return ok;
}

inline bool AllFinite(const viscera_proto::skeleton_state_t& k) {
  bool ok = std::isfinite(k.sim_time) && std::isfinite(k.sphere_radius);
  for (const auto& p : k.points)
    ok = ok && std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
  for (const auto& p : k.spheres)
    ok = ok && std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
  return ok;
}

/// A status always goes out (it says what happened); its numbers are checked where it is made.
inline bool AllFinite(const viscera_proto::session_status_t&) { return true; }
/// Step records go to the record only, as computed (replay compares them bit for bit).
inline bool AllFinite(const viscera_proto::step_record_t&) { return true; }

}  // namespace viscera::session
