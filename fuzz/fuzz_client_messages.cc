// The client's receive paths on any datagram: the bus decode, then what the client checks and
// shows. Heartbeats (ServerDirectory and its table and JSON) are fuzzed; frames and replies
// (FrameReceiver; statuses printed as JSON and tables) are wired but off until their array
// counts are checked before decoding: LCM 1.3.1's generated decode sizes an array (frame bytes,
// a reply's statuses, a status's tool names) before it checks the bytes are there, so one
// datagram can make a client allocate gigabytes (docs/reliability.md, open issue).
// VISCERA_FUZZ_ALL_CHANNELS=1 turns them on to reproduce it.
#include <cstdint>
#include <cstdlib>
#include <string>

#include <viscera_proto/heartbeat_t.hpp>
#include <viscera_proto/session_reply_t.hpp>

#include "bus/channels.h"
#include "bus/header.h"
#include "bus/lcm_bus.h"
#include "client/frame_receiver.h"
#include "client/server_directory.h"
#include "client/status_format.h"

namespace {

struct Client {
  Client() : bus("memq://"), frames(&bus, 1, [](const viscera_proto::jpeg_frame_t& f) {
    if (f.size != static_cast<int32_t>(f.data.size())) std::abort();  // the receiver checked it
  }) {
    bus.Subscribe<viscera_proto::heartbeat_t>(viscera::bus::kHeartbeatChannel,
                                              [this](const viscera_proto::heartbeat_t& hb, int64_t) {
                                                directory.Observe(hb);
                                                (void)viscera::client::ServersToTable(directory.Servers());
                                                (void)viscera::client::ServersToJson(directory.Servers()).dump();
                                              });
    bus.Subscribe<viscera_proto::session_reply_t>(
        viscera::bus::kReplyChannel, [](const viscera_proto::session_reply_t& reply, int64_t) {
          if (!viscera::bus::HeaderProblem(reply.header).empty()) return;
          for (const auto& s : reply.sessions) {
            (void)viscera::client::StatusToJson(s).dump();
            (void)viscera::client::StatusTable({s});
          }
        });
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
                                         viscera::bus::kReplyChannel};
  static const int open_channels = std::getenv("VISCERA_FUZZ_ALL_CHANNELS") != nullptr ? 3 : 1;
  client.bus.PublishRaw(channels[data[0] % open_channels], data + 1, static_cast<int>(size - 1));
  client.bus.Drain();
  return 0;
}
