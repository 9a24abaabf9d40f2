"""LipBlink from a voice end to end (issue 30): recordings made here by espeak-ng and sox
(tests/testing/voice_recordings.py: two voices, English and Japanese, known silences of 0.2 to
1.5 s, pink room noise at 20 and 10 dB SNR, 8 to 48 kHz, mono and stereo, WAV int16/int24/
float, FLAC, Ogg Vorbis, Ogg Opus, MP3) through the real koma_server, the C++ CLI, the Python
package and `koma batch`."""
import json
import os
import sys

import pytest

from conftest import run_cli, source_path

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "testing"))
import voice_recordings  # noqa: E402  (tests/testing/voice_recordings.py)

FPS = 24  # the film grid: speech and holds are in its frames


@pytest.fixture(scope="module")
def voices(tmp_path_factory):
    folder = str(tmp_path_factory.mktemp("voices"))
    clean, known, speech_rms = voice_recordings.make_clean(folder)
    noisy20 = voice_recordings.add_noise(folder, clean, speech_rms, 20)
    noisy10 = voice_recordings.add_noise(folder, clean, speech_rms, 10)
    v = voice_recordings.variant
    files = {
        "wav16-22k": noisy20,
        "wav16-8k": v(folder, noisy20, "a8k.wav", rate=8000),
        "wav16-16k": v(folder, noisy20, "a16k.wav", rate=16000),
        "wav24-44k-stereo": v(folder, noisy20, "a44k.wav", rate=44100, channels=2,
                              sox_format=("-b", "24")),
        "float-48k": v(folder, noisy20, "a48k.wav", rate=48000,
                       sox_format=("-e", "floating-point", "-b", "32")),
        "flac": v(folder, noisy20, "a.flac"),
        "ogg-vorbis": v(folder, noisy20, "a.ogg"),
        # sox writes a LAME gapless header with VBR (-C -2), none with its default CBR.
        "mp3-gapless": v(folder, noisy20, "a-vbr.mp3", sox_format=("-C", "-2")),
        "mp3": v(folder, noisy20, "a.mp3"),
        "opus": voice_recordings.opus(folder, noisy20, "a.opus"),
    }
    return {"folder": folder, "known": known, "files": files, "clean": clean,
            "noisy10": noisy10}


def lipblink(server, tmp_path, audio, *flags, out="out.motion3.json"):
    out_path = tmp_path / out
    done = run_cli("lipblink", "--audio", audio, "-o", str(out_path), "--json",
                   "--server", server.address, *flags)
    return json.loads(done.stdout), out_path


def within(found, known, tolerance):
    """Each found [begin, end) grid-frame interval within `tolerance` frames of the known one
    (seconds x 24), one for one."""
    if len(found) != len(known):
        return False
    return all(abs(f["begin"] - k[0] * FPS) <= tolerance and abs(f["end"] - k[1] * FPS) <= tolerance
               for f, k in zip(found, known))


# LAME's encoder delay (576 + 529 samples): sox's CBR MP3 has no gapless header, so it decodes
# this much late (docs/formats.md, "Audio"); with the header libsndfile removes the delay.
MP3_DELAY_S = 1105 / voice_recordings.RATE


def test_speech_matches_the_known_intervals_in_every_encoding(server, voices, tmp_path):
    found = {}
    for name, path in voices["files"].items():
        summary, _ = lipblink(server, tmp_path, path)
        found[name] = summary["voice"]["speech"]
        known = voices["known"]
        if name == "mp3":
            known = [(a + MP3_DELAY_S, b + MP3_DELAY_S) for a, b in known]
        assert within(found[name], known, 1), (name, found[name], known)
    # Every encoding of one recording at 16 kHz or more (rate, channels, sample format; FLAC,
    # Vorbis, Opus, a gapless MP3) gives the same intervals. At 8 kHz the recording loses its
    # band above 4 kHz (a sentence's last /s/), and an MP3 without the gapless header starts
    # late by its delay: the same intervals within a grid frame (after the delay).
    reference = found["wav16-22k"]
    for name, speech in found.items():
        if name in ("mp3", "wav16-8k"):
            shift = MP3_DELAY_S * FPS if name == "mp3" else 0
            assert within(speech, [((r["begin"] + shift) / FPS, (r["end"] + shift) / FPS)
                                   for r in reference], 1), (name, speech, reference)
        else:
            assert speech == reference, (name, speech, reference)


def test_speech_within_two_frames_at_10_db_snr(server, voices, tmp_path):
    summary, _ = lipblink(server, tmp_path, voices["noisy10"])
    assert within(summary["voice"]["speech"], voices["known"], 2), summary["voice"]["speech"]


@pytest.mark.parametrize("mode", ["random", "follow"])
def test_the_mouth_flaps_only_in_speech(server, voices, tmp_path, mode):
    summary, out = lipblink(server, tmp_path, voices["files"]["wav16-22k"], "--mode", mode,
                            out="out.csv")
    holds = summary["mouths"][0]["holds"]
    assert holds
    for a, b in zip(holds, holds[1:]):
        assert 1 <= a["length"] <= 3
        if a["begin"] + a["length"] == b["begin"]:
            assert a["shape"] != b["shape"], (a, b)
    # The written motion (30 fps CSV): closed (0) throughout every silence (0.2 s to 1.5 s),
    # one grid frame in from each end.
    rows = [line.split(",") for line in out.read_text().splitlines()[1:]]
    values = [float(r[1]) for r in rows]
    known = voices["known"]
    silences = [(0.0, known[0][0])] + [(known[i][1], known[i + 1][0])
                                       for i in range(len(known) - 1)]
    silences.append((known[-1][1], len(values) / 30))
    checked = 0
    assert min(end - begin for begin, end in silences) < 0.25
    for begin, end in silences:
        for k, value in enumerate(values):
            t = k / 30
            if begin + 1 / FPS <= t < end - 1 / FPS:
                assert value == 0.0, (mode, t, value)
                checked += 1
    assert checked > 50


def test_same_request_same_bytes(server, voices, tmp_path):
    path = voices["files"]["flac"]
    _, first = lipblink(server, tmp_path, path, "--cues", str(tmp_path / "a.json"),
                        out="a.motion3.json")
    _, second = lipblink(server, tmp_path, path, "--cues", str(tmp_path / "b.json"),
                         out="b.motion3.json")
    assert first.read_bytes() == second.read_bytes()
    assert (tmp_path / "a.json").read_bytes() == (tmp_path / "b.json").read_bytes()


def test_python_package_equals_the_cli(server, client, voices, tmp_path):
    path = voices["files"]["mp3"]
    summary, out = lipblink(server, tmp_path, path, "--auto-blink", "2", "--cues",
                            str(tmp_path / "cues.tsv"))
    result = client.lip_blink(audio=path, eyes={"auto_blink": {"enabled": True,
                                                               "mean_interval_s": 2.0}})
    assert result.output_bytes == out.read_bytes()
    assert result.rhubarb_tsv == (tmp_path / "cues.tsv").read_text()
    assert [list(s) for s in result.voice["speech"]] == \
        [[s["begin"], s["end"]] for s in summary["voice"]["speech"]]
    assert result.counts["blinks"] > 0 and result.counts["eye_curves"] == 2


def test_merged_into_a_body_motion(server, voices, tmp_path):
    body = source_path("samples", "arm_head.motion3.json")
    _, out = lipblink(server, tmp_path, voices["files"]["ogg-vorbis"], "--motion", body)
    written = json.loads(out.read_text())
    original = json.load(open(body))
    assert written["Curves"][:len(original["Curves"])] == original["Curves"]  # untouched
    assert written["Curves"][-1]["Id"] == "ParamMouthOpenY"
    assert written["Meta"]["CurveCount"] == len(original["Curves"]) + 1


def test_rhubarb_cues_in_give_the_same_speech(server, voices, tmp_path):
    summary, _ = lipblink(server, tmp_path, voices["files"]["wav16-16k"], "--cues",
                          str(tmp_path / "cues.json"))
    done = run_cli("lipblink", "--rhubarb", str(tmp_path / "cues.json"), "-o",
                   str(tmp_path / "from_cues.motion3.json"), "--json", "--server",
                   server.address)
    again = json.loads(done.stdout)
    assert again["voice"]["kind"] == "rhubarb"
    # koma's own cues: one per hold, so speech comes back as the holds' union.
    assert again["voice"]["speech"] == summary["voice"]["speech"]
    assert again["mouths"][0]["holds"] == summary["mouths"][0]["holds"]


def test_bad_audio_is_refused_naming_the_field(server, tmp_path):
    text = tmp_path / "notes.wav"
    text.write_text("this is not a recording\n")
    done = run_cli("lipblink", "--audio", str(text), "-o", str(tmp_path / "x.motion3.json"),
                   "--server", server.address, check=False)
    assert done.returncode == 1
    assert "INVALID_ARGUMENT: audio: not a recording libsndfile can read" in done.stderr


def test_batch_over_a_folder_of_recordings(server, voices, tmp_path):
    folder = tmp_path / "takes"
    folder.mkdir()
    for name in ("flac", "wav16-16k"):
        source = voices["files"][name]
        (folder / os.path.basename(source)).write_bytes(open(source, "rb").read())
    out = tmp_path / "out"
    done = run_cli("batch", "lipblink", str(folder), "-o", str(out), "--server", server.address,
                   "--quiet")
    assert done.returncode == 0, done.stderr
    for name in ("flac", "wav16-16k"):
        stem = os.path.basename(voices["files"][name]).rsplit(".", 1)[0]
        written = out / (stem + ".motion3.json")
        _, single = lipblink(server, tmp_path, voices["files"][name], out=stem + ".single.json")
        assert written.read_bytes() == single.read_bytes(), name


def page_data(path):
    """The JSON a koma report carries in <script type="application/json" id="koma-data">."""
    text = open(path, encoding="utf-8").read()
    begin = text.index('id="koma-data">') + len('id="koma-data">')
    return json.loads(text[begin:text.index("</script>", begin)])


def embedded_audio(data):
    import base64
    mime, payload = data["audio"]["src"].split(",", 1)
    assert mime.startswith("data:audio/") and mime.endswith(";base64"), mime
    return base64.b64decode(payload)


def test_report_of_a_recording(server, voices, tmp_path):
    audio = voices["files"]["wav16-16k"]
    report = tmp_path / "voice.html"
    summary, _ = lipblink(server, tmp_path, audio, "--auto-blink", "3", "--report", str(report))
    assert summary["outputs"]["report"] == str(report)
    data = page_data(report)
    # The recording, byte for byte, and the analysis the server answered.
    assert data["audio"]["embedded"] is True and data["audio"]["mime"] == "audio/wav"
    assert embedded_audio(data) == open(audio, "rb").read()
    voice = data["voice"]
    assert [{"begin": b, "end": e} for b, e in voice["speech"]] == summary["voice"]["speech"]
    for key in ("noise_floor_dbfs", "start_dbfs", "stay_dbfs", "loud_dbfs"):
        assert abs(voice[key] - summary["voice"][key]) <= 1e-5 * abs(summary["voice"][key]), key
    assert voice["frames"] == len(voice["loudness"]["y"]) > 0
    assert data["mouths"][0]["holds"] == [[h["begin"], h["length"], h["shape"].lower()]
                                          for h in summary["mouths"][0]["holds"]]
    # --report - writes the same page on standard output; with -o - too it is refused.
    done = run_cli("lipblink", "--audio", audio, "-o", str(tmp_path / "y.motion3.json"),
                   "--auto-blink", "3", "--report", "-", "--server", server.address)
    assert done.stdout == report.read_text(encoding="utf-8")
    refused = run_cli("lipblink", "--audio", audio, "-o", "-", "--report", "-",
                      "--server", server.address, check=False)
    assert refused.returncode == 2 and "--report -" in refused.stderr, refused.stderr
    # The limit is the voice's: without --audio it is a usage error.
    refused = run_cli("lipblink", source_path("samples/talk_blink.motion3.json"), "-o",
                      str(tmp_path / "z.csv"), "--report-audio-max-bytes", "5",
                      "--server", server.address, check=False)
    assert refused.returncode == 2 and "--report-audio-max-bytes" in refused.stderr


def test_report_links_a_large_recording(server, voices, tmp_path):
    audio = voices["files"]["flac"]
    (tmp_path / "pages").mkdir()
    report = tmp_path / "pages" / "r.html"
    lipblink(server, tmp_path, audio, "--report", str(report), "--report-audio-max-bytes", "1000")
    data = page_data(report)
    assert data["audio"]["embedded"] is False and data["audio"]["mime"] == "audio/flac"
    # Relative to the page's folder, and it names the recording.
    assert os.path.realpath(os.path.join(report.parent, data["audio"]["src"])) == \
        os.path.realpath(audio)
    assert os.path.getsize(report) < os.path.getsize(audio) + 200000


def test_batch_reports_of_recordings(server, voices, tmp_path):
    folder = tmp_path / "takes"
    folder.mkdir()
    source = voices["files"]["flac"]
    (folder / "take.flac").write_bytes(open(source, "rb").read())
    out = tmp_path / "out"
    done = run_cli("batch", "lipblink", str(folder), "-o", str(out), "--report",
                   "--server", server.address, "--quiet")
    assert done.returncode == 0, done.stderr
    data = page_data(out / "take.report.html")
    assert embedded_audio(data) == open(source, "rb").read()
    summary, _ = lipblink(server, tmp_path, str(folder / "take.flac"))
    assert [{"begin": b, "end": e} for b, e in data["voice"]["speech"]] == summary["voice"]["speech"]


def test_report_of_a_voice_merged_into_a_body_motion(server, voices, tmp_path):
    body = source_path("samples", "arm_head.motion3.json")
    report = tmp_path / "merged.html"
    summary, _ = lipblink(server, tmp_path, voices["files"]["ogg-vorbis"], "--motion", body,
                          "--report", str(report), out="merged.csv")
    data = page_data(report)
    # The player runs over the body motion's frames at its rate, the mouth the server wrote.
    assert data["fps"] == summary["fps"] and data["frames"] == summary["frames"]
    assert data["audio"]["mime"] == "audio/ogg"
    mouth = next(c for c in data["curves"] if c["id"] == "ParamMouthOpenY")
    rows = open(tmp_path / "merged.csv").read().splitlines()
    column = rows[0].split(",").index("ParamMouthOpenY")
    assert mouth["frames_after"] == [float(r.split(",")[column]) for r in rows[1:]]
    assert dict(data["header"]["options"])["motion"] == body
