// The client's receive paths on any datagram: the bus decode, then what the client checks and
// shows: frames (FrameReceiver: header, session, sequence, sizes), heartbeats
// (ServerDirectory and its table), replies and the statuses inside them (JSON and table
// output). The first input byte picks the channel.
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
  static const std::string channels[] = {"VISCERA_FRAME_1", viscera::bus::kHeartbeatChannel,
                                         viscera::bus::kReplyChannel};
  client.bus.PublishRaw(channels[data[0] % 3], data + 1, static_cast<int>(size - 1));
  client.bus.Drain();
  return 0;
}
