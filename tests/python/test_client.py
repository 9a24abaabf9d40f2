"""koma.Client against the real koma_server: inputs (path, text, bytes, Positions), results,
options checked before sending, server-side checks as KomaError, deadlines, connection
errors, TLS and the server's file size limit."""
import math
import os
import pathlib
import subprocess
import sys

import grpc
import pytest

import koma
from conftest import Server, run_cli, source_path

PITCH = source_path("samples", "pitch.bvh")


def test_health(client):
    assert client.health() == "SERVING"
    assert client.health("koma.v1.Retime") == "SERVING"


def test_path_text_bytes_and_pathlike_give_the_same_answer(client):
    by_path = client.retime_skeletal(PITCH)
    text = pathlib.Path(PITCH).read_text()
    assert client.retime_skeletal(text).output_bytes == by_path.output_bytes
    assert client.retime_skeletal(text.encode()).output_bytes == by_path.output_bytes
    assert client.retime_skeletal(pathlib.Path(PITCH)).output_bytes == by_path.output_bytes
    assert by_path.counts["frames"] == 130
    assert by_path.counts["omissions_applied"] == 5  # the README's figures
    assert by_path.counts["holds_applied"] == 459
    assert by_path.deleted_frames == [75, 76, 77, 78, 79]
    assert by_path.kinds[0] == "ORIGINAL" and set(by_path.kinds) <= {"ORIGINAL", "DUPLICATE",
                                                                     "HELD"}


def test_missing_path_is_an_os_error(client, tmp_path):
    with pytest.raises(FileNotFoundError):
        client.retime_skeletal(str(tmp_path / "missing.bvh"))


def test_write_writes_the_output_and_refuses_without_one(client, tmp_path):
    result = client.retime_skeletal(PITCH)
    result.write(tmp_path / "out.bvh")
    assert (tmp_path / "out.bvh").read_bytes() == result.output_bytes
    timing_only = client.retime_skeletal(PITCH, return_motion=False)
    assert timing_only.output is None and timing_only.source_frames == result.source_frames
    with pytest.raises(ValueError):
        timing_only.write(tmp_path / "none.bvh")


def test_positions_form_returns_positions_copied_by_the_timing_map(client):
    # Two joints; the child swings slow-fast-slow around the root over 48 frames at 24 fps.
    frames = []
    for f in range(48):
        s = f / 47
        angle = math.radians(120 * s * s * (3 - 2 * s))
        frames.append([(0.0, 0.0, 0.0), (10 * math.cos(angle), 10 * math.sin(angle), 0.0)])
    clip = koma.Positions(["Root", "Arm"], [-1, 0], 1 / 24, frames)
    result = client.retime_skeletal(clip, omissions=3, timing_fps=0)
    assert result.output is None
    assert len(result.source_frames) == 48
    assert result.counts["omissions_applied"] == 3
    assert all(20 <= f <= 27 for f in result.deleted_frames), result.deleted_frames
    values = result.response.motion.positions.values
    flat = clip.values
    for t, source in enumerate(result.source_frames):
        assert list(values[6 * t:6 * t + 6]) == flat[6 * source:6 * source + 6]


def test_positions_checks_its_shape():
    with pytest.raises(ValueError):
        koma.Positions(["a", "b"], [-1], 0.04, [0.0] * 12)
    with pytest.raises(ValueError):
        koma.Positions(["a"], [-1], 0.04, [0.0] * 7)


def test_a_utf8_byte_order_mark_is_skipped_and_utf16_is_named(client):
    # Windows tools start UTF-8 files with EF BB BF; the server skips it in every text format.
    bvh = pathlib.Path(PITCH).read_bytes()
    by_path = client.retime_skeletal(PITCH)
    assert client.retime_skeletal(b"\xef\xbb\xbf" + bvh).output_bytes == by_path.output_bytes
    motion = pathlib.Path(source_path("samples", "talk_blink.motion3.json")).read_bytes()
    assert (client.lip_blink(b"\xef\xbb\xbf" + motion).output_bytes ==
            client.lip_blink(motion).output_bytes)
    with pytest.raises(koma.KomaError, match=r"bvh_text: the file is UTF-16 \(little-endian"):
        client.retime_skeletal(bvh.decode("ascii").encode("utf-16"))


def test_counts_say_what_became_of_the_duplicates(client):
    result = client.retime_skeletal(PITCH)
    counts = result.counts
    assert counts["duplicates_applied"] == (result.kinds.count("DUPLICATE") +
                                            counts["duplicates_omitted"] +
                                            counts["duplicates_held"])


def test_curves_and_lip_blink_results(client):
    curves = client.retime_curves(source_path("samples", "arm_head.motion3.json"))
    assert curves.key_frames == [0, 9, 18, 27, 36, 45, 54, 63, 72, 81, 90]  # README's figures
    assert curves.timing_fps == 24
    assert curves.counts == {"curves": 5, "frames": 91, "key_poses": 11, "drawings": 21}
    assert set(curves.curves) == {"ParamAngleX", "ParamAngleY", "ParamBodyAngleX", "ParamArmLA",
                                  "ParamArmRA"}
    lip = client.lip_blink(source_path("samples", "talk_blink.motion3.json"))
    assert lip.seed == 0x6b6f6d61
    assert [m["id"] for m in lip.mouths] == ["ParamMouthOpenY"]
    assert lip.counts["blinks"] == 4 and lip.counts["mouth_holds"] == 22
    assert set(lip.timing) == {"ParamMouthOpenY", "ParamEyeLOpen", "ParamEyeROpen"}


def test_curves_timing_groups_and_merged_key_poses(client):
    sample = source_path("samples", "arm_head.motion3.json")
    grouped = client.retime_curves(sample, timing_groups=[
        {"name": "arms", "ids": ["ParamArm*"], "frames_per_drawing": 2}])
    assert list(grouped.groups) == ["body", "arms"]
    assert grouped.groups["arms"]["curves"] == ["ParamArmLA", "ParamArmRA"]
    assert grouped.groups["body"]["curves"] == ["ParamAngleX", "ParamAngleY", "ParamBodyAngleX"]
    arms = grouped.groups["arms"]
    assert arms["frames_per_drawing"] == 2
    assert grouped.timings[arms["timing"]]["frames_per_drawing"] == 2
    assert grouped.curves["ParamArmLA"]["timing"] == arms["timing"]
    assert grouped.key_frames == grouped.groups["body"]["key_frames"]
    assert len(grouped.key_frames_merged) == len(grouped.key_frames)
    # One group, every keyframe time a key pose: no groups listed, nothing merged.
    one = client.retime_curves(sample, default_timing_groups=False, merge_key_poses=False)
    assert one.groups == {} and one.key_frames_merged == []
    with pytest.raises(koma.KomaError, match=r"timing_groups\[0\]\.name: required") as error:
        client.retime_curves(sample, timing_groups=[{"ids": ["ParamArm*"]}])
    assert error.value.field == "timing_groups[0].name"


def test_curves_group_modes(client, server, tmp_path):
    """Group modes: the default face group is LipBlink's (its mouth and eyes exactly `koma
    lipblink`'s), a GROUP_KEEP group comes back as it came in, and the file is byte for byte
    what `koma curves` writes with the same groups."""
    sample = source_path("samples", "talk_blink.motion3.json")
    anime = client.retime_curves(sample)
    lip = client.lip_blink(sample)
    for curve_id in ("ParamMouthOpenY", "ParamEyeLOpen", "ParamEyeROpen"):
        assert anime.curves[curve_id]["values"] == lip.curves[curve_id], curve_id
        assert anime.curves[curve_id]["holds"] == {}
    assert len(set(anime.curves["ParamEyeLOpen"]["values"])) == 3
    kept = client.retime_curves(sample, timing_groups=[
        {"name": "eyes", "ids": ["ParamEye*"], "mode": "GROUP_KEEP"},
        {"name": "mouth", "ids": ["ParamMouth*"], "mode": "GROUP_LIP_BLINK",
         "mouth": {"mode": "MOUTH_FOLLOW"}, "seed": 5}])
    assert kept.groups["eyes"]["timing"] == -1 and kept.groups["eyes"]["key_frames"] == []
    assert kept.curves["ParamEyeLOpen"]["timing"] == -1
    follow = client.lip_blink(sample, mouth={"mode": "MOUTH_FOLLOW", "ids": ["ParamMouthOpenY"]},
                              eyes={"ids": []}, seed=5)
    assert kept.curves["ParamMouthOpenY"]["values"] == follow.curves["ParamMouthOpenY"]
    out = tmp_path / "kept.motion3.json"
    run_cli("curves", sample, "-o", str(out), "--server", server.address, "--group",
            "eyes=ParamEye*:mode=keep", "--group",
            "mouth=ParamMouth*:mode=lipblink,mouth-mode=follow,seed=5")
    assert kept.output_bytes == out.read_bytes()
    with pytest.raises(koma.KomaError, match=r"timing_groups\[0\]: mouth, eyes and seed are for"):
        client.retime_curves(sample, timing_groups=[
            {"name": "eyes", "ids": ["ParamEye*"], "mode": "GROUP_KEEP", "seed": 3}])


@pytest.mark.parametrize("call,options,error,words", [
    ("retime_skeletal", {"omisions": 3}, TypeError, "unknown option 'omisions'"),
    ("retime_skeletal", {"motion": {}}, TypeError, "unknown option 'motion'"),
    ("retime_skeletal", {"omissions": "3"}, TypeError, "omissions: expected an integer"),
    ("retime_skeletal", {"omissions": 2.5}, TypeError, "omissions: expected an integer"),
    ("retime_skeletal", {"keep_length": 1}, TypeError, "keep_length: expected True or False"),
    ("retime_skeletal", {"max_hold": True}, TypeError, "max_hold: expected an integer"),
    ("retime_skeletal", {"order": "BACKWARDS"}, ValueError, "order: 'BACKWARDS' is not one of"),
    ("retime_skeletal", {"timing_fps": "24"}, TypeError, "timing_fps: expected a number"),
    ("retime_skeletal", {"holds": 1 << 40}, ValueError, "holds: 1099511627776 does not fit"),
    ("retime_skeletal", {"joint_weights": 1.0}, TypeError, "joint_weights: expected a list"),
    ("retime_curves", {"mouth": {}}, TypeError, "unknown option 'mouth'"),
    ("retime_curves", {"curve_overrides": [{"curve": "x"}]}, TypeError,
     "unknown option 'curve_overrides[0].curve'"),
    ("lip_blink", {"mouth": {"mode": "LOUD"}}, ValueError, "mouth.mode: 'LOUD' is not one of"),
    ("lip_blink", {"eyes": {"auto_blink": {"hold": "2"}}}, TypeError,
     "eyes.auto_blink.hold: expected an integer"),
    ("lip_blink", {"mouth": {"speech": [(1, 2, 3)]}}, ValueError, "mouth.speech[0]: expected"),
])
def test_bad_options_raise_before_sending(call, options, error, words):
    # A client whose server does not exist: nothing may be sent.
    dead = koma.Client("127.0.0.1:1", timeout=5)
    source = PITCH if call == "retime_skeletal" else source_path("samples",
                                                                  "talk_blink.motion3.json")
    with pytest.raises(error) as caught:
        getattr(dead, call)(source, **options)
    assert words in str(caught.value)


@pytest.mark.parametrize("call,options,field", [
    ("retime_skeletal", {"omissions": -1}, "omissions"),
    ("retime_skeletal", {"max_hold": 0}, "max_hold"),
    ("retime_skeletal", {"timing_fps": float("nan")}, "timing_fps"),
    ("retime_skeletal", {"joint_weights": [1.0, 2.0]}, "joint_weights"),
    ("retime_curves", {"frames_per_drawing": 0}, "frames_per_drawing"),
    ("retime_curves", {"tame": 0.5}, "tame"),
    ("lip_blink", {"mouth": {"mid_ratio": 1.5}}, "mouth.mid_ratio"),
])
def test_values_out_of_range_come_back_as_koma_error_naming_the_field(client, call, options,
                                                                       field):
    source = PITCH if call == "retime_skeletal" else source_path("samples",
                                                                  "talk_blink.motion3.json")
    with pytest.raises(koma.KomaError) as caught:
        getattr(client, call)(source, **options)
    assert caught.value.code == grpc.StatusCode.INVALID_ARGUMENT
    assert caught.value.field == field, caught.value.message


def test_csv_fps_is_sent_and_checked(client):
    csv = source_path("tests", "testdata", "curves_crlf.csv")
    assert client.retime_curves(csv).timing_fps == 24  # 30 fps source: a grid
    assert client.retime_curves(csv, csv_fps=24).timing_fps == 0  # its own rate: no grid
    with pytest.raises(koma.KomaError) as caught:
        client.retime_curves(csv, csv_fps=-1)
    assert caught.value.field == "csv_fps"
    with pytest.raises(ValueError):
        client.retime_curves(source_path("samples", "arm_head.motion3.json"), csv_fps=24)


def test_deadline_exceeded(server):
    # 100k frames x 10 joints (24 MB on the wire): sending, parsing and retiming it takes far
    # longer than the 5 ms deadline, whatever the machine.
    frames = 100_000
    values = [float(i % 997) for i in range(frames * 30)]
    clip = koma.Positions([f"j{j}" for j in range(10)], [-1] + list(range(9)), 1 / 120, values)
    with koma.Client(server.address, timeout=0.005) as hurried:
        with pytest.raises(koma.KomaError) as caught:
            hurried.retime_skeletal(clip)
    assert caught.value.code == grpc.StatusCode.DEADLINE_EXCEEDED


def test_no_server_is_unavailable(tmp_path):
    # A port that was free a moment ago: bind, read, close.
    import socket
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    with koma.Client(f"127.0.0.1:{port}", timeout=5) as lonely:
        with pytest.raises(koma.KomaError) as caught:
            lonely.health()
    assert caught.value.code == grpc.StatusCode.UNAVAILABLE


def test_constructor_checks():
    with pytest.raises(ValueError):
        koma.Client("127.0.0.1:1", timeout=0)
    with pytest.raises(TypeError):
        koma.Client(None)
    with pytest.raises(TypeError):
        koma.Client("127.0.0.1:1", tls=42)


def test_file_size_limit_of_the_server(tmp_path):
    size = os.path.getsize(PITCH)
    limited = Server(str(tmp_path), f"--max_file_bytes={size - 1}")
    try:
        with koma.Client(limited.address, timeout=30) as c:
            with pytest.raises(koma.KomaError) as caught:
                c.retime_skeletal(PITCH)
            assert caught.value.code == grpc.StatusCode.RESOURCE_EXHAUSTED
            assert caught.value.field == "bvh_text"
            assert f"--max_file_bytes={size - 1}" in caught.value.message
            small = source_path("tests", "testdata", "two_joints_crlf.bvh")
            assert c.retime_skeletal(small, timing_fps=0).counts["frames"] == 3
    finally:
        limited.stop()


def _openssl(*args):
    subprocess.run(["openssl", *args], check=True, capture_output=True, timeout=60)


def test_tls(tmp_path):
    ca_key, ca, key, csr, cert = (str(tmp_path / n) for n in
                                  ("ca.key", "ca.pem", "server.key", "server.csr", "server.pem"))
    _openssl("req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", "2", "-subj",
             "/CN=koma-test-ca", "-keyout", ca_key, "-out", ca)
    _openssl("req", "-newkey", "rsa:2048", "-nodes", "-subj", "/CN=localhost", "-keyout", key,
             "-out", csr)
    (tmp_path / "ext").write_text("subjectAltName=IP:127.0.0.1,DNS:localhost\n")
    _openssl("x509", "-req", "-in", csr, "-CA", ca, "-CAkey", ca_key, "-CAcreateserial",
             "-days", "2", "-extfile", str(tmp_path / "ext"), "-out", cert)
    secure = Server(str(tmp_path), f"--tls_cert={cert}", f"--tls_key={key}")
    try:
        with koma.Client(secure.address, timeout=30, tls=ca) as c:
            assert c.health() == "SERVING"
            assert c.retime_skeletal(PITCH).counts["frames"] == 130
        with koma.Client(secure.address, timeout=5) as plain:
            with pytest.raises(koma.KomaError) as caught:
                plain.health()
            assert caught.value.code == grpc.StatusCode.UNAVAILABLE
        with koma.Client(secure.address, timeout=5, tls=True) as untrusting:  # system CAs only
            with pytest.raises(koma.KomaError) as caught:
                untrusting.health()
            assert caught.value.code == grpc.StatusCode.UNAVAILABLE
    finally:
        secure.stop()


def test_mutual_tls(tmp_path):
    pki = {n: str(tmp_path / n) for n in ("ca.key", "ca.pem", "server.key", "server.csr",
                                          "server.pem", "client.key", "client.csr",
                                          "client.pem", "ext")}
    _openssl("req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", "2", "-subj",
             "/CN=koma-test-ca", "-keyout", pki["ca.key"], "-out", pki["ca.pem"])
    (tmp_path / "ext").write_text("subjectAltName=IP:127.0.0.1,DNS:localhost\n")
    for who in ("server", "client"):
        _openssl("req", "-newkey", "rsa:2048", "-nodes", "-subj", f"/CN={who}", "-keyout",
                 pki[f"{who}.key"], "-out", pki[f"{who}.csr"])
        _openssl("x509", "-req", "-in", pki[f"{who}.csr"], "-CA", pki["ca.pem"], "-CAkey",
                 pki["ca.key"], "-CAcreateserial", "-days", "2", "-extfile", pki["ext"],
                 "-out", pki[f"{who}.pem"])
    secure = Server(str(tmp_path), f"--tls_cert={pki['server.pem']}",
                    f"--tls_key={pki['server.key']}", f"--tls_client_ca={pki['ca.pem']}")
    try:
        tls = (pki["ca.pem"], pki["client.pem"], pki["client.key"])
        with koma.Client(secure.address, timeout=30, tls=tls) as c:
            assert c.retime_skeletal(PITCH).counts["frames"] == 130
        with koma.Client(secure.address, timeout=5, tls=pki["ca.pem"]) as no_cert:
            with pytest.raises(koma.KomaError) as caught:
                no_cert.health()
            assert caught.value.code == grpc.StatusCode.UNAVAILABLE
        with pytest.raises(ValueError):
            koma.Client(secure.address, tls=(pki["ca.pem"], pki["client.pem"], None))
    finally:
        secure.stop()


def test_python_m_koma_health(server):
    from conftest import run_python_cli
    done = run_python_cli("health", "--server", server.address)
    assert done.returncode == 0 and done.stdout.strip() == "SERVING", done.stderr
    done = run_python_cli("health", "--server", "127.0.0.1:1", "--deadline", "2")
    assert done.returncode == 1 and done.stderr.startswith("koma: UNAVAILABLE: "), done.stderr


def test_import_path_is_the_built_package():
    # The stubs come from this build's proto/: the file fields exist.
    from koma.v1 import retime_pb2
    assert "bvh_text" in retime_pb2.RetimeSkeletalRequest.DESCRIPTOR.fields_by_name
    assert "csv_fps" in retime_pb2.LipBlinkRequest.DESCRIPTOR.fields_by_name


def test_real_take_cuts_rates_and_presets(client, server, tmp_path):
    """Issue 28 from Python: a T-pose first frame is a cut that comes out as it went in, the
    omission rate scales with the take, a drawing rate of 8 gives a median hold of 3, and
    `python3 -m koma` passes the new flags as the C++ CLI does."""
    from conftest import run_cli, run_python_cli
    sys.path.insert(0, source_path("tests", "e2e"))
    import make_real_takes  # tests/e2e/make_real_takes.py
    make_real_takes.main(source_path("tests", "testdata", "bvh_test1.bvh"), str(tmp_path))
    tpose = client.retime_skeletal(str(tmp_path / "tpose.bvh"))
    assert tpose.cut_frames == [1]
    assert tpose.source_frames[0] == 0 and tpose.source_frames.count(0) == 1
    assert all(d > 1 for d in tpose.deleted_frames)
    long_take = client.retime_skeletal(str(tmp_path / "long.bvh"), omissions_per_second=1.0)
    assert long_take.cut_frames == []
    assert long_take.counts["omissions_requested"] == 40  # 40 s
    threes = client.retime_skeletal(source_path("samples", "pitch.bvh"), drawings_per_second=8.0)
    runs = []
    for t, frame in enumerate(threes.source_frames):
        if t == 0 or frame != threes.source_frames[t - 1]:
            runs.append(0)
        runs[-1] += 1
    runs.sort()
    assert runs[(len(runs) - 1) // 2] == 3 and threes.counts["max_hold"] == 3
    with pytest.raises(koma.KomaError) as error:
        client.retime_skeletal(source_path("samples", "pitch.bvh"), omissions=2,
                               omissions_per_second=1.0)
    assert error.value.code.name == "INVALID_ARGUMENT"
    assert "omissions_per_second" in error.value.message
    out = tmp_path / "threes.bvh"
    done = run_python_cli("skeletal", source_path("samples", "pitch.bvh"), "-o", str(out),
                          "--drawings-per-second", "8", "--server", server.address)
    assert done.returncode == 0, done.stderr
    cli_out = tmp_path / "threes_cli.bvh"
    run_cli("skeletal", source_path("samples", "pitch.bvh"), "-o", str(cli_out), "--preset",
            "threes", "--server", server.address)
    assert out.read_bytes() == cli_out.read_bytes()


def grid_runs(result):
    """Sorted runs of one drawing in a TIMING_RATE answer (one output frame per grid frame)."""
    runs = []
    for t, frame in enumerate(result.source_frames):
        if t == 0 or frame != result.source_frames[t - 1]:
            runs.append(0)
        runs[-1] += 1
    return sorted(runs)


def test_defaults_are_anime_timing_and_presets_match_the_cli(client, server, tmp_path):
    """Issue 41 from Python: with no options a real take (2.5 s to 40 s, 30 and 120 fps) comes
    out on threes with omissions that scale with it; every named preset answers byte for byte
    what `koma skeletal --preset NAME` writes, "paper" the paper's counts."""
    from conftest import run_cli
    sys.path.insert(0, source_path("tests", "e2e"))
    import make_real_takes  # tests/e2e/make_real_takes.py
    make_real_takes.main(source_path("tests", "testdata", "bvh_test1.bvh"), str(tmp_path))
    for name in ("long.bvh", "take_120.bvh", "long_120.bvh"):
        take = client.retime_skeletal(str(tmp_path / name), output_rate="TIMING_RATE",
                                      return_motion=False)
        runs = grid_runs(take)
        seconds = len(take.source_frames) / 24
        assert runs[(len(runs) - 1) // 2] >= 2, (name, runs)
        assert 7.5 <= len(runs) / seconds <= 12.5, (name, len(runs) / seconds)
        assert take.counts["omissions_applied"] >= 0.5 * seconds, (name, take.counts)
        assert take.drawings_per_second == 8 and take.omissions_per_second == 1
    pitch = source_path("samples", "pitch.bvh")
    for preset in ("twos", "threes", "snappy", "subtle", "paper"):
        cli_out = tmp_path / f"{preset}_cli.bvh"
        run_cli("skeletal", pitch, "-o", str(cli_out), "--preset", preset, "--server",
                server.address)
        assert client.retime_skeletal(pitch, preset=preset).output == cli_out.read_text(), preset
    paper = client.retime_skeletal(pitch, preset="paper")
    assert paper.counts["omissions_requested"] == 4 and paper.counts["holds_requested"] == 43
    assert paper.drawings_per_second == 0 and paper.omissions_per_second == 0
    # A BVH with one more row than its Frames: line says: read whole, with the server's warning.
    text = open(pitch).read()
    last_row = text.rstrip("\n").rsplit("\n", 1)[1]
    extra = client.retime_skeletal(text + last_row + "\n")
    assert extra.warnings and "but 131 frames follow" in extra.warnings[0], extra.warnings
    assert extra.warnings[0].startswith("bvh_text: line 260: ") and len(extra.source_frames) == 131
    # Options beside a preset win; a count replaces the preset's omission rate, as on the line.
    snappy = client.retime_skeletal(pitch, preset="snappy", omissions=6)
    assert snappy.counts["omissions_requested"] == 6
    with pytest.raises(ValueError, match="preset: 'fours' is not one of"):
        client.retime_skeletal(pitch, preset="fours")


WAVE = source_path("samples", "wave.glb")


def test_gltf_path_and_bytes_give_the_cli_file(server, client, tmp_path):
    """A glTF file (path or bytes) travels whole; output_bytes is the retimed file, byte for
    byte what `koma skeletal IN.glb -o OUT.glb` writes for the same options."""
    by_path = client.retime_skeletal(WAVE, omissions=5,
                                     gltf_keys="GLTF_KEYS_LINEAR")
    by_bytes = client.retime_skeletal(pathlib.Path(WAVE).read_bytes(), omissions=5,
                                      gltf_keys="GLTF_KEYS_LINEAR")
    assert by_path.output_bytes == by_bytes.output_bytes
    assert by_path.output_bytes.startswith(b"glTF") and by_path.output is None
    assert [a["name"] for a in by_path.animations] == ["Wave"]
    wave = by_path.animations[0]
    assert wave["source_fps"] == 30 and wave["frame_count"] == 61
    assert wave["joints"][:3] == ["Hips", "Spine", "Head"]
    assert wave["keys_written"] == 61 and by_path.counts["omissions_applied"] == 5
    assert wave["source_frames"] == by_path.source_frames
    out = tmp_path / "wave_anime.glb"
    run_cli("skeletal", WAVE, "-o", str(out), "--omit", "5", "--gltf-keys", "linear",
            "--server", server.address)
    assert out.read_bytes() == by_path.output_bytes
    by_path.write(tmp_path / "written.glb")
    assert (tmp_path / "written.glb").read_bytes() == by_path.output_bytes


def test_fbx_path_and_bytes_give_the_cli_file(server, client, tmp_path):
    """An FBX file (path or bytes) travels whole; output_bytes is the retimed file, byte for byte
    what `koma skeletal IN.fbx -o OUT.fbx` writes, .take the take as read; a missing take is
    named."""
    fbx = source_path("samples", "huesitos.fbx")
    by_path = client.retime_skeletal(fbx, preset="twos")
    by_bytes = client.retime_skeletal(pathlib.Path(fbx).read_bytes(), preset="twos")
    assert by_path.output_bytes == by_bytes.output_bytes
    assert by_path.output_bytes.startswith(b"Kaydara FBX Binary")
    assert by_path.take["name"] == "Armature|Action" and by_path.take["source_fps"] == 25
    assert by_path.take["joints"][:2] == ["Armature", "Bone"]
    assert by_path.take["curves_written"] > 0 and by_path.drawings_per_second == 12
    out = tmp_path / "huesitos_anime.fbx"
    run_cli("skeletal", fbx, "-o", str(out), "--preset", "twos", "--server", server.address)
    assert out.read_bytes() == by_path.output_bytes
    with pytest.raises(koma.KomaError) as error:
        client.retime_skeletal(fbx, fbx_take="Run")
    assert 'fbx_take: take "Run": not in the file' in str(error.value)


def test_gltf_options_are_checked_by_the_server(client):
    with pytest.raises(koma.KomaError) as error:
        client.retime_skeletal(WAVE, gltf_animations=["Run"])
    assert error.value.code == grpc.StatusCode.INVALID_ARGUMENT
    assert 'gltf_animations[0]: "Run" is neither' in str(error.value)
    none = client.retime_skeletal(WAVE, gltf_retime_none=True)
    assert none.animations == [] and none.output_bytes.startswith(b"glTF")
