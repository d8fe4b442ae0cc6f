#pragma once
/// TokenStore: the client's memory of the sessions it created (id -> token, server), a
/// small JSON file readable by its owner only, so that `viscera destroy ID` can prove it
/// may. Default path: $VISCERA_SESSIONS, else ~/.viscera/sessions.json.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace viscera::client {

struct StoredSession {
  std::vector<uint8_t> token;
  std::string server_id;
};

/// The default store path (see above).
std::string DefaultTokenStorePath();

/// Lower-case hex of bytes, and back (@throws InputError on bad hex).
std::string ToHex(const std::vector<uint8_t>& bytes);
std::vector<uint8_t> FromHex(const std::string& hex);

class TokenStore {
 public:
  /// Reads `path` if it exists (a missing file is an empty store).
  /// @throws InputError when the file exists but is not a store.
  explicit TokenStore(std::string path);

  /// The stored session, or nullptr.
  const StoredSession* Find(int64_t id) const;
  /// Adds or replaces, and saves (mode 0600). @throws InputError when it cannot save.
  void Put(int64_t id, const StoredSession& session);
  /// Removes and saves (no-op when absent).
  void Erase(int64_t id);

 private:
  void Save() const;

  std::string path_;
  std::map<int64_t, StoredSession> sessions_;
};

}  // namespace viscera::client
