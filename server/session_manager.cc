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
#include "server/frame_schedule.h"
#include "server/idle_priority.h"
#include "server/record_disk.h"
#include "server/scene_budget.h"
#include "session/session_scene.h"
#include "skin/skin.h"

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
constexpr double kMaxPosition = 10.0;  // m: no operating room is larger

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

// Tokens and MACs never reach a record (docs/security.md): a record may be shared.
void Scrub(viscera_proto::header_t* header) {
  header->token.clear();
  header->token_len = 0;
  header->mac.clear();
  header->mac_len = 0;
}

}  // namespace

std::string PoseProblem(const viscera_proto::tool_pose_t& pose, int num_tools) {
  if (pose.tool < 0 || pose.tool >= num_tools) {
    return Cat("tool ", pose.tool, " does not exist (the scene has ", num_tools, ")");
  }
  for (const double x : pose.position) {
    if (!std::isfinite(x) || std::abs(x) > kMaxPosition) {
      return Cat("position (", pose.position[0], ", ", pose.position[1], ", ", pose.position[2],
                 ") m: not finite or beyond ", kMaxPosition, " m");
    }
  }
  double norm2 = 0.0;
  for (const double c : pose.orientation) norm2 += c * c;
  if (!std::isfinite(norm2) || norm2 < 0.25 || norm2 > 4.0) {
    return Cat("orientation quaternion of norm ", std::sqrt(norm2), ": not a rotation");
  }
  if (!std::isfinite(pose.jaw) || pose.jaw < 0.0 || pose.jaw > 1.0) {
    return Cat("jaw ", pose.jaw, ": must be within [0, 1]");
  }
  return "";
}

std::string FrameSettingsProblem(int width, int height, double rate_hz, int jpeg_quality,
                                 const std::string& skin_name, const ServerConfig& limits) {
  // every stream holds a frame buffer and a render thread: the server caps their size
  const auto side_ok = [](int side, int max) {
    return side == 0 || (side >= kMinFrameSide && side <= max);
  };
  if (!side_ok(width, limits.max_frame_width) || !side_ok(height, limits.max_frame_height)) {
    return Cat("frame size ", width, "x", height,
               ": each side must be 0 (server default) or within ", kMinFrameSide, "..",
               limits.max_frame_width, "x", limits.max_frame_height, " pixels");
  }
  if (!std::isfinite(rate_hz) || rate_hz > limits.max_frame_rate_hz ||
      (rate_hz > 0.0 && rate_hz < kMinFrameRateHz)) {
    return Cat("frame rate ", rate_hz, " Hz: must be within ", kMinFrameRateHz, "..",
               limits.max_frame_rate_hz, " Hz (0 = server default, < 0 = no frames)");
  }
  if (jpeg_quality < 0 || jpeg_quality > 100) {
    return Cat("JPEG quality ", jpeg_quality, ": must be within 1..100 (0 = server default)");
  }
  if (!skin_name.empty() && !skin::IsSkinName(skin_name)) {
    return Cat("unknown skin '", skin_name, "' (expected ", skin::kSkinNameList, ")");
  }
  return "";
}

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

double SessionManager::CoresCharged() const {
  double sum = 0.0;
  for (const auto& [id, running] : sessions_) sum += running.cores;
  for (const PendingCreate& p : pending_) sum += p.cores;
  return sum;
}

std::string SessionManager::FullMessage() const {
  const std::string full = Cat("server ", config_.server_id, " is full (", sessions_.size(), " of ",
                               config_.max_sessions, " sessions)");
  const std::optional<bus::ServerLoad> other =
      peers_ != nullptr ? peers_->Suggest(MonotonicNanos()) : std::nullopt;
  if (!other) return Cat(full, "; no other server with room heard");
  return Cat(full, "; server ", other->server_id, " has room (", other->sessions, " of ",
             other->max_sessions, " sessions): viscera create --server ", other->server_id);
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

void SessionManager::Reject(session::Session* session, const std::string& why) {
  ++rejected_;
  if (session != nullptr) session->CountRejected(why);
}

std::string SessionManager::CheckReplay(const viscera_proto::header_t& header,
                                        const std::string& channel, session::Session* session) {
  const int64_t now = bus::WallMicros();
  bus::ReplayGuard& guard = channel == bus::kRequestChannel ? replay_ : replay_poses_;
  const bus::ReplayGuard::Verdict verdict =
      guard.Check(header.sender, channel, header.seq, header.utime, now);
  if (verdict == bus::ReplayGuard::Verdict::kAccepted) return "";
  const std::string why = guard.Explain(verdict, header.seq, header.utime, now);
  ++rejected_;
  ++replayed_;
  if (session != nullptr) session->CountReplayed(Cat(channel, ": ", why));
  return why;
}

std::string SessionManager::CreateRateProblem() {
  if (config_.max_creates_per_minute <= 0) return "";
  const int64_t now = MonotonicNanos();
  constexpr int64_t kMinute = 60'000'000'000;
  while (!create_times_.empty() && now - create_times_.front() > kMinute) create_times_.pop_front();
  if (static_cast<int>(create_times_.size()) >= config_.max_creates_per_minute) {
    return Cat("too many creates: ", create_times_.size(), " in the last minute from ",
               config_.key_file.empty() ? "all clients" : "the holders of this server's key",
               " together (limit ", config_.max_creates_per_minute,
               " per minute; try again shortly)");
  }
  create_times_.push_back(now);
  return "";
}

double SessionManager::FrameLoadMpix() const {
  double sum = 0.0;
  for (const auto& [id, running] : sessions_) sum += running.frame_mpix_per_s;
  for (const PendingCreate& p : pending_) sum += p.frame_mpix_per_s;
  return sum;
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

void SessionManager::Reply(const session_request_t& request, int8_t result,
                           const std::string& message, int64_t session_id) {
  reply_.header = bus::MakeHeader(session_id, reply_seq_++);
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

  const std::string problem = bus::HeaderProblem(request.header);
  if (!problem.empty() || request.request_id == 0) {
    Reject(Find(request.header.session_id),
           Cat("bad request: ", problem.empty() ? "request_id 0" : problem));
    // another protocol version may not understand the reply, but it is all we can say
    Reply(request, session_reply_t::kBadRequest,
          problem.empty() ? "request_id must not be 0" : problem, request.header.session_id);
    return;
  }

  switch (request.command) {
    case session_request_t::kCreate:
      if (request.server_id != config_.server_id) {
        ++rejected_;
        Reply(request, session_reply_t::kBadRequest,
              "create must name its server (server_id from the heartbeat)");
        return;
      }
      if (const std::string why = CheckReplay(request.header, bus::kRequestChannel, nullptr);
          !why.empty()) {
        Reply(request, session_reply_t::kReplayed, why);
        return;
      }
      Create(request);
      return;
    case session_request_t::kList:
      for (const auto& [id, running] : sessions_)
        reply_.sessions.push_back(running.session->Status());
      reply_.num_sessions = static_cast<int32_t>(reply_.sessions.size());
      Reply(request, session_reply_t::kOk, "");
      return;
    case session_request_t::kStatus:
    case session_request_t::kDestroy:
    case session_request_t::kReset:
    case session_request_t::kPause:
    case session_request_t::kResume:
    case session_request_t::kCamera:
    case session_request_t::kKeepAlive:
    case session_request_t::kWatchFrames: break;
    default:
      Reject(Find(request.header.session_id), Cat("unknown command ", int{request.command}));
      Reply(request, session_reply_t::kBadRequest, Cat("unknown command ", int{request.command}),
            request.header.session_id);
      return;
  }

  const int64_t id = request.header.session_id;
  session::Session* session = Find(id);
  if (session == nullptr) {
    ++not_ours_;  // on a shared bus, most likely another server's session: not an attack
    Reply(request, session_reply_t::kUnknownSession,
          Cat("no session ", id, " on server ", config_.server_id), id);
    return;
  }
  if (request.command == session_request_t::kStatus) {
    // status needs no token: the same status goes out on VISCERA_STATUS_<id> to everyone
    reply_.sessions.push_back(session->Status());
    reply_.num_sessions = 1;
    Reply(request, session_reply_t::kOk, "", id);
    return;
  }
  if (request.command == session_request_t::kWatchFrames) {
    // no token, as the frames themselves: a watcher costs the server the frames it asked for
    // anyway before the lease existed, and changes nothing else
    session->WatchFrames();
    Reply(request, session_reply_t::kOk, "", id);
    return;
  }
  if (!bus::SecureEquals(request.header.token, session->config().token)) {
    Reject(session, request.header.token.empty() ? "request without the session token"
                                                 : "request with a wrong session token");
    Reply(request, session_reply_t::kBadToken,
          request.header.token.empty() ? "this command needs the session token"
                                       : "wrong session token",
          id);
    return;
  }
  // before any effect: a replayed or stale command changes nothing, not even the lease
  if (const std::string why = CheckReplay(request.header, bus::kRequestChannel, session);
      !why.empty()) {
    Reply(request, session_reply_t::kReplayed, why, id);
    return;
  }
  session->Touch();
  if (session->recorder() != nullptr) {
    record_request_ = request;
    Scrub(&record_request_.header);
    session->recorder()->Write(bus::kRequestChannel, record_request_, bus::WallMicros());
  }

  session::Command command;
  switch (request.command) {
    case session_request_t::kKeepAlive: Reply(request, session_reply_t::kOk, "", id); return;
    case session_request_t::kDestroy: {
      reply_.sessions.push_back(Retire(id));
      reply_.num_sessions = 1;
      Reply(request, session_reply_t::kOk, "", id);
      return;
    }
    case session_request_t::kReset: command.kind = session::Command::Kind::kReset; break;
    case session_request_t::kPause: command.kind = session::Command::Kind::kPause; break;
    case session_request_t::kResume: command.kind = session::Command::Kind::kResume; break;
    default: {  // kCamera: no mechanics involved, the render thread reads it directly
      session::CameraPose pose;
      pose.eye = Vec3(request.camera_eye[0], request.camera_eye[1], request.camera_eye[2]);
      pose.target =
          Vec3(request.camera_target[0], request.camera_target[1], request.camera_target[2]);
      pose.up = Vec3(request.camera_up[0], request.camera_up[1], request.camera_up[2]);
      pose.fov_deg = request.camera_fov_deg;
      pose.set_by_client = true;
      const Vec3 view = pose.target - pose.eye;
      const bool ok = pose.eye.allFinite() && pose.target.allFinite() && pose.up.allFinite() &&
                      pose.eye.cwiseAbs().maxCoeff() <= kMaxPosition &&
                      pose.target.cwiseAbs().maxCoeff() <= kMaxPosition && view.norm() > 1e-6 &&
                      pose.up.norm() > 1e-9 &&
                      view.normalized().cross(pose.up.normalized()).norm() > 1e-6 &&
                      std::isfinite(pose.fov_deg) && pose.fov_deg > 1.0 && pose.fov_deg < 179.0;
      if (!ok) {
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

void SessionManager::Create(const session_request_t& request) {
  if (const std::string problem = CreateRateProblem(); !problem.empty()) {
    ++rejected_;
    Reply(request, session_reply_t::kRefused, problem);
    return;
  }
  if (static_cast<int>(sessions_.size() + pending_.size()) >= config_.max_sessions) {
    ++rejected_;
    Reply(request, session_reply_t::kRefused, FullMessage());
    return;
  }
  if (const std::string problem = RecordDiskProblem(config_); !problem.empty()) {
    ++rejected_;
    Reply(request, session_reply_t::kRefused, problem);
    return;
  }
  if (!std::isfinite(request.skeleton_rate_hz) || request.skeleton_rate_hz > 1000.0) {
    ++rejected_;
    Reply(request, session_reply_t::kRefused, "skeleton rate must be at most 1000 Hz");
    return;
  }
  if (const std::string problem =
          FrameSettingsProblem(request.frame_width, request.frame_height, request.frame_rate_hz,
                               request.jpeg_quality, request.skin, config_);
      !problem.empty()) {
    ++rejected_;
    Reply(request, session_reply_t::kRefused, problem);
    return;
  }

  const double frame_rate =
      request.frame_rate_hz != 0.0 ? request.frame_rate_hz : config_.frame_rate_hz;
  const double mpix =
      frame_rate <= 0.0
          ? 0.0
          : 1e-6 * frame_rate *
                (request.frame_width > 0 ? request.frame_width : config_.frame_width) *
                (request.frame_height > 0 ? request.frame_height : config_.frame_height);
  if (const double in_use = FrameLoadMpix();
      config_.max_frame_mpix_per_s > 0.0 && in_use + mpix > config_.max_frame_mpix_per_s) {
    ++rejected_;
    Reply(request, session_reply_t::kRefused,
          Cat("frame bandwidth: this stream needs ", mpix,
              " Mpixel/s and the server's streams use ", in_use, " of its ",
              config_.max_frame_mpix_per_s, " (ask for a smaller or slower stream, or none)"));
    return;
  }

  const double cores =
      !capacity_
          ? 0.0
          : capacity_->SessionCores(
                frame_rate, request.frame_width > 0 ? request.frame_width : config_.frame_width,
                request.frame_height > 0 ? request.frame_height : config_.frame_height);
  if (const double charged = CoresCharged();
      capacity_ && charged > 0.0 && charged + cores > capacity_->BudgetCores() + 1e-9) {
    ++rejected_;
    Reply(request, session_reply_t::kRefused,
          Cat("server ", config_.server_id, " has no room for this session: it would cost ", cores,
              " core", frame_rate > 0.0 ? Cat(" (", frame_rate, " Hz frames included)") : "",
              ", and its ", sessions_.size(), " sessions use ", charged, " of its ",
              capacity_->BudgetCores(), " core budget",
              frame_rate > 0.0 ? "; ask for fewer or no frames (frame rate < 0)" : ""));
    return;
  }

  // Building the model may take long (mesh distance fields, settling): a helper thread does
  // it at low priority (nice 10), within the server's scene budget, so no session waits for it.
  const double rate = request.rate_hz != 0.0 ? request.rate_hz : config_.rate_hz;
  scene::SceneLimits limits = NetworkSceneLimits(config_, rate);
  auto stop = std::make_shared<std::atomic<bool>>(false);
  limits.check_stop = BuildStopCheck(stop, config_.max_build_s);
  const std::string inline_source = config_.scene_dir + "/<inline>";  // meshes: the scene dir
  // copies only, no `this`: a build still running at shutdown is left behind (StopAll)
  pending_.push_back({request, mpix, cores,
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
    const double mpix = p.frame_mpix_per_s, cores = p.cores;
    std::future<session::SessionScene> future = std::move(p.scene);
    pending_.erase(pending_.begin() + static_cast<long>(i));
    session::SessionScene scene;
    try {
      scene = future.get();  // the helper's exception, if any, arrives here as a value
    } catch (const std::exception& e) {
      ++rejected_;
      Reply(request, session_reply_t::kRefused, e.what());
      continue;
    }
    FinishCreate(request, std::move(scene), mpix, cores);
  }
}

void SessionManager::FinishCreate(const session_request_t& request, session::SessionScene scene,
                                  double frame_mpix_per_s, double cores) {
  if (static_cast<int>(sessions_.size()) >= config_.max_sessions) {
    ++rejected_;
    Reply(request, session_reply_t::kRefused, FullMessage());
    return;
  }
  session::SessionConfig sc;
  do {
    sc.id = NewSessionId();
  } while (sessions_.count(sc.id) != 0);
  sc.token = bus::RandomBytes(kTokenBytes);
  sc.server_id = config_.server_id;
  sc.scene = scene.label;
  sc.skeleton_rate_hz =
      request.skeleton_rate_hz != 0.0 ? request.skeleton_rate_hz : config_.skeleton_rate_hz;
  sc.status_rate_hz = config_.status_rate_hz;
  sc.realtime_priority = config_.realtime_priority;
  sc.lease_s = config_.session_lease_s;
  sc.spin_ns = config_.spin_us < 0.0 ? -1 : static_cast<int64_t>(config_.spin_us * 1e3);
  FrameStreamConfig frames;
  frames.rate_hz = request.frame_rate_hz != 0.0 ? request.frame_rate_hz : config_.frame_rate_hz;
  frames.lease_s = config_.frame_lease_s;
  frames.options.width = request.frame_width > 0 ? request.frame_width : config_.frame_width;
  frames.options.height = request.frame_height > 0 ? request.frame_height : config_.frame_height;
  frames.options.jpeg_quality =
      request.jpeg_quality > 0 ? request.jpeg_quality : config_.jpeg_quality;
  frames.options.skin = !request.skin.empty() ? request.skin : config_.skin;
  frames.options.skin_options.parametric.sides = config_.skin_sides;
  frames.options.skin_options.convolution.sides = config_.skin_sides;
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
    // the request as it came, and the scene as loaded with the rate in use: replay needs both
    const int64_t now = bus::WallMicros();
    record_request_ = request;
    Scrub(&record_request_.header);
    recorder->Write(bus::kRequestChannel, record_request_, now);
    session_request_t scene_record = record_request_;
    scene_record.header = bus::MakeHeader(sc.id, 0);
    scene_record.scene_toml = scene.toml;
    scene_record.scene_name = scene.source;  // meshes resolve against it on replay
    scene_record.rate_hz = scene.model->params().rate_hz;
    recorder->Write(bus::SessionChannel(bus::kScenePrefix, sc.id), scene_record, now);
  }

  Running& running = sessions_[sc.id];  // in the map first: nothing below can lose a thread
  running.frame_mpix_per_s = frame_mpix_per_s;
  running.cores = cores;
  running.session = std::make_unique<session::Session>(sc, scene.model, bus_, std::move(recorder));
  session::Session* session = running.session.get();
  session->Start();
  if (frames.rate_hz > 0.0) {
    running.frames = std::make_unique<FrameStreamer>(session, frame_bus_, frames);
    running.frames->Start();
  }
  if (!scene.model->params().task.targets.empty()) {
    // the exposure counts what the frames show: the same camera, framed for the same size
    running.exposure = std::make_unique<ExposureWatcher>(
        session, ExposureWatchConfig{frames.options.width, frames.options.height});
    running.exposure->Start();
  }
  num_sessions_ = static_cast<int>(sessions_.size());
  std::string message;
  for (const std::string& w : scene.warnings) message += (message.empty() ? "" : "; ") + w;
  reply_.sessions.push_back(session->Status());
  reply_.num_sessions = 1;
  reply_.header = bus::MakeHeader(sc.id, reply_seq_++);
  reply_.header.token = sc.token;
  reply_.header.token_len = static_cast<int32_t>(sc.token.size());
  reply_.request_id = request.request_id;
  reply_.command = request.command;
  reply_.result = session_reply_t::kOk;
  reply_.message = message;
  reply_.server_id = config_.server_id;
  bus_->Publish(bus::kReplyChannel, reply_);
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
  if (session->recorder() != nullptr) {
    record_pose_ = pose;
    Scrub(&record_pose_.header);
    session->recorder()->Write(*info.channel, record_pose_, info.recv_utime);
  }
}

}  // namespace viscera::server
