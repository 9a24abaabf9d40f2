"""e2e.hostile_wire (issue 42): hostile and extreme files in the newer formats (audio, glTF,
Spine, Rhubarb cues), each sent straight over the wire to the real koma_server with a short
deadline, as the Python package or any other client sends them.

For every file it checks: the answer is the expected gRPC code with a message naming the
cause, within the deadline plus a small margin; the server's CPU is idle again within a second
of the answer (no work left running for a client that has gone); a small call sent meanwhile on
another channel is answered OK in time (no starvation); and at the end the server's peak RSS is
within its --max_memory_mb budget plus a stated overhead and health says SERVING. It prints
each file's size, code, time and the server's peak RSS during it (docs/reliability.md).

Usage: hostile_wire_test.py KOMA_SERVER SAMPLES_DIR   (PYTHONPATH: the built koma package)
"""
import os
import subprocess
import sys
import tempfile
import threading
import time

import grpc

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), 'hostile'))
import hostile_files as hf  # noqa: E402
from koma import _health_pb2  # noqa: E402
from koma.v1 import retime_pb2 as pb  # noqa: E402

# Sanitizer builds run several times slower and hold more memory: scripts/test-sanitizers.sh
# sets KOMA_TEST_TIME_SCALE, which stretches every time and the memory overhead below.
SCALE = float(os.environ.get('KOMA_TEST_TIME_SCALE', '1'))
BUDGET_MB = 1024
OVERHEAD_MB = 96 * SCALE        # code, gRPC's threads and buffers, malloc's slack
MARGIN_S = 0.5 * SCALE          # an answer may come this long after the deadline
IDLE_WITHIN_S = 1.0 * SCALE     # the server's CPU is idle again this soon after an answer
SMALL_DEADLINE_S = 3.0 * SCALE

OK = grpc.StatusCode.OK
INVALID = grpc.StatusCode.INVALID_ARGUMENT
EXHAUSTED = grpc.StatusCode.RESOURCE_EXHAUSTED
DEADLINE = grpc.StatusCode.DEADLINE_EXCEEDED


def fail(message):
    print('FAIL: ' + message, flush=True)
    sys.exit(1)


def bvh_claiming(frames):
    """A one-joint BVH whose Frames line claims `frames` but which holds two."""
    return ('HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n'
            '  End Site\n  {\n    OFFSET 0 1 0\n  }\n}\nMOTION\nFrames: %d\n'
            'Frame Time: 0.033333\n0 0 0\n1 2 3\n' % frames).encode()


def samples_file(name):
    return open(os.path.join(sys.argv[2], name), 'rb').read()


def cases():
    """(name, rpc, request, deadline seconds, expected codes, what the message names: one of
    the |-separated fragments)."""
    skeletal = lambda **kw: ('RetimeSkeletal', pb.RetimeSkeletalRequest(**kw))  # noqa: E731
    curves = lambda **kw: ('RetimeCurves', pb.RetimeCurvesRequest(**kw))  # noqa: E731
    lipblink = lambda **kw: ('LipBlink', pb.LipBlinkRequest(**kw))  # noqa: E731
    voice = lambda audio: lipblink(audio=audio)  # noqa: E731
    hour_8ch_1mhz = hf.flac_silence(1_000_000, 8, 4, 7200 * 1_000_000)
    unknown_length = hf.flac_silence(1_000_000, 8, 2500, 0)  # 1.3 G samples, length unknown
    return [
        # Audio: cost from the product of rate, channels and length.
        ('flac 8 ch x 1 MHz x 2 h (the header)', *voice(hour_8ch_1mhz), 3.0, {EXHAUSTED},
         '--max_audio_samples'),
        ('flac 8 ch x 1 MHz, length unknown', *voice(unknown_length), 1.0, {EXHAUSTED, DEADLINE},
         ''),
        ('wav at 0 Hz', *voice(hf.wav(0, 1, 100)), 3.0, {INVALID}, 'sample rate'),
        ('wav claiming 4 GiB of samples', *voice(hf.wav(48000, 2, 4800, data_claim=0xFFFFFF00)),
         3.0, {INVALID, EXHAUSTED}, 'audio: '),
        ('empty audio', *voice(b''), 3.0, {INVALID}, 'audio'),
        ('random bytes as audio', *voice(os.urandom(4096)), 3.0, {INVALID}, 'audio: '),
        # glTF: the animation count and the sampled frames of all of them.
        ('glb of 60,000 animations', *skeletal(gltf=hf.gltf_animations(60000)), 3.0,
         {EXHAUSTED}, '--max_gltf_animations|--max_memory_mb'),
        ('glb of 200,000 empty animations', *skeletal(gltf=hf.gltf_animations(200000, empty=True)),
         3.0, {EXHAUSTED}, '--max_gltf_animations'),
        ('glb of 4,000 animations of 1,000 s', *skeletal(gltf=hf.gltf_animations(4000, (0, 1000))),
         3.0, {EXHAUSTED}, '--max_values'),
        ('glb of 4,000 animations (the limit)', *skeletal(gltf=hf.gltf_animations(4000)), 3.0,
         {OK, DEADLINE}, ''),
        ('glb key time 1e30 s', *skeletal(gltf=hf.gltf_animations(1, (0, 1e30))), 3.0,
         {EXHAUSTED}, '--max_values'),
        ('glb negative key time', *skeletal(gltf=hf.gltf_animations(1, (-1.0, 1.0))), 3.0,
         {INVALID}, 'key times are >= 0'),
        ('empty glb', *skeletal(gltf=b''), 3.0, {INVALID}, 'empty'),
        ('.gltf with 2 MB of broken base64', *skeletal(gltf=hf.gltf_text_broken_data_uri(2_000_000)),
         3.0, {INVALID}, 'buffers[0].uri: character 0 of its base64 data'),
        ('glb header only', *skeletal(gltf=b'glTF\x02\0\0\0\x0c\0\0\0'), 3.0, {INVALID}, 'gltf'),
        # FBX: nesting, a zip bomb, a take of a million seconds, ASCII.
        ('fbx zip bomb (2^31 doubles in 10 bytes)', *skeletal(fbx=hf.fbx_zip_bomb()), 3.0,
         {EXHAUSTED}, 'an array of 2147483648 elements'),
        ('fbx nested 100,000 deep', *skeletal(fbx=hf.fbx_nested(100000)), 3.0, {EXHAUSTED},
         'nested deeper than 32'),
        ('fbx take of 1,000,000 s', *skeletal(fbx=hf.fbx_long_take(
            samples_file('huesitos.fbx'), 1e6)), 3.0, {EXHAUSTED}, '--max_values'),
        ('ascii fbx', *skeletal(fbx=b'; FBX 7.4.0 project file\nFBXHeaderExtension:  {\n'), 3.0,
         {INVALID}, 'ASCII FBX'),
        # Spine: bones the runtimes refuse, and many keys.
        ('spine bone its own parent',
         *curves(spine_json=hf.spine([{"name": "root"}, {"name": "arm", "parent": "arm"}])),
         3.0, {INVALID}, 'bones[1].parent'),
        ('spine bone cycle', *curves(spine_json=hf.spine(
            [{"name": "root"}, {"name": "arm", "parent": "leg"}, {"name": "leg", "parent": "arm"}])),
         3.0, {INVALID}, 'bones[1].parent'),
        ('spine duplicate bone', *curves(spine_json=hf.spine(
            [{"name": "root"}, {"name": "arm", "parent": "root"}, {"name": "arm", "parent": "root"}])),
         3.0, {INVALID}, 'bones[2]'),
        ('spine as UTF-16', *curves(spine_json=b'\xff\xfe' + hf.spine().decode().encode('utf-16-le')),
         3.0, {INVALID}, 'UTF-16'),
        ('spine nested 100,000 deep', *curves(spine_json=b'[' * 100000 + b']' * 100000), 3.0,
         {INVALID}, 'nested deeper'),
        ('spine 1,000,000 keys', *curves(spine_json=hf.spine(keys=1_000_000, duration=3600.0)),
         3.0, {OK, DEADLINE, EXHAUSTED}, ''),
        # The older formats, one row each (their own batteries: tests/formats/*_malformed_test).
        ('bvh claiming 2,000,000,000 frames', *skeletal(bvh_text=bvh_claiming(2_000_000_000)),
         3.0, {INVALID, EXHAUSTED}, 'bvh_text: line'),
        ('motion3.json nested 100,000 deep',
         *curves(motion3_json=b'{"Curves":' + b'[' * 100000 + b']' * 100000 + b'}'), 3.0,
         {INVALID}, 'nested deeper'),
        ('csv of 1e999', *curves(csv_text=b'frame,ParamA\n0,0\n1,1e999\n'), 3.0, {INVALID},
         'csv_text: line 3'),
        # Rhubarb cues.
        ('rhubarb cue ending at 1e308 s', *lipblink(rhubarb_cues=hf.rhubarb(3, last_end=1e308)),
         3.0, {EXHAUSTED, INVALID}, 'rhubarb_cues'),
        ('rhubarb cut short', *lipblink(rhubarb_cues=hf.rhubarb(3)[:-7]), 3.0, {INVALID},
         'byte'),
        ('rhubarb 300,000 cues', *lipblink(rhubarb_cues=hf.rhubarb(300000)), 3.0,
         {OK, DEADLINE, EXHAUSTED}, ''),
    ]


def start_server(binary, work):
    port_file = os.path.join(work, 'port')
    log = open(os.path.join(work, 'server.log'), 'w')
    server = subprocess.Popen(
        [binary, '--address=127.0.0.1:0', '--port_file=' + port_file,
         '--max_memory_mb=%d' % BUDGET_MB, '--log_format=json', '--shutdown_grace_ms=2000'],
        stdout=log, stderr=subprocess.STDOUT)
    for _ in range(200):
        if os.path.exists(port_file) and open(port_file).read().strip():
            return server, '127.0.0.1:' + open(port_file).read().strip()
        if server.poll() is not None:
            fail('koma_server exited: ' + open(log.name).read())
        time.sleep(0.05)
    server.kill()
    fail('koma_server did not start in 10 s')


def cpu_seconds(pid):
    fields = open('/proc/%d/stat' % pid).read().rsplit(')', 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf('SC_CLK_TCK')


def status_kib(pid, key):
    for line in open('/proc/%d/status' % pid):
        if line.startswith(key + ':'):
            return int(line.split()[1])
    return 0


def idle_after(pid):
    """Seconds until the server used under 10 % of a core over 0.2 s, or None past the bound."""
    start = time.monotonic()
    while time.monotonic() - start < IDLE_WITHIN_S + 0.2:
        before = cpu_seconds(pid)
        time.sleep(0.2)
        if cpu_seconds(pid) - before < 0.02:
            return time.monotonic() - start
    return None


def call(channel, rpc, request, deadline, response_type):
    method = channel.unary_unary('/koma.v1.Retime/' + rpc,
                                 request_serializer=lambda m: m.SerializeToString(),
                                 response_deserializer=response_type.FromString)
    start = time.monotonic()
    try:
        method(request, timeout=deadline)
        return OK, '', time.monotonic() - start
    except grpc.RpcError as error:
        return error.code(), error.details() or '', time.monotonic() - start


RESPONSES = {'RetimeSkeletal': pb.RetimeSkeletalResponse, 'RetimeCurves': pb.RetimeCurvesResponse,
             'LipBlink': pb.LipBlinkResponse}


def main():
    server_bin, samples = sys.argv[1], sys.argv[2]
    pitch = open(os.path.join(samples, 'pitch.bvh'), 'rb').read()
    small = pb.RetimeSkeletalRequest(bvh_text=pitch)
    work = tempfile.mkdtemp()
    server, target = start_server(server_bin, work)
    options = [('grpc.max_send_message_length', 128 << 20),
               ('grpc.max_receive_message_length', 128 << 20)]
    hostile_channel = grpc.insecure_channel(target, options=options)
    small_channel = grpc.insecure_channel(target, options=options + [('grpc.use_local_subchannel_pool', 1)])
    failures = []
    table = cases()
    max_peak = 0
    try:
        # Warm both channels (connection set-up is not the server's answer time).
        for channel in (hostile_channel, small_channel):
            code, details, _ = call(channel, 'RetimeSkeletal', small, 10, pb.RetimeSkeletalResponse)
            if code != OK:
                fail('the warm-up call failed: %s %s' % (code, details))
        print('%-40s %9s %-20s %7s %9s %7s %s' % ('file', 'bytes', 'code', 'time s', 'peak MiB',
                                                  'idle s', 'small call'))
        for name, rpc, request, deadline, expected, fragment in table:
            with open('/proc/%d/clear_refs' % server.pid, 'w') as refs:
                refs.write('5')  # resets VmHWM: this file's own peak
            small_result = {}

            def small_call():
                time.sleep(0.2)
                small_result['answer'] = call(small_channel, 'RetimeSkeletal', small,
                                              SMALL_DEADLINE_S, pb.RetimeSkeletalResponse)

            helper = threading.Thread(target=small_call)
            helper.start()
            deadline *= SCALE
            code, details, seconds = call(hostile_channel, rpc, request, deadline, RESPONSES[rpc])
            idle = idle_after(server.pid)
            helper.join()
            peak = status_kib(server.pid, 'VmHWM') // 1024
            max_peak = max(max_peak, peak)
            small_code, small_details, small_seconds = small_result['answer']
            print('%-40s %9d %-20s %7.2f %9d %7s %s %.2f s' % (
                name, request.ByteSize(), code.name, seconds, peak,
                'none' if idle is None else '%.1f' % idle, small_code.name, small_seconds),
                flush=True)
            if details:
                print('    ' + details[:300])
            problems = []
            if code not in expected:
                problems.append('code %s, expected one of %s: %s' % (
                    code.name, sorted(c.name for c in expected), details))
            if code != OK and fragment and not any(f in details for f in fragment.split('|')):
                problems.append('the message does not name %r: %s' % (fragment, details))
            if code not in (OK, DEADLINE) and not details.strip():
                problems.append('an error without a message')
            if len(details) > 600:
                problems.append('a message of %d characters (a file quoted back?)' % len(details))
            if seconds > deadline + MARGIN_S:
                problems.append('answered after %.2f s, deadline %.1f s' % (seconds, deadline))
            if idle is None:
                problems.append('the server was still busy %.1f s after the answer' % IDLE_WITHIN_S)
            if small_code != OK:
                problems.append('the small call beside it failed: %s %s' % (small_code.name,
                                                                             small_details))
            if server.poll() is not None:
                problems.append('the server exited with %s' % server.returncode)
            failures += ['%s: %s' % (name, p) for p in problems]
            if server.poll() is not None:
                break
        health = grpc.insecure_channel(target).unary_unary(
            '/grpc.health.v1.Health/Check',
            request_serializer=_health_pb2.HealthCheckRequest.SerializeToString,
            response_deserializer=_health_pb2.HealthCheckResponse.FromString)
        status = health(_health_pb2.HealthCheckRequest(), timeout=5).status
        if status != _health_pb2.HealthCheckResponse.SERVING:
            failures.append('health says %s after the files' % status)
        if max_peak > BUDGET_MB + OVERHEAD_MB:
            failures.append('the server peaked at %d MiB, over the budget %d + %d MiB' % (
                max_peak, BUDGET_MB, OVERHEAD_MB))
    finally:
        server.terminate()
        try:
            server.wait(10)
        except subprocess.TimeoutExpired:
            server.kill()
            failures.append('the server did not stop within 10 s of SIGTERM')
    if failures:
        print('--- server log (last 30 lines)')
        print(''.join(open(os.path.join(work, 'server.log')).readlines()[-30:]))
        fail('%d problems:\n  ' % len(failures) + '\n  '.join(failures))
    print('hostile files over the wire: PASS (%d files, server peak %d MiB)' % (len(table), max_peak))


if __name__ == '__main__':
    main()
