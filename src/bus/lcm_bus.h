#pragma once
/// LcmBus: a small typed wrapper over lcm::LCM (Debian's LCM 1.3.1).
///
/// Threading: exactly one thread, the owner, pumps the bus (Pump / Drain) and so runs
/// every handler; Subscribe and Unsubscribe belong to that thread too (or to the
/// constructing thread before pumping starts). Publish may be called from any thread. LCM 1.3.1 has
/// no lambda subscribe, and an exception thrown through its C dispatch code is undefined behaviour,
/// so handlers are reached through a static trampoline that catches and counts everything.
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "bus/message_auth.h"
#include "common/check.h"

namespace viscera::bus {

/// LCM's usual multicast group and port, with ttl=0 so no datagram leaves this machine.
inline constexpr char kDefaultUrl[] = "udpm://239.255.76.67:7667?ttl=0";

/// The URL to use: `flag` when non-empty, else $LCM_DEFAULT_URL when set and non-empty,
/// else kDefaultUrl.
std::string ResolveUrl(const std::string& flag);

/// True when traffic on `url` can reach other hosts: udpm:// with a ttl above 0, or any
/// provider other than udpm://, memq:// and file:// (docs/security.md). A ttl of 0 (LCM's
/// default when absent) keeps multicast on this machine.
bool UrlLeavesHost(const std::string& url);

/// Counters of one bus since construction (a consistent-enough snapshot: each counter
/// is read atomically, not all of them together).
struct BusStats {
  int64_t received = 0;          ///< datagrams delivered to a subscription
  int64_t handled = 0;           ///< decoded and handled without an exception
  int64_t decode_failures = 0;   ///< malformed, truncated or of another type: dropped
  int64_t handler_failures = 0;  ///< a handler threw: caught, counted, bus lives on
  int64_t published = 0;         ///< messages handed to LCM successfully
  int64_t publish_failures = 0;  ///< encode or LCM publish failed
  int64_t auth_failures = 0;     ///< with a key: missing or wrong MAC, dropped undecoded
  int64_t oversize = 0;          ///< above the size limit, dropped undecoded
};

/// Why the bus dropped a datagram before any handler saw it.
enum class DropReason { kMalformed, kBadMac, kOversize };

/// What a handler learns about a datagram besides its content.
struct MessageInfo {
  const std::string* channel = nullptr;  ///< the channel it came on
  int64_t recv_utime = 0;                ///< LCM's receive time (µs, wall clock)
  int size = 0;                          ///< bytes on the wire
};

/// Identifies one subscription for Unsubscribe.
using SubscriptionId = int64_t;

class LcmBus {
 public:
  /// Handler of a decoded message; `recv_utime` is LCM's receive time (µs, wall clock).
  template <typename Msg>
  using Handler = std::function<void(const Msg& msg, int64_t recv_utime)>;
  /// Handler that also learns the channel (for subscriptions to a channel regex).
  template <typename Msg>
  using InfoHandler = std::function<void(const Msg& msg, const MessageInfo& info)>;
  /// Told about every datagram dropped before its handler (owner thread), with its bytes
  /// (valid during the call only).
  using DropHandler = std::function<void(const std::string& channel, DropReason reason,
                                         const uint8_t* data, int size)>;

  /// Opens LCM on `url` (udpm://, memq://, ...).
  /// @throws InputError when LCM cannot open the URL.
  explicit LcmBus(const std::string& url = kDefaultUrl);
  ~LcmBus();
  LcmBus(const LcmBus&) = delete;
  LcmBus& operator=(const LcmBus&) = delete;

  /// Encodes `msg` (an lcm-gen type) and publishes it on `channel`. Thread-safe.
  /// Failures are counted (and kept in last_error()), never thrown: a daemon must not
  /// die because one datagram could not be sent.
  /// @pre every array's count field matches the array's size (LCM encodes the count).
  /// @return true when LCM accepted the message.
  template <typename Msg>
  bool Publish(const std::string& channel, const Msg& msg);

  /// Publishes raw bytes on `channel` (for tests and forwarding), unsigned. Thread-safe.
  bool PublishRaw(const std::string& channel, const void* data, int size);

  /// With a pre-shared key, Publish signs every message and every datagram received must
  /// carry a valid MAC (others are dropped undecoded and counted in auth_failures).
  /// Call before publishing or pumping. nullptr turns authentication off.
  void SetAuth(std::shared_ptr<const MessageAuth> auth) { auth_ = std::move(auth); }
  bool authenticated() const { return auth_ != nullptr; }

  /// Datagrams larger than `bytes` (> 0) are dropped before the MAC check or decoding, and
  /// counted in oversize. Call before pumping; default: no limit.
  void SetMaxMessageSize(int bytes) { max_message_size_ = bytes; }

  /// Calls `on_drop` for every datagram dropped before reaching its handler (malformed or
  /// failing the MAC), so owners can count them per channel. Owner thread only.
  void SetDropHandler(DropHandler on_drop) { on_drop_ = std::move(on_drop); }

  /// Calls `handler` for every message on `channel` that decodes as a Msg, exactly
  /// (a datagram with trailing bytes is malformed). Owner thread only.
  /// @pre not called from inside a handler (LCM 1.3.1 would change its handler list
  ///      while iterating over it).
  /// @throws InputError when handler is empty or LCM refuses the subscription.
  template <typename Msg>
  SubscriptionId Subscribe(const std::string& channel, Handler<Msg> handler);

  /// Same, with the channel and size passed along; `channel` may be an LCM regex
  /// ("VISCERA_POSE_.*").
  template <typename Msg>
  SubscriptionId SubscribeWithInfo(const std::string& channel, InfoHandler<Msg> handler);

  /// Stops delivering to `id`. Safe inside a handler: LCM 1.3.1 must not unsubscribe
  /// while it dispatches, so the call is deferred until the dispatch returns.
  /// Unknown ids are ignored. Owner thread only.
  void Unsubscribe(SubscriptionId id);

  /// Waits up to `timeout_ms` (>= 0) for a message, then drains what is queued.
  /// @return messages handled. Owner thread only.
  int Pump(int timeout_ms);

  /// Handles every message already waiting, at most `max_messages` (so a flood cannot
  /// trap the owner thread). LCM 1.3.1's handleTimeout handles at most one message per
  /// call, hence the loop. @return messages handled. Owner thread only.
  int Drain(int max_messages = 10000);

  BusStats stats() const;
  /// The last decode, handler or publish failure, for status reports ("" if none).
  std::string last_error() const;
  const std::string& url() const { return url_; }

 private:
  enum class Outcome { kHandled, kDecodeFailed };

  struct Subscription {
    LcmBus* bus = nullptr;
    SubscriptionId id = 0;
    std::string channel;
    // Decodes into a fresh message (see SubscribeWithInfo) and calls the user's handler.
    std::function<Outcome(const lcm::ReceiveBuffer&, const std::string&)> dispatch;
    lcm::Subscription* lcm_subscription = nullptr;
  };

  // The one entry point LCM's C code calls: never lets an exception out.
  static void Trampoline(const lcm::ReceiveBuffer* rbuf, const std::string& channel,
                         Subscription* subscription);
  SubscriptionId AddSubscription(
      const std::string& channel,
      std::function<Outcome(const lcm::ReceiveBuffer&, const std::string&)> dispatch);
  bool PublishEncoded(const std::string& channel, const char* type_name);
  int HandleOne(int timeout_ms);
  void CheckOwnerThread();
  void RecordError(std::string message);

  std::string url_;
  // Declared before lcm_ so that they are destroyed after it.
  std::map<SubscriptionId, std::unique_ptr<Subscription>> subscriptions_;
  lcm::LCM lcm_;
  std::vector<SubscriptionId> pending_unsubscribe_;
  SubscriptionId next_id_ = 1;
  bool dispatching_ = false;
  std::thread::id owner_;  // set by the first Pump/Drain

  std::shared_ptr<const MessageAuth> auth_;
  int max_message_size_ = 0;  // 0: no limit
  DropHandler on_drop_;
  std::vector<uint8_t> verify_scratch_;  // owner thread

  std::mutex publish_mutex_;  // guards encode_buffer_
  std::vector<uint8_t> encode_buffer_;

  mutable std::mutex error_mutex_;
  std::string last_error_;

  std::atomic<int64_t> received_{0};
  std::atomic<int64_t> handled_{0};
  std::atomic<int64_t> decode_failures_{0};
  std::atomic<int64_t> handler_failures_{0};
  std::atomic<int64_t> published_{0};
  std::atomic<int64_t> publish_failures_{0};
  std::atomic<int64_t> auth_failures_{0};
  std::atomic<int64_t> oversize_{0};
};

// ---------------------------------------------------------------- template bodies

template <typename Msg>
bool LcmBus::Publish(const std::string& channel, const Msg& msg) {
  std::lock_guard<std::mutex> lock(publish_mutex_);
  const int size = msg.getEncodedSize();
  if (size < 0) {
    RecordError(Cat("encode of ", Msg::getTypeName(), " for ", channel, " failed"));
    ++publish_failures_;
    return false;
  }
  encode_buffer_.resize(static_cast<size_t>(size));
  if (msg.encode(encode_buffer_.data(), 0, size) != size) {
    RecordError(Cat("encode of ", Msg::getTypeName(), " for ", channel, " failed"));
    ++publish_failures_;
    return false;
  }
  return PublishEncoded(channel, Msg::getTypeName());
}

template <typename Msg>
SubscriptionId LcmBus::Subscribe(const std::string& channel, Handler<Msg> handler) {
  ThrowUnless(static_cast<bool>(handler), "LcmBus::Subscribe(", channel, "): empty handler");
  return SubscribeWithInfo<Msg>(
      channel, [handler = std::move(handler)](const Msg& msg, const MessageInfo& info) {
        handler(msg, info.recv_utime);
      });
}

template <typename Msg>
SubscriptionId LcmBus::SubscribeWithInfo(const std::string& channel, InfoHandler<Msg> handler) {
  ThrowUnless(static_cast<bool>(handler), "LcmBus::Subscribe(", channel, "): empty handler");
  auto dispatch = [handler = std::move(handler)](const lcm::ReceiveBuffer& rbuf,
                                                 const std::string& on) -> Outcome {
    const int size = static_cast<int>(rbuf.data_size);
    // A fresh message each time: lcm-gen 1.3.1's decode leaves an array whose count is 0
    // untouched, so a reused message would keep the previous datagram's bytes (a token!).
    if (!HeaderCountsFit(static_cast<const uint8_t*>(rbuf.data), size))
      return Outcome::kDecodeFailed;
    Msg msg;
    if (msg.decode(rbuf.data, 0, size) != size) return Outcome::kDecodeFailed;
    handler(msg, MessageInfo{&on, rbuf.recv_utime, size});
    return Outcome::kHandled;
  };
  return AddSubscription(channel, std::move(dispatch));
}

}  // namespace viscera::bus
