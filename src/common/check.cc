#include "common/check.h"

namespace viscera::internal {

void DemandFailed(const char* condition, const char* file, int line) {
  throw std::logic_error(
      Cat("viscera internal error: ", condition, " failed at ", file, ":", line));
}

}  // namespace viscera::internal
