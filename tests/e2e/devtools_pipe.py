"""Debian's headless Chromium driven over its DevTools pipe (--remote-debugging-pipe): no port,
no network besides the page's own, so it runs in a loopback-only namespace (in_netns.sh).

    with Browser(workdir) as browser:
        page = browser.open("http://127.0.0.1:18080/")
        page.evaluate("document.title")
        browser.cpu_seconds()  # CPU time of its processes so far, by process type
"""
import json
import os
import select
import signal
import subprocess
import time

FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--disable-dev-shm-usage",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--no-first-run", "--no-default-browser-check", "--disable-extensions", "--mute-audio",
         "--no-proxy-server", "--remote-debugging-pipe"]


def find_browser():
    # the real binary, not Debian's wrapper script (it adds flags of its own)
    for path in ("/usr/lib/chromium/chromium", "/usr/bin/chromium"):
        if os.access(path, os.X_OK):
            return path
    raise SystemExit("devtools_pipe: chromium not installed (tools/setup.sh)")


class Failure(Exception):
    pass


class Browser:
    def __init__(self, work, window="800,600", flags=FLAGS):
        """flags: Chromium's command line besides the window, profile and first page."""
        self.work = work
        self.buffer, self.next_id = b"", 0
        to_r, self.to_w = os.pipe()
        self.from_r, from_w = os.pipe()

        def plumb():
            # through high numbers first, so that no pipe end is overwritten before it is copied
            os.dup2(to_r, 100)
            os.dup2(from_w, 101)
            os.dup2(100, 3)
            os.dup2(101, 4)
            os.close(100)
            os.close(101)
        self.log = open(os.path.join(work, "chromium.log"), "wb")
        self.proc = subprocess.Popen(
            [find_browser()] + list(flags) + [f"--window-size={window}", f"--user-data-dir={work}/profile", "about:blank"],
            stdin=subprocess.DEVNULL, stdout=self.log, stderr=self.log, preexec_fn=plumb, close_fds=False,
            start_new_session=True)
        os.close(to_r)
        os.close(from_w)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def log_tail(self, lines=15):
        self.log.flush()
        text = open(os.path.join(self.work, "chromium.log"), "rb").read().decode(errors="replace")
        # without a D-Bus (containers, namespaces) Chromium complains at length: not the cause
        return [line for line in text.splitlines() if "dbus" not in line][-lines:]

    def cpu_seconds(self):
        """User + system CPU time of the browser's processes, in seconds, by Chromium's process
        type ("browser", "gpu-process", "renderer", "utility", ...): those alive now, each since it
        started (Chromium starts them all in its own process group)."""
        hz, out = os.sysconf("SC_CLK_TCK"), {}
        for pid in filter(str.isdigit, os.listdir("/proc")):
            try:
                with open(f"/proc/{pid}/stat") as f:
                    fields = f.read().rsplit(")", 1)[1].split()
                with open(f"/proc/{pid}/cmdline", "rb") as f:
                    args = f.read().replace(b"\0", b" ").split()  # a title set: one string
            except OSError:
                continue  # gone meanwhile
            if int(fields[2]) != self.proc.pid:  # the process group (field 5)
                continue
            kind = next((a[7:].decode() for a in args if a.startswith(b"--type=")), "browser")
            out[kind] = out.get(kind, 0.0) + (int(fields[11]) + int(fields[12])) / hz  # utime, stime
        return out

    def call(self, method, params=None, session=None, timeout=20.0):
        """One DevTools command's result (events in between are skipped); Failure on an error."""
        self.next_id += 1
        message = {"id": self.next_id, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = session
        os.write(self.to_w, json.dumps(message).encode() + b"\0")
        deadline = time.monotonic() + timeout
        while True:
            while b"\0" not in self.buffer:
                ready, _, _ = select.select([self.from_r], [], [], max(deadline - time.monotonic(), 0))
                if not ready:
                    raise Failure(f"no DevTools answer to {method} in {timeout} s")
                chunk = os.read(self.from_r, 1 << 20)
                if not chunk:
                    raise Failure(f"chromium exited (status {self.proc.wait()}) during {method}")
                self.buffer += chunk
            raw, self.buffer = self.buffer.split(b"\0", 1)
            reply = json.loads(raw)
            if reply.get("id") == self.next_id:
                if "error" in reply:
                    raise Failure(f"{method}: {reply['error']}")
                return reply["result"]

    def open(self, url):
        target = self.call("Target.createTarget", {"url": url})["targetId"]
        session = self.call("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
        return Page(self, session)

    def close(self):
        # politely, so that Chromium reaps its own children; else kill them all
        try:
            self.call("Browser.close", timeout=5)
            self.proc.wait(timeout=5)
        except (OSError, Failure, subprocess.TimeoutExpired):
            try:
                os.killpg(self.proc.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            self.proc.wait()


class Page:
    def __init__(self, browser, session):
        self.browser, self.session = browser, session

    def evaluate(self, expression, timeout=20.0):
        """The value of a JavaScript expression (promises awaited); None while the page has no
        JavaScript context yet (navigation) or when it throws."""
        try:
            result = self.browser.call("Runtime.evaluate", {"expression": expression, "returnByValue": True,
                                                            "awaitPromise": True}, self.session, timeout)
        except Failure as e:
            if "no DevTools answer" in str(e) or "exited" in str(e):
                raise
            return None
        if "exceptionDetails" in result:
            return None
        return result.get("result", {}).get("value")

    def wait_for(self, expression, seconds, what):
        """Polls `expression` until it is truthy; its value, or Failure naming `what`."""
        deadline = time.monotonic() + seconds
        while True:
            value = self.evaluate(expression)
            if value:
                return value
            if time.monotonic() > deadline:
                status = self.evaluate("document.getElementById('status')?.textContent")
                raise Failure(f"{what} (after {seconds} s; #status: {status!r})")
            time.sleep(0.25)
