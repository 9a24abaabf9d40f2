"""Peak memory per input byte, per file format, on the real koma_server (docs/reliability.md).

Starts koma_server without a memory budget (--max_memory_mb=0), then for each format sends one
large file straight over the wire (as the Python package sends files) and reads the server's
peak RSS during that call (VmHWM, reset before each through /proc/PID/clear_refs). Prints, per
file, its size, the peak above the idle server and the ratio: the figures the memory budget's
per-format factors (server/call_footprint.cc) are set from.

Usage: /usr/bin/python3 bench/format_memory.py KOMA_SERVER SAMPLES_DIR [--small]
  (PYTHONPATH: the built koma package, build/python). --small: files a tenth the size.
"""
import json
import os
import struct
import subprocess
import sys
import tempfile
import time

import grpc

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, '..', 'tests', 'e2e', 'hostile'))
import hostile_files as hf  # noqa: E402
from koma.v1 import retime_pb2 as pb  # noqa: E402


def bvh_take(pitch_text, frames):
    """pitch.bvh's motion repeated (forwards) to `frames` frames."""
    head, motion = pitch_text.split('MOTION', 1)
    lines = motion.strip().splitlines()
    rows = [line for line in lines[2:] if line.strip()]
    out = [head, 'MOTION\nFrames: %d\n' % frames, lines[1] + '\n']
    for i in range(frames):
        out.append(rows[i % len(rows)] + '\n')
    return ''.join(out).encode()


def motion3(curves, keys, fps=30.0):
    """A motion3.json of `curves` curves of `keys` linear keys each, a key every frame."""
    duration = (keys - 1) / fps
    out = []
    for c in range(curves):
        segments = [0.0, 0.0]
        for k in range(1, keys):
            segments += [0, round(k / fps, 4), round(((k * 37 + c) % 100) / 10.0, 2)]
        out.append({"Target": "Parameter", "Id": "Param%d" % c, "Segments": segments})
    doc = {"Version": 3, "Meta": {"Duration": round(duration, 4), "Fps": fps, "Loop": False,
                                   "AreBeziersRestricted": True, "CurveCount": curves,
                                   "TotalSegmentCount": curves * (keys - 1),
                                   "TotalPointCount": curves * keys},
           "Curves": out}
    return json.dumps(doc, separators=(',', ':')).encode()


def csv(curves, frames):
    lines = ['frame,' + ','.join('Param%d' % c for c in range(curves))]
    for f in range(frames):
        lines.append('%d,' % f + ','.join('%.2f' % (((f * 37 + c) % 100) / 10.0)
                                          for c in range(curves)))
    return ('\n'.join(lines) + '\n').encode()


def glb_keys(keys):
    """One animation moving a node through `keys` keys (binary-heavy: 16 bytes a key)."""
    times = [k / 30.0 for k in range(keys)]
    return hf.gltf_animations(1, tuple(times))


def files(samples, scale):
    pitch = open(os.path.join(samples, 'pitch.bvh')).read()
    n = lambda x: max(2, int(x * scale))  # noqa: E731
    return [
        ('BVH', 'RetimeSkeletal', lambda b: pb.RetimeSkeletalRequest(bvh_text=b),
         bvh_take(pitch, n(60000))),
        ('glTF (GLB, keys)', 'RetimeSkeletal', lambda b: pb.RetimeSkeletalRequest(gltf=b),
         glb_keys(n(500000))),
        ('glTF (GLB, 4,000 animations)', 'RetimeSkeletal',
         lambda b: pb.RetimeSkeletalRequest(gltf=b), hf.gltf_animations(n(4000) if scale < 1 else 4000)),
        ('motion3.json', 'RetimeCurves', lambda b: pb.RetimeCurvesRequest(motion3_json=b),
         motion3(40, n(12000))),
        ('curve CSV', 'RetimeCurves', lambda b: pb.RetimeCurvesRequest(csv_text=b),
         csv(40, n(60000))),
        ('Spine JSON', 'RetimeCurves', lambda b: pb.RetimeCurvesRequest(spine_json=b),
         hf.spine(keys=n(1_000_000), duration=3600.0)),
        ('audio (WAV)', 'LipBlink', lambda b: pb.LipBlinkRequest(audio=b),
         hf.wav(48000, 2, n(48000 * 300))),
        ('Rhubarb JSON', 'LipBlink', lambda b: pb.LipBlinkRequest(rhubarb_cues=b),
         hf.rhubarb(n(70000))),
    ]


RESPONSES = {'RetimeSkeletal': pb.RetimeSkeletalResponse, 'RetimeCurves': pb.RetimeCurvesResponse,
             'LipBlink': pb.LipBlinkResponse}


def kib(pid, key):
    for line in open('/proc/%d/status' % pid):
        if line.startswith(key + ':'):
            return int(line.split()[1])
    return 0


def main():
    server_bin, samples = sys.argv[1], sys.argv[2]
    scale = 0.1 if '--small' in sys.argv[3:] else 1.0
    work = tempfile.mkdtemp()
    port_file = os.path.join(work, 'port')
    server = subprocess.Popen([server_bin, '--address=127.0.0.1:0', '--port_file=' + port_file,
                               '--max_memory_mb=0', '--idle_trim_ms=1'],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        for _ in range(200):
            if os.path.exists(port_file) and open(port_file).read().strip():
                break
            time.sleep(0.05)
        channel = grpc.insecure_channel('127.0.0.1:' + open(port_file).read().strip(), options=[
            ('grpc.max_send_message_length', 256 << 20),
            ('grpc.max_receive_message_length', 256 << 20)])
        print('| format | file MB | peak MiB above idle | MiB per MB | answer |')
        print('|---|---|---|---|---|')
        for name, rpc, make, data in files(samples, scale):
            time.sleep(0.3)  # the previous call's memory trimmed (--idle_trim_ms)
            rest = kib(server.pid, 'VmRSS')
            with open('/proc/%d/clear_refs' % server.pid, 'w') as refs:
                refs.write('5')
            method = channel.unary_unary('/koma.v1.Retime/' + rpc,
                                         request_serializer=lambda m: m.SerializeToString(),
                                         response_deserializer=RESPONSES[rpc].FromString)
            try:
                method(make(data), timeout=120)
                answer = 'OK'
            except grpc.RpcError as error:
                answer = '%s: %s' % (error.code().name, (error.details() or '')[:80])
            peak = (kib(server.pid, 'VmHWM') - rest) / 1024
            mb = len(data) / 1e6
            print('| %s | %.1f | %.0f | %.1f | %s |' % (name, mb, peak, peak / mb, answer),
                  flush=True)
    finally:
        server.terminate()
        server.wait(10)


if __name__ == '__main__':
    main()
