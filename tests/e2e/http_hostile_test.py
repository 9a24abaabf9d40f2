"""e2e.http_hostile (issue 45): the hostile-file table of e2e.hostile_wire and the fuzz inputs
through the HTTP port's Connect API (binary bodies) of the real koma_server.

- Every row of tests/e2e/hostile_wire_test.py's table, its deadline as Connect-Timeout-Ms:
  one of the row's expected codes (the gRPC table's), a message naming the cause, the HTTP
  status Connect gives the code, answered within the deadline plus a margin.
- The RPC fuzz targets' regression inputs (fuzz/regressions) and 300 seeded mutations of the
  three sample requests (bytes flipped, cut, inserted): the HTTP answer is the gRPC answer to
  the same bytes (code and message, and on OK the same bytes).
- The server is alive and SERVING at the end.

Usage: http_hostile_test.py KOMA_SERVER SAMPLES_DIR FUZZ_REGRESSIONS_DIR
       (PYTHONPATH: the built koma package and tests/testing)
"""
import os
import random
import sys
import tempfile
import time

import grpc

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
server_bin, samples, regressions = sys.argv[1:4]
sys.argv[2] = samples  # hostile_wire_test.samples_file reads argv[2]
import hostile_wire_test as hw  # noqa: E402
from connect_client import ConnectClient  # noqa: E402
from koma import _health_pb2  # noqa: E402
from koma.v1 import retime_pb2 as pb  # noqa: E402
from koma_server import KomaServer  # noqa: E402

HTTP_STATUS = {'OK': 200, 'CANCELLED': 499, 'UNKNOWN': 500, 'INVALID_ARGUMENT': 400,
               'DEADLINE_EXCEEDED': 504, 'NOT_FOUND': 404, 'ALREADY_EXISTS': 409,
               'PERMISSION_DENIED': 403, 'RESOURCE_EXHAUSTED': 429, 'FAILED_PRECONDITION': 400,
               'ABORTED': 409, 'OUT_OF_RANGE': 400, 'UNIMPLEMENTED': 501, 'INTERNAL': 500,
               'UNAVAILABLE': 503, 'DATA_LOSS': 500, 'UNAUTHENTICATED': 401}
MUTATIONS = 300


def grpc_call(channel, rpc, request_bytes, timeout_s):
    call = channel.unary_unary('/koma.v1.Retime/' + rpc)
    try:
        return grpc.StatusCode.OK, '', call(request_bytes, timeout=timeout_s)
    except grpc.RpcError as error:
        return error.code(), error.details() or '', b''


def hostile_rows(client, failures):
    for name, rpc, request, deadline, expected, fragment in hw.cases():
        start = time.monotonic()
        code, message, _, status = client.call(rpc, request.SerializeToString(), deadline * 1000)
        seconds = time.monotonic() - start
        print('%-42s %-20s HTTP %d %6.2f s  %s' % (name, code.name, status, seconds,
                                                  message[:120]), flush=True)
        problems = []
        if code not in expected:
            problems.append('code %s, expected one of %s' % (
                code.name, sorted(c.name for c in expected)))
        if code != grpc.StatusCode.OK and fragment and not any(
                f in message for f in fragment.split('|')):
            problems.append('the message does not name %r: %s' % (fragment, message))
        if status != HTTP_STATUS[code.name]:
            problems.append('HTTP %d for %s' % (status, code.name))
        if seconds > deadline + hw.MARGIN_S:
            problems.append('answered after %.2f s, deadline %.1f s' % (seconds, deadline))
        failures += ['%s: %s' % (name, p) for p in problems]


def fuzz_inputs():
    """(label, rpc, request bytes): the regression inputs, then the seeded mutations."""
    # The RPC targets' inputs start with a byte that chooses the slicing (fuzz/rpc_fuzz_input.h).
    for rpc, folder in (('RetimeSkeletal', 'retime_skeletal'), ('RetimeCurves', 'retime_curves')):
        for name in sorted(os.listdir(os.path.join(regressions, folder))):
            yield folder + '/' + name, rpc, open(os.path.join(regressions, folder, name),
                                                 'rb').read()[1:]
    for name in sorted(os.listdir(os.path.join(regressions, 'gltf'))):
        glb = open(os.path.join(regressions, 'gltf', name), 'rb').read()
        yield 'gltf/' + name, 'RetimeSkeletal', pb.RetimeSkeletalRequest(
            gltf=glb).SerializeToString()
    read = lambda name: open(os.path.join(samples, name), 'rb').read()  # noqa: E731
    seeds = [('RetimeSkeletal', pb.RetimeSkeletalRequest(bvh_text=read('pitch.bvh'))),
             ('RetimeCurves', pb.RetimeCurvesRequest(motion3_json=read('arm_head.motion3.json'))),
             ('LipBlink', pb.LipBlinkRequest(audio=read('voice.flac')))]
    rng = random.Random(45)
    for i in range(MUTATIONS):
        rpc, request = seeds[i % len(seeds)]
        data = bytearray(request.SerializeToString())
        for _ in range(rng.randint(1, 8)):
            kind = rng.randrange(3)
            at = rng.randrange(len(data))
            if kind == 0:
                data[at] = rng.randrange(256)
            elif kind == 1:
                del data[at:at + rng.randint(1, 64)]
            else:
                data[at:at] = bytes(rng.randrange(256) for _ in range(rng.randint(1, 8)))
        yield 'mutation %d' % i, rpc, bytes(data)


def ascii_only(text):
    return ''.join(c if ord(c) < 128 else '?' for c in text)


def fuzz_rows(client, channel, failures):
    counts = {}
    for label, rpc, data in fuzz_inputs():
        http_code, http_message, http_answer, status = client.call(rpc, data, 10_000)
        grpc_code, grpc_message, grpc_answer = grpc_call(channel, rpc, data, 10)
        counts[grpc_code.name] = counts.get(grpc_code.name, 0) + 1
        # A message quoting bytes that are not UTF-8 reaches each client differently (JSON
        # carries U+FFFD for them, Python's gRPC decodes them as it can): compare the ASCII.
        if (http_code, ascii_only(http_message), http_answer) != (
                grpc_code, ascii_only(grpc_message), grpc_answer):
            failures.append('%s (%s): HTTP %s %r, gRPC %s %r' % (
                label, rpc, http_code.name, http_message[:200], grpc_code.name,
                grpc_message[:200]))
        elif status != HTTP_STATUS[grpc_code.name]:
            failures.append('%s: HTTP %d for %s' % (label, status, grpc_code.name))
        if grpc_code in (grpc.StatusCode.INTERNAL, grpc.StatusCode.UNKNOWN):
            failures.append('%s: %s %s' % (label, grpc_code.name, grpc_message))
    print('fuzz inputs through both ports: %s' % ', '.join(
        '%s %d' % item for item in sorted(counts.items())), flush=True)


def main():
    work = tempfile.mkdtemp(prefix='http_hostile.')
    http_port_file = os.path.join(work, 'http.port')
    server = KomaServer(server_bin, work, '--http_port=0', '--http_port_file=' + http_port_file,
                        '--max_memory_mb=%d' % hw.BUDGET_MB, '--http_max_body_bytes=268435456',
                        '--shutdown_grace_ms=2000')
    failures = []
    try:
        client = ConnectClient(int(open(http_port_file).read()))
        channel = grpc.insecure_channel(server.address, options=[
            ('grpc.max_send_message_length', 256 << 20)])
        hostile_rows(client, failures)
        fuzz_rows(client, channel, failures)
        health = channel.unary_unary(
            '/grpc.health.v1.Health/Check',
            request_serializer=_health_pb2.HealthCheckRequest.SerializeToString,
            response_deserializer=_health_pb2.HealthCheckResponse.FromString)
        if health(_health_pb2.HealthCheckRequest(), timeout=5).status != \
                _health_pb2.HealthCheckResponse.SERVING:
            failures.append('health is not SERVING after the inputs')
    finally:
        code = server.stop()
        if code != 0:
            failures.append('koma_server exited %s after SIGTERM' % code)
    if failures:
        print('--- server log (last 20 lines)')
        print(''.join(open(os.path.join(work, 'server.log')).readlines()[-20:]))
        hw.fail('%d problems:\n  ' % len(failures) + '\n  '.join(failures))
    print('hostile files and fuzz inputs through the HTTP port: PASS')


if __name__ == '__main__':
    main()
