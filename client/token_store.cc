#include "client/token_store.h"

#include <sys/stat.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>

#include <nlohmann/json.hpp>

#include "common/check.h"

namespace viscera::client {

std::string DefaultTokenStorePath() {
  const char* env = std::getenv("VISCERA_SESSIONS");
  if (env != nullptr && env[0] != '\0') return env;
  const char* home = std::getenv("HOME");
  return std::string(home != nullptr && home[0] != '\0' ? home : ".") + "/.viscera/sessions.json";
}

std::string ToHex(const std::vector<uint8_t>& bytes) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string out;
  out.reserve(bytes.size() * 2);
  for (const uint8_t b : bytes) {
    out += kDigits[b >> 4];
    out += kDigits[b & 15];
  }
  return out;
}

std::vector<uint8_t> FromHex(const std::string& hex) {
  ThrowUnless(hex.size() % 2 == 0, "token '", hex, "': odd number of hex digits");
  auto digit = [&](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    Fail("token '", hex, "': not hex");
  };
  std::vector<uint8_t> out(hex.size() / 2);
  for (size_t i = 0; i < out.size(); ++i) {
    out[i] = static_cast<uint8_t>(digit(hex[2 * i]) * 16 + digit(hex[2 * i + 1]));
  }
  return out;
}

TokenStore::TokenStore(std::string path) : path_(std::move(path)) {
  std::ifstream in(path_);
  if (!in.good()) return;
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    for (const auto& [id, s] : j.items()) {
      sessions_[std::stoll(id)] = StoredSession{FromHex(s.at("token").get<std::string>()),
                                                s.at("server_id").get<std::string>()};
    }
  } catch (const std::exception& e) {
    Fail("session store '", path_, "' is damaged (", e.what(), "); remove it");
  }
}

const StoredSession* TokenStore::Find(int64_t id) const {
  const auto it = sessions_.find(id);
  return it == sessions_.end() ? nullptr : &it->second;
}

void TokenStore::Put(int64_t id, const StoredSession& session) {
  sessions_[id] = session;
  Save();
}

void TokenStore::Erase(int64_t id) {
  if (sessions_.erase(id) > 0) Save();
}

void TokenStore::Save() const {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [id, s] : sessions_) {
    j[std::to_string(id)] = {{"token", ToHex(s.token)}, {"server_id", s.server_id}};
  }
  const std::string dir = path_.substr(0, path_.find_last_of('/'));
  if (dir != path_ && !dir.empty()) mkdir(dir.c_str(), 0700);  // one level is enough
  const std::string tmp = path_ + ".tmp";
  const mode_t old_mask = umask(077);
  std::ofstream out(tmp, std::ios::trunc);
  umask(old_mask);
  out << j.dump(2) << "\n";
  out.close();
  ThrowUnless(out.good() && std::rename(tmp.c_str(), path_.c_str()) == 0,
              "cannot save session store '", path_, "'");
}

}  // namespace viscera::client
