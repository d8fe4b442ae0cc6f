"""Bus: typed publish/subscribe over PyPI's `lcm`, with viscera headers and the MAC.

One thread owns a Bus: it publishes, subscribes and pumps. Processes that stream (the load
tester's workers) each open their own.
"""
import secrets
import select
import time

import lcm

import viscera_proto

DEFAULT_URL = "udpm://239.255.76.67:7667?ttl=0"  # as src/bus/lcm_bus.h: never leaves the host
PROTOCOL_VERSION = viscera_proto.header_t.kProtocolVersion


def resolve_url(url=None):
    """`url` when given, else $LCM_DEFAULT_URL when set, else DEFAULT_URL."""
    import os
    return url or os.environ.get("LCM_DEFAULT_URL") or DEFAULT_URL


def wall_micros():
    """Wall-clock time in microseconds since the Unix epoch (the header's utime)."""
    return time.time_ns() // 1000


HAS_SENDER = "sender" in viscera_proto.header_t.__slots__


def new_sender_id():
    """A random non-zero 63-bit sender id (protocol 4: one per sequence counter)."""
    return secrets.randbits(63) or 1


def make_header(session_id=0, seq=0, token=b"", sender=None):
    """A header of this protocol version, stamped now. `sender`: the id of the sequence
    counter `seq` comes from (protocol 4 on; a random one when None)."""
    h = viscera_proto.header_t()
    h.version = PROTOCOL_VERSION
    h.session_id = session_id
    h.seq = seq
    h.utime = wall_micros()
    if HAS_SENDER:
        h.sender = new_sender_id() if sender is None else sender
    h.token = bytes(token)
    h.token_len = len(h.token)
    h.mac = b""  # lcm-gen 1.3.1 defaults byte arrays to "" (a str): set bytes
    h.mac_len = 0
    return h


def header_problem(header):
    """Why a received header cannot be accepted, or "" (as bus::HeaderProblem)."""
    if header.version != PROTOCOL_VERSION:
        return f"protocol version {header.version}, this client speaks {PROTOCOL_VERSION}"
    if header.seq < 0:
        return f"negative sequence {header.seq}"
    if header.token_len != len(header.token):
        return "token count disagrees with the token"
    return ""


class BusError(OSError):
    """LCM could not open the URL: for udpm://, most often a network without a multicast
    route (as the viscera CLI explains it)."""

    def __init__(self, url, cause=None):
        hint = ("for udpm://, does this network have a multicast route? (sudo ip route add "
                "224.0.0.0/4 dev lo for one machine; tests/e2e/in_netns.sh makes a namespace "
                "with one)") if url.startswith("udpm://") else "is the URL well formed?"
        super().__init__(f"LCM could not open URL '{url}' ({hint})"
                         + (f"; LCM said: {cause}" if cause else ""))
        self.url = url


class Bus:
    """An LCM object with viscera's rules: signed when a key is set, and every received
    datagram checked (MAC, decode, header) before a handler sees it; drops are counted."""

    def __init__(self, url=None, auth=None):
        self.url = resolve_url(url)
        try:
            self.lc = lcm.LCM(self.url)
        except (RuntimeError, OSError, ValueError) as e:  # PyPI lcm: "Couldn't create LCM"
            raise BusError(self.url, e) from None
        self.auth = auth
        self.drops = {"bad_mac": 0, "malformed": 0, "bad_header": 0}
        self._seq = {}  # channel -> next header.seq of this sender
        self._senders = {}  # channel -> sender id of that sequence counter (protocol 4)

    def next_seq(self, channel):
        seq = self._seq.get(channel, 0)
        self._seq[channel] = seq + 1
        return seq

    def sender(self, channel):
        """The sender id of this bus's sequence counter on `channel` (drawn once)."""
        if channel not in self._senders:
            self._senders[channel] = new_sender_id()
        return self._senders[channel]

    def stamp(self, msg, channel):
        """Sets msg.header's seq (and sender) from this bus's counter of `channel`, and its
        time to now: a server refuses a (sender, seq) it has seen as a replay."""
        msg.header.seq = self.next_seq(channel)
        if HAS_SENDER:
            msg.header.sender = self.sender(channel)
        msg.header.utime = wall_micros()

    def publish(self, channel, msg):
        """Encodes, signs (with a key) and publishes `msg` (an lcm-gen type)."""
        data = msg.encode()
        if self.auth is not None:
            data = self.auth.sign(data)
        self.lc.publish(channel, data)

    def subscribe_raw(self, channel, handler):
        """Calls handler(data, channel, recv_utime) for each datagram on `channel` that
        passes the MAC check (with a key); decoding is the handler's (see fast.py)."""
        def on_data(chan, data):
            recv_utime = wall_micros()
            if self.auth is not None and not self.auth.verify(data):
                self.drops["bad_mac"] += 1
                return
            handler(data, chan, recv_utime)
        return self.lc.subscribe(channel, on_data)

    def subscribe(self, channel, msg_type, handler):
        """Calls handler(msg, channel, recv_utime) for each valid `msg_type` on `channel`
        (an LCM regex). Returns the subscription (for unsubscribe)."""
        def on_data(chan, data):
            recv_utime = wall_micros()
            if self.auth is not None and not self.auth.verify(data):
                self.drops["bad_mac"] += 1
                return
            try:
                msg = msg_type.decode(data)
            except Exception:  # wrong fingerprint, truncated: lcm-gen raises several kinds
                self.drops["malformed"] += 1
                return
            if header_problem(msg.header):
                self.drops["bad_header"] += 1
                return
            handler(msg, chan, recv_utime)
        return self.lc.subscribe(channel, on_data)

    def unsubscribe(self, subscription):
        self.lc.unsubscribe(subscription)

    def pump(self, timeout_s, max_messages=1 << 30):
        """Waits up to `timeout_s` for data, then handles what is already queued, at most
        `max_messages` (so a flood cannot hold a pacing loop). Returns messages handled."""
        handled = 0
        fd = self.lc.fileno()
        wait = max(0.0, timeout_s)
        while handled < max_messages:
            ready, _, _ = select.select([fd], [], [], wait)
            if not ready:
                return handled
            self.lc.handle()
            handled += 1
            wait = 0.0
        return handled

    def close(self):
        """Drops the LCM object (its socket closes); the Bus is unusable afterwards."""
        self.lc = None
