// The client's receive paths on any datagram: the bus decode (every array count checked
// first, bus/wire_counts.h), then what the client checks and shows: heartbeats (ServerDirectory,
// its table and JSON), frames (FrameReceiver), replies and statuses (printed as JSON and
// tables) and skeletons (the centre line `viscera drive` aims at). The first byte picks the
// channel.
#include <cstdint>
#include <cstdlib>
#include <iterator>
#include <string>

#include <viscera_proto/heartbeat_t.hpp>
#include <viscera_proto/session_reply_t.hpp>
#include <viscera_proto/session_status_t.hpp>
#include <viscera_proto/skeleton_state_t.hpp>

#include "bus/channels.h"
#include "bus/header.h"
#include "bus/lcm_bus.h"
#include "client/frame_receiver.h"
#include "client/server_directory.h"
#include "client/status_format.h"

namespace {

struct Client {
  Client()
      : bus("memq://"), frames(&bus, 1, [](const viscera_proto::jpeg_frame_t& f) {
          if (f.size != static_cast<int32_t>(f.data.size()))
            std::abort();  // the receiver checked it
        }) {
    bus.Subscribe<viscera_proto::heartbeat_t>(
        viscera::bus::kHeartbeatChannel, [this](const viscera_proto::heartbeat_t& hb, int64_t) {
          directory.Observe(hb);
          (void)viscera::client::ServersToTable(directory.Servers());
          (void)viscera::client::ServersToJson(directory.Servers()).dump();
        });
    bus.Subscribe<viscera_proto::session_reply_t>(
        viscera::bus::kReplyChannel, [](const viscera_proto::session_reply_t& reply, int64_t) {
          if (!viscera::bus::HeaderProblem(reply.header).empty()) return;
          for (const auto& s : reply.sessions) Show(s);
        });
    bus.Subscribe<viscera_proto::session_status_t>(
        "VISCERA_STATUS_1", [](const viscera_proto::session_status_t& s, int64_t) { Show(s); });
    bus.Subscribe<viscera_proto::skeleton_state_t>(
        "VISCERA_SKELETON_1", [](const viscera_proto::skeleton_state_t& s, int64_t) {
          if (s.num_points != static_cast<int32_t>(s.points.size()) ||
              s.num_spheres != static_cast<int32_t>(s.spheres.size())) {
            std::abort();  // the decode kept the counts and the arrays together
          }
          double sum = s.sphere_radius;
          for (const auto& c : s.spheres) sum += c[0] + c[1] + c[2];
          (void)sum;
        });
  }
  static void Show(const viscera_proto::session_status_t& s) {
    if (s.num_tools != static_cast<int32_t>(s.tool_names.size())) std::abort();
    (void)viscera::client::StatusToJson(s).dump();
    (void)viscera::client::StatusTable({s});
  }
  viscera::bus::LcmBus bus;
  viscera::client::FrameReceiver frames;
  viscera::client::ServerDirectory directory;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static Client client;
  if (size < 1) return 0;
  static const std::string channels[] = {viscera::bus::kHeartbeatChannel, "VISCERA_FRAME_1",
                                         viscera::bus::kReplyChannel, "VISCERA_STATUS_1",
                                         "VISCERA_SKELETON_1"};
  client.bus.PublishRaw(channels[data[0] % std::size(channels)], data + 1,
                        static_cast<int>(size - 1));
  client.bus.Drain();
  return 0;
}
