#pragma once
/// The WebSocket of the viewer page's skeleton stream (`/skeleton`), on a connection the
/// MJPEG server accepted and routed. The WebSocket protocol (handshake, framing) is Boost.Beast's;
/// this file only hands it the request head already read and the messages to send.
#include <functional>
#include <optional>
#include <string>

namespace viscera::client {

/// True when `head` (a parsed request's raw head) asks to upgrade to a WebSocket.
bool IsWebSocketUpgrade(const std::string& head);

/// Completes the WebSocket handshake of the request `head` on the connected socket `fd`, then
/// sends every text message `next` returns until it returns nullopt, a send fails, or the peer
/// speaks (the page never sends: anything it sends, a close frame included, ends the stream).
/// `fd` stays open and the caller's. @returns "" on a clean end, else what failed.
std::string ServeWebSocket(int fd, const std::string& head,
                           const std::function<std::optional<std::string>()>& next);

/// True when the peer of `fd` sent bytes or closed its side (a page's WebSocket never sends).
bool PeerSpokeOrLeft(int fd);

}  // namespace viscera::client
