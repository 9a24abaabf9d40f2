"""koma_server on 127.0.0.1 and a free port, for the Python test harnesses (tests/python's
fixtures, tests/docs/commands_test.py): the one place they start, wait for and stop a server.
The shell tests' counterpart is tests/e2e/lib.sh. Every wait is bounded."""
import os
import signal
import subprocess
import time


class KomaServer:
    """Starts SERVER_BIN --address=127.0.0.1:0 with FLAGS, its output appended to
    WORKDIR/server.log, and waits (at most 20 s) for the port it writes; `address` is then
    127.0.0.1:PORT."""

    def __init__(self, server_bin, workdir, *flags):
        self.port_file = os.path.join(workdir, f"port-{time.monotonic_ns()}")
        self.log = open(os.path.join(workdir, "server.log"), "ab")
        self.process = subprocess.Popen(
            [server_bin, "--address=127.0.0.1:0", f"--port_file={self.port_file}", *flags],
            stdout=self.log, stderr=self.log)
        deadline = time.monotonic() + 20
        while not (os.path.exists(self.port_file) and open(self.port_file).read().strip()):
            if self.process.poll() is not None:
                self.log.close()
                raise RuntimeError(f"koma_server exited with {self.process.returncode}; see "
                                   f"{self.log.name}")
            if time.monotonic() > deadline:
                self.stop()
                raise RuntimeError(f"koma_server did not write its port within 20 s; see "
                                   f"{self.log.name}")
            time.sleep(0.02)
        self.address = f"127.0.0.1:{open(self.port_file).read().strip()}"

    def stop(self, timeout_s=20):
        """SIGTERM; SIGKILL if it still runs after timeout_s. Returns the exit code, or None if
        it had to be killed."""
        code = self.process.poll()
        if code is None:
            self.process.send_signal(signal.SIGTERM)
            try:
                code = self.process.wait(timeout=timeout_s)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait(timeout=5)
                code = None
        self.log.close()
        return code
