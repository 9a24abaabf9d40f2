"""Checks of `koma live` for tests/e2e/live_e2e_test.sh (Debian's python3, standard library
and tests/testing/voice_recordings.py). Modes:

  lines JSONL [--frames N] [--silent]
      one JSON object per line, one per grid frame from 0 in order, every documented field of
      docs/live.md with its type, mouth and eyes one of closed/half/open, mouth_level the
      closed/half/open level of the mouth, blink = the eyes not open, a frame's time
      grid_frame / 24; --frames: exactly N lines; --silent: no frame is speech.
  record MOTION3 JSONL
      the --record motion3.json: Fps 24, Duration = frames / 24, the curves ParamMouthOpenY,
      ParamEyeLOpen and ParamEyeROpen on stepped keys whose value at every grid frame is that
      frame's mouth_level / eye_level of the JSON lines.
  recordings FOLDER
      espeak-ng speaks known sentences, sox joins them (tests/testing/voice_recordings.py) and
      writes them at 16 and 48 kHz (16-bit), at 44.1 kHz stereo 32-bit float, and as Ogg
      Vorbis; prints the paths, one a line.
  agree KOMA SERVER FOLDER [--core LIVE_VOICE_COMPARE] FILE...
      each FILE through `koma live --speed 0 --lookahead L --json` (L = 0..3) and `koma
      lipblink --audio FILE --json`: after the first second, the live speech runs at lookahead
      3 are the offline ones (the response's voice.speech, grid frames) within one grid frame
      at each boundary (docs/semantics.md, "LipBlink from a live voice"; at lookahead 2 a
      word's closure may split a run, which is printed, not checked). With --core: at every
      lookahead the streamed speech runs are exactly those of the core's live analysis of the
      file (tests/core/live_voice_compare), so the audio went over the wire unchanged.
Exits 1 with the reasons on a failure.
"""
import json
import os
import subprocess
import sys

FPS = 24
FIELDS = {
    "grid_frame": int, "time_s": (int, float), "speech": bool, "mouth": str,
    "mouth_level": (int, float), "new_drawing": bool, "hold_start": bool, "eyes": str,
    "blink": bool, "blink_start": bool, "eye_level": (int, float),
    "loudness_dbfs": (int, float), "noise_floor_dbfs": (int, float), "late_ms": (int, float),
    "wall_late_ms": (int, float), "wall_s": (int, float),
}
SHAPES = {"closed", "half", "open"}
# Lookahead -> the largest boundary difference allowed, grid frames (None: printed only).
TOLERANCE = {0: None, 1: None, 2: None, 3: 1}


def fail(message):
    print(f"FAIL: {message}", file=sys.stderr)
    sys.exit(1)


def read_lines(path):
    frames = []
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            try:
                frames.append(json.loads(line))
            except ValueError as e:
                fail(f"{path}:{number}: not JSON ({e}): {line[:80]!r}")
    return frames


def check_lines(path, frames_expected=None, silent=False):
    frames = read_lines(path)
    if not frames:
        fail(f"{path}: no frames")
    if frames_expected is not None and len(frames) != frames_expected:
        fail(f"{path}: {len(frames)} frames, expected {frames_expected}")
    for i, f in enumerate(frames):
        where = f"{path}: line {i + 1}"
        for name, kind in FIELDS.items():
            if name not in f:
                fail(f"{where}: no {name}: {f}")
            if not isinstance(f[name], kind) or (kind is not bool and isinstance(f[name], bool)
                                                  and name != "speech"):
                fail(f"{where}: {name} = {f[name]!r} is not {kind}")
        if f["grid_frame"] != i:
            fail(f"{where}: grid_frame {f['grid_frame']}, expected {i} (one line per frame)")
        if abs(f["time_s"] - i / FPS) > 1e-9:
            fail(f"{where}: time_s {f['time_s']} is not {i}/{FPS}")
        if f["mouth"] not in SHAPES or f["eyes"] not in SHAPES:
            fail(f"{where}: mouth {f['mouth']!r}, eyes {f['eyes']!r}")
        level = {"closed": 0.0, "half": 0.5, "open": 1.0}
        if f["mouth_level"] != level[f["mouth"]] or f["eye_level"] != level[f["eyes"]]:
            fail(f"{where}: levels {f['mouth_level']}, {f['eye_level']} for {f['mouth']}, "
                 f"{f['eyes']} (defaults: 0, 0.5, 1)")
        if not f["speech"] and f["mouth"] != "closed":
            fail(f"{where}: a pause with the mouth {f['mouth']}")
        if f["blink"] != (f["eyes"] != "open"):
            fail(f"{where}: blink {f['blink']} with the eyes {f['eyes']}")
        new = i > 0 and f["mouth"] != frames[i - 1]["mouth"]
        if f["new_drawing"] != new:
            fail(f"{where}: new_drawing {f['new_drawing']}, the mouth {f['mouth']} after "
                 f"{frames[i - 1]['mouth'] if i else None}")
        if f["late_ms"] < 0 or f["late_ms"] > 126 or f["wall_late_ms"] < 0 or f["wall_s"] < 0:
            fail(f"{where}: late_ms {f['late_ms']}, wall_late_ms {f['wall_late_ms']}, "
                 f"wall_s {f['wall_s']}")
        if silent and f["speech"]:
            fail(f"{where}: speech in silence")
    return frames


def level_at(segments, t):
    """The value of a stepped motion3 curve at time t (seconds)."""
    value = segments[1]
    k = 2
    while k < len(segments):
        if segments[k] != 2:
            fail(f"segment type {segments[k]} is not stepped (2)")
        if segments[k + 1] <= t + 1e-9:
            value = segments[k + 2]
        k += 3
    return value


def check_record(motion3, jsonl):
    frames = read_lines(jsonl)
    with open(motion3, encoding="utf-8") as f:
        doc = json.load(f)
    meta = doc["Meta"]
    if meta["Fps"] != FPS or abs(meta["Duration"] - len(frames) / FPS) > 1e-9:
        fail(f"{motion3}: Fps {meta['Fps']}, Duration {meta['Duration']} for {len(frames)} frames")
    curves = {c["Id"]: c["Segments"] for c in doc["Curves"]}
    if sorted(curves) != ["ParamEyeLOpen", "ParamEyeROpen", "ParamMouthOpenY"]:
        fail(f"{motion3}: curves {sorted(curves)}")
    if meta["CurveCount"] != 3:
        fail(f"{motion3}: CurveCount {meta['CurveCount']}")
    for f in frames:
        t = f["grid_frame"] / FPS
        for cid, key in (("ParamMouthOpenY", "mouth_level"), ("ParamEyeLOpen", "eye_level"),
                         ("ParamEyeROpen", "eye_level")):
            if level_at(curves[cid], t) != f[key]:
                fail(f"{motion3}: {cid} at frame {f['grid_frame']} is "
                     f"{level_at(curves[cid], t)}, streamed {f[key]}")


def runs(frames):
    out = []
    for f in frames:
        if not f["speech"]:
            continue
        g = f["grid_frame"]
        if out and out[-1][1] == g:
            out[-1][1] = g + 1
        else:
            out.append([g, g + 1])
    return [tuple(r) for r in out]


def cut(intervals, first):
    return [(max(b, first), e) for b, e in intervals if e > first]


def boundary_error(live, offline):
    if len(live) != len(offline):
        return None
    return max((max(abs(a[0] - b[0]), abs(a[1] - b[1])) for a, b in zip(live, offline)),
               default=0)


def core_runs(core, path):
    done = subprocess.run([core, path], capture_output=True, text=True, timeout=120, check=True)
    return {r["lookahead"]: [tuple(i) for i in r["live"]]
            for r in map(json.loads, done.stdout.splitlines())}


def agree(koma, server, folder, files, core=None):
    problems = []
    for path in files:
        out = os.path.join(folder, os.path.basename(path) + ".lipblink.motion3.json")
        done = subprocess.run([koma, "lipblink", "--audio", path, "-o", out, "--json", "-q",
                               "--server", server], capture_output=True, text=True, timeout=120)
        if done.returncode != 0:
            fail(f"koma lipblink --audio {path}: {done.stderr}")
        voice = json.loads(done.stdout)["voice"]
        if voice["frame_fps"] != FPS:
            fail(f"{path}: the offline analysis is at {voice['frame_fps']} fps")
        offline = [(i["begin"], i["end"]) for i in voice["speech"]]
        if not offline:
            fail(f"{path}: no speech offline")
        expected = core_runs(core, path) if core else {}
        for lookahead, tolerance in sorted(TOLERANCE.items()):
            jsonl = os.path.join(folder, f"{os.path.basename(path)}.live{lookahead}.jsonl")
            with open(jsonl, "w", encoding="utf-8") as f:
                done = subprocess.run([koma, "live", "--input", path, "--speed", "0", "--json",
                                       "-q", "--lookahead", str(lookahead), "--server", server],
                                      stdout=f, stderr=subprocess.PIPE, text=True, timeout=120)
            if done.returncode != 0:
                fail(f"koma live --input {path}: {done.stderr}")
            frames = check_lines(jsonl)
            live = runs(frames)
            error = boundary_error(cut(live, FPS), cut(offline, FPS))
            verdict = "printed"
            if tolerance is not None:
                verdict = "ok" if error is not None and error <= tolerance else "FAIL"
            if core and live != expected[lookahead]:
                verdict += f"; FAIL: the core's live analysis has {expected[lookahead]}"
            print(f"{os.path.basename(path)} lookahead {lookahead}: live {cut(live, FPS)}, "
                  f"offline {cut(offline, FPS)}: largest boundary difference {error} "
                  f"(allowed {tolerance}): {verdict}")
            if "FAIL" in verdict:
                problems.append(f"{path} lookahead {lookahead}: live {live}, offline {offline}"
                                + (f", core {expected[lookahead]}" if core else ""))
    if problems:
        fail("; ".join(problems))


def recordings(folder):
    here = os.path.dirname(os.path.abspath(__file__))
    sys.path.insert(0, os.path.join(here, "..", "testing"))
    import voice_recordings as vr  # tests/testing/voice_recordings.py
    clean, _, _ = vr.make_clean(folder)
    print(vr.variant(folder, clean, "espeak16k.wav", rate=16000))
    print(vr.variant(folder, clean, "espeak48k.wav", rate=48000))
    print(vr.variant(folder, clean, "espeak44k-stereo-float.wav", rate=44100, channels=2,
                     sox_format=("-e", "floating-point", "-b", "32")))
    print(vr.variant(folder, clean, "espeak22k.ogg"))  # Ogg Vorbis: decoded to float, F32LE


def main(argv):
    mode = argv[1]
    if mode == "lines":
        frames = None
        if "--frames" in argv:
            frames = int(argv[argv.index("--frames") + 1])
        check_lines(argv[2], frames, "--silent" in argv)
    elif mode == "record":
        check_record(argv[2], argv[3])
    elif mode == "recordings":
        recordings(argv[2])
    elif mode == "agree":
        files = argv[5:]
        core = None
        if files and files[0] == "--core":
            core, files = files[1], files[2:]
        agree(argv[2], argv[3], argv[4], files, core)
    else:
        fail(f"unknown mode {mode}")


if __name__ == "__main__":
    main(sys.argv)
