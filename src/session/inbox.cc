#include "session/inbox.h"

#include "common/check.h"

namespace viscera::session {

Inbox::Inbox(int num_tools) {
  VISCERA_DEMAND(num_tools >= 0);
  poses_.resize(static_cast<size_t>(num_tools));
  for (PoseInput& p : poses_) p.target.active = false;
  commands_.reserve(kMaxCommands);
}

bool Inbox::PostPose(int tool, const PoseInput& pose) {
  VISCERA_DEMAND(tool >= 0 && tool < num_tools());
  std::lock_guard<std::mutex> lock(mutex_);
  PoseInput& slot = poses_[static_cast<size_t>(tool)];
  // a reordered or replayed datagram must not move the tool back in time; a new client
  // (its sequence starts again at 0) sends newer send times
  if (slot.seq >= 0 && pose.seq <= slot.seq && pose.client_utime <= slot.client_utime) {
    return false;
  }
  slot = pose;
  return true;
}

bool Inbox::PostCommand(const Command& command) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (commands_.size() >= kMaxCommands) return false;
  commands_.push_back(command);
  return true;
}

void Inbox::Take(std::vector<PoseInput>* poses, std::vector<Command>* commands) {
  commands->clear();
  std::lock_guard<std::mutex> lock(mutex_);
  poses->assign(poses_.begin(), poses_.end());
  commands->swap(commands_);
}

}  // namespace viscera::session
