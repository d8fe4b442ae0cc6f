#pragma once
/// The tools' grasps: jaws that close near the tube hold the nearest point of its centre line with
/// a stiff spring, which engages at the jaws' offset from the tube, draws the tube in, and fades
/// out on a release or a slip (a pull beyond what the jaws' friction holds). The state's tools
/// carry the grasps (ToolState::grasping, grasp_s, grasp_offset, grasp_scale, held_sphere,
/// slipped); these are working copies, taken from the state by Follow and given back by Update.
#include <cstdlib>
#include <vector>

#include "collision/contact_detector.h"
#include "collision/sphere_chain.h"
#include "common/types.h"
#include "mechanics/model.h"
#include "mechanics/state.h"

namespace viscera::mechanics {

class Grasps {
 public:
  /// For `model`'s tools on `chain`; a grasp holds its nearest sphere and those within
  /// `held_span` of it between the jaws. @pre model and chain outlive this.
  Grasps(const Model& model, const collision::SphereChain& chain, int held_span);

  /// Takes the grasps the state carries; says whether a held sphere changed (Held changes).
  bool Follow(const State& state);
  /// Tool `index` has no target yet: it holds nothing.
  void Clear(int index) { grasping_[index] = false; }
  /// After tool `index`'s jaws and tip (at ts->tip) moved over h: grasps, draws the tube in,
  /// slips or releases, and gives the grasp back to ts. `active`: the device's target is.
  void Update(int index, double h, bool active, const Points& q, ToolState* ts);

  int size() const { return static_cast<int>(grasping_.size()); }
  bool grasping(int index) const { return grasping_[index]; }
  /// The grasp spring's stiffness (N/m), faded by its scale.
  double Stiffness(int index) const {
    return grasp_scale_[index] * model_.params().tools[index].grasp_stiffness;
  }
  /// The grasped point of the centre line.
  const CurvePoint& at(int index) const { return grasp_at_[index]; }
  /// The grasp spring's stretch: jaws (at `tip`) - tube - offset.
  Vec3 Stretch(int index, const Vec3& tip, const Points& q) const {
    return tip - Model::Evaluate(grasp_at_[index], q) - grasp_offset_[index];
  }

  /// The sphere the jaws of tool `index` hold (-1: none), kept after a release until the
  /// spheres are out of the shaft (Release).
  int held_sphere(int index) const { return held_sphere_[index]; }
  void Release(int index) { held_sphere_[index] = -1; }
  /// A tool's candidate with a sphere between its jaws, where the shaft's contact would fight the
  /// grasp (the tube sank half its radius into the tool).
  bool Held(const collision::ContactCandidate& c) const {
    return c.kind == collision::ContactKind::kTool && held_sphere_[c.b] >= 0 &&
           std::abs(c.a - held_sphere_[c.b]) <= held_span_;
  }

 private:
  const Model& model_;
  const collision::SphereChain& chain_;
  int held_span_;
  std::vector<bool> grasping_;
  std::vector<CurvePoint> grasp_at_;
  // A grasp engages at the jaws' current offset from the tube, which then shrinks (the tube is
  // drawn into the jaws), and fades out on release: the force never jumps.
  std::vector<Vec3> grasp_offset_;
  std::vector<double> grasp_scale_;
  // The tube slipped out of closed jaws (ToolState::slipped): it fades out and no grasp starts
  // until they open.
  std::vector<char> slipped_;
  // The sphere nearest to the jaws when they grasped (-1: none).
  std::vector<int> held_sphere_;
};

}  // namespace viscera::mechanics
