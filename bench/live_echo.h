// LiveLipBlink without the analysis, for koma_echo_server (the transport-only baseline of
// bench/live_scale.sh, docs/benchmarks.md "LiveLipBlink: latency and streams"): a stream reads
// the setup and the audio as koma_server's does (server/live_stream.cc: one read and one write
// in flight, decided frames queued under a lock, gRPC's operations started outside it) and
// answers one LiveLipBlinkFrame per 24 fps grid frame, as soon as the audio that would decide it
// (the frame plus its lookahead) is in, at koma's message size. It decodes nothing: the
// samples are counted from the bytes. So koma's streams per core over the echo's is what the
// decoding and the voice analysis cost beyond gRPC and the kernel's TCP.
#ifndef KOMA_BENCH_LIVE_ECHO_H_
#define KOMA_BENCH_LIVE_ECHO_H_

#include <grpcpp/grpcpp.h>

#include "koma/v1/retime.pb.h"

namespace koma::echo {

// A new stream's reactor; it deletes itself when done.
grpc::ServerBidiReactor<v1::LiveLipBlinkRequest, v1::LiveLipBlinkFrame>* OpenLiveEchoStream();

}  // namespace koma::echo

#endif  // KOMA_BENCH_LIVE_ECHO_H_
