"""The Python side of LipBlink from a live voice (issue 44): Client.live (the LiveLipBlink
bidirectional stream), koma.AudioFile / koma.Microphone, and `python3 -m koma live` with
--json, --record (a motion3.json the C++ `koma` reads back) and --vmc (OSC bundles received by
a python3-liblo server on loopback), against the real koma_server. Real-time runs are short
(at most 1 s of audio each)."""
import array
import json
import math
import os
import signal
import socket
import struct
import subprocess
import sys
import time
import wave

import pytest

import koma
from conftest import Server, run_cli, run_python_cli, source_path
from koma._live import JSON_FIELDS

FPS = 24
VOICE = source_path("samples", "voice.flac")
VOICE_SAMPLES, VOICE_RATE = 61191, 16000  # soxi samples/voice.flac
VOICE_FRAMES = math.ceil(VOICE_SAMPLES * FPS / VOICE_RATE)  # 92 grid frames


def decided(frames):
    """The frames' JSON lines without the client's own clock (wall_late_ms, wall_s)."""
    return [{k: v for k, v in (f if isinstance(f, dict) else f.to_dict()).items()
             if not k.startswith("wall_")} for f in frames]


def runs(flags):
    """[begin, end) runs of True."""
    out, begin = [], None
    for i, flag in enumerate(list(flags) + [False]):
        if flag and begin is None:
            begin = i
        elif not flag and begin is not None:
            out.append((begin, i))
            begin = None
    return out


def cut(intervals, first):
    return [(max(b, first), e) for b, e in intervals if e > first]


def live_cli(server, *flags, env=None):
    if env is None:
        return run_python_cli("live", "--server", server.address, *flags)
    return subprocess.run([sys.executable, "-m", "koma", "live", "--server", server.address,
                           *flags], capture_output=True, text=True, timeout=120, env=env)


@pytest.fixture(scope="module")
def voice_frames(client):
    return list(client.live_file(VOICE, speed=0, lookahead=3))


def test_frames_from_0_one_per_grid_frame_and_the_offline_speech(client, voice_frames):
    frames = voice_frames
    assert [f.grid_frame for f in frames] == list(range(VOICE_FRAMES))
    for f in frames:
        assert f.time_s == pytest.approx(f.grid_frame / FPS)
        assert f.mouth in ("closed", "half", "open") and f.eyes in ("open", "half", "closed")
        assert f.late_ms <= 3 * 1000 / FPS + 1e-6
        assert (f.mouth == "closed") or f.speech
    # The acceptance: streamed and offline agree, after the first second, within one
    # grid frame at lookahead 3.
    offline = client.lip_blink(audio=VOICE).voice
    assert offline["frame_fps"] == FPS
    live = cut(runs(f.speech for f in frames), FPS)
    want = cut(offline["speech"], FPS)
    assert live and len(live) == len(want), (live, want)
    for (a, b), (c, d) in zip(live, want):
        assert abs(a - c) <= 1 and abs(b - d) <= 1, (live, want)


def _voice_s16():
    return subprocess.run(["sox", VOICE, "-t", "raw", "-e", "signed-integer", "-b", "16", "-L",
                           "-"], capture_output=True, check=True).stdout


def test_the_generator_api_any_chunks_and_f32le(client, voice_frames):
    raw = _voice_s16()
    chunks = [raw[i:i + 2 * 333] for i in range(0, len(raw), 2 * 333)]  # odd sizes, whole samples
    s16 = decided(client.live(iter(chunks), VOICE_RATE, 1, lookahead=3))
    assert s16 == decided(voice_frames)
    samples = array.array("h", raw)
    floats = array.array("f", (s / 32768.0 for s in samples)).tobytes()
    f32 = list(client.live([floats[:4000], floats[4000:]], VOICE_RATE, 1, "f32le", lookahead=3))
    assert [f.speech for f in f32] == [f.speech for f in voice_frames]


def test_stopping_early_cancels_the_stream(client):
    frames = client.live_file(VOICE, speed=0)
    first = [next(frames) for _ in range(3)]
    frames.close()
    assert [f.grid_frame for f in first] == [0, 1, 2]
    assert len(list(client.live_file(VOICE, speed=0, seconds=1))) == FPS


def test_a_file_plays_at_real_time(client):
    start = time.monotonic()
    seen = []
    for frame in client.live_file(VOICE, seconds=1.0, lookahead=0):
        seen.append((time.monotonic() - start, frame.grid_frame))
    elapsed = time.monotonic() - start
    assert [g for _, g in seen] == list(range(FPS))
    assert 0.95 <= elapsed < 2.5, elapsed
    # Frame g is decided once its audio has come: not before its end (with lookahead 0).
    for at, g in seen:
        assert at >= (g + 1) / FPS - 0.02, (g, at)


def test_cli_json_lines(server, client):
    done = live_cli(server, "--input", VOICE, "--json", "--speed", "0")
    assert done.returncode == 0, done.stderr
    lines = [json.loads(line) for line in done.stdout.splitlines()]
    assert [line["grid_frame"] for line in lines] == list(range(VOICE_FRAMES))
    assert all(tuple(line) == JSON_FIELDS for line in lines)
    assert decided(lines) == decided(client.live_file(VOICE, speed=0))  # lookahead 2
    assert all(0 <= line["wall_late_ms"] < 10000 and line["wall_s"] >= 0 for line in lines)
    assert "\n    1.0 s  speech " in done.stderr  # the human lines: stderr
    assert f"koma live: {VOICE_FRAMES} frames (3.83 s at 24 fps)" in done.stderr
    quiet = live_cli(server, "--input", VOICE, "--speed", "0", "-q")
    assert quiet.returncode == 0 and quiet.stdout == "" and quiet.stderr == ""


def test_cli_record_is_a_motion3_koma_reads_back(server, tmp_path):
    out = tmp_path / "take.motion3.json"
    done = live_cli(server, "--input", VOICE, "--json", "--speed", "0", "--record", str(out),
                    "--auto-blink", "1", "--seed", "7")
    assert done.returncode == 0, done.stderr
    lines = [json.loads(line) for line in done.stdout.splitlines()]
    motion = json.loads(out.read_text())
    meta = motion["Meta"]
    assert motion["Version"] == 3 and meta["Fps"] == FPS and meta["Loop"] is False
    assert meta["Duration"] == pytest.approx(len(lines) / FPS)
    curves = {c["Id"]: c for c in motion["Curves"]}
    assert list(curves) == ["ParamMouthOpenY", "ParamEyeLOpen", "ParamEyeROpen"]
    segments = sum((len(c["Segments"]) - 2) // 3 for c in motion["Curves"])
    assert (meta["CurveCount"], meta["TotalSegmentCount"], meta["TotalPointCount"]) == \
        (3, segments, 3 + segments)
    blinked = False
    for curve_id, field in (("ParamMouthOpenY", "mouth_level"), ("ParamEyeLOpen", "eye_level"),
                            ("ParamEyeROpen", "eye_level")):
        c = curves[curve_id]
        assert c["Target"] == "Parameter"
        s = c["Segments"]
        assert (len(s) - 2) % 3 == 0 and all(t == 2 for t in s[2::3])  # stepped throughout
        points = [(s[0], s[1])] + [(s[k + 1], s[k + 2]) for k in range(2, len(s), 3)]
        assert points[-1][0] == pytest.approx(len(lines) / FPS)
        # The stepped value at each grid frame is the frame's level.
        for line in lines:
            g = line["grid_frame"]
            value = [v for t, v in points if t <= g / FPS + 1e-9][-1]
            assert value == pytest.approx(line[field]), (curve_id, g)
        blinked |= any(v < 1 for _, v in points) and field == "eye_level"
    assert blinked and any(line["mouth_level"] > 0 for line in lines)
    # The C++ CLI reads it back: retimed, and through LipBlink (one more frame: the end point).
    run_cli("curves", str(out), "-o", str(tmp_path / "curves.motion3.json"),
            "--server", server.address)
    summary = json.loads(run_cli("lipblink", str(out), "-o", str(tmp_path / "lb.motion3.json"),
                                 "--json", "--server", server.address).stdout)
    assert {m["id"] for m in summary["mouths"]} == {"ParamMouthOpenY"}
    assert {e["id"] for e in summary["eyes"]} == {"ParamEyeLOpen", "ParamEyeROpen"}
    assert json.loads((tmp_path / "lb.motion3.json").read_text())["Meta"]["Fps"] == FPS


def test_cli_vmc_bundles_per_frame(server):
    liblo = pytest.importorskip("liblo", reason="python3-liblo (scripts/install-deps.sh)")
    received = []
    receiver = liblo.ServerThread(proto=liblo.UDP)
    receiver.add_method(None, None, lambda path, args, types: received.append(
        (path, types, tuple(args))))
    receiver.start()
    try:
        # The mouth's levels 0, 1, 2: sent as 0, 0.5, 1 (the setup's range mapped to 0..1).
        done = live_cli(server, "--input", VOICE, "--json", "--speed", "0", "--auto-blink", "1",
                        "--mouth-max", "2", "--vmc", f"127.0.0.1:{receiver.port}")
        assert done.returncode == 0, done.stderr
        deadline = time.monotonic() + 5
        lines = [json.loads(line) for line in done.stdout.splitlines()]
        while len(received) < 3 * len(lines) and time.monotonic() < deadline:
            time.sleep(0.01)
    finally:
        receiver.stop()
        receiver.free()
    assert len(lines) == VOICE_FRAMES and len(received) == 3 * len(lines)
    for k, line in enumerate(lines):
        a, blink, apply = received[3 * k:3 * k + 3]
        assert a[:2] == ("/VMC/Ext/Blend/Val", "sf") and a[2][0] == "A"
        assert blink[:2] == ("/VMC/Ext/Blend/Val", "sf") and blink[2][0] == "Blink"
        assert apply == ("/VMC/Ext/Blend/Apply", "", ())
        assert a[2][1] == pytest.approx(line["mouth_level"] / 2, abs=1e-6)
        assert blink[2][1] == pytest.approx(1 - line["eye_level"], abs=1e-6)
    assert any(r[2][1] > 0 for r in received[1::3])  # the auto-blinks were sent
    assert {r[2][1] for r in received[0::3]} == {0.0, 0.5, 1.0}


def test_a_vmc_bundle_byte_for_byte():
    pytest.importorskip("liblo", reason="python3-liblo (scripts/install-deps.sh)")
    from koma._vmc import VmcSender, levels
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as receiver:
        receiver.bind(("127.0.0.1", 0))
        receiver.settimeout(5)
        mouth, eyes = levels(mouth_max=2)
        sender = VmcSender("127.0.0.1", receiver.getsockname()[1], mouth_range=mouth,
                           eye_range=eyes, mouth_clip="aa", blink_clip="blink")

        class Frame:
            mouth_level, eye_level = 1.0, 0.5  # half open: 0.5 of 0..2; half shut
        sender.send(Frame())
        data = receiver.recv(2048)

    def message(address, *args):
        def padded(b):
            return b + b"\0" * (4 - len(b) % 4)
        tags = "," + "".join("s" if isinstance(a, str) else "f" for a in args)
        body = padded(address.encode()) + padded(tags.encode())
        for a in args:
            body += padded(a.encode()) if isinstance(a, str) else struct.pack(">f", a)
        return struct.pack(">i", len(body)) + body
    assert data == (b"#bundle\0" + struct.pack(">II", 0, 1)  # time tag: immediately
                    + message("/VMC/Ext/Blend/Val", "aa", 0.5)
                    + message("/VMC/Ext/Blend/Val", "blink", 0.5)
                    + message("/VMC/Ext/Blend/Apply"))


def test_cli_vmc_without_liblo_names_the_package(server, tmp_path):
    (tmp_path / "liblo.py").write_text("raise ImportError('hidden by the test')\n")
    env = dict(os.environ, PYTHONPATH=f"{tmp_path}{os.pathsep}{os.environ.get('PYTHONPATH', '')}")
    done = live_cli(server, "--input", VOICE, "--vmc", env=env)
    assert done.returncode == 1 and "python3-liblo" in done.stderr, done.stderr


def test_cli_microphone_through_arecord_null_device(server):
    start = time.monotonic()
    done = live_cli(server, "--device", "null", "--seconds", "0.5", "--json")
    assert done.returncode == 0, done.stderr
    lines = [json.loads(line) for line in done.stdout.splitlines()]
    assert [line["grid_frame"] for line in lines] == list(range(12))
    assert time.monotonic() - start >= 0.5  # paced at real time, though null gives at once


def test_missing_tools_are_named(server, tmp_path):
    env = dict(os.environ, PATH=str(tmp_path))  # neither sox nor arecord
    done = live_cli(server, "--input", VOICE, env=env)
    assert done.returncode == 1 and "sox" in done.stderr and "not on PATH" in done.stderr, \
        done.stderr
    done = live_cli(server, "--seconds", "1", env=env)
    assert done.returncode == 1 and "alsa-utils" in done.stderr, done.stderr
    done = live_cli(server, "--speed", "2")
    assert done.returncode == 2 and "--speed: only with --input" in done.stderr
    done = live_cli(server, "--device", "no-such-device", "--seconds", "1")
    assert done.returncode == 1 and "koma: --device no-such-device: arecord -D no-such-device: " \
        "exited with status 1: " in done.stderr and "arecord -L" in done.stderr, done.stderr
    done = live_cli(server, "--input", "no-such.wav")
    assert done.returncode == 1
    assert done.stderr == "koma: --input no-such.wav: cannot read no-such.wav: No such file or " \
        "directory\n"
    done = live_cli(server, "--input", VOICE, "--device", "null")
    assert done.returncode == 2 and "give one audio source" in done.stderr


def _voice_wav24(wav):
    """The FLAC's samples as a 24-bit stereo WAV: each sample in both channels, a zero byte
    below it."""
    raw = _voice_s16()
    frames = bytearray(len(raw) * 3)
    for channel in (0, 3):
        frames[channel + 1::6] = raw[0::2]
        frames[channel + 2::6] = raw[1::2]
    with wave.open(str(wav), "wb") as w:
        w.setnchannels(2)
        w.setsampwidth(3)
        w.setframerate(VOICE_RATE)
        w.writeframes(bytes(frames))
    return wav


def test_wav_files_through_the_wave_module(client, tmp_path):
    # Read without sox: the same frames.
    wav = _voice_wav24(tmp_path / "voice24.wav")
    source = koma.AudioFile(wav)
    assert (source.sample_rate, source.channels, source.sample_format) == \
        (VOICE_RATE, 2, "f32le")  # as koma live: 16-bit PCM as S16LE, the rest as F32LE
    source.close()
    assert decided(client.live_file(wav, speed=0)) == decided(client.live_file(VOICE, speed=0))


@pytest.fixture(scope="module")
def eight_channel_server(tmp_path_factory):
    s = Server(str(tmp_path_factory.mktemp("live8")), "--max_audio_channels=8")
    yield s
    s.stop()


def _error(client, chunks, *args, **kwargs):
    with pytest.raises(koma.KomaError) as caught:
        list(client.live(chunks, *args, **kwargs))
    return caught.value


def test_errors_name_the_field(client, eight_channel_server):
    e = _error(client, [b"\0\0"], 0, 1)
    assert e.code.name == "INVALID_ARGUMENT" and e.field == "setup.sample_rate"
    assert e.message == "setup.sample_rate: 0 must be in [1000, 384000] samples per second"
    with koma.Client(eight_channel_server.address) as eight:
        e = _error(eight, [b"\0" * 18], 16000, 9)
    assert e.code.name == "INVALID_ARGUMENT" and e.field == "setup.channels"
    assert e.message == "setup.channels: 9 exceeds the server limit --max_audio_channels=8"
    e = _error(client, [b"\0" * 640, b"\0" * 3], 16000, 1)
    assert e.code.name == "INVALID_ARGUMENT"
    assert e.message == ("audio (message 2): 3 bytes is not a whole number of sample frames "
                         "(1 channel x 2 bytes = 2 bytes each)")
    e = _error(client, [], 16000, 1, lookahead=4)
    assert e.field == "setup.lookahead_frames"
    with pytest.raises(ValueError, match="sample_format"):
        client.live([], 16000, 1, "s24le")
    with pytest.raises(TypeError, match="unknown option 'mouth.idz'"):
        client.live([], 16000, 1, mouth={"idz": ["ParamMouthOpenY"]})


def test_chunks_must_be_bytes(client):
    with pytest.raises(TypeError, match="iterable of byte chunks"):
        client.live(b"\0" * 640, 16000, 1)
    with pytest.raises(TypeError, match="chunks of bytes, got int"):
        list(client.live([b"\0" * 640, 7], 16000, 1))


def test_ctrl_c_ends_the_audio_and_keeps_the_take(server, tmp_path):
    record = tmp_path / "take.motion3.json"
    process = subprocess.Popen(
        [sys.executable, "-m", "koma", "live", "--server", server.address, "--device", "null",
         "--json", "--record", str(record)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        lines = [json.loads(process.stdout.readline()) for _ in range(5)]
        process.send_signal(signal.SIGINT)
        rest, err = process.communicate(timeout=20)
    finally:
        if process.poll() is None:
            process.kill()
    assert process.returncode == 0, err
    lines += [json.loads(line) for line in rest.splitlines()]
    assert [line["grid_frame"] for line in lines] == list(range(len(lines)))
    assert f"koma live: {len(lines)} frames" in err
    assert json.loads(record.read_text())["Meta"]["Duration"] == pytest.approx(len(lines) / FPS)


def test_the_audio_waits_when_4_s_ahead_of_the_frames_read(client):
    taken = []

    def silence():  # 30 s of 10 ms chunks, as fast as they are taken
        for k in range(3000):
            taken.append(k)
            yield b"\0" * 320

    frames = client.live(silence(), 16000, 1)
    assert next(frames).grid_frame == 0
    time.sleep(1.0)  # not reading: the chunks stop about 4 s of audio ahead
    assert 400 <= len(taken) <= 420, len(taken)  # 4 s + one grid frame = 405
    assert len(list(frames)) == 30 * FPS - 1  # then all of it, once read
    assert len(taken) == 3000


def test_the_audio_iterators_error_is_raised(client):
    def chunks():
        yield b"\0" * 640
        raise RuntimeError("the microphone fell off")
    with pytest.raises(RuntimeError, match="fell off"):
        list(client.live(chunks(), 16000, 1))


def test_cli_server_error(server):
    done = live_cli(server, "--input", VOICE, "--speed", "0", "--timing-fps", "2000")
    assert done.returncode == 1
    assert done.stderr.startswith("koma: INVALID_ARGUMENT: setup.timing_fps: 2000 must be in"), \
        done.stderr


def test_the_same_as_the_cpp_koma_live(server, tmp_path):
    if run_cli("live", "--help", check=False).returncode != 0:
        pytest.skip("this build's koma has no `live` subcommand")
    flags = ["--input", VOICE, "--speed", "0", "--json", "--seed", "7", "--auto-blink", "1",
             "--lookahead", "1", "--mouth-max", "2", "--server", server.address]
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as cpp_vmc, \
            socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as py_vmc:
        for receiver in (cpp_vmc, py_vmc):
            receiver.bind(("127.0.0.1", 0))
            receiver.settimeout(5)
        cpp = run_cli("live", *flags, "--record", str(tmp_path / "cpp.motion3.json"), "--vmc",
                      f"127.0.0.1:{cpp_vmc.getsockname()[1]}")
        py = run_python_cli("live", *flags, "--record", str(tmp_path / "py.motion3.json"),
                            "--vmc", f"127.0.0.1:{py_vmc.getsockname()[1]}")
        assert py.returncode == 0, py.stderr
        # The VMC bundles byte for byte (the kernel keeps the 92 datagrams until read).
        for _ in range(VOICE_FRAMES):
            assert py_vmc.recv(2048) == cpp_vmc.recv(2048)
    # The --record files byte for byte; the JSON lines but for the client's own clock.
    assert (tmp_path / "py.motion3.json").read_bytes() == \
        (tmp_path / "cpp.motion3.json").read_bytes()
    def strip(text):
        return [line.split(',"wall_late_ms"')[0] for line in text.splitlines()]
    assert strip(py.stdout) == strip(cpp.stdout) and len(strip(py.stdout)) == VOICE_FRAMES
    # The human lines (after the first, which describes the file) but for the times measured.
    def words(text):
        return [line.split(";")[0] for line in text.splitlines()[1:]]
    assert words(py.stderr) == words(cpp.stderr)
    assert py.stderr.startswith(f"koma live: {VOICE}: FLAC, decoded by sox, 16000 Hz, "
                                f"1 channel, S16LE -> {server.address}\n")
    # A 24-bit stereo WAV goes as F32LE from both.
    wav = str(_voice_wav24(tmp_path / "voice24.wav"))
    flags = ["--input", wav, "--speed", "0", "--json", "--server", server.address]
    cpp, py = run_cli("live", *flags), run_python_cli("live", *flags)
    assert py.returncode == 0, py.stderr
    assert strip(py.stdout) == strip(cpp.stdout) and len(strip(py.stdout)) == VOICE_FRAMES
    assert "2 channels, F32LE" in py.stderr.splitlines()[0]
    assert "2 channels, F32LE" in cpp.stderr.splitlines()[0]


def test_wav_sample_widths_as_16_bit_or_float():
    from koma._live_sources import _to_f32, _to_s16
    assert array.array("f", _to_f32(bytes([0, 0, 0x80, 0xFF, 0xFF, 0x7F, 0, 0, 0x40]), 3)) \
        .tolist() == [-1.0, 1 - 2 ** -23, 0.5]
    assert array.array("f", _to_f32(bytes([0, 0, 0, 0xC0]), 4)).tolist() == [-0.5]
    assert _to_s16(bytes([0x00, 0x80, 0xFF]), 1) == bytes([0, 0x80, 0, 0x00, 0, 0x7F])
    assert _to_s16(bytes([0x11, 0x22, 0x34, 0x12, 0xFF, 0xFF, 0x00, 0x80]), 4) == \
        bytes([0x34, 0x12, 0x00, 0x80])


def test_a_float_wav_needs_sox(server, client, tmp_path):
    wav = tmp_path / "float.wav"
    subprocess.run(["sox", VOICE, "-e", "floating-point", "-b", "32", str(wav)], check=True)
    assert decided(client.live_file(wav, speed=0)) == decided(client.live_file(VOICE, speed=0))
    done = live_cli(server, "--input", str(wav), env=dict(os.environ, PATH=str(tmp_path)))
    assert done.returncode == 1 and "not a WAV file Python's wave module reads" in done.stderr \
        and "install the Debian package sox" in done.stderr, done.stderr


def test_cli_deadline(server):
    done = live_cli(server, "--input", VOICE, "--json", "--deadline", "0.5")  # real time
    assert done.returncode == 1 and "koma: DEADLINE_EXCEEDED: " in done.stderr, done.stderr
    lines = [json.loads(line) for line in done.stdout.splitlines()]
    assert len(lines) <= 12 and [line["grid_frame"] for line in lines] == \
        list(range(len(lines)))
    assert live_cli(server, "--input", VOICE, "--speed", "0", "-q", "--deadline", "0") \
        .returncode == 0  # 0: none, as koma live
