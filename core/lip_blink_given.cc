// Validation of given holds and blinks, and the given mouth's paint (the eyes' is in
// lip_blink_eyes.cc, beside the paint it shares with ConvertEyes).
#include "core/lip_blink_given.h"

#include "absl/strings/str_cat.h"
#include "core/lip_blink_internal.h"

namespace koma {

absl::Status ValidateGivenHolds(const std::vector<MouthHold>& holds, int frame_count,
                                absl::string_view path) {
  for (size_t i = 0; i < holds.size(); ++i) {
    const MouthHold& h = holds[i];
    const std::string at = absl::StrCat(path, "[", i, "]");
    if (h.length < 1) {
      return absl::InvalidArgumentError(absl::StrCat(at, ".length: ", h.length, " must be >= 1"));
    }
    if (h.begin < 0 || h.begin > frame_count - h.length) {
      return absl::InvalidArgumentError(
          absl::StrCat(at, ": frames [", h.begin, ", ", int64_t{h.begin} + h.length,
                       ") are not within the clip's ", frame_count, " frames"));
    }
    if (i > 0 && h.begin < holds[i - 1].begin + holds[i - 1].length) {
      return absl::InvalidArgumentError(absl::StrCat(
          at, ": begins at ", h.begin, ", before ", path, "[", i - 1, "] ends (",
          holds[i - 1].begin, " + ", holds[i - 1].length, " frames); holds go in time order"));
    }
  }
  return absl::OkStatus();
}

absl::Status ValidateGivenBlinks(const std::vector<Blink>& blinks, int frame_count,
                                 absl::string_view path) {
  for (size_t i = 0; i < blinks.size(); ++i) {
    const Blink& b = blinks[i];
    const std::string at = absl::StrCat(path, "[", i, "]");
    if (b.hold < 1 || b.hold > 3) {
      return absl::InvalidArgumentError(absl::StrCat(at, ".hold: ", b.hold, " must be 1, 2 or 3"));
    }
    if (b.open_span < 0 || b.open_span > frame_count) {  // bounded: the paint adds it to frames
      return absl::InvalidArgumentError(absl::StrCat(
          at, ".open_span: ", b.open_span, " must be within 0 .. the clip's ", frame_count,
          " frames"));
    }
    if (!(0 <= b.closing_begin && b.closing_begin <= b.closed_begin &&
          b.closed_begin <= b.closed_end && b.closed_end < frame_count)) {
      return absl::InvalidArgumentError(absl::StrCat(
          at, ": closing_begin ", b.closing_begin, ", closed_begin ", b.closed_begin,
          ", closed_end ", b.closed_end, " must be in order within the clip's ", frame_count,
          " frames"));
    }
    if (i > 0 && b.closing_begin <= blinks[i - 1].closed_end) {
      return absl::InvalidArgumentError(
          absl::StrCat(at, ".closing_begin: ", b.closing_begin, " is not after ", path, "[", i - 1,
                       "].closed_end ", blinks[i - 1].closed_end, "; blinks go in time order"));
    }
  }
  return absl::OkStatus();
}

MouthResult PaintGivenMouth(absl::Span<const double> input, const MouthOptions& options,
                            const std::vector<MouthHold>& holds) {
  MouthResult result;
  lip_blink_internal::BeginMouthResult(input, options, &result);
  result.holds = holds;
  for (const MouthHold& h : holds) {
    const double level = h.shape == MouthShape::kClosed
                             ? result.closed
                             : (h.shape == MouthShape::kMid ? result.mid : result.open);
    for (int f = h.begin; f < h.begin + h.length; ++f) result.values[static_cast<size_t>(f)] = level;
    if (!result.speech.empty() && result.speech.back().end == h.begin) {
      result.speech.back().end = h.begin + h.length;
    } else {
      result.speech.push_back({h.begin, h.begin + h.length});
    }
  }
  return result;
}

}  // namespace koma
