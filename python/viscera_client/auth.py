"""The optional pre-shared-key MAC of viscera messages (docs/protocol.md, "Security").

The same scheme as src/bus/message_auth.cc: the key is BLAKE2b-256 of the key file's whole
content; the MAC is libsodium's crypto_auth, HMAC-SHA-512 truncated to 32 bytes, over the
encoded datagram as it is with header.mac_len = 0 and no mac bytes, inserted after mac_len.
"""
import hashlib
import hmac
import struct

import viscera_proto

MAC_BYTES = 32
# encoded top-level message: 8-byte fingerprint, then header_t big-endian: version (2),
# session_id (8), seq (8), utime (8), [sender (8), protocol 4 on], token_len (4), token,
# mac_len (4), mac. Read from the generated type, so the layout follows proto/.
HAS_SENDER = "sender" in viscera_proto.header_t.__slots__
_TOKEN_LEN_OFFSET = 8 + 2 + 8 + 8 + 8 + (8 if HAS_SENDER else 0)


def mac_len_offset(data):
    """Offset of header.mac_len in an encoded viscera message, or -1 when malformed."""
    if len(data) < _TOKEN_LEN_OFFSET + 4:
        return -1
    (token_len,) = struct.unpack_from(">i", data, _TOKEN_LEN_OFFSET)
    if token_len < 0 or token_len > len(data) - _TOKEN_LEN_OFFSET - 8:
        return -1
    return _TOKEN_LEN_OFFSET + 4 + token_len


class MessageAuth:
    """Signs and checks encoded messages with one 32-byte key."""

    def __init__(self, key):
        if len(key) != 32:
            raise ValueError(f"a viscera key has 32 bytes, got {len(key)}")
        self._key = bytes(key)

    @classmethod
    def from_key_file(cls, path):
        """The key of a pre-shared key file (`viscera keygen FILE` writes one).

        Raises ValueError when the file holds fewer than 16 bytes; OSError when unreadable.
        """
        with open(path, "rb") as f:
            content = f.read()
        if len(content) < 16:
            raise ValueError(f"key file '{path}' holds {len(content)} bytes; a pre-shared key "
                             "needs at least 16 (viscera keygen FILE makes one)")
        return cls(hashlib.blake2b(content, digest_size=32).digest())

    def _mac(self, message):
        return hmac.new(self._key, message, hashlib.sha512).digest()[:MAC_BYTES]

    def sign(self, datagram):
        """The datagram with its MAC inserted. Raises ValueError when it is not an encoded
        viscera message without a MAC."""
        offset = mac_len_offset(datagram)
        if offset < 0 or offset + 4 > len(datagram) or datagram[offset:offset + 4] != b"\0\0\0\0":
            raise ValueError("not an unsigned viscera message")
        mac = self._mac(datagram)
        return datagram[:offset] + struct.pack(">i", MAC_BYTES) + mac + datagram[offset + 4:]

    def verify(self, data):
        """True when `data` carries a valid MAC of this key; never raises."""
        offset = mac_len_offset(data)
        if offset < 0 or offset + 4 + MAC_BYTES > len(data):
            return False
        if struct.unpack_from(">i", data, offset)[0] != MAC_BYTES:
            return False
        mac = data[offset + 4:offset + 4 + MAC_BYTES]
        signed = data[:offset] + b"\0\0\0\0" + data[offset + 4 + MAC_BYTES:]
        return hmac.compare_digest(mac, self._mac(signed))
