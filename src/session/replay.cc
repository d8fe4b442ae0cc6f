#include "session/replay.h"

#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <vector>

#include <lcm/lcm-cpp.hpp>
#include <viscera_proto/force_feedback_t.hpp>
#include <viscera_proto/session_request_t.hpp>
#include <viscera_proto/skeleton_state_t.hpp>
#include <viscera_proto/step_record_t.hpp>

#include "bus/channels.h"
#include "bus/wire_counts.h"
#include "common/check.h"
#include "session/force_feedback.h"
#include "session/session_scene.h"
#include "session/step_record.h"
#include "session/stepper.h"

namespace viscera::session {
namespace {

bool StartsWith(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

template <typename Msg>
Msg DecodeOrThrow(const lcm::LogEvent& e, const std::string& path) {
  Msg msg;
  // every array count first: LCM's decode would size its arrays before checking them
  ThrowUnless(bus::ArrayCountsFit<Msg>(static_cast<const uint8_t*>(e.data), e.datalen) &&
                  msg.decode(e.data, 0, e.datalen) == e.datalen,
              path, ": malformed ", Msg::getTypeName(), " on ", e.channel, " (event ", e.eventnum,
              ")");
  return msg;
}

}  // namespace

ReplayResult ReplayRecord(const std::string& path, const ReplayObserver& on_step,
                          const scene::SceneLimits& limits) {
  lcm::LogFile log(path, "r");
  ThrowUnless(log.good(), "cannot read session record '", path, "'");

  ReplayResult result;
  std::unique_ptr<SessionScene> scene;
  std::unique_ptr<Stepper> stepper;
  std::string step_channel, skeleton_channel, force_channel;
  std::vector<mechanics::ToolTarget> targets;
  std::vector<int64_t> pose_seqs;  // per tool, of the last step record
  viscera_proto::force_feedback_t expected{};
  // recorded skeletons by step, compared once the replay reaches that step
  std::map<int64_t, viscera_proto::skeleton_state_t> pending;

  auto compare_pending = [&]() {
    const int64_t now = stepper->state().steps;
    while (!pending.empty() && pending.begin()->first <= now) {
      const auto& [step, k] = *pending.begin();
      if (step == now) {
        const mechanics::State& s = stepper->state();
        ThrowUnless(k.num_points == s.q.rows(), path, ": skeleton of ", k.num_points,
                    " points, model has ", s.q.rows());
        for (int i = 0; i < s.q.rows(); ++i) {
          for (int a = 0; a < 3; ++a) {
            const double d = std::abs(k.points[static_cast<size_t>(i)][a] - s.q(i, a));
            result.max_deviation = std::max(
                result.max_deviation, std::isnan(d) ? std::numeric_limits<double>::infinity() : d);
          }
        }
        ++result.skeletons_compared;
      }
      pending.erase(pending.begin());
    }
  };

  for (const lcm::LogEvent* e = log.readNextEvent(); e != nullptr; e = log.readNextEvent()) {
    if (scene == nullptr) {
      if (!StartsWith(e->channel, bus::kScenePrefix)) continue;
      const auto request = DecodeOrThrow<viscera_proto::session_request_t>(*e, path);
      // the scene record keeps the scene's text and, in scene_name, the file it came from
      scene = std::make_unique<SessionScene>(LoadSessionScene(
          "", "", request.scene_toml, request.rate_hz, std::numeric_limits<double>::infinity(),
          request.scene_name.empty() ? "<inline>" : request.scene_name, limits));
      result.session_id = request.header.session_id;
      result.scene = request.scene_name.empty() ? "<inline>" : request.scene_name;
      result.rate_hz = scene->model->params().rate_hz;
      stepper = std::make_unique<Stepper>(*scene->model);
      step_channel = bus::SessionChannel(bus::kStepPrefix, result.session_id);
      skeleton_channel = bus::SessionChannel(bus::kSkeletonPrefix, result.session_id);
      force_channel = bus::SessionChannel(bus::kForcePrefix, result.session_id);
      continue;
    }
    if (e->channel == skeleton_channel) {
      auto k = DecodeOrThrow<viscera_proto::skeleton_state_t>(*e, path);
      const int64_t step = k.step;
      if (step <= stepper->state().steps) {
        pending.emplace(step, std::move(k));
        compare_pending();
      } else {
        pending.emplace(step, std::move(k));
      }
    } else if (e->channel == force_channel) {
      // the session records a step's forces right after the step: compare with the replay now
      const auto f = DecodeOrThrow<viscera_proto::force_feedback_t>(*e, path);
      std::string difference;
      if (f.tool < 0 || static_cast<size_t>(f.tool) >= targets.size() ||
          static_cast<size_t>(f.tool) >= stepper->state().tools.size()) {
        difference = Cat("force message for tool ", f.tool, " before any step with it");
      } else {
        const size_t i = static_cast<size_t>(f.tool);
        FillForceFeedback(stepper->state(), i, targets[i], pose_seqs[i], &expected);
        difference = ForceFeedbackDifference(f, expected);
      }
      ++result.forces_compared;
      if (!difference.empty()) {
        if (result.force_mismatches++ == 0) {
          result.first_force_mismatch =
              Cat("event ", e->eventnum, ", recorded vs replayed: ", difference);
        }
      }
    } else if (e->channel == step_channel) {
      const auto r = DecodeOrThrow<viscera_proto::step_record_t>(*e, path);
      ThrowUnless(r.step == stepper->state().steps, path, ": step record for step ", r.step,
                  " but the replay is at step ", stepper->state().steps, " (a gap in the record)");
      if (r.kind == viscera_proto::step_record_t::kReset) {
        stepper->Reset();
        ++result.resets;
      } else {
        ThrowUnless(r.kind == viscera_proto::step_record_t::kStep && TargetsOf(r, &targets), path,
                    ": malformed step record (event ", e->eventnum, ")");
        pose_seqs.resize(r.tools.size());
        for (size_t i = 0; i < r.tools.size(); ++i) pose_seqs[i] = r.tools[i].pose_seq;
        stepper->Advance(targets);
        ++result.steps;
      }
      if (on_step) on_step(*scene->model, stepper->state());
      compare_pending();
    }
  }
  ThrowUnless(scene != nullptr, "'", path, "' holds no session scene (", bus::kScenePrefix,
              "<id>): not a viscerad session record");
  result.recoveries = stepper->recoveries();
  result.final_state = stepper->state();
  return result;
}

}  // namespace viscera::session
