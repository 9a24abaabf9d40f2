#!/usr/bin/env python3
"""e2e.live_faults: LiveLipBlink's faults and limits against the real koma_server on loopback.

  live_faults_test.py KOMA_SERVER          (PYTHONPATH: the built Python package, build/python)

One server with --live_max_streams=1 --live_max_queued_frames=24:
- a client killed with SIGKILL mid-stream, and one that closes its channel without half-closing:
  the server's stream count goes back (a new stream is accepted within ~1 s) and it lives on;
- a client that sends fast and reads nothing: bounded (the server stops reading, its RSS stays
  flat), RESOURCE_EXHAUSTED naming --live_max_queued_frames for a client that reads later, the
  call cancelled ~5 s after for one that never reads (the log line says why), the slot freed;
Another with --live_max_seconds=2: audio that never stops ends RESOURCE_EXHAUSTED naming the
flag after the 48 frames of 2 s. A third (the default flags): 1,000 short streams, 250 at once, twice; its RSS after the
first round near idle and not growing in the second (no leak). Bounded: every loop by count and
time, about 30-40 s in all; both servers get SIGTERM and must exit 0.
"""
import array
import asyncio
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time

import grpc
from koma.v1 import retime_pb2 as pb
from koma.v1 import retime_pb2_grpc as rpc

SCALE = float(os.environ.get('KOMA_TEST_TIME_SCALE', '1'))
RATE = 16000
FRAMES_PER_SECOND = 24


def fail(message, log=None):
    if log:
        print('--- %s (last 40 lines)' % log, flush=True)
        print(''.join(open(log).readlines()[-40:]), flush=True)
    print('FAIL: ' + message, flush=True)
    sys.exit(1)


def audio(seconds, start=0):
    """S16 mono at RATE: a voice-like buzz (harmonics of a gliding pitch), 0.3 s on, 0.2 s off."""
    out = array.array('h')
    for i in range(start, start + int(seconds * RATE)):
        t = i / RATE
        on = (t % 0.5) < 0.3
        f0 = 140 + 40 * math.sin(2 * math.pi * 3 * t)
        x = sum(math.sin(2 * math.pi * h * f0 * t) / h for h in (1, 2, 3, 5)) if on else 0.0
        out.append(int(8000 * x))
    return out.tobytes()


def setup_message():
    m = pb.LiveLipBlinkRequest()
    m.setup.sample_rate = RATE
    m.setup.channels = 1
    m.setup.sample_format = pb.LIVE_SAMPLE_S16LE
    return m


def rss_mib(pid):
    for line in open('/proc/%d/status' % pid):
        if line.startswith('VmRSS:'):
            return int(line.split()[1]) / 1024.0
    return 0.0


class Server:
    def __init__(self, binary, work, name, flags):
        self.log = os.path.join(work, name + '.log')
        port_file = os.path.join(work, name + '.port')
        self.process = subprocess.Popen(
            [binary, '--address=127.0.0.1:0', '--port_file=' + port_file,
             '--shutdown_grace_ms=3000', '--shutdown_delay_ms=0'] + flags,
            stdout=open(self.log, 'w'), stderr=subprocess.STDOUT)
        for _ in range(200):
            if os.path.exists(port_file) and open(port_file).read().strip():
                self.target = '127.0.0.1:' + open(port_file).read().strip()
                return
            if self.process.poll() is not None:
                fail('koma_server exited at start', self.log)
            time.sleep(0.05)
        self.process.kill()
        fail('koma_server did not start in 10 s', self.log)

    def alive(self, what):
        if self.process.poll() is not None:
            fail('koma_server died (%s): exit %s' % (what, self.process.returncode), self.log)

    def rss(self):
        return rss_mib(self.process.pid)

    def lines(self, pattern, within=2.0):
        """The log lines matching `pattern`, waiting up to `within` s for one (a stream's line
        is written when the server is done with it, just after its client has the status)."""
        start = time.monotonic()
        while True:
            found = [line for line in open(self.log) if re.search(pattern, line)]
            if found or time.monotonic() - start > within * SCALE:
                return found
            time.sleep(0.05)

    def stop(self):
        self.process.send_signal(signal.SIGTERM)
        try:
            code = self.process.wait(timeout=15 * SCALE)
        except subprocess.TimeoutExpired:
            self.process.kill()
            fail('koma_server still runs 15 s after SIGTERM', self.log)
        if code != 0:
            fail('koma_server exited %d after SIGTERM' % code, self.log)


def short_stream(stub, seconds=0.2, timeout=10):
    """A whole stream of `seconds` of audio: (code, details, frames)."""
    def messages():
        yield setup_message()
        yield pb.LiveLipBlinkRequest(audio=audio(seconds))
    frames = 0
    try:
        for _ in stub.LiveLipBlink(messages(), timeout=timeout):
            frames += 1
        return grpc.StatusCode.OK, '', frames
    except grpc.RpcError as e:
        return e.code(), e.details() or '', frames


def accepted_within(stub, seconds):
    """Seconds until a new stream is accepted and answered OK (None past `seconds`), and the
    last refusal."""
    start = time.monotonic()
    last = None
    for _ in range(1000):
        code, details, frames = short_stream(stub)
        if code == grpc.StatusCode.OK and frames == 5:  # 0.2 s: 4.8 frames
            return time.monotonic() - start, last
        last = (code, details, frames)
        if time.monotonic() - start > seconds:
            return None, last
        time.sleep(0.02)
    return None, last


def client_mode(target):
    """The SIGKILLed client: real-time audio in 10 ms messages, reading; prints 'reading'."""
    channel = grpc.insecure_channel(target)
    stub = rpc.RetimeStub(channel)
    chunk = audio(0.01)

    def messages():
        yield setup_message()
        start = time.monotonic()
        for i in range(3000):  # 30 s at most
            yield pb.LiveLipBlinkRequest(audio=chunk)
            time.sleep(max(0.0, start + 0.01 * (i + 1) - time.monotonic()))
    for n, _ in enumerate(stub.LiveLipBlink(messages(), timeout=40)):
        if n == 2:
            print('reading', flush=True)


def vanishing_clients(server):
    stub = rpc.RetimeStub(grpc.insecure_channel(server.target))
    # SIGKILL: the process' sockets close with no RST_STREAM or GOAWAY first.
    client = subprocess.Popen([sys.executable, os.path.abspath(__file__), '--client',
                               server.target], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              env=dict(os.environ))
    try:
        ready = []
        reader = threading.Thread(target=lambda: ready.append(client.stdout.readline()))
        reader.start()
        reader.join(10 * SCALE)
        if not ready or ready[0].strip() != b'reading':
            fail('the client did not start reading in 10 s: %s' % client.stderr.read(2000)
                 if client.poll() is not None else 'the client did not start reading in 10 s')
        code, details, _ = short_stream(stub)
        if code != grpc.StatusCode.RESOURCE_EXHAUSTED or '--live_max_streams' not in details:
            fail('a second stream beside the first: %s %s (want RESOURCE_EXHAUSTED, '
                 '--live_max_streams=1)' % (code, details), server.log)
        client.kill()
        client.wait(5)
    finally:
        if client.poll() is None:
            client.kill()
            client.wait(5)
    took, last = accepted_within(stub, 3 * SCALE)
    server.alive('after a client was killed')
    if took is None or took > 1.5 * SCALE:
        fail('after the client was SIGKILLed, no new stream was accepted within %s s: %s'
             % (took, last), server.log)
    print('SIGKILLed client: a new stream accepted %.0f ms after' % (took * 1000), flush=True)

    # The channel closed without WritesDone (nor a cancel of the call).
    channel = grpc.insecure_channel(server.target)
    release = threading.Event()

    def messages():
        yield setup_message()
        yield pb.LiveLipBlinkRequest(audio=audio(0.5))
        release.wait(20)
    call = rpc.RetimeStub(channel).LiveLipBlink(messages(), timeout=30)
    next(call)
    channel.close()
    release.set()
    took, last = accepted_within(stub, 3 * SCALE)
    server.alive('after a client closed its channel')
    if took is None or took > 1.5 * SCALE:
        fail('after a client closed its channel, no new stream was accepted within %s s: %s'
             % (took, last), server.log)
    print('closed channel: a new stream accepted %.0f ms after' % (took * 1000), flush=True)
    cancelled = server.lines(r'rpc LiveLipBlink .*code=CANCELLED')
    if len(cancelled) < 2:
        fail('the two vanished clients are not logged code=CANCELLED', server.log)


def non_reader(server, read_later):
    """A client that sends 0.1 s messages about 50 times faster than real time (the server's
    writes keep up) and reads nothing: its receive window fills, the server's writes stop, the
    decided frames queue up to --live_max_queued_frames and the stream ends; the status waits
    behind the write in flight."""
    # A small receive window that does not grow (without these, gRPC's BDP probe grows it past
    # the 7,200 frames of 300 s: the client library holds them all and the server never waits).
    stub = rpc.RetimeStub(grpc.insecure_channel(server.target, options=[
        ('grpc.http2.bdp_probe', 0), ('grpc.http2.lookahead_bytes', 16384)]))
    tenth = audio(0.1)
    sent = [0]
    stop = threading.Event()

    def messages():
        yield setup_message()
        for _ in range(3000):  # 300 s of audio at most; the server stops reading long before
            if stop.is_set():
                return
            yield pb.LiveLipBlinkRequest(audio=tenth)
            sent[0] += 1
            time.sleep(0.002)
        stop.wait(30)  # no half-close
    rest = server.rss()
    # The slot of the stream before may not be free yet (its client has its status before the
    # server is done with it): retry a refused start.
    for _ in range(50):
        begun = time.monotonic()
        call = stub.LiveLipBlink(messages(), timeout=60)
        while sent[0] < 5 and not call.done() and time.monotonic() - begun < 5:
            time.sleep(0.01)
        if sent[0] >= 5:
            break
        if call.code() != grpc.StatusCode.RESOURCE_EXHAUSTED:
            fail('a stream did not start: %s %s' % (call.code(), call.details()), server.log)
        time.sleep(0.05)
    # The window fills and the stream ends in a fraction of a second. For 2 s: the server's
    # RSS. A client that reads later reads then, well before the 5 s the server gives it.
    peak = rest
    while time.monotonic() - begun < 2.0:
        peak = max(peak, server.rss())
        time.sleep(0.05)
    if peak > rest + 64:
        fail('the server RSS grew from %.0f to %.0f MiB for a client reading nothing'
             % (rest, peak), server.log)
    frames, code, details = 0, None, ''
    if read_later:
        try:
            for _ in call:
                frames += 1
            code = grpc.StatusCode.OK
        except grpc.RpcError as e:
            code, details = e.code(), e.details() or ''
        if code != grpc.StatusCode.RESOURCE_EXHAUSTED or '--live_max_queued_frames' not in details:
            fail('a client reading late got %s "%s" after %d frames (want RESOURCE_EXHAUSTED '
                 'naming --live_max_queued_frames)' % (code, details, frames), server.log)
        took, last = accepted_within(stub, 3 * SCALE)
    else:
        # The slot frees when the stream ends (the window filled, well under a second here, plus
        # the 2 s the frames took); the call itself is cancelled 5 s after no frame was written.
        took, last = accepted_within(stub, 10 * SCALE)
        freed = time.monotonic() - begun
        cancelled = server.lines(r'rpc LiveLipBlink .*code=CANCELLED .*the client read nothing '
                                 r'for 5 s after the stream ended \(the client read none of the '
                                 r'last 24 frames', within=10.0)
        cancelled_after = time.monotonic() - begun
        call.cancel()
    stop.set()
    server.alive('after a client that reads nothing')
    if took is None:
        fail('the stream of a client reading nothing kept its slot: %s' % (last,), server.log)
    if read_later:
        freed = time.monotonic() - begun
    print('reading nothing: server RSS %.0f -> peak %.0f MiB in the first 2 s; %s; a new stream '
          'accepted %.1f s after the stream began'
          % (rest, peak,
             'read at 2 s: %d frames then %s' % (frames, code) if read_later else 'never read',
             freed), flush=True)
    if not read_later:
        if not freed <= 4.0 * SCALE:
            fail('the never-reading stream freed its slot %.1f s after it began, want <= 4'
                 % freed, server.log)
        if not cancelled or not 5.0 <= cancelled_after <= 10.0 * SCALE:
            fail('the never-reading stream was not cancelled 5-10 s after it began, with a log '
                 'line saying why (%.1f s)' % cancelled_after, server.log)


def endless_audio(server):
    stub = rpc.RetimeStub(grpc.insecure_channel(server.target))
    tenth = audio(0.1)

    def messages():
        yield setup_message()
        start = time.monotonic()
        for _ in range(600):  # 60 s of audio at most, 10 s at most
            if time.monotonic() - start > 10:
                return
            yield pb.LiveLipBlinkRequest(audio=tenth)
            time.sleep(0.002)
    frames, code, details = [], None, ''
    try:
        for f in stub.LiveLipBlink(messages(), timeout=30):
            frames.append(f.grid_frame)
        code = grpc.StatusCode.OK
    except grpc.RpcError as e:
        code, details = e.code(), e.details() or ''
    if code != grpc.StatusCode.RESOURCE_EXHAUSTED or (
            'the stream reached 2 s of audio, the server limit --live_max_seconds' not in details):
        fail('endless audio: %s "%s" (want RESOURCE_EXHAUSTED naming --live_max_seconds)'
             % (code, details), server.log)
    if frames != list(range(48)):
        fail('endless audio: frames %s, want 0..47 (2 s at 24 fps)' % frames[:60], server.log)
    if not server.lines(r'rpc LiveLipBlink .*frames=48 .*code=RESOURCE_EXHAUSTED .*'
                        r'--live_max_seconds'):
        fail('no log line for the endless stream', server.log)
    print('endless audio: RESOURCE_EXHAUSTED after frames 0..47', flush=True)


async def many_streams(target, count, at_once, seconds):
    """`count` streams, `at_once` open together (each sends half its audio, reads a frame, and
    waits for the rest of its group), over 4 channels. Returns the number that ended OK with
    every frame in order."""
    first, second = audio(seconds / 2), audio(seconds / 2, start=int(seconds / 2 * RATE))
    want = math.ceil(seconds * FRAMES_PER_SECOND)
    channels = [grpc.aio.insecure_channel(target) for _ in range(4)]
    stubs = [rpc.RetimeStub(c) for c in channels]
    good = 0

    async def one(i, all_open, opened):
        nonlocal good
        call = stubs[i % 4].LiveLipBlink(timeout=30)
        frames = []
        try:
            await call.write(setup_message())
            await call.write(pb.LiveLipBlinkRequest(audio=first))
            frames.append((await call.read()).grid_frame)
            opened[0] += 1
            if opened[0] == at_once:
                all_open.set()
            await asyncio.wait_for(all_open.wait(), 20)
            await call.write(pb.LiveLipBlinkRequest(audio=second))
            await call.done_writing()
            for _ in range(want + 1):
                f = await call.read()
                if f is grpc.aio.EOF:
                    break
                frames.append(f.grid_frame)
            if await call.code() == grpc.StatusCode.OK and frames == list(range(want)):
                good += 1
        except (grpc.RpcError, asyncio.TimeoutError, AttributeError):
            call.cancel()

    for group in range(0, count, at_once):
        n = min(at_once, count - group)
        all_open, opened = asyncio.Event(), [0]
        await asyncio.wait_for(asyncio.gather(*(one(group + i, all_open, opened)
                                                for i in range(n))), 60)
    for c in channels:
        await c.close()
    return good


def thousand_streams(server):
    stub = rpc.RetimeStub(grpc.insecure_channel(server.target))
    for _ in range(20):  # warm: gRPC's and koma's threads and pools
        short_stream(stub)
    time.sleep(1.0)
    idle = server.rss()
    rounds = []
    for r in range(2):
        start = time.monotonic()
        good = asyncio.run(many_streams(server.target, 1000, 250, 0.5))
        took = time.monotonic() - start
        server.alive('after 1,000 streams')
        if good != 1000:
            fail('round %d: %d of 1,000 streams ended OK with their 12 frames' % (r + 1, good),
                 server.log)
        time.sleep(1.5)  # --idle_trim_ms (1 s) gives the heap back
        rounds.append((took, server.rss()))
    after1, after2 = rounds[0][1], rounds[1][1]
    print('1,000 streams (250 at once, 0.5 s of audio each) twice in %.1f s and %.1f s: '
          'server RSS idle %.1f MiB, after the first round %.1f, after the second %.1f'
          % (rounds[0][0], rounds[1][0], idle, after1, after2), flush=True)
    # Under the sanitizers (scripts/test-sanitizers.sh sets KOMA_TEST_TIME_SCALE) ASan's
    # quarantine keeps freed memory, so RSS says nothing: LeakSanitizer checks instead when the
    # server exits (Server.stop fails the test on its non-zero exit).
    # What stays: gRPC's threads (more on more cores) and malloc's arenas, +33 MiB on 2 cores.
    if SCALE == 1 and after1 > idle + 80:
        fail('RSS %.1f MiB after 1,000 streams, idle %.1f' % (after1, idle), server.log)
    if SCALE == 1 and after2 > after1 + 8:
        fail('RSS grew from %.1f to %.1f MiB in the second 1,000 streams: a leak'
             % (after1, after2), server.log)
    ok_lines = len(server.lines(r'rpc LiveLipBlink .*frames=12 .*code=OK'))
    if ok_lines != 2000:
        fail('%d log lines of 12-frame OK streams, want 2,000' % ok_lines, server.log)


def main():
    if len(sys.argv) == 3 and sys.argv[1] == '--client':
        client_mode(sys.argv[2])
        return
    binary = sys.argv[1]
    work = tempfile.mkdtemp()
    started = time.monotonic()
    servers = []
    try:
        servers.append(Server(binary, work, 'faults',
                              ['--live_max_streams=1', '--live_max_queued_frames=24',
                               '--live_idle_seconds=20']))
        vanishing_clients(servers[-1])
        non_reader(servers[-1], read_later=True)
        non_reader(servers[-1], read_later=False)
        servers[-1].stop()
        servers.append(Server(binary, work, 'endless', ['--live_max_seconds=2']))
        endless_audio(servers[-1])
        servers[-1].stop()
        servers.append(Server(binary, work, 'scale', []))
        thousand_streams(servers[-1])
        servers[-1].stop()
    finally:
        for s in servers:
            if s.process.poll() is None:
                s.process.kill()
    shutil.rmtree(work, ignore_errors=True)  # kept when a check fails
    print('PASS in %.1f s' % (time.monotonic() - started), flush=True)


if __name__ == '__main__':
    main()
