// The viewer's /skeleton WebSocket (MjpegServer) over a real socket on 127.0.0.1, with Beast's
// client: the latest skeleton message first, then each new one; foreign origins refused.
#include <sys/socket.h>

#include <string>

#include <gtest/gtest.h>
#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core/buffers_to_string.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/websocket/stream.hpp>

#include "client/mjpeg_server.h"
#include "tests/common/eventually.h"

namespace viscera::client {
namespace {

namespace asio = boost::asio;
namespace websocket = boost::beast::websocket;

// A WebSocket client of /skeleton (Beast); reads give up after 10 s.
struct SkeletonClient {
  asio::io_context io;
  websocket::stream<asio::ip::tcp::socket> ws{io};
  explicit SkeletonClient(int port, const std::string& origin = "") {
    ws.next_layer().connect({asio::ip::make_address("127.0.0.1"), static_cast<uint16_t>(port)});
    const timeval timeout{10, 0};
    setsockopt(ws.next_layer().native_handle(), SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof(timeout));
    if (!origin.empty()) {
      ws.set_option(websocket::stream_base::decorator([origin](websocket::request_type& request) {
        request.set(boost::beast::http::field::origin, origin);
      }));
    }
  }
  std::string Read() {
    boost::beast::flat_buffer buffer;
    boost::beast::error_code error;
    ws.read(buffer, error);
    return error ? "(" + error.message() + ")" : boost::beast::buffers_to_string(buffer.data());
  }
};

TEST(MjpegServer, SkeletonSocketSendsTheLatestMessageThenEachNewOne) {
  MjpegServer server("127.0.0.1", 0, "t", /*expect_scene=*/true);
  server.PostSkeleton("{\"step\":1}");
  server.PostSkeleton("{\"step\":2}");  // the latest wins
  SkeletonClient page(server.port());
  page.ws.handshake("127.0.0.1", "/skeleton");
  EXPECT_EQ(page.Read(), "{\"step\":2}");
  server.PostSkeleton("{\"step\":3}");
  EXPECT_EQ(page.Read(), "{\"step\":3}");
  EXPECT_EQ(server.stats().active_sockets, 1);
  EXPECT_EQ(server.stats().skeletons_posted, 3);
  boost::beast::error_code ignored;
  page.ws.next_layer().shutdown(asio::ip::tcp::socket::shutdown_both, ignored);
  EXPECT_TRUE(testing::Eventually([&] { return server.stats().active_sockets == 0; }));
}

// Cross-site WebSocket hijacking: a page of another site may open a WebSocket to any address.
TEST(MjpegServer, SkeletonSocketRefusesForeignOrigins) {
  MjpegServer server("127.0.0.1", 0, "t", /*expect_scene=*/true);
  server.PostSkeleton("{}");
  SkeletonClient foreign(server.port(), "http://evil.example");
  boost::beast::error_code error;
  foreign.ws.handshake("127.0.0.1", "/skeleton", error);
  EXPECT_TRUE(error);  // 403
  SkeletonClient own(server.port(), "http://127.0.0.1:" + std::to_string(server.port()));
  own.ws.handshake("127.0.0.1", "/skeleton");
  EXPECT_EQ(own.Read(), "{}");
}

}  // namespace
}  // namespace viscera::client
