// The sinks `koma live` writes text with (client/live_sink.h): --json's one object per frame
// and line, and the human lines (one per second of audio, a summary at the end).
#ifndef KOMA_CLIENT_LIVE_OUTPUT_H_
#define KOMA_CLIENT_LIVE_OUTPUT_H_

#include <cstdio>
#include <memory>
#include <string>

#include "client/live_sink.h"
#include "koma/v1/retime.pb.h"

namespace koma::client {

// "closed", "half", "open" (MOUTH_CLOSED, MOUTH_MID, MOUTH_OPEN; the eyes' drawings too).
const char* LiveShapeName(v1::MouthShape shape);

// One frame as its --json line (no newline): grid_frame, time_s, speech, mouth, mouth_level,
// new_drawing, hold_start, eyes, blink (the eyes not open), blink_start, eye_level,
// loudness_dbfs, noise_floor_dbfs, late_ms (the server's), wall_late_ms, wall_s
// (LiveFrameTiming). docs/live.md describes them.
std::string LiveFrameJson(const v1::LiveLipBlinkFrame& frame, const LiveFrameTiming& timing);

// Writes LiveFrameJson lines to `out`, flushed after each. An error when a write fails.
std::unique_ptr<LiveSink> NewLiveJsonSink(std::FILE* out);

// Writes a line per second of audio and a summary at Close to `out`.
std::unique_ptr<LiveSink> NewLiveTextSink(std::FILE* out);

}  // namespace koma::client

#endif  // KOMA_CLIENT_LIVE_OUTPUT_H_
