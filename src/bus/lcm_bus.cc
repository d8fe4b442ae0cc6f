#include "bus/lcm_bus.h"

#include <algorithm>
#include <cstdlib>
#include <exception>
#include <utility>

namespace viscera::bus {

std::string ResolveUrl(const std::string& flag) {
  if (!flag.empty()) return flag;
  const char* env = std::getenv("LCM_DEFAULT_URL");
  if (env != nullptr && env[0] != '\0') return env;
  return kDefaultUrl;
}

bool UrlLeavesHost(const std::string& url) {
  if (url.rfind("memq://", 0) == 0 || url.rfind("file://", 0) == 0) return false;
  if (url.rfind("udpm://", 0) != 0) return true;
  const size_t query = url.find('?');
  if (query == std::string::npos) return false;
  // every ttl, not the first: LCM takes the last of repeated options ("?ttl=0&ttl=1" sends
  // with TTL 1), so any one that is not 0 may leave the host
  bool leaves = false;
  for (size_t start = query + 1; start < url.size();) {
    const size_t end = std::min(url.find('&', start), url.size());
    const std::string option = url.substr(start, end - start);
    if (option.rfind("ttl=", 0) == 0) {
      const std::string value = option.substr(4);
      // anything but a plain 0 may leave the host (LCM reads it with atoi)
      leaves = leaves || value.empty() || value.find_first_not_of('0') != std::string::npos;
    }
    start = end + 1;
  }
  return leaves;
}

LcmBus::LcmBus(const std::string& url) : url_(url), lcm_(url) {
  ThrowUnless(lcm_.good(), "LCM could not open URL '", url,
              "' (for udpm://, does this network namespace have a multicast route?)");
}

// lcm_ is declared after subscriptions_, so LCM (and its pointers into our
// Subscription records) goes first; the records outlive every use.
LcmBus::~LcmBus() = default;

bool LcmBus::PublishRaw(const std::string& channel, const void* data, int size) {
  if (size < 0 || lcm_.publish(channel, data, static_cast<unsigned int>(size)) != 0) {
    RecordError(Cat("LCM publish on ", channel, " (", size, " bytes) failed"));
    ++publish_failures_;
    return false;
  }
  ++published_;
  return true;
}

bool LcmBus::PublishEncoded(const std::string& channel, const char* type_name) {
  // caller holds publish_mutex_
  if (auth_ != nullptr && !auth_->Sign(&encode_buffer_)) {
    RecordError(Cat("cannot sign ", type_name, " for ", channel,
                    ": not a viscera message with an empty mac"));
    ++publish_failures_;
    return false;
  }
  return PublishRaw(channel, encode_buffer_.data(), static_cast<int>(encode_buffer_.size()));
}

SubscriptionId LcmBus::AddSubscription(
    const std::string& channel,
    std::function<Outcome(const lcm::ReceiveBuffer&, const std::string&)> dispatch) {
  VISCERA_DEMAND(!dispatching_);
  auto subscription = std::make_unique<Subscription>();
  subscription->bus = this;
  subscription->id = next_id_++;
  subscription->channel = channel;
  subscription->dispatch = std::move(dispatch);
  // LCM keeps the raw pointer as its context; unique_ptr keeps the address stable.
  subscription->lcm_subscription =
      lcm_.subscribeFunction(channel, &LcmBus::Trampoline, subscription.get());
  ThrowUnless(subscription->lcm_subscription != nullptr, "LCM could not subscribe to '", channel,
              "' on ", url_);
  const SubscriptionId id = subscription->id;
  subscriptions_.emplace(id, std::move(subscription));
  return id;
}

void LcmBus::Unsubscribe(SubscriptionId id) {
  if (dispatching_) {
    pending_unsubscribe_.push_back(id);
    return;
  }
  const auto it = subscriptions_.find(id);
  if (it == subscriptions_.end()) return;
  lcm_.unsubscribe(it->second->lcm_subscription);
  subscriptions_.erase(it);
}

void LcmBus::Trampoline(const lcm::ReceiveBuffer* rbuf, const std::string& channel,
                        Subscription* subscription) {
  LcmBus& bus = *subscription->bus;
  ++bus.received_;
  // Nothing may escape into LCM's C code: catch everything, count it, keep going.
  const auto* data = static_cast<const uint8_t*>(rbuf->data);
  const int size = static_cast<int>(rbuf->data_size);
  try {
    if (bus.max_message_size_ > 0 &&
        rbuf->data_size > static_cast<uint32_t>(bus.max_message_size_)) {
      ++bus.oversize_;
      bus.RecordError(Cat("message of ", rbuf->data_size, " bytes on ", channel, " (limit ",
                          bus.max_message_size_, "): dropped"));
      if (bus.on_drop_) bus.on_drop_(channel, DropReason::kOversize, data, size);
      return;
    }
    if (bus.auth_ != nullptr &&
        !bus.auth_->Verify(static_cast<const uint8_t*>(rbuf->data),
                           static_cast<int>(rbuf->data_size), &bus.verify_scratch_)) {
      ++bus.auth_failures_;
      bus.RecordError(Cat("message without a valid MAC on ", channel, " (", rbuf->data_size,
                          " bytes): dropped"));
      if (bus.on_drop_) bus.on_drop_(channel, DropReason::kBadMac, data, size);
      return;
    }
    if (subscription->dispatch(*rbuf, channel) == Outcome::kDecodeFailed) {
      ++bus.decode_failures_;
      bus.RecordError(
          Cat("malformed message on ", channel, " (", rbuf->data_size, " bytes): dropped"));
      if (bus.on_drop_) bus.on_drop_(channel, DropReason::kMalformed, data, size);
      return;
    }
    ++bus.handled_;
  } catch (const std::exception& e) {
    ++bus.handler_failures_;
    bus.RecordError(Cat("handler for ", channel, " threw: ", e.what()));
  } catch (...) {
    ++bus.handler_failures_;
    bus.RecordError(Cat("handler for ", channel, " threw a non-std exception"));
  }
}

int LcmBus::HandleOne(int timeout_ms) {
  dispatching_ = true;
  const int status = lcm_.handleTimeout(timeout_ms);
  dispatching_ = false;
  // Unsubscriptions requested by handlers run now that LCM is out of its dispatch.
  std::vector<SubscriptionId> pending;
  pending.swap(pending_unsubscribe_);
  for (const SubscriptionId id : pending) Unsubscribe(id);
  if (status < 0) RecordError(Cat("LCM handleTimeout failed on ", url_));
  return status > 0 ? 1 : 0;
}

int LcmBus::Pump(int timeout_ms) {
  ThrowUnless(timeout_ms >= 0, "LcmBus::Pump: timeout_ms must be >= 0, got ", timeout_ms);
  CheckOwnerThread();
  const int first = HandleOne(timeout_ms);
  if (first == 0) return 0;
  return first + Drain();
}

int LcmBus::Drain(int max_messages) {
  CheckOwnerThread();
  int handled = 0;
  while (handled < max_messages && HandleOne(0) > 0) ++handled;
  return handled;
}

void LcmBus::CheckOwnerThread() {
  // LCM 1.3.1 allows a single thread in handle*; the first pumping thread owns the bus.
  if (owner_ == std::thread::id{}) owner_ = std::this_thread::get_id();
  VISCERA_DEMAND(owner_ == std::this_thread::get_id());
}

void LcmBus::RecordError(std::string message) {
  std::lock_guard<std::mutex> lock(error_mutex_);
  last_error_ = std::move(message);
}

BusStats LcmBus::stats() const {
  BusStats s;
  s.received = received_.load();
  s.handled = handled_.load();
  s.decode_failures = decode_failures_.load();
  s.handler_failures = handler_failures_.load();
  s.published = published_.load();
  s.publish_failures = publish_failures_.load();
  s.auth_failures = auth_failures_.load();
  s.oversize = oversize_.load();
  return s;
}

std::string LcmBus::last_error() const {
  std::lock_guard<std::mutex> lock(error_mutex_);
  return last_error_;
}

}  // namespace viscera::bus
