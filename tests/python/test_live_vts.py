"""`python3 -m koma live --vts` (koma/_vts.py) against the real koma_server and the stand-in for
VTube Studio's plugin API that e2e.live_vts uses (tests/e2e/vts_standin.py: python3-websockets
on loopback, checking every request's shape, and its `check` mode comparing the requests with
the run's --json frames): a new token asked for and saved 0600, the saved one reused, a refused
one replaced, re-sends while no frame comes, an unknown parameter's APIError once, Deny,
access revoked and the connection closed mid-stream, nothing listening, usage errors, the
websockets module missing, and the same requests as the C++ `koma live --vts`. Real-time runs
are short (at most 2.5 s of wall time each)."""
import json
import os
import signal
import socket
import stat
import subprocess
import sys
import time

import pytest

from conftest import CLI_BIN, run_cli, source_path

pytest.importorskip("websockets", reason="python3-websockets (scripts/install-deps.sh)")

VOICE = source_path("samples", "voice.flac")
VOICE_FRAMES = 92
STANDIN = source_path("tests", "e2e", "vts_standin.py")


class StandIn:
    """vts_standin.py serve on a free loopback port; .url, .log (the requests as JSON lines)."""

    def __init__(self, workdir, name, *flags):
        self.log = os.path.join(workdir, f"{name}.log")
        port_file = os.path.join(workdir, f"{name}.port")
        self.process = subprocess.Popen(
            [sys.executable, STANDIN, "serve", port_file, self.log, *flags],
            stderr=subprocess.PIPE, text=True)
        deadline = time.monotonic() + 10
        while not os.path.exists(port_file):
            assert self.process.poll() is None, self.process.stderr.read()
            assert time.monotonic() < deadline, "the stand-in did not start"
            time.sleep(0.02)
        with open(port_file) as f:
            self.url = f"ws://127.0.0.1:{f.read().strip()}"

    def stop(self):
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGTERM)
        _, err = self.process.communicate(timeout=10)
        assert self.process.returncode == 0, err

    def requests(self):
        """The requests received, in order (the log's entries with one)."""
        with open(self.log) as f:
            return [e["request"] for e in map(json.loads, f) if "request" in e]


@pytest.fixture
def standins(tmp_path):
    started = []

    def start(name, *flags):
        started.append(StandIn(str(tmp_path), name, *flags))
        return started[-1]
    yield start
    for s in started:
        if s.process.poll() is None:
            s.process.kill()
            s.process.wait()


def live(server, *flags, env=None):
    return subprocess.run([sys.executable, "-m", "koma", "live", "--server", server.address,
                           *flags], capture_output=True, text=True, timeout=60,
                          env=dict(os.environ, **(env or {})))


def check(standin, tmp_path, name, stdout, *flags):
    """vts_standin.py check: the flow, every --json frame injected with its values, re-sends."""
    frames = tmp_path / f"{name}.jsonl"
    frames.write_text(stdout)
    done = subprocess.run([sys.executable, STANDIN, "check", standin.log, str(frames), *flags],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout


def test_a_new_token_saved_then_reused_then_replaced(server, standins, tmp_path):
    xdg = tmp_path / "xdg"
    token_file = xdg / "koma" / "vts-token"
    # 1. No token yet: asked for, saved at the default place (folders created, 0600), used.
    new = standins("new", "--token", "token-one")
    done = live(server, "--input", VOICE, "--speed", "0", "--json", "--auto-blink", "0.5",
                "--vts", new.url, env={"XDG_CONFIG_HOME": str(xdg)})
    new.stop()
    assert done.returncode == 0, done.stderr
    check(new, tmp_path, "new", done.stdout, "--flow", "new")
    assert len(done.stdout.splitlines()) == VOICE_FRAMES and '"blink":true' in done.stdout
    assert token_file.read_text() == "token-one\n"
    assert stat.S_IMODE(token_file.stat().st_mode) == 0o600
    assert 'click "Allow" in its popup to let "koma" by "koma contributors"' in done.stderr
    # 2. The saved token alone ($HOME/.config without XDG_CONFIG_HOME); other parameter
    # names and mouth levels.
    saved = standins("saved", "--valid-token", "token-one")
    home = tmp_path / "home"
    (home / ".config").mkdir(parents=True)
    os.rename(xdg / "koma", home / ".config" / "koma")
    env = {k: v for k, v in os.environ.items() if k != "XDG_CONFIG_HOME"}
    done = subprocess.run(
        [sys.executable, "-m", "koma", "live", "--server", server.address, "--input", VOICE,
         "--speed", "0", "--json", "--mouth-min", "2", "--mouth-max", "6", "--vts", saved.url,
         "--vts-mouth-param", "MouthSmile", "--vts-eye-left-param", "EyeLeftX",
         "--vts-eye-right-param", "EyeRightX"],
        capture_output=True, text=True, timeout=60, env=dict(env, HOME=str(home)))
    saved.stop()
    assert done.returncode == 0, done.stderr
    check(saved, tmp_path, "saved", done.stdout, "--flow", "saved", "--mouth", "MouthSmile",
          "--left", "EyeLeftX", "--right", "EyeRightX", "--mouth-min", "2", "--mouth-max", "6")
    assert "Allow" not in done.stderr
    # 3. The saved token refused (revoked): a new one asked for, saved over it, used.
    token_file = home / ".config" / "koma" / "vts-token"
    refreshed = standins("refreshed", "--token", "token-two")
    done = live(server, "--input", VOICE, "--speed", "0", "--json", "--vts", refreshed.url,
                "--vts-token-file", str(token_file))
    refreshed.stop()
    assert done.returncode == 0, done.stderr
    check(refreshed, tmp_path, "refreshed", done.stdout, "--flow", "refreshed")
    assert "VTube Studio refused the saved token: Token invalid or revoked." in done.stderr
    assert token_file.read_text() == "token-two\n"
    assert stat.S_IMODE(token_file.stat().st_mode) == 0o600


def test_the_last_values_are_re_sent_while_no_frame_comes(server, standins, tmp_path):
    # Frames 0.83 s apart (5 ms of audio a second, no lookahead): re-sends in between, so no
    # two injects are further apart than 0.75 s.
    slow = standins("slow", "--valid-token", "t")
    (tmp_path / "token").write_text("t\n")
    start = time.monotonic()
    done = live(server, "--input", VOICE, "--speed", "0.05", "--seconds", "0.125",
                "--lookahead", "0", "--json", "--vts", slow.url, "--vts-token-file",
                str(tmp_path / "token"))
    slow.stop()
    assert done.returncode == 0, done.stderr
    assert time.monotonic() - start >= 2.5
    summary = check(slow, tmp_path, "slow", done.stdout, "--flow", "saved", "--max-gap", "0.75")
    assert "3 frames injected" in summary, summary
    ids = [r["requestID"] for r in slow.requests()]
    resends = [i for i in ids if i.startswith("koma-resend-")]
    assert resends and resends == [f"koma-resend-{n}" for n in range(1, len(resends) + 1)]


def test_an_unknown_parameter_is_printed_once(server, standins, tmp_path):
    unknown = standins("unknown", "--valid-token", "t")
    (tmp_path / "token").write_text("t")
    done = live(server, "--input", VOICE, "--speed", "0", "-q", "--vts", unknown.url,
                "--vts-token-file", str(tmp_path / "token"), "--vts-mouth-param",
                "KomaNoSuchParameter")
    unknown.stop()
    assert done.returncode == 0, done.stderr
    assert done.stderr.count("APIError 453") == 1, done.stderr
    assert "koma: warning: --vts: VTube Studio: APIError 453: Parameter KomaNoSuchParameter " \
        "not found. (VTube Studio has no input parameter of that name: check " \
        "--vts-mouth-param" in done.stderr


def test_deny_exits_1_before_any_audio(server, standins, tmp_path):
    denied = standins("denied", "--deny")
    token_file = tmp_path / "denied" / "vts-token"
    done = live(server, "--input", VOICE, "--speed", "0", "--json", "--vts", denied.url,
                "--vts-token-file", str(token_file))
    denied.stop()
    assert done.returncode == 1
    assert done.stdout == ""
    assert "koma live:" not in done.stderr  # the first human line comes after Start
    assert "koma: --vts: VTube Studio refused AuthenticationTokenRequest: APIError 50: User " \
        "has denied API access for your plugin. (koma was denied: run koma live again and " \
        "click Allow in VTube Studio's popup)\n" in done.stderr, done.stderr
    assert not token_file.exists()
    assert [r["messageType"] for r in denied.requests()] == ["AuthenticationTokenRequest"]


@pytest.mark.parametrize("how", ["revoke", "close"])
def test_access_revoked_or_closed_mid_stream_ends_it(server, standins, tmp_path, how):
    standin = standins(how, "--valid-token", "t", f"--{how}-after", "10")
    (tmp_path / "token").write_text("t")
    done = live(server, "--input", VOICE, "--seconds", "2", "--json", "--vts", standin.url,
                "--vts-token-file", str(tmp_path / "token"))  # real time: ends after ~0.6 s
    standin.stop()
    assert done.returncode == 1
    assert len(done.stdout.splitlines()) < 48
    injects = [r for r in standin.requests()
               if r["messageType"] == "InjectParameterDataRequest"]
    assert 10 <= len(injects) <= 13
    want = ("koma: --vts: VTube Studio: APIError 8: This request requires authentication. "
            "(the session is no longer authenticated: run koma live again)\n"
            if how == "revoke" else "koma: --vts: VTube Studio closed the connection\n")
    assert done.stderr.endswith(want), done.stderr


def test_nothing_listening_names_the_url(server):
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    done = live(server, "--input", VOICE, "--speed", "0", "--vts", f"ws://127.0.0.1:{port}")
    assert done.returncode == 1
    assert done.stderr.startswith(f"koma: --vts: cannot open ws://127.0.0.1:{port}/: ")
    assert "(is VTube Studio running, with \"Start API (allow plugins)\" on, on this port?)" \
        in done.stderr, done.stderr


def test_usage_errors_name_the_flag(server, tmp_path):
    done = live(server, "--input", VOICE, "--vts", "wss://127.0.0.1:8001")
    assert done.returncode == 2
    assert done.stderr == "koma: --vts: \"wss://127.0.0.1:8001\": wss:// (TLS) is not " \
        "supported; use ws://\n"
    done = live(server, "--input", VOICE, "--vts-mouth-param", "")
    assert done.returncode == 2 and done.stderr == "koma: --vts-mouth-param must not be empty\n"
    done = live(server, "--input", VOICE, "--vts", "127.0.0.1")
    assert done.returncode == 2 and "must be ws://HOST:PORT or HOST:PORT" in done.stderr


def test_urls_as_the_cpp_client_reads_them():
    from koma._vts import parse_url
    assert parse_url("ws://localhost:8001") == ("localhost", 8001, "/")
    assert parse_url("192.168.1.20:8001") == ("192.168.1.20", 8001, "/")
    assert parse_url("ws://example") == ("example", 80, "/")
    assert parse_url("WS://[::1]:9/api") == ("::1", 9, "/api")
    for bad in ("ws://:8001", "ws://host:", "host", "ws://h:0", "ws://h:65536", "ws://[::1",
                "ws://h:8x", "wss://h:1"):
        with pytest.raises(ValueError):
            parse_url(bad)


def test_without_websockets_names_the_package(server, tmp_path):
    (tmp_path / "websockets.py").write_text("raise ImportError('hidden by the test')\n")
    done = live(server, "--input", VOICE, "--vts", env={
        "PYTHONPATH": f"{tmp_path}{os.pathsep}{os.environ.get('PYTHONPATH', '')}"})
    assert done.returncode == 1 and "python3-websockets" in done.stderr, done.stderr


def test_the_same_requests_as_the_cpp_koma_live(server, standins, tmp_path):
    if "--vts" not in run_cli("live", "--help", check=False).stdout:
        pytest.skip(f"{CLI_BIN} has no `live --vts`")
    flags = ["live", "--server", server.address, "--input", VOICE, "--speed", "0", "--json",
             "--seed", "7", "--auto-blink", "1", "--mouth-max", "2"]
    got = {}
    for who, command in (("cpp", [CLI_BIN]), ("py", [sys.executable, "-m", "koma"])):
        standin = standins(who, "--token", "token-one")
        done = subprocess.run(
            [*command, *flags, "--vts", standin.url, "--vts-token-file",
             str(tmp_path / who / "vts-token")], capture_output=True, text=True, timeout=60)
        standin.stop()
        assert done.returncode == 0, done.stderr
        assert (tmp_path / who / "vts-token").read_text() == "token-one\n"
        # Re-sends depend on timing; the rest is the same bytes of JSON, parsed.
        got[who] = [r for r in standin.requests()
                    if not r["requestID"].startswith("koma-resend-")]
        got[who + " stderr"] = [line for line in done.stderr.splitlines()
                                if "VTube Studio" in line]
    assert len(got["py"]) == 2 + VOICE_FRAMES
    assert got["py"] == got["cpp"]
    assert got["py stderr"] == got["cpp stderr"]


def test_a_sender_re_sends_every_half_second(standins, tmp_path):
    from koma._vts import VtsSender
    standin = standins("sender", "--valid-token", "t")
    (tmp_path / "token").write_text("t")
    sender = VtsSender(standin.url, str(tmp_path / "token"), mouth_range=(0.0, 2.0))

    class Frame:
        grid_frame, mouth_level, eye_level = 5, 1.0, 0.5
    sender.start()
    sender.send(Frame())
    time.sleep(1.25)
    assert sender.close() is None
    standin.stop()
    entries = [json.loads(line) for line in open(standin.log)]
    injects = [e for e in entries if "request" in e][1:]
    assert [e["request"]["requestID"] for e in injects] == \
        ["koma-frame-5", "koma-resend-1", "koma-resend-2"]
    values = [{"id": "MouthOpen", "value": 0.5}, {"id": "EyeOpenLeft", "value": 0.5},
              {"id": "EyeOpenRight", "value": 0.5}]
    assert all(e["request"]["data"] == {"faceFound": False, "mode": "set",
                                        "parameterValues": values} for e in injects)
    gaps = [b["t"] - a["t"] for a, b in zip(injects, injects[1:])]
    assert all(0.45 <= g <= 0.7 for g in gaps), gaps
