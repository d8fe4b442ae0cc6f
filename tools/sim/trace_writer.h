#pragma once
/// Writes a simulation trace as JSON Lines: one object per recorded frame with
///   t (s), q and qd (#N lists of [x, y, z], m and m/s), length (m), momentum ([px, py, pz], N s,
///   the tube's), energy {kinetic, gravity, stretch, bend, continuous, attachment, total} (J),
///   step_us (CPU time of the step that produced the frame, microseconds); with contacts: spheres
///   (centres, [x, y, z]),
///   sphere_radius (m), contacts {self, environment, tool}, min_clearance (m, null if none),
///   tool_force {name: [fx, fy, fz]} (N, the force on the user's hand), tool_tip and
///   tool_tip_velocity (m, m/s), grasp_s, grip, slips.
#include <cstdio>
#include <string>

#include "mechanics/forces.h"
#include "mechanics/interactions.h"
#include "mechanics/state.h"

namespace viscera::tools {

class TraceWriter {
 public:
  /// @throws InputError when the file cannot be opened.
  explicit TraceWriter(const std::string& path);
  ~TraceWriter();
  TraceWriter(const TraceWriter&) = delete;
  TraceWriter& operator=(const TraceWriter&) = delete;

  /// `interactions` may be null (no contacts and no tools).
  void Write(const mechanics::Model& model, const mechanics::State& state,
             const mechanics::Interactions* interactions, double length,
             const mechanics::Energies& energy, double step_us);
  int frames() const { return frames_; }

 private:
  void Points(const char* key, const viscera::Points& p);
  std::FILE* file_;
  std::string line_;
  viscera::Points centres_;
  int frames_ = 0;
};

}  // namespace viscera::tools
