"""A real OSC receiver for tests/e2e/live_vmc_e2e_test.sh, through Debian's python3-liblo (the
liblo that VMC receivers' own tests use; koma sends through the same library's C API, but the
bytes are decoded here by liblo's server, and the unit test decodes them by hand). Modes:

  receive PORT_FILE OUT_JSON STOP_FILE
      binds a free UDP port on 127.0.0.1, writes its number to PORT_FILE, and records every
      bundle (its messages: address, type tags, arguments) until STOP_FILE exists, then writes
      them to OUT_JSON.
  check OUT_JSON FRAMES_JSONL MOUTH_CLIP BLINK_CLIP MOUTH_MIN MOUTH_MAX
      one bundle per frame of `koma live --json`, in order, each exactly
      /VMC/Ext/Blend/Val ,sf MOUTH_CLIP (mouth_level - min) / (max - min),
      /VMC/Ext/Blend/Val ,sf BLINK_CLIP 1 - eye_level, /VMC/Ext/Blend/Apply with no argument;
      values as float32. Prints the counts of each mouth and blink value seen.
Exits 1 with the reasons on a failure.
"""
import json
import os
import struct
import sys


def receive(port_file, out_json, stop_file):
    import liblo  # python3-liblo

    server = liblo.Server(proto=liblo.UDP)  # no port: liblo picks a free one
    bundles = []
    current = []

    def on_start(timetag, user_data):
        current.clear()

    def on_end(user_data):
        bundles.append(list(current))

    def on_message(path, args, types, src):
        current.append({"address": path, "types": types, "args": list(args)})
        return 0

    server.add_bundle_handlers(on_start, on_end)
    server.add_method(None, None, on_message)
    with open(port_file + ".tmp", "w") as out:
        out.write(str(server.port))
    os.rename(port_file + ".tmp", port_file)
    while not os.path.exists(stop_file):
        server.recv(50)  # ms
    while server.recv(0):  # whatever is still queued
        pass
    with open(out_json, "w") as out:
        json.dump(bundles, out)


def f32(value):
    return struct.unpack("<f", struct.pack("<f", value))[0]


def check(out_json, frames_jsonl, mouth_clip, blink_clip, mouth_min, mouth_max):
    with open(out_json) as f:
        bundles = json.load(f)
    with open(frames_jsonl) as f:
        frames = [json.loads(line) for line in f if line.strip()]
    errors = []
    if not frames:
        errors.append("no frames in " + frames_jsonl)
    if len(bundles) != len(frames):
        errors.append(f"{len(bundles)} bundles for {len(frames)} frames")
    lo, hi = float(mouth_min), float(mouth_max)
    mouth_seen, blink_seen = {}, {}
    for i, (bundle, frame) in enumerate(zip(bundles, frames)):
        mouth = f32(min(1.0, max(0.0, (frame["mouth_level"] - lo) / (hi - lo))))
        blink = f32(1.0 - frame["eye_level"])
        want = [
            {"address": "/VMC/Ext/Blend/Val", "types": "sf", "args": [mouth_clip, mouth]},
            {"address": "/VMC/Ext/Blend/Val", "types": "sf", "args": [blink_clip, blink]},
            {"address": "/VMC/Ext/Blend/Apply", "types": "", "args": []},
        ]
        if bundle != want:
            errors.append(f"bundle {i} (grid frame {frame['grid_frame']}): {bundle}, want {want}")
            if len(errors) > 10:
                break
        mouth_seen[mouth] = mouth_seen.get(mouth, 0) + 1
        blink_seen[blink] = blink_seen.get(blink, 0) + 1
    print(f"{len(bundles)} bundles; {mouth_clip} values {sorted(mouth_seen.items())}; "
          f"{blink_clip} values {sorted(blink_seen.items())}")
    if errors:
        print("FAIL:\n  " + "\n  ".join(errors), file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    mode, args = sys.argv[1], sys.argv[2:]
    if mode == "receive":
        receive(*args)
    elif mode == "check":
        check(*args)
    else:
        sys.exit(f"unknown mode {mode}")
