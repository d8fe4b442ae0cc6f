"""Running real viscerad processes for the Python tests (inside a private network
namespace: ctest starts these tests through tests/e2e/in_netns.sh)."""
import os
import subprocess
import tempfile
import time

from viscera_client import Client

VISCERAD = os.environ["VISCERAD"]
SOURCE_DIR = os.environ["VISCERA_SOURCE_DIR"]
URL = os.environ.get("VISCERA_TEST_URL", "udpm://239.255.76.67:7667?ttl=0")
PUSH_SCENE = os.path.join(SOURCE_DIR, "tests", "e2e", "scenes", "push.toml")


def require_private_netns():
    if os.environ.get("VISCERA_IN_NETNS") != "1":
        raise RuntimeError("run through tests/e2e/in_netns.sh: these tests need a private "
                           "network namespace")


class Server:
    """A viscerad with `args`; stopped with SIGTERM (its exit status checked) on stop()."""

    def __init__(self, server_id, *args):
        self.server_id = server_id
        self.err = tempfile.NamedTemporaryFile("w+", prefix=f"viscerad-{server_id}-", suffix=".err")
        self.proc = subprocess.Popen(
            [VISCERAD, "--server-id", server_id, "--lcm-url", URL, "--scene-dir",
             os.path.join(SOURCE_DIR, "scenes"), *args], stderr=self.err)

    def stderr(self):
        self.err.seek(0)
        return self.err.read()

    def stop(self):
        if self.proc.poll() is None:
            self.proc.terminate()
        code = self.proc.wait(timeout=30)
        return code


def wait_for_servers(client, ids, timeout_s=20.0):
    """Polls heartbeats until every id in `ids` is heard (with a deadline, no fixed sleep);
    returns {id: ServerInfo}."""
    deadline = time.monotonic() + timeout_s
    heard = {}
    while time.monotonic() < deadline:
        for s in client.servers(listen_s=0.5):
            heard[s.server_id] = s
        if all(i in heard for i in ids):
            return heard
    raise AssertionError(f"servers {sorted(set(ids) - set(heard))} not heard within {timeout_s} s")


def poll(predicate, client, timeout_s=10.0, what="condition"):
    """Pumps `client` until predicate() is true, or fails after timeout_s."""
    deadline = time.monotonic() + timeout_s
    while not predicate():
        if time.monotonic() > deadline:
            raise AssertionError(f"{what}: not within {timeout_s} s")
        client.pump(0.05)


def new_client(**kwargs):
    return Client(URL, **kwargs)
