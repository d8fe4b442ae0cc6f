#include "assessment/running.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace viscera::assessment {
namespace {

std::vector<std::string> ToolNames(const mechanics::ModelParams& params) {
  std::vector<std::string> names;
  for (const mechanics::ToolParams& t : params.tools) names.push_back(t.name);
  return names;
}

}  // namespace

RunningScore::RunningScore(const mechanics::ModelParams& params)
    : params_(params),
      p_(*params.task.running),
      damage_(p_, params.length, ToolNames(params)),
      tools_(params.tools.size()),
      covered_(static_cast<size_t>(damage_.segments()), 0) {}

bool RunningScore::InView(const Vec3& p) const {
  const Vec3 axis = (view_->look_at - view_->eye).normalized();
  const Vec3 d = p - view_->eye;
  const double along = d.dot(axis);
  if (along <= 0.0) return false;
  Vec3 up = view_->up - view_->up.dot(axis) * axis;
  up.normalize();
  const Vec3 right = axis.cross(up);
  const double half_v = std::tan(0.5 * view_->fov_y_deg * std::numbers::pi / 180.0);
  const double half_h = half_v * view_->aspect;
  return std::abs(d.dot(up)) <= half_v * along && std::abs(d.dot(right)) <= half_h * along;
}

// A segment is inspected when its middle lies in the view within camera_range of the lens. The
// control points of a Catmull-Rom curve lie on it, so the middle is read between the two
// nearest (the spline's sag between them is far below a segment's length).
void RunningScore::CameraCoverage(const Points& q) {
  const int n = static_cast<int>(q.rows());
  for (int k = 0; k < damage_.segments(); ++k) {
    const double s = std::min(1.0, (k + 0.5) * p_.segment / params_.length);
    const double x = s * (n - 1);
    const int i = std::min(n - 2, static_cast<int>(x));
    const Vec3 mid = q.row(i).transpose() + (x - i) * (q.row(i + 1) - q.row(i)).transpose();
    if ((mid - view_->eye).norm() <= p_.camera_range && InView(mid)) covered_[k] = 1;
  }
}

void RunningScore::Grasped(int tool, double s) {
  ++grasps_;
  if (first_grasp_ < 0.0) first_grasp_ = time_, first_s_ = s;
  const double half = 0.5 * p_.segment / params_.length;  // half a segment, in s
  Tool& t = tools_[static_cast<size_t>(tool)];
  // a grasp where the same jaws just held is a retry, not progress
  if (t.last_grasp_s >= 0.0 && std::abs(s - t.last_grasp_s) < half) ++regrasps_;
  t.last_grasp_s = s;
  covered_[static_cast<size_t>(damage_.SegmentOf(s))] = 1;
  if (last_s_ >= 0.0 && std::abs(s - last_s_) >= half) {
    const int direction = s > last_s_ ? 1 : -1;
    if (direction_ != 0 && direction != direction_) ++reversals_;
    direction_ = direction;
  }
  last_s_ = s;
}

void RunningScore::AddStep(const mechanics::State& state, double dt) {
  time_ += dt;
  bool any_grasp = false;
  for (size_t i = 0; i < tools_.size() && i < state.tools.size(); ++i) {
    const mechanics::ToolState& ts = state.tools[i];
    Tool& t = tools_[i];
    if (!ts.initialized) continue;
    if (t.had_tip) path_ += (ts.tip - t.last_tip).norm();
    t.last_tip = ts.tip;
    t.had_tip = true;
    const bool holding = ts.grasping && !ts.slipped;
    if (holding && !t.grasping) Grasped(static_cast<int>(i), ts.grasp_s);
    t.grasping = holding;
    any_grasp = any_grasp || holding;
    t.slips = ts.slips;
    const double pull = holding ? ts.grasp_pull : 0.0;
    damage_.Add(static_cast<int>(i), holding, ts.grasp_s, holding ? ts.grip_force : 0.0, pull,
                time_, dt);
    if (view_ && ts.target.active && !InView(ts.tip)) out_of_view_ += dt;
  }
  if (any_grasp) last_grasp_end_ = time_;
  // the two shafts (port to tip) touching
  if (state.tools.size() >= 2 && state.tools[0].initialized && state.tools[1].initialized) {
    const double reach = params_.tools[0].radius + params_.tools[1].radius;
    const bool clash =
        SegmentSegmentDistanceSquared(params_.tools[0].port, state.tools[0].tip,
                                      params_.tools[1].port, state.tools[1].tip) < reach * reach;
    if (clash && !clashing_) ++clashes_;
    clashing_ = clash;
  }
  if (view_ && state.q.rows() >= 2) CameraCoverage(state.q);
}

void RunningScore::Fill(RunningReport* r) const {
  *r = RunningReport{};
  r->segments = damage_.segments();
  r->segment_length = p_.segment;
  int seen = 0;
  for (int k = 0; k < r->segments; ++k) {
    if (covered_[static_cast<size_t>(k)]) {
      ++seen;
    } else {
      r->missed.push_back(k);
    }
  }
  r->coverage = r->segments > 0 ? static_cast<double>(seen) / r->segments : 0.0;
  r->reversals = reversals_;
  r->grasps = grasps_;
  r->regrasps = regrasps_;
  for (const Tool& t : tools_) r->slips += t.slips;
  r->path_length = path_;
  r->instrument_collisions = clashes_;
  r->out_of_view_time = out_of_view_;
  r->time = first_grasp_ >= 0.0 ? last_grasp_end_ - first_grasp_ : 0.0;
  r->max_grip = damage_.max_grip();
  r->max_pressure = damage_.max_grip() / p_.jaw_area;
  r->max_traction = damage_.max_traction();
  r->max_dose = damage_.max_dose();
  r->events = damage_.events();
  for (int k = 0; k < r->segments; ++k)
    if (damage_.flags()[static_cast<size_t>(k)]) r->damaged.push_back(k);
  r->run_length = first_s_ >= 0.0 ? std::abs(last_s_ - first_s_) * params_.length : 0.0;
  r->estimate_length = p_.estimate_length;
  r->estimate_error =
      p_.estimate_length > 0.0 ? (r->run_length - p_.estimate_length) / p_.estimate_length : 0.0;
  // the thresholds and pass marks, and the verdict
  r->pinch_force = p_.pinch_force;
  r->damage_dose = p_.damage_dose;
  r->traction_break = p_.traction_break;
  r->jaw_area = p_.jaw_area;
  r->pass_coverage = p_.pass_coverage;
  r->pass_time = p_.pass_time;
  r->pass_path = p_.pass_path;
  r->pass_out_of_view = p_.pass_out_of_view;
  r->pass_reversals = p_.pass_reversals;
  r->pass_slips = p_.pass_slips;
  r->pass_damage_events = p_.pass_damage_events;
  r->pass_estimate_error = p_.pass_estimate_error;
  const bool estimating = p_.estimate_length > 0.0;
  if (!estimating && r->coverage < p_.pass_coverage - 1e-12) r->failed.push_back("coverage");
  if (estimating && std::abs(r->estimate_error) > p_.pass_estimate_error)
    r->failed.push_back("estimate");
  if (static_cast<int>(r->events.size()) > p_.pass_damage_events) r->failed.push_back("damage");
  if (r->slips > p_.pass_slips) r->failed.push_back("slips");
  if (r->reversals > p_.pass_reversals) r->failed.push_back("reversals");
  if (p_.pass_time > 0.0 && r->time > p_.pass_time) r->failed.push_back("time");
  if (p_.pass_path > 0.0 && r->path_length > p_.pass_path) r->failed.push_back("path");
  if (p_.pass_out_of_view > 0.0 && r->out_of_view_time > p_.pass_out_of_view)
    r->failed.push_back("out of view");
  r->passed = r->failed.empty();
}

}  // namespace viscera::assessment
