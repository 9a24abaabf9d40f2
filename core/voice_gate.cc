#include "core/voice_gate.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"

namespace koma {
namespace {

// Seconds -> frames on a grid of `fps`: rounded, at least `at_least` (floor of x + 0.5 is
// exact arithmetic: the same everywhere).
int Frames(double seconds, double fps, int at_least) {
  return std::max(at_least, static_cast<int>(std::floor(seconds * fps + 0.5)));
}

bool InUnit(double v) { return std::isfinite(v) && v >= 0.0 && v <= 1.0; }

}  // namespace

absl::Status ValidateVoiceGateOptions(const VoiceGateOptions& o) {
  const auto invalid = [](auto&&... parts) {
    return absl::InvalidArgumentError(absl::StrCat(parts...));
  };
  if (!InUnit(o.min_voicing)) return invalid("min_voicing: ", o.min_voicing, " must be in [0, 1]");
  if (!InUnit(o.min_change)) return invalid("min_change: ", o.min_change, " must be in [0, 1]");
  if (!InUnit(o.min_density)) {
    return invalid("min_density: ", o.min_density, " must be in [0, 1]");
  }
  for (const auto& [name, v] : {std::pair<const char*, double>{"max_gap_s", o.max_gap_s},
                                {"min_frames_s", o.min_frames_s}, {"reach_s", o.reach_s}}) {
    if (!(std::isfinite(v) && v >= 0.0 && v <= 10.0)) {
      return invalid(name, ": ", v, " must be in [0, 10] s");
    }
  }
  return absl::OkStatus();
}

std::vector<FrameInterval> VoiceLikeStretches(absl::Span<const VoiceFrame> frames, int step,
                                              double fps, const VoiceGateOptions& o) {
  const int n = static_cast<int>(frames.size());
  if (!o.enabled) return n > 0 ? std::vector<FrameInterval>{{0, n}} : std::vector<FrameInterval>{};
  const int max_gap = Frames(o.max_gap_s, fps, 1);
  const int min_frames = Frames(o.min_frames_s, fps, 1);
  const int reach = Frames(o.reach_s, fps, 0);
  const auto changing = [&](int g) { return g >= 0 && frames[g].change >= o.min_change; };
  // Voiced and steady; the frames past either end count as held (they hold nothing to reach).
  const auto held = [&](int g) {
    return g < 0 || g >= n ||
           (frames[g].voicing >= o.min_voicing && !(frames[g].change >= o.min_change));
  };
  std::vector<FrameInterval> out;
  int first = -1, last = -1, count = 0;
  const auto close = [&] {
    if (count >= min_frames && count >= o.min_density * (last + 1 - first)) {
      // Widened up to `reach` frames, but never into a held sound (two voiced frames in a row
      // whose spectrum stays put): a word's /s/ or /k/ is not periodic and a voice's steady
      // frame comes alone, while the music under a voice holds its notes, and the mouth must
      // close where the voice stops.
      FrameInterval s{first, last + 1};
      while (s.begin > 0 && first - s.begin < reach && !(held(s.begin - 1) && held(s.begin - 2))) {
        --s.begin;
      }
      while (s.end < n && s.end - (last + 1) < reach && !(held(s.end) && held(s.end + 1))) {
        ++s.end;
      }
      if (!out.empty() && s.begin <= out.back().end) {
        out.back().end = std::max(out.back().end, s.end);
      } else {
        out.push_back(s);
      }
    }
  };
  for (int g = 0; g < n; ++g) {
    if (!(frames[g].voicing >= o.min_voicing && changing(g) && changing(g - step))) continue;
    if (count > 0 && g - last > max_gap) {
      close();
      count = 0;
    }
    if (count == 0) first = g;
    last = g;
    ++count;
  }
  if (count > 0) close();
  return out;
}

std::vector<FrameInterval> VoiceLikeStretches(const VoiceFeatures& features, double fps,
                                              const VoiceGateOptions& options) {
  VoiceGateOptions o = options;
  if (!features.usable()) o.enabled = false;
  return VoiceLikeStretches(features.frames(), features.step(), fps, o);
}

std::vector<FrameInterval> Intersect(absl::Span<const FrameInterval> a,
                                     absl::Span<const FrameInterval> b) {
  std::vector<FrameInterval> out;
  size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    const int begin = std::max(a[i].begin, b[j].begin);
    const int end = std::min(a[i].end, b[j].end);
    if (begin < end) out.push_back({begin, end});
    if (a[i].end < b[j].end) {
      ++i;
    } else {
      ++j;
    }
  }
  return out;
}

}  // namespace koma
