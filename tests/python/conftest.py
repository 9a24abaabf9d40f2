"""Fixtures for the koma Python package's tests: the real koma_server on a loopback port, the
C++ `koma` CLI to compare with, and the repository's sample files.

ctest (tests/python/CMakeLists.txt) sets KOMA_SERVER_BIN, KOMA_CLI_BIN, KOMA_SOURCE_DIR and
PYTHONPATH (the built package); run by hand the same way:
    KOMA_SERVER_BIN=build/server/koma_server KOMA_CLI_BIN=build/client/koma \
    KOMA_SOURCE_DIR=. PYTHONPATH=build/python /usr/bin/python3 -m pytest tests/python
"""
import os
import subprocess
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "testing"))
from koma_server import KomaServer  # noqa: E402  (tests/testing/koma_server.py)

SOURCE_DIR = os.environ.get("KOMA_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
SERVER_BIN = os.environ.get("KOMA_SERVER_BIN", os.path.join(SOURCE_DIR, "build/server/koma_server"))
CLI_BIN = os.environ.get("KOMA_CLI_BIN", os.path.join(SOURCE_DIR, "build/client/koma"))


def source_path(*parts):
    return os.path.join(SOURCE_DIR, *parts)


class Server(KomaServer):
    """koma_server on 127.0.0.1 with a free port (tests/testing/koma_server.py), stopped with
    SIGTERM."""

    def __init__(self, workdir, *flags):
        super().__init__(SERVER_BIN, workdir, "--log_level=warn", "--shutdown_delay_ms=0", *flags)


@pytest.fixture(scope="session")
def server(tmp_path_factory):
    s = Server(str(tmp_path_factory.mktemp("server")))
    yield s
    s.stop()


@pytest.fixture(scope="session")
def client(server):
    import koma
    with koma.Client(server.address, timeout=60) as c:
        yield c


def run_cli(*args, check=True):
    """The C++ `koma` CLI; returns the CompletedProcess (stdout, stderr as text)."""
    done = subprocess.run([CLI_BIN, *args], capture_output=True, text=True, timeout=120)
    if check and done.returncode != 0:
        raise AssertionError(f"koma {' '.join(args)} failed: {done.stderr}")
    return done


def run_python_cli(*args):
    """`python3 -m koma` with this interpreter and package."""
    import sys
    return subprocess.run([sys.executable, "-m", "koma", *args], capture_output=True, text=True,
                          timeout=120)
