#pragma once
/// Three levels of checks, as in Drake:
///  - VISCERA_ASSERT: debug-only, for hot-path invariants.
///  - VISCERA_DEMAND: always on, for viscera's own broken invariants (a bug if it fires).
///  - ThrowUnless / Fail: always on, for bad user input; the message carries the values.
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

namespace viscera {

/// Thrown for invalid user input (scene files, command-line values, API arguments).
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

namespace internal {
[[noreturn]] void DemandFailed(const char* condition, const char* file, int line);
}  // namespace internal

/// Concatenates streamable values into a message.
template <typename... Args>
std::string Cat(Args&&... args) {
  std::ostringstream out;
  (out << ... << std::forward<Args>(args));
  return out.str();
}

/// @throws InputError with the concatenated message.
template <typename... Args>
[[noreturn]] void Fail(Args&&... args) {
  throw InputError(Cat(std::forward<Args>(args)...));
}

/// @throws InputError with the concatenated message unless `ok`.
template <typename... Args>
void ThrowUnless(bool ok, Args&&... args) {
  if (!ok) Fail(std::forward<Args>(args)...);
}

}  // namespace viscera

#define VISCERA_DEMAND(condition)                                                        \
  do {                                                                                   \
    if (!(condition)) ::viscera::internal::DemandFailed(#condition, __FILE__, __LINE__); \
  } while (false)

#ifdef NDEBUG
#define VISCERA_ASSERT(condition) ((void)0)
#else
#define VISCERA_ASSERT(condition) VISCERA_DEMAND(condition)
#endif
