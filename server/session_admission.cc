// SessionManager's admission: whether the server takes a well-formed request, by its state
// (sessions, load, disk, creates of late), the session's token and the replay guards. Each
// refusal is counted and answered here.
#include <cmath>
#include <optional>

#include "bus/channels.h"
#include "bus/header.h"
#include "bus/message_auth.h"
#include "common/check.h"
#include "common/clock.h"
#include "server/record_disk.h"
#include "server/request_checks.h"
#include "server/session_manager.h"

namespace viscera::server {

using viscera_proto::session_reply_t;
using viscera_proto::session_request_t;

std::optional<SessionManager::AdmittedCreate> SessionManager::AdmitCreate(
    const session_request_t& request) {
  if (const std::string why = CheckReplay(request.header, bus::kRequestChannel, nullptr);
      !why.empty()) {
    Reply(request, session_reply_t::kReplayed, why);
    return std::nullopt;
  }
  // the rate limit first: a create refused below still took its place in the last minute
  if (const std::string problem = CreateRateProblem(); !problem.empty()) {
    RefuseCreate(request, problem);
    return std::nullopt;
  }
  if (static_cast<int>(sessions_.size() + pending_.size()) >= config_.max_sessions) {
    RefuseCreate(request, FullMessage());
    return std::nullopt;
  }
  if (const std::string problem = RecordDiskProblem(config_); !problem.empty()) {
    RefuseCreate(request, problem);
    return std::nullopt;
  }
  if (const std::string problem = CreateSettingsProblem(request, config_); !problem.empty()) {
    RefuseCreate(request, problem);
    return std::nullopt;
  }

  AdmittedCreate admitted;
  admitted.settings = ResolveCreateSettings(request, config_);
  const CreateSettings& s = admitted.settings;
  admitted.frame_mpix_per_s = s.FrameMpixPerS();
  if (const double in_use = FrameLoadMpix();
      config_.max_frame_mpix_per_s > 0.0 &&
      in_use + admitted.frame_mpix_per_s > config_.max_frame_mpix_per_s) {
    RefuseCreate(request, Cat("frame bandwidth: this stream needs ", admitted.frame_mpix_per_s,
                              " Mpixel/s and the server's streams use ", in_use, " of its ",
                              config_.max_frame_mpix_per_s,
                              " (ask for a smaller or slower stream, or none)"));
    return std::nullopt;
  }

  admitted.cores =
      !capacity_ ? 0.0 : capacity_->SessionCores(s.frame_rate_hz, s.frame_width, s.frame_height);
  if (const double charged = CoresCharged();
      capacity_ && charged > 0.0 && charged + admitted.cores > capacity_->BudgetCores() + 1e-9) {
    const bool frames = s.frame_rate_hz > 0.0;
    RefuseCreate(
        request,
        Cat("server ", config_.server_id, " has no room for this session: it would cost ",
            admitted.cores, " core",
            frames ? Cat(" (", s.frame_rate_hz, " Hz frames included)") : "", ", and its ",
            sessions_.size(), " sessions use ", charged, " of its ", capacity_->BudgetCores(),
            " core budget", frames ? "; ask for fewer or no frames (frame rate < 0)" : ""));
    return std::nullopt;
  }
  return admitted;
}

session::Session* SessionManager::AdmitToSession(const session_request_t& request) {
  const int64_t id = request.header.session_id;
  session::Session* session = Find(id);
  if (session == nullptr) {
    ++not_ours_;  // on a shared bus, most likely another server's session: not an attack
    Reply(request, session_reply_t::kUnknownSession,
          Cat("no session ", id, " on server ", config_.server_id), id);
    return nullptr;
  }
  // status needs no token: the same status goes out on VISCERA_STATUS_<id> to everyone; nor
  // does watching frames, as the frames themselves: a watcher costs the server the frames it
  // asked for anyway before the lease existed, and changes nothing else
  if (request.command == session_request_t::kStatus ||
      request.command == session_request_t::kWatchFrames) {
    return session;
  }
  if (!bus::SecureEquals(request.header.token, session->config().token)) {
    Reject(session, request.header.token.empty() ? "request without the session token"
                                                 : "request with a wrong session token");
    Reply(request, session_reply_t::kBadToken,
          request.header.token.empty() ? "this command needs the session token"
                                       : "wrong session token",
          id);
    return nullptr;
  }
  // before any effect: a replayed or stale command changes nothing, not even the lease
  if (const std::string why = CheckReplay(request.header, bus::kRequestChannel, session);
      !why.empty()) {
    Reply(request, session_reply_t::kReplayed, why, id);
    return nullptr;
  }
  return session;
}

void SessionManager::RefuseCreate(const session_request_t& request, const std::string& why) {
  ++rejected_;
  Reply(request, session_reply_t::kRefused, why);
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
  for (const PendingCreate& p : pending_) sum += p.admitted.frame_mpix_per_s;
  return sum;
}

double SessionManager::CoresCharged() const {
  double sum = 0.0;
  for (const auto& [id, running] : sessions_) sum += running.cores;
  for (const PendingCreate& p : pending_) sum += p.admitted.cores;
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

}  // namespace viscera::server
