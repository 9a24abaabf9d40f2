#include "client/live_record.h"

#include <optional>
#include <utility>

#include "absl/strings/str_cat.h"
#include "client/files.h"
#include "core/curves.h"
#include "formats/motion3.h"
#include "formats/number_format.h"

namespace koma::client {
namespace {

// Stepped keys of per-frame `levels`: frame 0, every frame whose level differs from the one
// before, and the end (frame N, the last level held to it).
std::vector<CurvePoint> SteppedKeys(const std::vector<double>& levels) {
  std::vector<CurvePoint> keys;
  for (size_t g = 0; g < levels.size(); ++g) {
    if (g == 0 || levels[g] != levels[g - 1]) {
      keys.push_back({static_cast<double>(g), levels[g]});
    }
  }
  keys.push_back({static_cast<double>(levels.size()), levels.back()});
  return keys;
}

class RecordSink : public LiveSink {
 public:
  explicit RecordSink(std::string path) : path_(std::move(path)) {}

  absl::Status Start(const v1::LiveLipBlinkSetup& setup) override {
    fps_ = setup.has_timing_fps() ? setup.timing_fps() : 24.0;
    return absl::OkStatus();
  }

  absl::Status Frame(const v1::LiveLipBlinkFrame& frame, const LiveFrameTiming&) override {
    mouth_.push_back(frame.mouth_level());
    eyes_.push_back(frame.eye_level());
    return absl::OkStatus();
  }

  absl::Status Close() override {
    absl::StatusOr<std::string> text = LiveMotion3(fps_, mouth_, eyes_);
    if (!text.ok()) {
      return absl::Status(text.status().code(),
                          absl::StrCat("--record ", path_, ": ", text.status().message()));
    }
    return WriteFile(path_, *text);
  }

 private:
  std::string path_;
  double fps_ = 24.0;
  std::vector<double> mouth_;
  std::vector<double> eyes_;
};

}  // namespace

absl::StatusOr<std::string> LiveMotion3(double fps, const std::vector<double>& mouth,
                                        const std::vector<double>& eyes) {
  if (mouth.empty()) return absl::InvalidArgumentError("no frame was streamed: nothing to write");
  if (mouth.size() != eyes.size()) {
    return absl::InvalidArgumentError(
        absl::StrCat(mouth.size(), " mouth levels but ", eyes.size(), " eye levels"));
  }
  // A blank motion with the three curves, then their segments as stepped keys.
  const std::string end_s = formats::FormatDouble(static_cast<double>(mouth.size()) / fps);
  std::string curves;
  for (const char* id : {"ParamMouthOpenY", "ParamEyeLOpen", "ParamEyeROpen"}) {
    absl::StrAppend(&curves, curves.empty() ? "" : ", ", "{\"Target\": \"Parameter\", \"Id\": \"",
                    id, "\", \"Segments\": [0, 0, 0, ", end_s, ", 0]}");
  }
  const std::string blank = absl::StrCat(
      "{\"Version\": 3, \"Meta\": {\"Duration\": ", end_s, ", \"Fps\": ", formats::FormatDouble(fps),
      ", \"Loop\": false, \"AreBeziersRestricted\": true, \"CurveCount\": 3, "
      "\"TotalSegmentCount\": 3, \"TotalPointCount\": 6, \"UserDataCount\": 0, "
      "\"TotalUserDataSize\": 0}, \"Curves\": [",
      curves, "]}");
  absl::StatusOr<formats::Motion3File> file = formats::ParseMotion3(blank);
  if (!file.ok()) return absl::InternalError(file.status().message());
  const std::vector<CurvePoint> eye_keys = SteppedKeys(eyes);
  return formats::WriteMotion3(*file, {SteppedKeys(mouth), eye_keys, eye_keys});
}

std::unique_ptr<LiveSink> NewLiveRecordSink(const std::string& path) {
  return std::make_unique<RecordSink>(path);
}

}  // namespace koma::client
