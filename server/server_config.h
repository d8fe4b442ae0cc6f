#pragma once
/// What viscerad is told on its command line.
#include <chrono>
#include <string>

namespace viscera::server {

struct ServerConfig {
  std::string lcm_url;    ///< LCM URL, already resolved (bus::ResolveUrl)
  std::string server_id;  ///< name announced in heartbeats
  int max_sessions = 4;   ///< sessions accepted at most
  std::chrono::milliseconds heartbeat_period{1000};
  std::string scene_dir = "scenes";  ///< where create finds NAME.toml
  std::string log_dir;               ///< session records go here ("" = none)
  double rate_hz = 0.0;            ///< mechanics rate when a create asks for none; 0 = the scene's
  double max_rate_hz = 1000.0;     ///< highest mechanics rate a create may ask for (Hz)
  double skeleton_rate_hz = 30.0;  ///< default skeleton_state_t rate (Hz); <= 0: none
  double status_rate_hz = 4.0;     ///< session_status_t rate (Hz)
  // Frame streams, when a create asks for no particular value (docs/frame-streams.md says why).
  double frame_rate_hz = 25.0;      ///< jpeg_frame_t per second; <= 0: no frames by default
  double max_frame_rate_hz = 60.0;  ///< highest frame rate a create may ask for (Hz)
  /// Frames are drawn only while a viewer renewed the frame lease (kWatchFrames) within this
  /// long (s); 0: always, watched or not.
  double frame_lease_s = 5.0;
  /// Lower a stream's frame rate, then its size, while frames or mechanics steps run late, and
  /// climb back when calm (FrameGovernor); off: the rate and size asked for, always.
  bool adaptive_frames = true;
  std::string skin = "parametric";  ///< skin drawn
  /// Vertices per ring of the parametric and convolution skins (hybrid: both). 16, not the
  /// convolution skin's 32: 640x480 convolution frames at 60 fps on one core
  /// (docs/benchmarks.md, Rendering).
  int skin_sides = 16;
  int frame_width = 640;  ///< pixels
  int frame_height = 480;
  int max_frame_width = 1920;  ///< largest frame a create may ask for (pixels)
  int max_frame_height = 1080;
  int jpeg_quality = 80;      ///< 1..100
  int realtime_priority = 0;  ///< > 0: SCHED_FIFO for mechanics and I/O threads (1..99)
  double spin_us = -1.0;  ///< mechanics loops spin this long before each deadline (us; < 0 auto)
  std::string key_file;   ///< pre-shared key: every message must carry its MAC ("" = none)
  bool insecure = false;  ///< start off loopback without a key (docs/security.md)

  // Replay protection and leases (docs/security.md).
  double max_clock_skew_s = 10.0;  ///< |utime - server clock| a session-changing message may have
  double session_lease_s = 60.0;   ///< a session without client traffic this long ends
  // Limits (docs/security.md, "Limits"); reported in every heartbeat.
  int max_message_bytes = 256 * 1024;  ///< larger datagrams are dropped before decoding
  int max_creates_per_minute = 30;     ///< all key holders (or all clients) together
  double max_frame_mpix_per_s = 40.0;  ///< all frame streams together (width x height x rate)
  int max_control_points = 1000;       ///< of a create's scene
  int max_obstacles = 32;
  int max_mesh_resolution = 100;      ///< grid cells along a mesh's longest side
  int64_t max_mesh_bytes = 16 << 20;  ///< size of a mesh file a scene names
  int max_substeps = 64;
  double max_settle_s = 10.0;
  double max_session_load = 1.0;             ///< estimated mechanics load, fraction of one core
  int max_spheres = 2000;                    ///< collision spheres (intestine.length / radius)
  double max_margin_radii = 4.0;             ///< contacts.margin, in tube radii
  int max_tools = 8;                         ///< [[tool]] tables (one force message each per step)
  int max_mesh_triangles = 200000;           ///< of one mesh obstacle
  double max_build_s = 30.0;                 ///< a create's scene build (wall time, s); 0 = none
  int64_t min_record_free_bytes = 64 << 20;  ///< creates refused below this free space for records
};

}  // namespace viscera::server
