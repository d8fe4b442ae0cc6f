#include "server/session_manager.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <optional>
#include <utility>

#include "bus/channels.h"
#include "bus/header.h"
#include "bus/message_auth.h"
#include "common/check.h"
#include "common/clock.h"
#include "server/idle_priority.h"
#include "server/request_checks.h"
#include "server/scene_budget.h"
#include "session/session_scene.h"

namespace viscera::server {

using viscera_proto::session_reply_t;
using viscera_proto::session_request_t;

namespace {

// (sender, channel) pairs each replay guard keeps: the request channel's and the pose
// channels' (docs/security.md).
constexpr size_t kReplayEntriesPerClass = 1 << 15;
// How long a shutdown waits for a scene build to see its stop flag.
constexpr std::chrono::milliseconds kBuildStopWait{500};

constexpr size_t kTokenBytes = 16;

// Session ids stay below 2^53 so that JSON numbers (doubles) carry them exactly.
int64_t NewSessionId() {
  const std::vector<uint8_t> r = bus::RandomBytes(8);
  uint64_t v = 0;
  for (const uint8_t b : r) v = (v << 8) | b;
  return static_cast<int64_t>((v & ((uint64_t{1} << 53) - 1)) | 1);
}

// The session id of a per-session channel name (prefix + decimal id), or 0.
int64_t SessionOfChannel(const std::string& channel, const char* prefix) {
  const std::string p(prefix);
  if (channel.rfind(p, 0) != 0 || channel.size() == p.size() || channel.size() > p.size() + 18) {
    return 0;
  }
  int64_t id = 0;
  for (size_t i = p.size(); i < channel.size(); ++i) {
    if (channel[i] < '0' || channel[i] > '9') return 0;
    id = id * 10 + (channel[i] - '0');
  }
  return id;
}

uint64_t ReadBe(const uint8_t* p, int bytes) {
  uint64_t v = 0;
  for (int i = 0; i < bytes; ++i) v = (v << 8) | p[i];
  return v;
}

}  // namespace

SessionManager::SessionManager(const ServerConfig& config, bus::LcmBus* bus, bus::LcmBus* frame_bus)
    : config_(config),
      bus_(bus),
      frame_bus_(frame_bus),
      replay_(static_cast<int64_t>(config.max_clock_skew_s * 1e6), kReplayEntriesPerClass),
      replay_poses_(static_cast<int64_t>(config.max_clock_skew_s * 1e6), kReplayEntriesPerClass) {
  VISCERA_DEMAND(bus_ != nullptr && frame_bus_ != nullptr);
  // nothing sent before this start is taken: a create captured before a restart stays stale
  replay_.SetEpoch(bus::WallMicros());
  replay_poses_.SetEpoch(bus::WallMicros());
}

SessionManager::~SessionManager() { StopAll(); }

void SessionManager::SetMaxSessions(int max_sessions) {
  VISCERA_DEMAND(max_sessions >= 1);
  config_.max_sessions = max_sessions;
}

void SessionManager::SetCapacity(const CapacityEstimate& estimate) {
  SetMaxSessions(estimate.max_sessions);
  capacity_ = estimate;
}

void SessionManager::StopAll() {
  // Builds stop at their next check (every settling step, between phases); one still inside a
  // long step after kBuildStopWait is left to end with the process: its future is let go of
  // (a future of std::async waits in its destructor) and it holds only copies.
  for (PendingCreate& p : pending_) p.stop->store(true);
  const auto give_up = std::chrono::steady_clock::now() + kBuildStopWait;
  for (PendingCreate& p : pending_) {
    if (p.scene.wait_until(give_up) != std::future_status::ready) {
      std::fprintf(
          stderr,
          "viscerad: a scene build is still in a step at shutdown; left to end with the process\n");
      new std::future<session::SessionScene>(std::move(p.scene));  // never waited for, never freed
    }
  }
  pending_.clear();
  for (auto& [id, running] : sessions_) {
    if (running.frames != nullptr) running.frames->RequestStop();  // all at once, then wait
    if (running.exposure != nullptr) running.exposure->RequestStop();
  }
  for (auto& [id, running] : sessions_) running.session->Stop();
  sessions_.clear();  // each render thread ends before its session is destroyed
  retiring_.clear();
  num_sessions_ = 0;
}

int64_t SessionManager::unconverged_solves() const {
  int64_t sum = ended_unconverged_solves_;
  for (const auto& [id, running] : sessions_) sum += running.session->Status().unconverged_solves;
  return sum;
}

session::Session* SessionManager::Find(int64_t id) {
  const auto it = sessions_.find(id);
  return it == sessions_.end() ? nullptr : it->second.session.get();
}

viscera_proto::session_status_t SessionManager::Retire(int64_t id) {
  const auto it = sessions_.find(id);
  if (it->second.frames != nullptr) it->second.frames->RequestStop();
  if (it->second.exposure != nullptr) it->second.exposure->RequestStop();
  it->second.session->Stop();
  viscera_proto::session_status_t status = it->second.session->Status();
  ended_unconverged_solves_ += status.unconverged_solves;
  retiring_.push_back(std::move(it->second));  // its render thread may be mid-frame
  sessions_.erase(it);
  num_sessions_ = static_cast<int>(sessions_.size());
  return status;
}

void SessionManager::ExpireLeases() {
  const int64_t now = MonotonicNanos();
  std::vector<int64_t> expired;
  for (const auto& [id, running] : sessions_) {
    if (running.session->LeaseLeft(now) <= 0.0) expired.push_back(id);
  }
  for (const int64_t id : expired) {
    session::Session* session = Find(id);
    session->SetError(
        Cat("lease expired: no pose, command or keep-alive for ", session->config().lease_s, " s"));
    Retire(id);
    ++expired_;
    std::fprintf(stderr, "viscerad: session %lld ended: its lease of %g s expired\n",
                 static_cast<long long>(id), config_.session_lease_s);
  }
}

void SessionManager::OnDrop(const std::string& channel, bus::DropReason reason, const uint8_t* data,
                            int size) {
  const char* what = reason == bus::DropReason::kBadMac     ? "message without a valid MAC"
                     : reason == bus::DropReason::kOversize ? "oversize message"
                                                            : "malformed message";
  Reject(Find(SessionOfChannel(channel, bus::kPosePrefix)), Cat(what, " on ", channel));
  if (reason != bus::DropReason::kOversize || channel != bus::kRequestChannel) return;
  // say why to the client: request_id follows the header's mac (encoded layout, big-endian)
  const int mac_len_at = bus::MacLenOffset(data, size);
  if (mac_len_at < 0 || mac_len_at + 4 > size) return;
  const int32_t mac_len = static_cast<int32_t>(ReadBe(data + mac_len_at, 4));
  if (mac_len < 0 || mac_len > size - mac_len_at - 4 - 9) return;
  session_request_t request{};
  request.request_id = static_cast<int64_t>(ReadBe(data + mac_len_at + 4 + mac_len, 8));
  request.command = static_cast<int8_t>(data[mac_len_at + 4 + mac_len + 8]);
  Reply(request, session_reply_t::kRefused,
        Cat("message of ", size, " bytes: above this server's limit of ", config_.max_message_bytes,
            " bytes (--max-message-size)"));
}

void SessionManager::Reject(session::Session* session, const std::string& why) {
  ++rejected_;
  if (session != nullptr) session->CountRejected(why);
}

void SessionManager::Reply(const session_request_t& request, int8_t result,
                           const std::string& message, int64_t session_id,
                           const std::vector<uint8_t>& token) {
  reply_.header = bus::MakeHeader(session_id, reply_seq_++);
  if (!token.empty()) {
    reply_.header.token = token;
    reply_.header.token_len = static_cast<int32_t>(token.size());
  }
  reply_.request_id = request.request_id;
  reply_.command = request.command;
  reply_.result = result;
  reply_.message = message;
  reply_.server_id = config_.server_id;
  bus_->Publish(bus::kReplyChannel, reply_);
  reply_.sessions.clear();
  reply_.num_sessions = 0;
}

void SessionManager::OnRequest(const session_request_t& request, const bus::MessageInfo& info) {
  (void)info;
  // another server's business
  if (!request.server_id.empty() && request.server_id != config_.server_id) return;
  reply_.sessions.clear();
  reply_.num_sessions = 0;
  if (!Validate(request)) return;
  switch (request.command) {
    case session_request_t::kCreate:
      if (const std::optional<AdmittedCreate> admitted = AdmitCreate(request)) {
        StartCreate(request, *admitted);
      }
      return;
    case session_request_t::kList:
      for (const auto& [id, running] : sessions_)
        reply_.sessions.push_back(running.session->Status());
      reply_.num_sessions = static_cast<int32_t>(reply_.sessions.size());
      Reply(request, session_reply_t::kOk, "");
      return;
    default:
      if (session::Session* session = AdmitToSession(request)) Dispatch(request, session);
      return;
  }
}

bool SessionManager::Validate(const session_request_t& request) {
  const int64_t id = request.header.session_id;
  const std::string problem = bus::HeaderProblem(request.header);
  if (!problem.empty() || request.request_id == 0) {
    Reject(Find(id), Cat("bad request: ", problem.empty() ? "request_id 0" : problem));
    // another protocol version may not understand the reply, but it is all we can say
    Reply(request, session_reply_t::kBadRequest,
          problem.empty() ? "request_id must not be 0" : problem, id);
    return false;
  }
  switch (request.command) {
    case session_request_t::kCreate:
      if (request.server_id != config_.server_id) {
        ++rejected_;
        Reply(request, session_reply_t::kBadRequest,
              "create must name its server (server_id from the heartbeat)");
        return false;
      }
      return true;
    case session_request_t::kList:
    case session_request_t::kStatus:
    case session_request_t::kDestroy:
    case session_request_t::kReset:
    case session_request_t::kPause:
    case session_request_t::kResume:
    case session_request_t::kCamera:
    case session_request_t::kKeepAlive:
    case session_request_t::kWatchFrames: return true;
    default:
      Reject(Find(id), Cat("unknown command ", int{request.command}));
      Reply(request, session_reply_t::kBadRequest, Cat("unknown command ", int{request.command}),
            id);
      return false;
  }
}

void SessionManager::Dispatch(const session_request_t& request, session::Session* session) {
  const int64_t id = request.header.session_id;
  switch (request.command) {
    case session_request_t::kStatus:
      reply_.sessions.push_back(session->Status());
      reply_.num_sessions = 1;
      Reply(request, session_reply_t::kOk, "", id);
      return;
    case session_request_t::kWatchFrames:
      session->WatchFrames();
      Reply(request, session_reply_t::kOk, "", id);
      return;
    default: break;
  }
  // an authentic command renews the lease and is recorded, even one refused below
  session->Touch();
  records_.WriteRequest(session->recorder(), request, bus::WallMicros());

  session::Command command;
  switch (request.command) {
    case session_request_t::kKeepAlive: Reply(request, session_reply_t::kOk, "", id); return;
    case session_request_t::kDestroy:
      reply_.sessions.push_back(Retire(id));
      reply_.num_sessions = 1;
      Reply(request, session_reply_t::kOk, "", id);
      return;
    case session_request_t::kReset: command.kind = session::Command::Kind::kReset; break;
    case session_request_t::kPause: command.kind = session::Command::Kind::kPause; break;
    case session_request_t::kResume: command.kind = session::Command::Kind::kResume; break;
    default: {  // kCamera: no mechanics involved, the render thread reads it directly
      const session::CameraPose pose = CameraPoseOf(request);
      if (!CameraPoseUsable(pose)) {
        Reject(session, "camera: non-finite or degenerate pose, or fov outside (1, 179) deg");
        Reply(request, session_reply_t::kRefused,
              Cat("camera: eye and target must differ and lie within ", kMaxPosition,
                  " m, up must be non-zero and not along the view, fov within (1, 179) deg"),
              id);
        return;
      }
      session->SetCamera(pose);
      Reply(request, session_reply_t::kOk, "", id);
      return;
    }
  }
  if (!session->inbox().PostCommand(command)) {
    Reject(session, "command queue full");
    Reply(request, session_reply_t::kRefused, "too many commands waiting", id);
    return;
  }
  Reply(request, session_reply_t::kOk, "", id);
}

void SessionManager::StartCreate(const session_request_t& request, const AdmittedCreate& admitted) {
  // Building the model may take long (mesh distance fields, settling): a helper thread does
  // it at low priority (nice 10), within the server's scene budget, so no session waits for it.
  const double rate = admitted.settings.rate_hz;
  scene::SceneLimits limits = NetworkSceneLimits(config_, rate);
  auto stop = std::make_shared<std::atomic<bool>>(false);
  limits.check_stop = BuildStopCheck(stop, config_.max_build_s);
  const std::string inline_source = config_.scene_dir + "/<inline>";  // meshes: the scene dir
  // copies only, no `this`: a build still running at shutdown is left behind (StopAll)
  pending_.push_back({request, admitted,
                      std::async(std::launch::async,
                                 [scene_dir = config_.scene_dir, max_rate = config_.max_rate_hz,
                                  request, rate, limits, inline_source] {
                                   NiceThisThread();
                                   return session::LoadSessionScene(
                                       scene_dir, request.scene_name, request.scene_toml, rate,
                                       max_rate, inline_source, limits);
                                 }),
                      stop});
}

void SessionManager::Poll() {
  ExpireLeases();
  std::erase_if(retiring_, [](const Running& r) {
    return (r.frames == nullptr || r.frames->finished()) &&
           (r.exposure == nullptr || r.exposure->finished());
  });
  for (size_t i = 0; i < pending_.size();) {
    PendingCreate& p = pending_[i];
    if (p.scene.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
      ++i;
      continue;
    }
    const session_request_t request = p.request;
    const AdmittedCreate admitted = p.admitted;
    std::future<session::SessionScene> future = std::move(p.scene);
    pending_.erase(pending_.begin() + static_cast<long>(i));
    session::SessionScene scene;
    try {
      scene = future.get();  // the helper's exception, if any, arrives here as a value
    } catch (const std::exception& e) {
      RefuseCreate(request, e.what());
      continue;
    }
    FinishCreate(request, std::move(scene), admitted);
  }
}

void SessionManager::FinishCreate(const session_request_t& request, session::SessionScene scene,
                                  const AdmittedCreate& admitted) {
  if (static_cast<int>(sessions_.size()) >= config_.max_sessions) {
    RefuseCreate(request, FullMessage());
    return;
  }
  session::SessionConfig sc;
  do {
    sc.id = NewSessionId();
  } while (sessions_.count(sc.id) != 0);
  sc.token = bus::RandomBytes(kTokenBytes);
  sc.server_id = config_.server_id;
  sc.scene = scene.label;
  sc.skeleton_rate_hz = admitted.settings.skeleton_rate_hz;
  sc.status_rate_hz = config_.status_rate_hz;
  sc.realtime_priority = config_.realtime_priority;
  sc.lease_s = config_.session_lease_s;
  sc.spin_ns = config_.spin_us < 0.0 ? -1 : static_cast<int64_t>(config_.spin_us * 1e3);
  const FrameStreamConfig frames = admitted.settings.FrameStream(config_);
  // while frames stream, a snapshot every step (it costs a copy of the control points): a
  // frame then shows the pose of its tick, not one up to a snapshot period older
  sc.snapshot_rate_hz =
      frames.rate_hz > 0.0 ? scene.model->params().rate_hz : std::max(30.0, sc.skeleton_rate_hz);

  std::unique_ptr<session::Recorder> recorder;
  if (!config_.log_dir.empty()) {
    try {
      recorder =
          std::make_unique<session::Recorder>(Cat(config_.log_dir, "/session-", sc.id, ".lcmlog"));
    } catch (const std::exception& e) {
      Reply(request, session_reply_t::kRefused, Cat("cannot record the session: ", e.what()));
      return;
    }
    records_.WriteCreate(recorder.get(), request, sc.id, scene, bus::WallMicros());
  }

  Running& running = sessions_[sc.id];  // in the map first: nothing below can lose a thread
  running.frame_mpix_per_s = admitted.frame_mpix_per_s;
  running.cores = admitted.cores;
  running.session = std::make_unique<session::Session>(sc, scene.model, bus_, std::move(recorder));
  session::Session* session = running.session.get();
  session->Start();
  if (frames.rate_hz > 0.0) {
    running.frames = std::make_unique<FrameStreamer>(session, frame_bus_, frames);
    running.frames->Start();
  }
  if (!scene.model->params().task.targets.empty() || scene.model->params().task.running) {
    // the exposure and running the bowel's camera coverage count what the frames show: the
    // same camera, framed for the same size
    running.exposure = std::make_unique<ExposureWatcher>(
        session, ExposureWatchConfig{frames.options.width, frames.options.height});
    running.exposure->Start();
  }
  num_sessions_ = static_cast<int>(sessions_.size());
  std::string message;
  for (const std::string& w : scene.warnings) message += (message.empty() ? "" : "; ") + w;
  reply_.sessions.push_back(session->Status());
  reply_.num_sessions = 1;
  Reply(request, session_reply_t::kOk, message, sc.id, sc.token);
  std::fprintf(stderr, "viscerad: session %lld created (scene %s, %g Hz)\n",
               static_cast<long long>(sc.id), sc.scene.c_str(), scene.model->params().rate_hz);
}

void SessionManager::OnPose(const viscera_proto::tool_pose_t& pose, const bus::MessageInfo& info) {
  const int64_t id = pose.header.session_id;
  session::Session* session = Find(id);
  if (session == nullptr) {
    ++not_ours_;  // another server's session on a shared bus: counted apart from rejected
    return;
  }
  // the exact name: VISCERA_POSE_0<id> parses to the same id but is another (sender, channel)
  // for the replay guard, so a captured pose replayed there passed it
  if (*info.channel != bus::SessionChannel(bus::kPosePrefix, id)) {
    Reject(session, Cat("pose for session ", id, " on channel ", *info.channel));
    return;
  }
  if (const std::string problem = bus::HeaderProblem(pose.header); !problem.empty()) {
    Reject(session, Cat("pose: ", problem));
    return;
  }
  if (!bus::SecureEquals(pose.header.token, session->config().token)) {
    Reject(session, pose.header.token.empty() ? "pose without the session token"
                                              : "pose with a wrong session token");
    return;
  }
  if (!CheckReplay(pose.header, *info.channel, session).empty()) return;
  session->Touch();
  if (const std::string problem = PoseProblem(pose, session->num_tools()); !problem.empty()) {
    Reject(session, Cat("pose: ", problem));
    return;
  }
  session::PoseInput input;
  input.target.tip = Vec3(pose.position[0], pose.position[1], pose.position[2]);
  input.target.orientation = Eigen::Quaterniond(pose.orientation[0], pose.orientation[1],
                                                pose.orientation[2], pose.orientation[3])
                                 .normalized();
  input.target.jaw = pose.jaw;
  input.target.active = true;
  input.seq = pose.header.seq;
  input.client_utime = pose.header.utime;
  input.received_ns = MonotonicNanos();
  if (!session->inbox().PostPose(pose.tool, input)) {
    Reject(session, Cat("stale pose (seq ", pose.header.seq, " after a newer one)"));
    return;
  }
  session->CountPose();
  records_.WritePose(session->recorder(), *info.channel, pose, info.recv_utime);
}

}  // namespace viscera::server
