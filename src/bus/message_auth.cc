#include "bus/message_auth.h"
#include "bus/wire_counts.h"

#include <sodium.h>
#include <sys/stat.h>

#include <cstdio>
#include <fstream>
#include <iterator>

#include "common/check.h"

namespace viscera::bus {
namespace {

// Encoded layout of a top-level message: 8-byte type fingerprint, then header_t's fields
// big-endian: version (2), session_id (8), seq (8), utime (8), sender (8), token_len (4),
// token, mac_len (4), mac.
constexpr int kTokenLenOffset = 8 + 2 + 8 + 8 + 8 + 8;

int32_t ReadBe32(const uint8_t* p) {
  return static_cast<int32_t>((uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) |
                              (uint32_t{p[2]} << 8) | uint32_t{p[3]});
}

void WriteBe32(int32_t v, uint8_t* p) {
  const auto u = static_cast<uint32_t>(v);
  p[0] = static_cast<uint8_t>(u >> 24);
  p[1] = static_cast<uint8_t>(u >> 16);
  p[2] = static_cast<uint8_t>(u >> 8);
  p[3] = static_cast<uint8_t>(u);
}

void InitSodium() {
  // sodium_init is thread-safe and idempotent; < 0 means no usable randomness.
  VISCERA_DEMAND(sodium_init() >= 0);
}

}  // namespace

std::vector<uint8_t> RandomBytes(size_t n) {
  InitSodium();
  std::vector<uint8_t> out(n);
  randombytes_buf(out.data(), n);
  return out;
}

bool SecureEquals(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  if (a.size() != b.size()) return false;
  if (a.empty()) return true;
  return sodium_memcmp(a.data(), b.data(), a.size()) == 0;
}

int MacLenOffset(const uint8_t* data, int size) {
  if (size < kTokenLenOffset + 4) return -1;
  const int32_t token_len = ReadBe32(data + kTokenLenOffset);
  if (token_len < 0 || token_len > size - kTokenLenOffset - 8) return -1;
  return kTokenLenOffset + 4 + token_len;
}

// Since the client-side fix, not only the header's: every array count and string length of
// the type the datagram's fingerprint names (bus/wire_counts.cc). The name stays so that
// message_auth.h and the bus template, included almost everywhere, keep their bytes.
bool HeaderCountsFit(const uint8_t* data, int size) {
  const int offset = MacLenOffset(data, size);
  if (offset < 0 || offset + 4 > size) return false;
  const int32_t mac_len = ReadBe32(data + offset);
  return mac_len >= 0 && mac_len <= size - offset - 4 && CountsFitForFingerprint(data, size);
}

MessageAuth::MessageAuth(const Key& key) : key_(key) { InitSodium(); }

MessageAuth MessageAuth::FromKeyFile(const std::string& path) {
  InitSodium();
  std::ifstream in(path, std::ios::binary);
  ThrowUnless(in.good(), "cannot read key file '", path, "'");
  const std::vector<uint8_t> content((std::istreambuf_iterator<char>(in)),
                                     std::istreambuf_iterator<char>());
  ThrowUnless(content.size() >= 16, "key file '", path, "' holds ", content.size(),
              " bytes; a pre-shared key needs at least 16 (viscera keygen FILE makes one)");
  Key key{};
  crypto_generichash(key.data(), key.size(), content.data(), content.size(), nullptr, 0);
  return MessageAuth(key);
}

void MessageAuth::WriteKeyFile(const std::string& path) {
  InitSodium();
  uint8_t raw[32];
  randombytes_buf(raw, sizeof(raw));
  char hex[2 * sizeof(raw) + 1];
  sodium_bin2hex(hex, sizeof(hex), raw, sizeof(raw));
  const mode_t old_mask = umask(077);
  FILE* f = std::fopen(path.c_str(), "w");
  umask(old_mask);
  ThrowUnless(f != nullptr, "cannot write key file '", path, "'");
  const bool ok = std::fprintf(f, "%s\n", hex) == static_cast<int>(sizeof(hex));
  ThrowUnless(std::fclose(f) == 0 && ok, "cannot write key file '", path, "'");
  sodium_memzero(raw, sizeof(raw));
}

bool MessageAuth::Sign(std::vector<uint8_t>* datagram) const {
  const int size = static_cast<int>(datagram->size());
  const int offset = MacLenOffset(datagram->data(), size);
  if (offset < 0 || offset + 4 > size || ReadBe32(datagram->data() + offset) != 0) return false;
  uint8_t mac[crypto_auth_BYTES];
  static_assert(crypto_auth_BYTES == kMacBytes);
  crypto_auth(mac, datagram->data(), datagram->size(), key_.data());
  WriteBe32(kMacBytes, datagram->data() + offset);
  datagram->insert(datagram->begin() + offset + 4, mac, mac + kMacBytes);
  return true;
}

bool MessageAuth::Verify(const uint8_t* data, int size, std::vector<uint8_t>* scratch) const {
  const int offset = MacLenOffset(data, size);
  if (offset < 0 || offset + 4 + kMacBytes > size) return false;
  if (ReadBe32(data + offset) != kMacBytes) return false;
  // the message as it was signed: mac_len = 0, no mac bytes
  scratch->assign(data, data + offset);
  scratch->insert(scratch->end(), {0, 0, 0, 0});
  scratch->insert(scratch->end(), data + offset + 4 + kMacBytes, data + size);
  return crypto_auth_verify(data + offset + 4, scratch->data(), scratch->size(), key_.data()) == 0;
}

}  // namespace viscera::bus
