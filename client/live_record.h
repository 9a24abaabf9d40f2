// `koma live --record OUT.motion3.json`: what was streamed, as a Live2D motion3.json written
// when the stream ends (client/live_sink.h). Curves ParamMouthOpenY (each frame's
// mouth_level), ParamEyeLOpen and ParamEyeROpen (eye_level), on stepped keys at the film grid
// (a key where the level changes, frame 0 always, and one at the end), so the drawings hold;
// Meta.Fps the grid's rate, Meta.Duration the frames streamed / fps. Written through
// formats/motion3.h, so `koma lipblink` and `koma curves` read it.
#ifndef KOMA_CLIENT_LIVE_RECORD_H_
#define KOMA_CLIENT_LIVE_RECORD_H_

#include <memory>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "client/live_sink.h"

namespace koma::client {

// The motion3.json text of `mouth` and `eyes` levels, one per grid frame from 0, at `fps`.
// INVALID_ARGUMENT when no frame was streamed, or the sizes differ.
absl::StatusOr<std::string> LiveMotion3(double fps, const std::vector<double>& mouth,
                                        const std::vector<double>& eyes);

// The sink: collects the levels, writes `path` (client/files.h's WriteFile) at Close.
std::unique_ptr<LiveSink> NewLiveRecordSink(const std::string& path);

}  // namespace koma::client

#endif  // KOMA_CLIENT_LIVE_RECORD_H_
