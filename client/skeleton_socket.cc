#include "client/skeleton_socket.h"

#include <poll.h>

#include <boost/asio/buffer.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core/error.hpp>
#include <boost/beast/http/empty_body.hpp>
#include <boost/beast/http/parser.hpp>
#include <boost/beast/websocket/rfc6455.hpp>
#include <boost/beast/websocket/stream.hpp>

#include "common/check.h"

namespace viscera::client {
namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;

// Parses a complete request head; false when Beast finds it malformed.
bool ParseHead(const std::string& head, http::request_parser<http::empty_body>* parser) {
  beast::error_code error;
  parser->eager(true);
  parser->put(asio::buffer(head.data(), head.size()), error);
  return !error && parser->is_header_done();
}

}  // namespace

bool IsWebSocketUpgrade(const std::string& head) {
  http::request_parser<http::empty_body> parser;
  return ParseHead(head, &parser) && websocket::is_upgrade(parser.get());
}

bool PeerSpokeOrLeft(int fd) {
  pollfd state{fd, POLLIN | POLLRDHUP, 0};
  return poll(&state, 1, 0) > 0 && state.revents != 0;
}

std::string ServeWebSocket(int fd, const std::string& head,
                           const std::function<std::optional<std::string>()>& next) {
  http::request_parser<http::empty_body> parser;
  if (!ParseHead(head, &parser) || !websocket::is_upgrade(parser.get()))
    return "not a WebSocket upgrade";
  asio::io_context io;
  websocket::stream<asio::ip::tcp::socket> socket(io);
  beast::error_code error;
  socket.next_layer().assign(asio::ip::tcp::v4(), fd, error);
  if (error) return Cat("cannot adopt the socket: ", error.message());
  std::string problem;
  socket.set_option(websocket::stream_base::decorator([](websocket::response_type& response) {
    response.set(http::field::server, "viscera view");
  }));
  socket.accept(parser.release(), error);
  if (error) {
    problem = Cat("handshake: ", error.message());
  } else {
    socket.text(true);
    while (std::optional<std::string> message = next()) {
      if (PeerSpokeOrLeft(fd)) break;
      socket.write(asio::buffer(*message), error);
      if (error) {
        problem = Cat("send: ", error.message());
        break;
      }
    }
  }
  socket.next_layer().release(error);  // the fd goes back to the caller, open
  return problem;
}

}  // namespace viscera::client
