// LiveLipBlink's streams on gRPC's callback API (docs/api.md, "LiveLipBlink"): each stream a
// reactor that reads the setup and the audio, runs the live voice analysis (core/live_voice.h)
// as messages arrive, and writes every decided frame, one write in flight at a time. Every
// buffer is bounded: the decided frames waiting for the client (--live_max_queued_frames), a
// message's bytes (--live_max_message_bytes), the audio's length (--live_max_seconds), the
// time without a message (--live_idle_seconds), and the streams at once (--live_max_streams).
#ifndef KOMA_SERVER_LIVE_STREAM_H_
#define KOMA_SERVER_LIVE_STREAM_H_

#include <grpcpp/grpcpp.h>

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <set>
#include <thread>

#include "koma/v1/retime.pb.h"
#include "server/request_limits.h"

namespace koma::server {

class LiveStream;

// The streams in flight: counted against --live_max_streams, and looked at every
// kLiveTickSeconds by one thread for idle streams and finished streams whose client reads
// nothing (their gRPC call is then cancelled, so its memory goes).
class LiveStreams {
 public:
  explicit LiveStreams(const RequestLimits& limits) : limits_(limits) {}
  ~LiveStreams();  // after every stream is done (the server waits for its calls)

  // A new stream's reactor: it reads and answers, or answers RESOURCE_EXHAUSTED at once when
  // --live_max_streams are in flight.
  grpc::ServerBidiReactor<v1::LiveLipBlinkRequest, v1::LiveLipBlinkFrame>* Open(
      grpc::CallbackServerContext* context);
  // Ends every stream with UNAVAILABLE (the server is shutting down), after the frames decided
  // so far; new streams are refused the same way.
  void EndAll();
  int in_flight() const;

 private:
  friend class LiveStream;
  // The stream has its Finish: its --live_max_streams slot is free (once; Remove too).
  void Release(LiveStream* stream);
  // OnDone: whether the stream may be deleted now (else the ticker deletes it when done).
  bool Remove(LiveStream* stream);
  // `f(stream)` on every stream, without the lock, each pinned so it outlives the call.
  template <typename F>
  void ForEach(F f);
  void Tick();

  const RequestLimits limits_;
  mutable std::mutex mu_;
  std::condition_variable wake_;
  std::set<LiveStream*> streams_;  // until OnDone (the ticker may still cancel a finished one)
  int open_ = 0;                   // streams not yet finished: what --live_max_streams bounds
  bool ending_ = false, stopping_ = false;
  std::thread ticker_;  // started with the first stream
};

}  // namespace koma::server

#endif  // KOMA_SERVER_LIVE_STREAM_H_
