/// viscerad: the viscera haptic server. Runs training sessions (one mechanics thread each)
/// for clients over LCM and announces itself with a heartbeat once a second.
#include <malloc.h>
#include <pthread.h>
#include <unistd.h>

#include <sched.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <exception>
#include <filesystem>
#include <iterator>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>

#include "bus/channels.h"
#include "bus/lcm_bus.h"
#include "common/check.h"
#include "render/frame_renderer.h"
#include "render/offscreen_context.h"
#include "server/capacity_estimate.h"
#include "server/io_loop.h"
#include "server/session_manager.h"
#include "skin/skin.h"

namespace {

std::string DefaultServerId() {
  char host[256] = {};
  if (gethostname(host, sizeof(host) - 1) != 0) host[0] = '\0';
  return std::string("viscerad-") + (host[0] != '\0' ? host : "local") + "-" +
         std::to_string(getpid());
}

const char* SignalName(int signal) { return signal == SIGINT ? "SIGINT" : "SIGTERM"; }

// --max-sessions 0: as many sessions as the measured cost of `scene` fits in this
// process's cores (docs/capacity.md); one per core if the scene cannot be measured.
// A stop abandons the measurement.
// Admission from then on charges each session its steps, and its frames only if it streams
// them (SessionManager::SetCapacity).
void AutoCapacity(viscera::server::IoLoop* loop, const viscera::server::ServerConfig& config,
                  const std::string& scene, const std::atomic<bool>& stopping) {
  try {
    const viscera::server::CapacityEstimate e = viscera::server::EstimateCapacity(
        config, scene, 0.3, [&stopping] { return stopping.load(); });
    std::fprintf(stderr, "viscerad: %s (--max-sessions N overrides)\n", e.Describe().c_str());
    loop->SetCapacity(e);
  } catch (const viscera::server::MeasurementStopped&) {
    std::fprintf(stderr, "viscerad: capacity measurement abandoned: stopping\n");
  } catch (const std::exception& e) {
    const int cores = viscera::server::AvailableCores();
    const std::string why = viscera::Cat("max ", cores, " sessions, one per core: scene '", scene,
                                         "' could not be measured (", e.what(), ")");
    std::fprintf(stderr, "viscerad: %s\n", why.c_str());
    loop->SetMaxSessions(cores);
    loop->SetCapacityNote(why);
  }
}

int Run(viscera::server::ServerConfig config, const std::string& capacity_scene) {
  // Block SIGINT/SIGTERM in every thread (the I/O thread inherits the mask) and take
  // them synchronously here: no handler, no global flag.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

  // before any thread starts: setenv is not thread-safe, and llvmpipe reads it once
  viscera::render::LimitRasterizerThreads();
  viscera::render::KeepRenderMemoryMapped();
  if (config.realtime_priority > 0) {
    // before any thread starts: LCM's receive thread, the I/O thread and the mechanics
    // threads all inherit SCHED_FIFO, so a busy machine cannot delay poses or steps
    sched_param param{};
    param.sched_priority = config.realtime_priority;
    if (const int err = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param); err != 0) {
      std::fprintf(stderr, "viscerad: --realtime %d refused (%s): normal scheduling\n",
                   config.realtime_priority, std::strerror(err));
    }
  }
  // --max-sessions 0: one per core until the measurement (a second or two: the scene's model,
  // steps, frames) is done, so that the server answers at once; measured off the I/O thread
  const bool measure = config.max_sessions == 0;
  if (measure) config.max_sessions = viscera::server::AvailableCores();
  viscera::server::IoLoop loop(config);
  loop.SetCapacityNote(
      measure ? viscera::Cat("max ", config.max_sessions,
                             " sessions, one per core, until the cost of a ", capacity_scene,
                             " session is measured")
              : viscera::Cat("max ", config.max_sessions, " sessions: --max-sessions"));
  loop.Start();
  // a stop does not wait for the measurement (nice 19: minutes on a busy machine)
  std::atomic<bool> stopping{false};
  std::thread estimator;
  if (measure) {
    estimator = std::thread([&loop, &stopping, config, capacity_scene] {
      // Normal priority (never the I/O thread's SCHED_FIFO): at nice 19 a machine busy with
      // other work left it nothing for minutes, and meanwhile the server held one session per
      // core (a load test started right after viscerad was refused its fourth session). It
      // counts CPU time, so sharing the cores costs it no accuracy; sessions created during
      // its second or so of CPU share the cores with it once.
      sched_param normal{};
      pthread_setschedparam(pthread_self(), SCHED_OTHER, &normal);
      AutoCapacity(&loop, config, capacity_scene, stopping);
    });
  }
  std::fprintf(stderr,
               "viscerad: server '%s' up on %s (heartbeat on %s, max %d sessions%s, scenes in %s, "
               "records in %s%s)\n",
               config.server_id.c_str(), config.lcm_url.c_str(), viscera::bus::kHeartbeatChannel,
               config.max_sessions, measure ? " until measured" : "", config.scene_dir.c_str(),
               config.log_dir.empty() ? "(none)" : config.log_dir.c_str(),
               config.key_file.empty() ? "" : ", MAC required");

  // Wake now and then to notice an I/O thread that died.
  const timespec poll{0, 200'000'000};
  while (true) {
    const int signal = sigtimedwait(&stop_signals, nullptr, &poll);
    if (signal == SIGINT || signal == SIGTERM) {
      std::fprintf(stderr, "viscerad: %s received, stopping\n", SignalName(signal));
      stopping = true;
      if (estimator.joinable()) estimator.join();
      loop.Stop();
      std::fprintf(
          stderr, "viscerad: stopped cleanly after %lld heartbeats (%lld messages rejected)\n",
          static_cast<long long>(loop.heartbeats_sent()), static_cast<long long>(loop.rejected()));
      return 0;
    }
    if (loop.failed()) {
      stopping = true;
      if (estimator.joinable()) estimator.join();
      loop.Stop();
      std::fprintf(stderr, "viscerad: I/O thread failed: %s\n", loop.error().c_str());
      return 1;
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  // Two malloc arenas, not glibc's 8 per core: sessions come and go all day with their
  // threads, and each new thread's arena kept its own fragments (a 4-minute soak grew by
  // 90 MB with the default and stayed flat with 2; docs/reliability.md). The mechanics
  // loop allocates nothing, so the arenas' locks cost it nothing.
  mallopt(M_ARENA_MAX, 2);
  CLI::App app{"viscerad: the viscera haptic server (small intestine simulation over LCM)"};
  app.set_version_flag("--version", std::string("viscerad ") + VISCERA_VERSION);
  std::string lcm_url;
  viscera::server::ServerConfig config;
  config.server_id = DefaultServerId();
  app.add_option(
      "--lcm-url", lcm_url,
      "LCM URL (default: $LCM_DEFAULT_URL, else " + std::string(viscera::bus::kDefaultUrl) + ")");
  app.add_option("--server-id", config.server_id, "Name announced in heartbeats")
      ->capture_default_str();
  config.max_sessions = 0;
  std::string capacity_scene = "cavity";
  app.add_option("--max-sessions", config.max_sessions,
                 "Sessions accepted at most; 0 = as many as this machine's cores hold, from the "
                 "measured cost of --capacity-scene")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
  app.add_option("--capacity-scene", capacity_scene,
                 "Scene whose step (and frame) cost sets the default --max-sessions")
      ->capture_default_str();
  app.add_option("--scene-dir", config.scene_dir, "Directory of the scenes a create may name")
      ->capture_default_str();
  app.add_option("--log-dir", config.log_dir,
                 "Directory for session records (session-ID.lcmlog); none when empty");
  app.add_option("--rate", config.rate_hz,
                 "Mechanics rate (Hz) when a create asks for none; 0 = the scene's rate")
      ->check(CLI::Range(0.0, 10000.0))
      ->capture_default_str();
  app.add_option("--max-rate", config.max_rate_hz, "Highest mechanics rate a session may ask (Hz)")
      ->check(CLI::Range(1.0, 10000.0))
      ->capture_default_str();
  app.add_option("--skeleton-rate", config.skeleton_rate_hz,
                 "Default skeleton_state_t rate (Hz); 0 = none")
      ->check(CLI::Range(0.0, 1000.0))
      ->capture_default_str();
  app.add_option("--status-rate", config.status_rate_hz, "session_status_t rate (Hz)")
      ->check(CLI::Range(0.1, 100.0))
      ->capture_default_str();
  app.add_option("--frame-rate", config.frame_rate_hz,
                 "Default frames per second of a session's stream; 0 = no frames by default")
      ->check(CLI::Range(0.0, 1000.0))
      ->capture_default_str();
  app.add_option("--frame-lease", config.frame_lease_s,
                 "Draw a session's frames only while a viewer renewed its frame lease within S s "
                 "(0 = always)")
      ->check(CLI::Range(0.0, 3600.0))
      ->capture_default_str();
  std::string adaptive_frames = "on";
  app.add_option("--adaptive-frames", adaptive_frames,
                 "Under load, lower a stream's frame rate, then its size, and climb back when "
                 "calm (on); off: the rate and size asked for, always")
      ->check(CLI::IsMember({"on", "off"}))
      ->capture_default_str();
  app.add_option("--max-frame-rate", config.max_frame_rate_hz,
                 "Highest frame rate a session may ask (Hz)")
      ->check(CLI::Range(1.0, 1000.0))
      ->capture_default_str();
  app.add_option("--skin", config.skin,
                 std::string("Default skin: ") + viscera::skin::kSkinNameList)
      ->check(CLI::IsMember(std::vector<std::string>(std::begin(viscera::skin::kSkinNames),
                                                     std::end(viscera::skin::kSkinNames))))
      ->capture_default_str();
  app.add_option("--skin-sides", config.skin_sides,
                 "Vertices per ring of the parametric and convolution skins")
      ->check(CLI::Range(6, 64))
      ->capture_default_str();
  std::string frame_size = "640x480", max_frame_size = "1920x1080";
  app.add_option("--frame-size", frame_size, "Default frame size WIDTHxHEIGHT (pixels)")
      ->capture_default_str();
  app.add_option("--max-frame-size", max_frame_size,
                 "Largest frame size a session may ask (WIDTHxHEIGHT)")
      ->capture_default_str();
  app.add_option("--jpeg-quality", config.jpeg_quality, "Default JPEG quality")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  app.add_option("--realtime", config.realtime_priority,
                 "SCHED_FIFO priority (1..99) for the mechanics and I/O threads; 0 = normal")
      ->check(CLI::Range(0, 99))
      ->capture_default_str();
  app.add_option(
         "--spin-us", config.spin_us,
         "Mechanics loops sleep until this long before each deadline, then spin (us; 0 = sleep "
         "only; -1 = 50 with --realtime granted, else 0)")
      ->check(CLI::Range(-1.0, 100000.0))
      ->capture_default_str();
  app.add_option("--key-file", config.key_file,
                 "Pre-shared key file: sign every message and accept only signed ones");
  app.add_flag("--insecure", config.insecure,
               "Start on a bus that reaches other hosts (udpm ttl > 0) without --key-file: every "
               "session token then travels in clear (docs/security.md)");
  app.add_option(
         "--max-clock-skew", config.max_clock_skew_s,
         "Replay protection: largest |utime - this clock| of a session-changing message (s)")
      ->check(CLI::Range(0.1, 3600.0))
      ->capture_default_str();
  app.add_option("--session-lease", config.session_lease_s,
                 "End a session whose client sent nothing (pose, command, keep-alive) this long "
                 "(s); 0 = never")
      ->check(CLI::Range(0.0, 86400.0))
      ->capture_default_str();
  app.add_option("--max-message-size", config.max_message_bytes,
                 "Largest datagram accepted (bytes)")
      ->check(CLI::Range(1024, 64 << 20))
      ->capture_default_str();
  app.add_option("--max-creates-per-minute", config.max_creates_per_minute,
                 "Creates per minute, all key holders (or all clients) together; 0 = no limit")
      ->check(CLI::Range(0, 100000))
      ->capture_default_str();
  app.add_option(
         "--max-frame-bandwidth", config.max_frame_mpix_per_s,
         "All frame streams together (megapixels per second: width x height x rate); 0 = no limit")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  app.add_option("--max-control-points", config.max_control_points,
                 "Control points of a create's scene")
      ->check(CLI::Range(4, 1000000))
      ->capture_default_str();
  app.add_option("--max-obstacles", config.max_obstacles, "Obstacles of a create's scene")
      ->check(CLI::Range(0, 100000))
      ->capture_default_str();
  app.add_option("--max-mesh-resolution", config.max_mesh_resolution,
                 "Distance-field cells along a mesh obstacle's longest side")
      ->check(CLI::Range(8, 200))
      ->capture_default_str();
  app.add_option("--max-mesh-bytes", config.max_mesh_bytes,
                 "Size of a mesh file a create's scene names (bytes)")
      ->check(CLI::Range(int64_t{1}, int64_t{1} << 32))
      ->capture_default_str();
  app.add_option("--max-substeps", config.max_substeps,
                 "Mechanics sub-steps per step of a create's scene")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  app.add_option("--max-settle", config.max_settle_s, "Settle time of a create's scene (s)")
      ->check(CLI::Range(0.0, 60.0))
      ->capture_default_str();
  app.add_option("--max-session-load", config.max_session_load,
                 "Estimated mechanics load of one session (fraction of a core, from timed steps); "
                 "0 = no limit")
      ->check(CLI::Range(0.0, 64.0))
      ->capture_default_str();
  app.add_option("--max-spheres", config.max_spheres,
                 "Collision spheres of a create's scene (intestine.length / intestine.radius)")
      ->check(CLI::Range(2, 1000000))
      ->capture_default_str();
  app.add_option("--max-contact-margin", config.max_margin_radii,
                 "contacts.margin of a create's scene (tube radii)")
      ->check(CLI::Range(0.0, 1000.0))
      ->capture_default_str();
  app.add_option("--max-tools", config.max_tools,
                 "Tools of a create's scene (one force message each per step)")
      ->check(CLI::Range(0, 1000))
      ->capture_default_str();
  app.add_option("--max-mesh-triangles", config.max_mesh_triangles,
                 "Triangles of a mesh obstacle of a create's scene")
      ->check(CLI::Range(1, 100000000))
      ->capture_default_str();
  app.add_option(
         "--max-build-time", config.max_build_s,
         "Wall time a create's scene build may take before it is abandoned (s); 0 = no limit")
      ->check(CLI::Range(0.0, 3600.0))
      ->capture_default_str();
  app.add_option("--min-record-free", config.min_record_free_bytes,
                 "Creates are refused while the record directory's disk has less free (bytes)")
      ->check(CLI::Range(int64_t{0}, int64_t{1} << 62))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  if (config.skeleton_rate_hz == 0.0) config.skeleton_rate_hz = -1.0;  // "none" for sessions
  if (config.frame_rate_hz == 0.0) config.frame_rate_hz = -1.0;
  config.adaptive_frames = adaptive_frames == "on";
  try {
    viscera::render::ParseFrameSize(max_frame_size, &config.max_frame_width,
                                    &config.max_frame_height);
    viscera::ThrowUnless(std::max(config.max_frame_width, config.max_frame_height) <= 4096 &&
                             std::min(config.max_frame_width, config.max_frame_height) >=
                                 viscera::server::kMinFrameSide,
                         "--max-frame-size: each side must be within ",
                         viscera::server::kMinFrameSide, "..4096 pixels");
    viscera::render::ParseFrameSize(frame_size, &config.frame_width, &config.frame_height);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "viscerad: %s\n", e.what());
    return 2;
  }
  // the defaults must be what a create could ask for
  if (const std::string problem = viscera::server::FrameSettingsProblem(
          config.frame_width, config.frame_height, config.frame_rate_hz, config.jpeg_quality,
          config.skin, config);
      !problem.empty()) {
    std::fprintf(stderr, "viscerad: default frames (--frame-size, --frame-rate): %s\n",
                 problem.c_str());
    return 2;
  }
  if (config.rate_hz > config.max_rate_hz) {
    std::fprintf(stderr, "viscerad: --rate %g is above --max-rate %g\n", config.rate_hz,
                 config.max_rate_hz);
    return 2;
  }
  if (!config.log_dir.empty()) {
    // README's `--log-dir out/records` on a fresh checkout: made here, not refused per create
    std::error_code error;
    std::filesystem::create_directories(config.log_dir, error);
    if (error || !std::filesystem::is_directory(config.log_dir)) {
      std::fprintf(stderr, "viscerad: --log-dir %s: cannot make the directory (%s)\n",
                   config.log_dir.c_str(), error ? error.message().c_str() : "not a directory");
      return 2;
    }
  }
  config.lcm_url = viscera::bus::ResolveUrl(lcm_url);
  if (viscera::bus::UrlLeavesHost(config.lcm_url) && config.key_file.empty() && !config.insecure) {
    std::fprintf(
        stderr,
        "viscerad: %s reaches other hosts, and without --key-file anyone on the network could "
        "read every session token and drive any session. Give --key-file (viscera keygen FILE), "
        "use ttl=0, or accept the risk with --insecure (docs/security.md)\n",
        config.lcm_url.c_str());
    return 2;
  }

  try {
    return Run(config, capacity_scene);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "viscerad: %s\n", e.what());
    return 1;
  }
}
