#pragma once
/// MessageAuth: the optional pre-shared-key MAC of viscera messages (docs/protocol.md,
/// "Security"). Every viscera message starts with header_t, whose last fields are
/// `mac_len` and `mac`; the MAC is libsodium's crypto_auth (HMAC-SHA-512-256) over the
/// whole encoded datagram as it is with mac_len = 0 and no mac bytes. It works on raw
/// encoded bytes, so the bus signs and checks every type alike, before decoding.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace viscera::bus {

/// Bytes of a MAC in header_t.mac.
inline constexpr int kMacBytes = 32;

class MessageAuth {
 public:
  using Key = std::array<uint8_t, 32>;

  /// @pre key is secret and random (or derived from a secret file: FromKeyFile).
  explicit MessageAuth(const Key& key);

  /// The key of a pre-shared key file: BLAKE2b-256 of its whole content, so any file of
  /// at least 16 bytes works (`viscera keygen FILE` writes 32 random bytes, hex).
  /// @throws InputError when the file cannot be read or holds fewer than 16 bytes.
  static MessageAuth FromKeyFile(const std::string& path);

  /// Writes a new key file: 32 random bytes as 64 hex digits and a newline, mode 0600.
  /// @throws InputError when the file cannot be written.
  static void WriteKeyFile(const std::string& path);

  /// Signs an encoded message in place: inserts the MAC into its header.
  /// @return false (datagram untouched) when it is not an encoded viscera message with
  ///         mac_len = 0.
  bool Sign(std::vector<uint8_t>* datagram) const;

  /// True when `data` carries a valid MAC of this key. `scratch` is reused (no allocation
  /// once grown). Never throws: anything malformed is simply not authentic.
  bool Verify(const uint8_t* data, int size, std::vector<uint8_t>* scratch) const;

 private:
  Key key_;
};

/// `n` bytes from the operating system's CSPRNG (libsodium randombytes_buf).
std::vector<uint8_t> RandomBytes(size_t n);

/// Constant-time equality of two byte strings (different sizes are unequal).
bool SecureEquals(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b);

/// Offset of header.mac_len in an encoded top-level viscera message, or -1 when `data`
/// is too short or its token_len is out of range.
int MacLenOffset(const uint8_t* data, int size);

/// True when the header's token_len and mac_len fit in the datagram. LCM 1.3.1's generated
/// C++ decode resizes an array to its count *before* checking the bytes are there, so a
/// 60-byte datagram claiming a 2 GB token made the decoder allocate and zero 2 GB (found by
/// fuzz/fuzz_server_messages); the bus checks this before decoding any viscera message.
bool HeaderCountsFit(const uint8_t* data, int size);

}  // namespace viscera::bus
