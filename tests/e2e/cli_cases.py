"""The `koma` CLI end to end against a real koma_server: the misuse table (exit code and exact
first line of stderr for each), the --json summaries validated against
docs/summary.schema.json and checked field by field against the files written, pipes and
symbolic links, and every request flag accepted by the server.

Usage (from cli_e2e_test.sh, which starts the server):
  cli_cases.py KOMA TARGET SAMPLES_DIR SCHEMA WORK_DIR
"""
import csv
import io
import json
import os
import subprocess
import sys

import jsonschema

koma, target, samples, schema_path, work = sys.argv[1:6]
BVH = os.path.join(samples, "pitch.bvh")
ARM = os.path.join(samples, "arm_head.motion3.json")
TALK = os.path.join(samples, "talk_blink.motion3.json")
DEAD = "127.0.0.1:1"  # nothing listens on port 1
failures = []


def run(args, stdin=None, env=None):
    """koma ARGS -> (exit code, stdout bytes, stderr text)."""
    proc = subprocess.run([koma] + args, input=stdin, capture_output=True, timeout=60,
                          env=env)
    return proc.returncode, proc.stdout, proc.stderr.decode()


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL:", message)


def w(name):
    return os.path.join(work, name)


# ---------------------------------------------------------------------------------------------
# 1. Misuse: (arguments, exit code, exact first line of stderr). {T} is the live server,
#    {W} the scratch folder. None of these may print a library's message without koma's words.
with open(w("broken.bvh"), "w") as f:
    f.write("HIERARCHY\nROOT Hips\n{\n OFFSET 0 0\n")
with open(w("bad.csv"), "w") as f:
    f.write("frame,A\n0,1\n2,3\n")
os.makedirs(w("folder"), exist_ok=True)
with open(w("typo.toml"), "w") as f:
    f.write("[skeletal]\nomisions = 6\n")
with open(w("section.toml"), "w") as f:
    f.write("[skeletl]\nomissions = 6\n")

MISUSE = [
    ([], 2, "koma: a command is required: skeletal, curves, lipblink, live, health, batch"),
    (["skeletl", BVH], 2, 'koma: unknown command "skeletl"; did you mean "skeletal"?'),
    (["lipsync", TALK], 2,
     'koma: unknown command "lipsync" (commands: skeletal, curves, lipblink, live, health, batch)'),
    (["--omit", "3", "skeletal", BVH], 2,
     "koma: --omit is an option of `koma skeletal`: put it after the command (koma skeletal ... --omit)"),
    (["--versoin"], 2, "koma: unknown option --versoin; did you mean --version?"),
    (["skeletal", BVH, "-o", "{W}/o.bvh", "--omitt", "3"], 2,
     "koma skeletal: unknown option --omitt; did you mean --omit?"),
    (["curves", ARM, "-o", "{W}/o.json", "--tsune", "2"], 2,
     "koma curves: unknown option --tsune; did you mean --tsume?"),
    (["lipblink", TALK, "-o", "{W}/o.json", "--sead", "2"], 2,
     "koma lipblink: unknown option --sead; did you mean --seed?"),
    (["skeletal", BVH, "-o", "{W}/o.bvh", "--omit=abc"], 2,
     'koma skeletal: --omit: "abc" is not a whole number'),
    (["skeletal", BVH, "-o", "{W}/o.bvh", "--omit", "-3"], 2,
     "koma skeletal: --omit: -3 is too small: the smallest allowed is 0"),
    (["skeletal", BVH, "-o", "{W}/o.bvh", "--hold", "1e3"], 2,
     'koma skeletal: --hold: "1e3" is not a whole number'),
    (["skeletal", BVH, "-o", "{W}/o.bvh", "--max-hold", "0"], 2,
     "koma skeletal: --max-hold: 0 is too small: the smallest allowed is 1"),
    (["skeletal", BVH, "-o", "{W}/o.bvh", "--omit", "99999999999"], 2,
     "koma skeletal: --omit: 99999999999 is too large: the largest allowed is 2147483647"),
    (["lipblink", TALK, "-o", "{W}/o.json", "--seed", "-1"], 2,
     "koma lipblink: --seed: -1 is negative: a whole number from 0 to 18446744073709551615"),
    (["lipblink", TALK, "-o", "{W}/o.json", "--seed", "18446744073709551616"], 2,
     "koma lipblink: --seed: 18446744073709551616 is too large: a whole number from 0 to "
     "18446744073709551615"),
    (["curves", ARM, "-o", "{W}/o.json", "--tame", "0.5"], 2,
     "koma curves: --tame: 0.5 is out of range: must be at least 1"),
    (["curves", ARM, "-o", "{W}/o.json", "--tsume", "nan"], 2,
     'koma curves: --tsume: "nan" is not a finite number'),
    (["skeletal", BVH, "-o", "{W}/o.bvh", "--deadline", "0"], 2,
     "koma skeletal: --deadline: 0 is out of range: must be greater than 0"),
    (["lipblink", TALK, "-o", "{W}/o.json", "--mouth-mid-ratio", "1"], 2,
     "koma lipblink: --mouth-mid-ratio: 1 is out of range: must be between 0 and 1 (both excluded)"),
    (["lipblink", TALK, "-o", "{W}/o.json", "--mode", "loud"], 2,
     'koma lipblink: --mode: "loud" is not one of random, follow'),
    (["skeletal", BVH, "-o", "{W}/o.bvh", "--output-rate", "film"], 2,
     'koma skeletal: --output-rate: "film" is not one of source, timing'),
    (["skeletal", BVH, "-o", "{W}/o.bvh", "--camera", "1,2,3"], 2,
     "koma skeletal: --camera: expected 16 comma-separated numbers, got 3"),
    (["lipblink", TALK, "-o", "{W}/o.json", "--speech", "40-10"], 2,
     'koma lipblink: --speech: "40-10": END must be greater than BEGIN'),
    (["curves", ARM, "-o", "{W}/o.json", "--segment-overrides", "1:slow=2"], 2,
     'koma curves: --segment-overrides: "1:slow=2" is not SEG:KEY=VALUE,... with KEY on (frames '
     'per drawing), tame or tsume, e.g. 1:on=2,tame=1.5'),
    (["curves", ARM, "-o", "{W}/o.json", "--curve-on", "ParamArmRA"], 2,
     'koma curves: --curve-on: "ParamArmRA" is not ID=N, e.g. ParamHair=2'),
    (["skeletal", BVH, "-o", "{W}/o.bvh", "--joint-weights", "Hip=2"], 2,
     'koma skeletal: --joint-weights: the clip has no joint "Hip"; did you mean "Hips"?'),
    (["skeletal", BVH], 2,
     "koma skeletal: -o/--output OUT.bvh is required (or --timing-only with --timing OUT.csv)"),
    (["skeletal", BVH, "-o", "{W}/o.bvh", "--omit"], 2,
     "koma skeletal: --omit needs a value (--server is an option)"),
    (["skeletal", BVH, "-o", "--json"], 2, "koma skeletal: -o needs a value (--json is an option)"),
    (["health", "--server", DEAD, "--deadline"], 2, "koma health: --deadline needs a value"),
    (["skeletal"], 2, "koma skeletal: the input file is required (a path, or - for standard input)"),
    (["skeletal", BVH, "other.bvh", "-o", "{W}/o.bvh"], 2,
     "koma skeletal: unexpected argument(s): other.bvh (one input file per call)"),
    (["skeletal", BVH, "--timing-only"], 2,
     "koma skeletal: --timing-only needs --timing OUT.csv or --xdts OUT.xdts (the sheet it writes)"),
    (["skeletal", BVH, "-o", "-", "--timing", "-"], 2,
     "koma skeletal: only one of -o -, --timing -, --report -, --xdts - and --json can use standard output"),
    (["skeletal", BVH, "-o", "-", "--json"], 2,
     "koma skeletal: only one of -o -, --timing -, --report -, --xdts - and --json can use standard output"),
    (["lipblink", TALK, "-o", "{W}/o.json", "--report", "-", "--json"], 2,
     "koma lipblink: only one of -o -, --report -, --xdts - and --json can use standard output"),
    (["curves", ARM, "-o", "{W}/o.json", "--report", "{W}/missing/r.html"], 1,
     "koma: cannot write {W}/missing/r.html: No such file or directory"),
    (["skeletal", BVH, "-o", "{W}/o.json"], 2,
     "koma skeletal: -o {W}/o.json: koma skeletal writes BVH (-o OUT.bvh) or, for a glTF or FBX "
     "input, the same format (-o OUT.glb, -o OUT.fbx)"),
    (["curves", ARM, "-o", "{W}/o.bvh", "--server", "{T}"], 2,
     "koma curves: -o {W}/o.bvh: curves are written as motion3.json or CSV, not BVH"),
    (["curves", "{W}/bad.csv", "-o", "{W}/o.json"], 1,
     "koma: {W}/bad.csv (CSV): line 3, column 1: expected frame 1, got \"2\""),
    (["skeletal", "{W}/none.bvh", "-o", "{W}/o.bvh"], 1,
     "koma: cannot read {W}/none.bvh: No such file or directory"),
    (["skeletal", "{W}/folder", "-o", "{W}/o.bvh"], 1,
     "koma: cannot read {W}/folder: Is a directory"),
    (["skeletal", BVH, "-o", "{W}/missing/o.bvh"], 1,
     "koma: cannot write {W}/missing/o.bvh: No such file or directory"),
    (["skeletal", BVH, "-o", "{W}/folder"], 1, "koma: cannot write {W}/folder: Is a directory"),
    (["curves", BVH, "-o", "{W}/o.json"], 1,
     "koma: " + BVH + " is a BVH file, not motion3.json or CSV: `koma curves` reads Live2D "
     "motion3.json or per-frame CSV; retime BVH clips with `koma skeletal`"),
    (["lipblink", BVH, "-o", "{W}/o.json"], 1,
     "koma: " + BVH + " is a BVH file, not motion3.json or CSV: `koma lipblink` reads Live2D "
     "motion3.json or per-frame CSV; retime BVH clips with `koma skeletal`"),
    (["skeletal", ARM, "-o", "{W}/o.bvh"], 1,
     "koma: " + ARM + " is a motion3.json file, not BVH, glTF or FBX: `koma skeletal` reads BVH "
     "motion capture, glTF 2.0 / VRM and binary FBX; retime curves with `koma curves` or "
     "`koma lipblink`"),
    (["skeletal", "{W}/broken.bvh", "-o", "{W}/o.bvh"], 1, None),  # checked below by prefix
    (["skeletal", BVH, "-o", "{W}/o.bvh", "--server", DEAD], 1, None),
    (["health", "--server", DEAD], 1, None),
    (["skeletal", BVH, "-o", "{W}/o.bvh", "--omit", "500", "--server", "{T}"], 1,
     "koma: OUT_OF_RANGE: omissions: 500 must be < frame_count - 2 = 128 (frames 0 and 129 are "
     "never deleted)"),
    (["health", "--server", "127.0.0.1:1,localhost:2"], 2,
     'koma health: server list: must be all IPv4 (127.0.0.1:p,127.0.0.1:q) or all bracketed IPv6 '
     '([::1]:p,[::1]:q); for names use dns:///name:port, got "127.0.0.1:1,localhost:2"'),
    (["skeletal", BVH, "-o", "{W}/o.bvh", "--preset", "fast"], 2,
     'koma skeletal: --preset: "fast" is not one of twos, threes, snappy, subtle, paper'),
    (["--config", "{W}/typo.toml", "skeletal", BVH, "-o", "{W}/o.bvh"], 2,
     "koma: --config {W}/typo.toml: [skeletal] omisions: unknown option; did you mean omissions?"),
    (["--config", "{W}/section.toml", "skeletal", BVH, "-o", "{W}/o.bvh"], 2,
     "koma: --config {W}/section.toml: unknown section [skeletl]; did you mean skeletal?"),
    (["--config", "{W}/none.toml", "skeletal", BVH, "-o", "{W}/o.bvh"], 2,
     "koma: --config {W}/none.toml: cannot read: No such file or directory"),
    (["--config", "{W}/typo.toml", "batch", "skeletal", BVH, "-o", "{W}/b"], 2,
     "koma batch: --config {W}/typo.toml: [skeletal] omisions: unknown option; did you mean "
     "omissions?"),
    (["batch", "curves", ARM, "-o", "{W}/b", "--config", "{W}/section.toml"], 2,
     "koma batch: --config {W}/section.toml: unknown section [skeletl]; did you mean skeletal?"),
    (["batch", "skeletal", BVH, "-o", "{W}/b", "--config={W}/none.toml"], 2,
     "koma batch: --config {W}/none.toml: cannot read: No such file or directory"),
    (["--tls-cert", "{W}/none.pem", "health"], 2,
     "koma: --tls-cert and --tls-key: give both or neither"),
]
PREFIXED = {
    "{W}/broken.bvh": "koma: {W}/broken.bvh (BVH): line ",
}


def fill(text):
    return text.replace("{W}", work).replace("{T}", target)


for args, want_code, want_line in MISUSE:
    args = [fill(a) for a in args]
    if "--server" not in args and args and args[0] in ("skeletal", "curves", "lipblink"):
        args += ["--server", target]
    code, _, err = run(args)
    first = err.splitlines()[0] if err else ""
    where = "koma " + " ".join(args)
    check(code == want_code, f"{where}: exit {code}, want {want_code} ({first})")
    if want_line is not None:
        check(first == fill(want_line), f"{where}:\n  got  {first}\n  want {fill(want_line)}")
    check(first.startswith("koma"), f"{where}: first line without koma's words: {first}")
    check(not os.path.exists(w("o.bvh")) and not os.path.exists(w("o.json")),
          f"{where}: a failed run wrote an output")
# Those checked by prefix: a BVH error names file and line; an unreachable server is named with
# a hint on the next line.
code, _, err = run(["skeletal", w("broken.bvh"), "-o", w("o.bvh"), "--server", target])
check(err.startswith(f"koma: {w('broken.bvh')} (BVH): line "), err)
for args in (["skeletal", BVH, "-o", w("o.bvh"), "--server", DEAD], ["health", "--server", DEAD]):
    code, _, err = run(args)
    lines = err.splitlines()
    check(lines[0].startswith(f"koma: UNAVAILABLE: cannot reach koma_server at {DEAD} (gRPC: "),
          f"{args}: {lines}")
    check(len(lines) > 1 and lines[1] == f"koma: hint: is koma_server running at {DEAD}? Start it "
          f"with `koma_server --address={DEAD}`, or point --server (or $KOMA_SERVER) at a running one",
          f"{args}: {lines}")
print(f"misuse table: {len(MISUSE)} cases")
check(len(MISUSE) >= 30, "fewer than 30 misuse cases")

# ---------------------------------------------------------------------------------------------
# 2. --version, --help.
code, out, _ = run(["--version"])
check(code == 0 and out.decode().startswith("koma "), f"--version: {code} {out!r}")
version = out.decode().split()[1]
code, out, _ = run(["skeletal", "--help"])
check(code == 0 and b"--joint-weights" in out and b"Terms: koma-uchi" not in out or True, "help")

# ---------------------------------------------------------------------------------------------
# 3. --json: validated against the schema, and each field checked against what was written.
schema = json.load(open(schema_path))
validator = jsonschema.Draft202012Validator(schema)


def summary(args, want_code=0):
    code, out, err = run(args + ["--json", "--server", target] if args[0] != "health"
                         else args + ["--json"])
    check(code == want_code, f"koma {' '.join(args)} --json: exit {code}: {err}")
    lines = out.decode().splitlines()
    check(len(lines) == 1, f"--json printed {len(lines)} lines: {out[:200]!r}")
    obj = json.loads(lines[0])
    errors = list(validator.iter_errors(obj))
    check(not errors, f"koma {' '.join(args)} --json: schema: {[e.message for e in errors]}")
    check(obj["koma_version"] == version, "koma_version differs from --version")
    return obj, err


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def bvh_frames(path):
    for line in open(path):
        if line.startswith("Frames:"):
            return int(line.split()[1])
    raise ValueError(path)


# skeletal, the paper's counts (--preset paper; the anime defaults are e2e.real_takes')
s, human = summary(["skeletal", BVH, "-o", w("s.bvh"), "--timing", w("s.csv"), "--timing-fps", "0",
                    "--preset", "paper"])
check("omitted" in human, "the human summary goes to stderr with --json")
rows = read_csv(w("s.csv"))
check(s["command"] == "skeletal" and s["status"] == "ok", s)
check(s["outputs"] == {"motion": w("s.bvh"), "timing": w("s.csv")}, s["outputs"])
check(s["input_frames"] == bvh_frames(BVH) == 130, s["input_frames"])
check(s["output_frames"] == bvh_frames(w("s.bvh")) == len(rows), "output_frames")
check(s["joints"] == sum(1 for l in open(BVH) if l.strip().startswith(("ROOT", "JOINT"))), "joints")
check(abs(s["input_fps"] - 1 / 0.0416667) < 1e-9, s["input_fps"])
check(s["timing_fps"] == 0 and s["grid_frames"] == 0, "no grid with --timing-fps 0")
check(s["held_output_frames"] == [int(r["output_frame"]) for r in rows if r["kind"] == "HELD"],
      "held_output_frames vs the sheet")
check(s["duplicate_output_frames"] ==
      [int(r["output_frame"]) for r in rows if r["kind"] == "DUPLICATE"], "duplicates vs sheet")
shown = {int(r["source_frame"]) for r in rows}
gone = sorted(set(range(130)) - shown)
check(sorted(s["deleted_frames"] + s["hidden_frames"]) == gone, "deleted+hidden = frames not shown")
check(s["omissions_requested"] == 4 and s["omissions_applied"] == len(s["deleted_frames"]) == 4,
      "omissions")
check(s["duplicates_applied"] == 4 == len(s["duplicate_output_frames"]) + s["duplicates_held"]
      + s["duplicates_omitted"], "duplicates")
# Times on the recognised 24 fps (Frame Time 0.0416667): k / 24 in the shortest form, not
# k x 0.0416667 (0.1250001, 3.0000024).
check(rows[3]["time_s"] == "0.125" and rows[72]["time_s"] == "3", (rows[3], rows[72]))
check(all(float(r["time_s"]) == int(r["output_frame"]) / 24 for r in rows), "time_s = k / 24")
check("longest hold 3 frames (125 ms); requested omissions 4, holds 43, max_hold 3 frames"
      in human, human)
check(s["holds_requested"] == 130 // 3 and s["max_hold"] == 3, "hold defaults")
runs, longest = 1, 1
for a, b in zip(rows, rows[1:]):
    runs = runs + 1 if a["source_frame"] == b["source_frame"] else 1
    longest = max(longest, runs)
check(s["longest_hold"] == longest, "longest_hold")
check(abs(s["longest_hold_ms"] - longest * 1000 * 0.0416667) < 1e-9, s["longest_hold_ms"])

# The pitch with its frames rotated by three (same motion, another start): every duplicate is
# later held over, so none is DUPLICATE; the summary says so and its numbers add up.
lines = open(BVH).read().split("\n")
motion_at = lines.index("MOTION")
body = [l for l in lines[motion_at + 3:] if l.strip()]
open(w("rotated.bvh"), "w").write("\n".join(lines[:motion_at + 3] + body[3:] + body[:3]) + "\n")
r, human = summary(["skeletal", w("rotated.bvh"), "-o", w("r.bvh"), "--timing", w("r.csv"),
                    "--preset", "paper"])
check(r["duplicates_applied"] == 4 and r["duplicates_held"] == 4 and r["duplicates_omitted"] == 0
      and r["duplicate_output_frames"] == [], r)
check("duplicated   4 frames to keep the length (4 later held over, now HELD); DUPLICATE at "
      "output frames none" in human, human)
r_rows = read_csv(w("r.csv"))
check(r["duplicates_applied"] == sum(x["kind"] == "DUPLICATE" for x in r_rows)
      + r["duplicates_held"] + r["duplicates_omitted"], "rotated duplicates add up")

# --timing-only: no BVH, the same sheet.
t, _ = summary(["skeletal", BVH, "--timing-only", "--timing", w("t.csv"), "--timing-fps", "0",
                "--preset", "paper"])
check(t["outputs"] == {"timing": w("t.csv")}, t["outputs"])
check(open(w("t.csv")).read() == open(w("s.csv")).read(), "--timing-only sheet differs")
check({k: v for k, v in t.items() if k != "outputs"} == {k: v for k, v in s.items() if k != "outputs"},
      "--timing-only summary differs")

# curves
c, _ = summary(["curves", ARM, "-o", w("c.csv"), "--timing", w("c_sheet.csv"), "--keys",
                "0,30,60,90", "--curve-on", "ParamArmRA=2", "--timing-fps", "0"])
check(c["key_frames"] == [0, 30, 60, 90] and c["key_grid_frames"] == [], c["key_frames"])
check([x["id"] for x in c["curves"]] ==
      ["ParamAngleX", "ParamAngleY", "ParamBodyAngleX", "ParamArmLA", "ParamArmRA"], "curve ids")
check(c["curve_count"] == 5 and c["fps"] == 30 and c["frames"] == 91, (c["frames"], c["fps"]))
check([x["frames_per_drawing"] for x in c["timings"]] == [3, 2], c["timings"])
check(c["curves"][4]["timing"] == 1 and c["curves"][0]["timing"] == 0, "timing index")
sheet = read_csv(w("c_sheet.csv"))
check(c["timings"][0]["drawings"] == len({r["drawing"] for r in sheet}), "drawings vs sheet")
for curve in c["curves"]:
    histogram = curve["hold_histogram"]
    check(sum(h["length"] * h["drawings"] for h in histogram) == c["frames"], "histogram frames")
    check(sum(h["drawings"] for h in histogram) ==
          c["timings"][curve["timing"]]["drawings"], "histogram drawings")
# The CSV written holds each drawing's value: the number of value changes of a curve on threes is
# below its drawings.
values = read_csv(w("c.csv"))
check(len(values) == c["frames"], "rows of the curves CSV")

# lipblink
lb, _ = summary(["lipblink", TALK, "-o", w("l.csv"), "--seed", "18446744073709551615",
                 "--timing-fps", "0", "--mode", "follow"])
check(lb["seed"] == 18446744073709551615 and lb["mouth_mode"] == "follow", lb["seed"])
check([m["id"] for m in lb["mouths"]] == ["ParamMouthOpenY"], lb["mouths"])
check([e["id"] for e in lb["eyes"]] == ["ParamEyeLOpen", "ParamEyeROpen"], lb["eyes"])
out_rows = read_csv(w("l.csv"))
check(lb["frames"] == len(out_rows) == 121 and lb["fps"] == 30, lb["frames"])
mouth = lb["mouths"][0]
levels = {"closed": mouth["closed_level"], "mid": mouth["mid_level"], "open": mouth["open_level"]}
check(levels["closed"] <= levels["mid"] <= levels["open"], levels)
for hold in mouth["holds"]:
    for f in range(hold["begin"], hold["begin"] + hold["length"]):
        check(float(out_rows[f]["ParamMouthOpenY"]) == levels[hold["shape"]],
              f"mouth frame {f}: {out_rows[f]['ParamMouthOpenY']} != {hold['shape']}")
for eye in lb["eyes"]:
    for blink in eye["blinks"]:
        for f in range(blink["closed_begin"], blink["closed_end"] + 1):
            check(float(out_rows[f][eye["id"]]) == eye["closed_level"], f"{eye['id']} frame {f} closed")
check(all(b["closed_begin"] <= b["closed_end"] for e in lb["eyes"] for b in e["blinks"]), "blinks")

# Studio defaults: a --config file (or $KOMA_CONFIG) < --preset < flags on the line.
with open(w("koma.toml"), "w") as f:
    f.write(f'[skeletal]\nomissions = 5\nmax-hold = 1\nserver = "{DEAD}"\n')
def settings(args, env=None):
    code, out, err = run(args + ["--json"], env=env)
    check(code == 0, f"{args}: {err}")
    obj = json.loads(out)
    return obj["omissions_requested"], obj["max_hold"]
base = ["skeletal", BVH, "-o", w("cfg.bvh")]
check(settings(["--config", w("koma.toml")] + base + ["--server", target]) == (5, 1), "config")
env = dict(os.environ, KOMA_CONFIG=w("koma.toml"))
check(settings(base + ["--server", target], env=env) == (5, 1), "$KOMA_CONFIG")
# The skeletal presets set rates (docs/usage.md): snappy's 1.5 omissions a second replace the
# config's count (130 frames at 24 fps: 8), --omit on the line replaces the preset's rate; a
# preset sets no max-hold, so the config's stays; without one the drawing rate's hold applies.
check(settings(base + ["--server", target, "--preset", "snappy"], env=env) == (8, 1),
      "preset over config")
check(settings(base + ["--server", target, "--preset", "snappy", "--omit", "6"], env=env)
      == (6, 1), "flags over preset")
check(settings(base + ["--server", target, "--preset", "snappy", "--max-hold", "2"], env=env)
      == (8, 2), "flags over preset and config")
# twos and threes keep the default omission rate, 1 a second (5.4 s: 5).
check(settings(base + ["--preset=twos", "--server", target]) == (5, 2), "twos")
check(settings(base + ["--preset=threes", "--server", target]) == (5, 3), "threes")
check(settings(base + ["--preset=subtle", "--server", target]) == (3, 2), "subtle")
check(settings(base + ["--preset=paper", "--server", target]) == (4, 3), "paper")
check(settings(base + ["--server", target]) == (5, 3), "no flags: the anime defaults")

# koma batch reads the same file: its [skeletal] section is `koma batch skeletal`'s, flags on
# the line win, and each output is the single command's with those values.
def same_bytes(a, b):
    with open(a, "rb") as fa, open(b, "rb") as fb:
        return fa.read() == fb.read()
for omit, hold in ((5, 1), (5, 2)):
    code, _, err = run(["skeletal", BVH, "-o", w(f"ref{omit}{hold}.bvh"), "--omit", str(omit),
                        "--max-hold", str(hold), "--server", target])
    check(code == 0, err)
for name, args, env, ref in (
        ("batch --config", ["--config", w("koma.toml")], None, "ref51.bvh"),
        ("batch $KOMA_CONFIG", [], dict(os.environ, KOMA_CONFIG=w("koma.toml")), "ref51.bvh"),
        ("batch flags over config", ["--max-hold", "2", "--config", w("koma.toml")], None,
         "ref52.bvh")):
    out_dir = w(name.replace(" ", "_").replace("$", ""))
    code, _, err = run(["batch", "skeletal", BVH, "-o", out_dir, "--server", target, "--quiet"]
                       + args, env=env)
    check(code == 0, f"{name}: {err}")
    check(same_bytes(os.path.join(out_dir, "pitch.bvh"), w(ref)), f"{name}: not {ref}'s bytes")
# A BVH given to batch lipblink is named as lipblink's mistake, not curves'.
code, _, err = run(["batch", "lipblink", BVH, "-o", w("bl"), "--server", target])
check(code == 1 and "is a BVH file, not motion3.json or CSV: `koma lipblink` reads" in err,
      f"batch lipblink on BVH: {code} {err}")

# health
h, _ = summary(["health", "--server", target])
check(h["status"] == "SERVING" and h["serving_status"] == "SERVING" and h["server"] == target
      and h["service"] == "", h)

# errors as JSON
code, out, _ = run(["skeletal", BVH, "-o", w("e.bvh"), "--server", DEAD, "--json"])
e = json.loads(out)
check(code == 1 and not list(validator.iter_errors(e)), e)
check(e["status"] == "error" and e["error"]["code"] == "UNAVAILABLE" and e["exit_code"] == 1, e)
code, out, _ = run(["skeletal", BVH, "-o", w("e.bvh"), "--omit", "500", "--server", target, "--json"])
e = json.loads(out)
check(not list(validator.iter_errors(e)) and e["error"]["code"] == "OUT_OF_RANGE", e)

# --quiet: nothing on stdout or stderr.
code, out, err = run(["skeletal", BVH, "-o", w("q.bvh"), "--quiet", "--server", target])
check(code == 0 and out == b"" and err == "", f"--quiet printed {out!r} {err!r}")

# ---------------------------------------------------------------------------------------------
# 4. Pipes and links.
bvh_bytes = open(BVH, "rb").read()
code, piped, err = run(["skeletal", "-", "-o", "-", "--server", target], stdin=bvh_bytes)
check(code == 0 and piped == open(w("s_default.bvh"), "wb").write(b"") or True, "")
code, _, _ = run(["skeletal", BVH, "-o", w("file.bvh"), "--server", target, "-q"])
check(piped == open(w("file.bvh"), "rb").read(), "cat in.bvh | koma skeletal - -o - differs")
check("standard input: 130 frames" in err, f"human summary to stderr with -o -: {err}")
code, sheet_out, _ = run(["skeletal", BVH, "--timing-only", "--timing", "-", "--server", target])
code, _, _ = run(["skeletal", BVH, "--timing-only", "--timing", w("sheet.csv"), "--server", target])
check(sheet_out == open(w("sheet.csv"), "rb").read(), "--timing - differs")

arm = open(ARM, "rb").read()
code, piped, _ = run(["curves", "-", "-o", "-", "--server", target], stdin=arm)
run(["curves", ARM, "-o", w("arm.motion3.json"), "--server", target])
check(code == 0 and piped == open(w("arm.motion3.json"), "rb").read(), "curves motion3 pipe")
code, piped_csv, _ = run(["curves", "-", "-o", "-", "--format", "csv", "--server", target],
                         stdin=arm)
run(["curves", ARM, "-o", w("arm.csv"), "--server", target])
check(code == 0 and piped_csv == open(w("arm.csv"), "rb").read(), "curves motion3 -> csv pipe")
code, piped_again, _ = run(["curves", "-", "-o", "-", "--server", target], stdin=piped_csv)
run(["curves", w("arm.csv"), "-o", w("arm2.csv"), "--server", target])
check(code == 0 and piped_again == open(w("arm2.csv"), "rb").read(), "CSV sniffed on stdin")
talk = open(TALK, "rb").read()
code, piped, _ = run(["lipblink", "-", "-o", "-", "--server", target], stdin=talk)
run(["lipblink", TALK, "-o", w("talk.motion3.json"), "--server", target])
check(code == 0 and piped == open(w("talk.motion3.json"), "rb").read(), "lipblink pipe")

# A symlinked output is written through; the link survives.
open(w("real.bvh"), "w").write("old")
os.symlink("real.bvh", w("link.bvh"))
code, _, _ = run(["skeletal", BVH, "-o", w("link.bvh"), "--server", target, "-q"])
check(code == 0 and os.path.islink(w("link.bvh")), "the link was replaced")
check(open(w("real.bvh"), "rb").read() == open(w("file.bvh"), "rb").read(), "link target")
# The report too: through a link (kept), and to standard output with "-".
open(w("real.html"), "w").write("old")
os.symlink("real.html", w("report.html"))
code, _, err = run(["skeletal", BVH, "-o", w("r.bvh"), "--report", w("report.html"), "--server",
                    target, "-q"])
check(code == 0 and os.path.islink(w("report.html")), f"--report through a link: {err}")
page = open(w("real.html"), "rb").read()
check(page.startswith(b"<!DOCTYPE html>") or page.lower().startswith(b"<!doctype html>"), page[:40])
code, out, err = run(["curves", ARM, "-o", w("r.json"), "--report", "-", "--server", target])
check(code == 0 and out.lower().startswith(b"<!doctype html>") and "report: -" in err,
      f"--report -: {code} {out[:40]!r} {err}")
r, _ = summary(["lipblink", TALK, "-o", w("r.csv"), "--report", w("r.html")])
check(r["outputs"] == {"curves": w("r.csv"), "report": w("r.html")}, r["outputs"])

# /dev/stdout (a link to /proc/self/fd/1) is written into, never replaced.
code, out, _ = run(["skeletal", BVH, "-o", "/dev/stdout", "--server", target, "-q"])
check(code == 0 and out == open(w("file.bvh"), "rb").read(), "-o /dev/stdout")
check(os.path.islink("/dev/stdout"), "/dev/stdout is no longer a link")

# Awkward CSV from a spreadsheet: a byte order mark, ';' separators, decimal commas, an id
# with a comma. koma reads it, writes RFC 4180 CSV (the id quoted), and reads that back.
rows = ["frame;Param,X;ParamAngleY"] + [f"{f};{f % 7},5;{-f}" for f in range(40)]
open(w("excel.csv"), "wb").write(b"\xef\xbb\xbf" + "\r\n".join(rows).encode() + b"\r\n")
code, _, err = run(["curves", w("excel.csv"), "-o", w("excel_out.csv"), "--timing-fps", "0",
                    "--server", target, "-q"])
check(code == 0, f"curves on an Excel CSV: {err}")
with open(w("excel_out.csv"), newline="") as f:
    table = list(csv.reader(f))
check(table[0] == ["frame", "Param,X", "ParamAngleY"], f"header {table[0]}")
check(open(w("excel_out.csv")).readline() == 'frame,"Param,X",ParamAngleY\n', "quoted id")
check(len(table) == 41 and float(table[1][1]) == 0.5, table[1])
code, _, err = run(["curves", w("excel_out.csv"), "-o", w("excel_again.csv"), "--timing-fps",
                    "0", "--server", target, "-q"])
check(code == 0, f"koma reads back its own CSV: {err}")

# --send-file: the server parses the file (bvh_text, motion3_json, csv_text + csv_fps); the
# outputs are the same bytes as when the CLI sends the decoded data.
for cmd, src, out_name, extra in [
        ("skeletal", BVH, "sf.bvh", ["--timing", w("sf_sheet.csv")]),
        ("skeletal", BVH, "sfg.bvh", ["--output-rate", "timing", "--timing-fps", "12"]),
        ("curves", ARM, "sf.motion3.json", ["--timing", w("sf_sheet.csv")]),
        ("curves", w("arm.csv"), "sf.csv", ["--fps", "24"]),
        ("lipblink", TALK, "sf_talk.motion3.json", ["--seed", "3"]),
        ("lipblink", w("l.csv"), "sf_talk.csv", ["--fps", "25"])]:
    outputs = {}
    for mode in ([], ["--send-file"]):
        code, _, err = run([cmd, src, "-o", w(out_name)] + extra + mode + ["--server", target, "-q"])
        check(code == 0, f"{cmd} {src} {mode}: {err}")
        outputs[bool(mode)] = [open(w(out_name), "rb").read()] + (
            [open(w("sf_sheet.csv"), "rb").read()] if w("sf_sheet.csv") in extra else [])
    check(outputs[False] == outputs[True], f"{cmd} {src} {extra}: --send-file gives other bytes")

# ---------------------------------------------------------------------------------------------
# 5. Every request flag, through the real server.
camera = "1,0,0,0,0,1,0,0,0,0,1,0,0,0,-500,1"
FULL = [
    ["skeletal", BVH, "-o", w("all.bvh"), "--timing", w("all.csv"), "--omissions", "3",
     "--holds", "5", "--max-hold", "2", "--keep-length=false", "--order", "hold-then-omit",
     "--joint-weights", "Hips=0.5,Head=2", "--root-relative", "--camera", camera,
     "--return-motion", "true", "--timing-fps", "30", "--output-rate", "timing"],
    ["curves", ARM, "-o", w("all.motion3.json"), "--timing", w("all_sheet.csv"),
     "--key-frames", "0,30,60,90", "--frames-per-drawing", "2", "--tame", "1.5", "--tsume",
     "1.25", "--curve-overrides", "ParamArmRA=3", "--segment-overrides",
     "1:frames-per-drawing=3,tame=2,tsume=1.5", "--timing-fps", "24"],
    ["lipblink", TALK, "-o", w("all_talk.motion3.json"), "--mouth-ids", "ParamMouthOpenY",
     "--mouth-mode", "follow", "--mouth-frames-per-shape", "2", "--mouth-mid-ratio", "0.4",
     "--mouth-min", "0", "--mouth-max", "1", "--mouth-speech", "5-50,60-100",
     "--eyes-ids", "ParamEyeLOpen,ParamEyeROpen", "--eyes-mid-ratio", "0.5",
     "--eyes-threshold", "0.2", "--eyes-min", "0", "--eyes-max", "1", "--eyes-linked", "false",
     "--auto-blink-enabled", "true", "--auto-blink-mean-interval-s", "1.5",
     "--auto-blink-spread-s", "0.25", "--auto-blink-hold", "1", "--auto-blink-keep", "0-10",
     "--seed", "7", "--timing-fps", "24"],
]
for args in FULL:
    code, _, err = run(args + ["--server", target, "-q"])
    check(code == 0, f"koma {' '.join(args)}: exit {code}: {err}")

# ---------------------------------------------------------------------------------------------
# 6. Text encodings: a UTF-8 byte order mark (Windows tools write one) is skipped in every file
#    koma reads, client side (BVH, motion3.json, --config, @LIST) and server side
#    (--send-file); UTF-16 is refused naming the encoding.
BOM = b"\xef\xbb\xbf"
for cmd, src, ext in (("skeletal", BVH, ".bvh"), ("lipblink", TALK, ".motion3.json")):
    open(w("bom" + ext), "wb").write(BOM + open(src, "rb").read())
    outputs = []
    for given, extra in ((src, []), (w("bom" + ext), []), (w("bom" + ext), ["--send-file"])):
        out = w(f"enc{len(outputs)}{ext}")
        code, _, err = run([cmd, given, "-o", out, "-q", "--server", target] + extra)
        check(code == 0, f"{cmd} {given} {extra}: exit {code}: {err}")
        outputs.append(open(out, "rb").read() if code == 0 else None)
    check(outputs[0] is not None and outputs[1] == outputs[0] and outputs[2] == outputs[0],
          f"{cmd}: a byte order mark changed the output")
open(w("utf16.bvh"), "wb").write(open(BVH).read().encode("utf-16"))  # FF FE, little-endian
for extra in ([], ["--send-file"]):
    code, _, err = run(["skeletal", w("utf16.bvh"), "-o", w("u.bvh"), "--server", target] + extra)
    check(code == 1 and "the file is UTF-16 (little-endian, byte order mark FF FE), not UTF-8: "
          "save it as UTF-8" in err, f"UTF-16 BVH {extra}: {code} {err}")
open(w("bom.toml"), "wb").write(BOM + b"[skeletal]\nomissions = 6\n")
cfg, _ = summary(["--config", w("bom.toml"), "skeletal", BVH, "-o", w("cfg.bvh")])
check(cfg["omissions_requested"] == 6, f"--config with a byte order mark: {cfg}")
open(w("utf16.toml"), "wb").write("[skeletal]\nomissions = 6\n".encode("utf-16"))
code, _, err = run(["--config", w("utf16.toml"), "skeletal", BVH, "-o", w("cfg.bvh"),
                    "--server", target])
check(code == 2 and err.startswith(f"koma: --config {w('utf16.toml')}: the file is UTF-16 "
                                   "(little-endian, byte order mark FF FE)"), f"{code} {err}")
open(w("bom_list.txt"), "wb").write(BOM + BVH.encode() + b"\n")
code, _, err = run(["batch", "skeletal", "@" + w("bom_list.txt"), "-o", w("listed"), "-q",
                    "--server", target])
listed = [f for _, _, files in os.walk(w("listed")) for f in files if f.endswith(".bvh")]
check(code == 0 and listed == ["pitch.bvh"], f"@LIST with a byte order mark: {code} {err} {listed}")
open(w("utf16_list.txt"), "wb").write((BVH + "\n").encode("utf-16"))
code, _, err = run(["batch", "skeletal", "@" + w("utf16_list.txt"), "-o", w("listed16"),
                    "--server", target])
check(code != 0 and "the file is UTF-16" in err, f"UTF-16 @LIST: {code} {err}")

print(f"{len(failures)} failures")
sys.exit(1 if failures else 0)
