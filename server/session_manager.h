#pragma once
/// SessionManager: the server's sessions, driven by the I/O thread. It validates and
/// routes every request and pose (bad input is dropped, counted and, for requests,
/// answered; never thrown), creates and destroys sessions, and answers status and list.
#include <atomic>
#include <cstdint>
#include <deque>
#include <future>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>

#include <viscera_proto/session_reply_t.hpp>
#include <viscera_proto/session_request_t.hpp>
#include <viscera_proto/tool_pose_t.hpp>

#include "bus/lcm_bus.h"
#include "bus/replay_guard.h"
#include "server/capacity_estimate.h"
#include "server/create_settings.h"
#include "server/exposure_watcher.h"
#include "server/frame_streamer.h"
#include "server/peer_directory.h"
#include "server/request_checks.h"
#include "server/server_config.h"
#include "server/session_record.h"
#include "session/session.h"
#include "session/session_scene.h"

namespace viscera::server {

class SessionManager {
 public:
  /// @pre bus and frame_bus outlive the manager; only the I/O thread calls the On* members.
  /// @param frame_bus where render threads publish frames: a bus of its own, so that a
  ///        frame's tens of fragments never hold the publish lock a force message waits for.
  SessionManager(const ServerConfig& config, bus::LcmBus* bus, bus::LcmBus* frame_bus);
  /// Stops every session (StopAll).
  ~SessionManager();
  SessionManager(const SessionManager&) = delete;
  SessionManager& operator=(const SessionManager&) = delete;

  void OnRequest(const viscera_proto::session_request_t& request, const bus::MessageInfo& info);
  void OnPose(const viscera_proto::tool_pose_t& pose, const bus::MessageInfo& info);
  /// A datagram the bus dropped (malformed, bad MAC, oversize): counted, and charged to the
  /// session when its channel names one. An oversize request is answered (kRefused, with
  /// the limit) when its request_id can be read from the raw bytes.
  void OnDrop(const std::string& channel, bus::DropReason reason, const uint8_t* data, int size);

  /// Finishes creations whose model is built (building a model can take a while, e.g. a
  /// mesh obstacle's distance field: a helper thread at idle priority builds it so neither
  /// the I/O thread nor a session waits), ends sessions whose lease ran out, and lets go of
  /// destroyed sessions whose render thread has ended. Call from the I/O loop; cheap when
  /// nothing is pending.
  void Poll();
  bool creating() const { return !pending_.empty(); }

  /// Stops every session: final status, records flushed.
  void StopAll();

  /// Other servers on the bus: a refusal because this one is full names one with room.
  /// @pre peers (nullable) outlives the manager and is only touched by the I/O thread.
  void SetPeers(const PeerDirectory* peers) { peers_ = peers; }

  /// Creates beyond `max_sessions` running sessions are refused from now on. @pre >= 1.
  void SetMaxSessions(int max_sessions);
  /// Admission by the measured cost from now on: at most estimate.max_sessions sessions,
  /// and a create is refused when its own cost (steps, plus frames if it streams them:
  /// CapacityEstimate::SessionCores) would take the sessions past the cores' budget. An
  /// idle server still takes any one session.
  void SetCapacity(const CapacityEstimate& estimate);

  int num_sessions() const { return num_sessions_.load(); }
  /// Messages dropped since start as invalid (all reasons, all sessions): undecodable,
  /// bad MAC, wrong token, bad values, replays, refused creates.
  int64_t rejected() const { return rejected_.load(); }
  /// Poses and requests for sessions this server does not run (not in rejected): on a bus
  /// shared by several servers, each hears the others' traffic.
  int64_t not_ours() const { return not_ours_.load(); }
  /// Of those, replayed or stale session-changing messages.
  int64_t replayed() const { return replayed_.load(); }
  /// Sessions ended because their lease ran out.
  int64_t expired() const { return expired_.load(); }
  /// Linear solves accepted short of their tolerance (session_status_t::unconverged_solves),
  /// summed over the sessions running (as of their latest status) and those ended since start.
  /// I/O thread only.
  int64_t unconverged_solves() const;

 private:
  /// What admission decided for a create: its settings with the server's defaults, and what
  /// it is charged until it ends.
  struct AdmittedCreate {
    CreateSettings settings;
    double frame_mpix_per_s = 0.0;  // its share of max_frame_mpix_per_s
    double cores = 0.0;             // what admission charged it (SetCapacity)
  };

  /// Answers `request` (`token`: the session token, for a create's answer only). The reply
  /// carries the statuses put in reply_.sessions before the call.
  void Reply(const viscera_proto::session_request_t& request, int8_t result,
             const std::string& message, int64_t session_id = 0,
             const std::vector<uint8_t>& token = {});
  // A request goes through three steps, each answering it when it ends there: Validate (its
  // form), admission (the server's state, the session's token, the replay guard), then the
  // command (StartCreate, the list, Dispatch).
  /// False (answered kBadRequest) for a request of bad form: its header, request_id 0, an
  /// unknown command, a create that does not name this server.
  bool Validate(const viscera_proto::session_request_t& request);
  /// Whether a create may start (session_admission.cc): not a replay, within the create rate,
  /// the sessions, the disk, the server's limits, its frame bandwidth and cores. Answers a
  /// refusal.
  std::optional<AdmittedCreate> AdmitCreate(const viscera_proto::session_request_t& request);
  /// The session a command is for, once its token and the replay guard let it through (status
  /// and frame watching need no token); nullptr when refused (answered).
  session::Session* AdmitToSession(const viscera_proto::session_request_t& request);
  /// Counts and answers a create refused (kRefused).
  void RefuseCreate(const viscera_proto::session_request_t& request, const std::string& why);
  /// Runs an admitted session command and answers it.
  void Dispatch(const viscera_proto::session_request_t& request, session::Session* session);
  /// Starts building an admitted create's scene on a helper thread (Poll finishes it).
  void StartCreate(const viscera_proto::session_request_t& request, const AdmittedCreate& admitted);
  void FinishCreate(const viscera_proto::session_request_t& request, session::SessionScene scene,
                    const AdmittedCreate& admitted);
  void Reject(session::Session* session, const std::string& why);
  /// The replay verdict on an otherwise authentic message: "" to go on, else why it was
  /// dropped (counted, charged to `session` when there is one).
  std::string CheckReplay(const viscera_proto::header_t& header, const std::string& channel,
                          session::Session* session);
  /// Why no create may start now ("" if one may): max_creates_per_minute reached by all key
  /// holders together (a sender id is the client's own choice: a per-sender limit stopped
  /// nobody, and its sweep over every sender ever seen slowed every command).
  std::string CreateRateProblem();
  /// Frame streams of all sessions and creations in flight (megapixels per second).
  double FrameLoadMpix() const;
  /// Cores charged to all sessions and creations in flight (0 without SetCapacity).
  double CoresCharged() const;
  /// Stops session `id` (which exists) and moves it to retiring_ (its render thread may be
  /// mid-frame). @return its final status.
  viscera_proto::session_status_t Retire(int64_t id);
  void ExpireLeases();
  /// Why a create is refused when the server is full, naming a peer with room if known.
  std::string FullMessage() const;
  session::Session* Find(int64_t id);

  ServerConfig config_;
  std::optional<CapacityEstimate> capacity_;  // admission by cores once measured
  bus::LcmBus* bus_;

  /// A session and its render thread (none without frames). The streamer reads the session:
  /// declared after it, it is destroyed (stopped) first.
  struct Running {
    std::unique_ptr<session::Session> session;
    std::unique_ptr<FrameStreamer> frames;
    // scenes with [[target]] or [running]; ends before the session
    std::unique_ptr<ExposureWatcher> exposure;
    double frame_mpix_per_s = 0.0;  // its share of max_frame_mpix_per_s
    double cores = 0.0;             // what admission charged it (SetCapacity)
  };

  bus::LcmBus* frame_bus_;
  const PeerDirectory* peers_ = nullptr;
  std::map<int64_t, Running> sessions_;
  /// Destroyed sessions whose render thread is still finishing its frame: a destroy never
  /// waits for a frame on the I/O thread. Poll drops them once the thread has ended.
  std::vector<Running> retiring_;
  struct PendingCreate {
    viscera_proto::session_request_t request;
    AdmittedCreate admitted;
    std::future<session::SessionScene> scene;  // the helper's result or its exception
    std::shared_ptr<std::atomic<bool>> stop;   // set: the helper abandons the build
  };
  std::vector<PendingCreate> pending_;
  std::atomic<int> num_sessions_{0};
  std::atomic<int64_t> rejected_{0};
  std::atomic<int64_t> not_ours_{0};
  std::atomic<int64_t> replayed_{0};
  std::atomic<int64_t> expired_{0};
  int64_t ended_unconverged_solves_ = 0;  // of the sessions retired (I/O thread)
  bus::ReplayGuard replay_;               // the request channel's senders
  bus::ReplayGuard replay_poses_;         // the pose channels': a pose flood cannot fill the other
  std::deque<int64_t> create_times_;      // creates accepted within the last minute (ns)
  int64_t reply_seq_ = 0;
  viscera_proto::session_reply_t
      reply_{};             // zeroed: Reply() sends num_sessions before any list set it
  ScrubbedRecord records_;  // requests and poses into session records, without tokens
};

}  // namespace viscera::server
