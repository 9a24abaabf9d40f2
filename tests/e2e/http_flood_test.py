"""e2e.http_flood (issue 45): the HTTP port and the gRPC port share one admission. The real
koma_server with one worker and a queue of one (--worker_threads=1 --max_queued=1); calls of a
2.4 MB clip (~0.1 s each, above --inline_max_bytes, so they need the pool).

1. Six HTTP clients flood the Connect API with it for FLOOD_S seconds while one gRPC client
   sends the same call and another sends small calls (a Pitch-size clip, run inline): the
   flood's answers are OK or resource_exhausted (429) naming --max_queued, the gRPC client of
   large calls is refused RESOURCE_EXHAUSTED with the same message (the HTTP flood holds the
   queue it needs), and every small gRPC call is OK with its median latency under SMALL_P50_S.
2. The same the other way: six gRPC clients flood, an HTTP client of large calls is refused
   429 resource_exhausted naming --max_queued, small HTTP calls are OK in time.

Usage: http_flood_test.py KOMA_SERVER SAMPLES_DIR   (PYTHONPATH: the koma package, tests/testing)
"""
import os
import random
import statistics
import sys
import tempfile
import threading
import time

import grpc

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from connect_client import ConnectClient  # noqa: E402
from koma.v1 import retime_pb2 as pb  # noqa: E402
from koma_server import KomaServer  # noqa: E402

SCALE = float(os.environ.get('KOMA_TEST_TIME_SCALE', '1'))
FLOOD_S = 3.0
FLOODERS = 6
SMALL_P50_S = 0.1 * SCALE
EXHAUSTED = grpc.StatusCode.RESOURCE_EXHAUSTED
OK = grpc.StatusCode.OK


def heavy_bvh(frames=6000, joints=20):
    """A random clip of `frames` frames and `joints` joints as BVH text (~2.4 MB)."""
    rng = random.Random(7)
    lines = ['HIERARCHY', 'ROOT J0', '{', 'OFFSET 0 0 0',
             'CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation']
    for j in range(1, joints):
        lines += ['JOINT J%d' % j, '{', 'OFFSET 0 1 0', 'CHANNELS 3 Zrotation Xrotation Yrotation']
    lines += ['End Site', '{', 'OFFSET 0 1 0', '}'] + ['}'] * joints
    lines += ['MOTION', 'Frames: %d' % frames, 'Frame Time: 0.0083333']
    row = 6 + 3 * (joints - 1)
    lines += [' '.join('%.2f' % rng.uniform(-90, 90) for _ in range(row)) for _ in range(frames)]
    return ('\n'.join(lines) + '\n').encode()


class Caller:
    """Calls one request in a loop until `stop`, recording (code, message, seconds)."""

    def __init__(self, call, request, stop, pause_s=0.0):
        self.results = []
        self.thread = threading.Thread(target=self.run, args=(call, request, stop, pause_s))
        self.thread.start()

    def run(self, call, request, stop, pause_s):
        while not stop.is_set():
            start = time.monotonic()
            code, message = call(request)
            self.results.append((code, message, time.monotonic() - start))
            if pause_s:
                time.sleep(pause_s)


def grpc_caller(address):
    call = grpc.insecure_channel(address).unary_unary('/koma.v1.Retime/RetimeSkeletal')

    def one(request):
        try:
            call(request, timeout=30)
            return OK, ''
        except grpc.RpcError as error:
            return error.code(), error.details() or ''
    return one


def http_caller(port):
    client = ConnectClient(port, timeout_s=30)

    def one(request):
        code, message, _, _ = client.call('RetimeSkeletal', request, 30_000)
        return code, message
    return one


def check(name, results, failures, want_refused, small=False):
    codes = [code for code, _, _ in results]
    refused = [m for code, m, _ in results if code == EXHAUSTED]
    other = [(code.name, m) for code, m, _ in results if code not in (OK, EXHAUSTED)]
    median = statistics.median(s for _, _, s in results) if results else float('nan')
    print('  %-34s %4d calls: %4d OK, %4d RESOURCE_EXHAUSTED, median %.3f s' % (
        name, len(codes), codes.count(OK), len(refused), median), flush=True)
    if not results:
        failures.append('%s: no call finished' % name)
    if other:
        failures.append('%s: other answers: %s' % (name, other[:3]))
    if any('--max_queued' not in m for m in refused):
        failures.append('%s: a refusal does not name --max_queued: %s' % (name, refused[0]))
    if want_refused and not refused:
        failures.append('%s: never refused: admission is not shared' % name)
    if small and (codes.count(OK) != len(codes) or median > SMALL_P50_S):
        failures.append('%s: small calls not all OK in time (median %.3f s, bound %.3f s)' % (
            name, median, SMALL_P50_S))


def round_of(flood, others, failures, title):
    print(title, flush=True)
    stop = threading.Event()
    flooders = [Caller(make(), request, stop) for make, request in flood]
    watchers = [(name, Caller(make(), request, stop, 0.01), want, small)
                for name, make, request, want, small in others]
    time.sleep(FLOOD_S)
    stop.set()
    for caller in flooders + [w[1] for w in watchers]:
        caller.thread.join(60)
    check('the flood', [r for c in flooders for r in c.results], failures, True)
    for name, caller, want, small in watchers:
        check(name, caller.results, failures, want, small)


def main():
    server_bin, samples = sys.argv[1:3]
    work = tempfile.mkdtemp(prefix='http_flood.')
    port_file = os.path.join(work, 'http.port')
    server = KomaServer(server_bin, work, '--http_port=0', '--http_port_file=' + port_file,
                        '--worker_threads=1', '--max_queued=1', '--http_threads=8',
                        '--log_level=warn')
    failures = []
    try:
        port = int(open(port_file).read())
        heavy = pb.RetimeSkeletalRequest(bvh_text=heavy_bvh()).SerializeToString()
        small = pb.RetimeSkeletalRequest(
            bvh_text=open(os.path.join(samples, 'pitch.bvh'), 'rb').read()).SerializeToString()
        to_grpc = lambda: grpc_caller(server.address)  # noqa: E731
        to_http = lambda: http_caller(port)  # noqa: E731
        round_of([(to_http, heavy)] * FLOODERS,
                 [('gRPC large calls beside it', to_grpc, heavy, True, False),
                  ('gRPC small calls beside it', to_grpc, small, False, True)],
                 failures, 'HTTP flood (%d clients), gRPC beside it:' % FLOODERS)
        round_of([(to_grpc, heavy)] * FLOODERS,
                 [('HTTP large calls beside it', to_http, heavy, True, False),
                  ('HTTP small calls beside it', to_http, small, False, True)],
                 failures, 'gRPC flood (%d clients), HTTP beside it:' % FLOODERS)
    finally:
        code = server.stop()
        if code != 0:
            failures.append('koma_server exited %s after SIGTERM' % code)
    if failures:
        print('FAIL: %d problems:\n  %s' % (len(failures), '\n  '.join(failures)))
        sys.exit(1)
    print('one admission for both ports: PASS')


if __name__ == '__main__':
    main()
