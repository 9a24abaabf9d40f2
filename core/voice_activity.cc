#include "core/voice_activity.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "core/voice_gate.h"

namespace koma {
namespace {

constexpr double kLn2 = 0.69314718055994530942;
constexpr double kLn10 = 2.30258509299404568402;
constexpr double kSqrtHalf = 0.70710678118654752440;
// At or below this mean square a frame is digital silence (10 log10(1e-15) = -150 dB).
constexpr double kSilenceMeanSquare = 1e-15;
// The speech's loud level for FOLLOW: this percentile of its frames' loudness; the
// recording's range (for the unset stay threshold): the same percentile of all its frames.
constexpr double kLoudPercentile = 90.0;
constexpr double kRangePercentile = 90.0;

// ln(m) for m in [sqrt(1/2), sqrt(2)): 2 atanh(s), s = (m - 1) / (m + 1), |s| <= 0.172, as
// the series 2 (s + s^3/3 + s^5/5 + ...) to s^23 (the next term is below 1e-19 of the sum).
double LogNearOne(double m) {
  const double s = (m - 1.0) / (m + 1.0);
  const double s2 = s * s;
  double sum = 0.0;
  for (int k = 23; k >= 3; k -= 2) sum = (sum + 1.0 / k) * s2;  // Horner, fixed order
  return 2.0 * s * (1.0 + sum);
}

bool IsFinitePositive(double v) { return std::isfinite(v) && v > 0.0; }

}  // namespace

double MeanSquareToDbfs(double mean_square) {
  if (!(mean_square > kSilenceMeanSquare)) return kSilenceDbfs;  // NaN too
  int exponent = 0;
  double m = std::frexp(mean_square, &exponent);  // exact: m in [0.5, 1)
  if (m < kSqrtHalf) {
    m *= 2.0;
    --exponent;
  }
  const double ln = LogNearOne(m) + static_cast<double>(exponent) * kLn2;
  return 10.0 * ln / kLn10;
}

FrameLoudness::FrameLoudness(int sample_rate, double frame_fps)
    : grid_(sample_rate, frame_fps) {}

void FrameLoudness::Add(absl::Span<const float> mono) {
  size_t i = 0;
  while (i < mono.size()) {
    if (samples_ >= next_boundary_) {
      // A new frame starts here (frames of no samples, when a frame is shorter than a
      // sample, stay empty: silence).
      sums_.push_back(0.0);
      counts_.push_back(0);
      next_boundary_ = grid_.FirstSample(static_cast<int64_t>(sums_.size()));
      continue;
    }
    const int64_t take =
        std::min<int64_t>(next_boundary_ - samples_, static_cast<int64_t>(mono.size() - i));
    double sum = 0.0;
    for (int64_t k = 0; k < take; ++k) {
      const double x = mono[i + k];
      sum += x * x;
    }
    sums_.back() += sum;
    counts_.back() += take;
    samples_ += take;
    i += static_cast<size_t>(take);
  }
}

std::vector<double> FrameLoudness::Dbfs(int frames) const {
  std::vector<double> out(static_cast<size_t>(std::max(frames, 0)), kSilenceDbfs);
  const size_t n = std::min(out.size(), sums_.size());
  for (size_t g = 0; g < n; ++g) {
    if (counts_[g] > 0) out[g] = MeanSquareToDbfs(sums_[g] / static_cast<double>(counts_[g]));
  }
  return out;
}

absl::Status ValidateVoiceOptions(const VoiceOptions& o) {
  const auto invalid = [](auto&&... parts) {
    return absl::InvalidArgumentError(absl::StrCat(parts...));
  };
  if (o.noise_floor_dbfs &&
      !(std::isfinite(*o.noise_floor_dbfs) && *o.noise_floor_dbfs <= 0.0)) {
    return invalid("noise_floor_dbfs: ", *o.noise_floor_dbfs, " must be finite and <= 0 dBFS");
  }
  if (!(o.noise_percentile > 0.0 && o.noise_percentile < 100.0)) {
    return invalid("noise_percentile: ", o.noise_percentile, " must be in (0, 100)");
  }
  if (!(IsFinitePositive(o.start_above_floor_db) && o.start_above_floor_db <= 200.0)) {
    return invalid("start_above_floor_db: ", o.start_above_floor_db,
                   " must be in (0, 200] dB");
  }
  if (o.stay_above_floor_db && !(IsFinitePositive(*o.stay_above_floor_db) &&
                                  *o.stay_above_floor_db <= o.start_above_floor_db)) {
    return invalid("stay_above_floor_db: ", *o.stay_above_floor_db,
                   " must be in (0, start_above_floor_db = ", o.start_above_floor_db, "] dB");
  }
  if (!(std::isfinite(o.min_speech_dbfs) && o.min_speech_dbfs <= 0.0 &&
        o.min_speech_dbfs >= kSilenceDbfs)) {
    return invalid("min_speech_dbfs: ", o.min_speech_dbfs, " must be in [", kSilenceDbfs,
                   ", 0] dBFS");
  }
  if (o.bridge_gap_frames < 0) {
    return invalid("bridge_gap_frames: ", o.bridge_gap_frames, " must be >= 0");
  }
  if (o.faint_gap_frames < 0) {
    return invalid("faint_gap_frames: ", o.faint_gap_frames, " must be >= 0");
  }
  if (!(std::isfinite(o.pause_above_floor_db) && o.pause_above_floor_db >= 0.0 &&
        o.pause_above_floor_db <= 200.0)) {
    return invalid("pause_above_floor_db: ", o.pause_above_floor_db, " must be in [0, 200] dB");
  }
  if (o.keep_tail_frames < 0) {
    return invalid("keep_tail_frames: ", o.keep_tail_frames, " must be >= 0");
  }
  if (o.min_speech_frames < 1) {
    return invalid("min_speech_frames: ", o.min_speech_frames, " must be >= 1");
  }
  if (!(IsFinitePositive(o.open_below_peak_db) && o.open_below_peak_db <= 200.0)) {
    return invalid("open_below_peak_db: ", o.open_below_peak_db, " must be in (0, 200] dB");
  }
  if (!(std::isfinite(o.closed_below_peak_db) &&
        o.closed_below_peak_db > o.open_below_peak_db && o.closed_below_peak_db <= 200.0)) {
    return invalid("closed_below_peak_db: ", o.closed_below_peak_db,
                   " must be in (open_below_peak_db = ", o.open_below_peak_db, ", 200] dB");
  }
  if (!(std::isfinite(o.hysteresis_db) && o.hysteresis_db >= 0.0 && o.hysteresis_db <= 200.0)) {
    return invalid("hysteresis_db: ", o.hysteresis_db, " must be in [0, 200] dB");
  }
  return ValidateVoiceGateOptions(o.gate);
}

double Percentile(std::vector<double> values, double p) {
  if (values.empty()) return kSilenceDbfs;
  const auto rank = static_cast<size_t>(p / 100.0 * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), values.begin() + rank, values.end());
  return values[rank];
}

namespace {

// Maximal runs of frames >= stay that hold a frame >= start.
std::vector<FrameInterval> Runs(absl::Span<const double> dbfs, double start, double stay) {
  std::vector<FrameInterval> runs;
  const int n = static_cast<int>(dbfs.size());
  for (int f = 0; f < n;) {
    if (!(dbfs[f] >= stay)) {
      ++f;
      continue;
    }
    const int begin = f;
    bool started = false;
    for (; f < n && dbfs[f] >= stay; ++f) started |= dbfs[f] >= start;
    if (started) runs.push_back({begin, f});
  }
  return runs;
}

// Whether the gap [begin, end) between two runs is bridged: a short one always, a longer one
// up to `faint_gap_frames` when all its frames stay above `pause_dbfs` (no pause in it).
bool Bridged(absl::Span<const double> dbfs, int begin, int end, const VoiceOptions& o,
             double pause_dbfs) {
  const int gap = end - begin;
  if (gap <= o.bridge_gap_frames) return true;
  if (gap > o.faint_gap_frames) return false;
  for (int f = begin; f < end; ++f) {
    if (!(dbfs[f] > pause_dbfs)) return false;
  }
  return true;
}

// Bridged gaps closed, then runs shorter than `min_speech_frames` dropped.
std::vector<FrameInterval> BridgeAndDrop(absl::Span<const double> dbfs,
                                         const std::vector<FrameInterval>& runs,
                                         const VoiceOptions& o, double pause_dbfs) {
  const int min_length = o.min_speech_frames;
  std::vector<FrameInterval> merged;
  for (const FrameInterval& r : runs) {
    if (!merged.empty() && Bridged(dbfs, merged.back().end, r.begin, o, pause_dbfs)) {
      merged.back().end = r.end;
    } else {
      merged.push_back(r);
    }
  }
  std::vector<FrameInterval> out;
  for (const FrameInterval& r : merged) {
    if (r.end - r.begin >= min_length) out.push_back(r);
  }
  return out;
}

// The drawing frame by frame, a Schmitt trigger on the two boundaries (open at loud - open_db,
// closed below loud - closed_db): a class is left only past its boundary by half the
// hysteresis. Each interval starts from closed, as the mouth does.
void Follow(absl::Span<const double> dbfs, const VoiceOptions& o, VoiceActivity& v) {
  const double open_at = v.loud_dbfs - o.open_below_peak_db;
  const double mid_at = v.loud_dbfs - o.closed_below_peak_db;
  const double h = o.hysteresis_db / 2.0;
  for (const FrameInterval& interval : v.speech) {
    MouthShape shape = MouthShape::kClosed;
    for (int f = interval.begin; f < interval.end; ++f) {
      const double l = dbfs[f];
      switch (shape) {
        case MouthShape::kClosed:
          if (l > open_at + h) {
            shape = MouthShape::kOpen;
          } else if (l > mid_at + h) {
            shape = MouthShape::kMid;
          }
          break;
        case MouthShape::kMid:
          if (l > open_at + h) {
            shape = MouthShape::kOpen;
          } else if (l < mid_at - h) {
            shape = MouthShape::kClosed;
          }
          break;
        case MouthShape::kOpen:
          if (l < mid_at - h) {
            shape = MouthShape::kClosed;
          } else if (l < open_at - h) {
            shape = MouthShape::kMid;
          }
          break;
      }
      v.follow[f] = shape;
    }
  }
}

// The speech intervals the voice-like stretches allow: an interval with no stretch in it is
// dropped (music, noise); one cut to its stretches, except that its parts outside them of at
// most `keep_tail` frames at either end or between two stretches are kept: loudness places a
// word's soft end better than the gate, so a clean or noisy take keeps the loudness's
// boundaries, while speech over music, whose loud interval runs on through the music, ends
// where the voice does. Then pieces shorter than `min_speech_frames` are dropped.
std::vector<FrameInterval> GateIntervals(const std::vector<FrameInterval>& speech,
                                         const std::vector<FrameInterval>& voice_like,
                                         const VoiceOptions& o) {
  const int keep_tail = o.keep_tail_frames;
  std::vector<FrameInterval> out;
  for (const FrameInterval& interval : speech) {
    std::vector<FrameInterval> pieces =
        Intersect(absl::MakeConstSpan(&interval, 1), voice_like);
    if (pieces.empty()) continue;
    if (pieces.front().begin - interval.begin <= keep_tail) pieces.front().begin = interval.begin;
    if (interval.end - pieces.back().end <= keep_tail) pieces.back().end = interval.end;
    std::vector<FrameInterval> joined;
    for (const FrameInterval& p : pieces) {
      if (!joined.empty() && p.begin - joined.back().end <= keep_tail) {
        joined.back().end = p.end;
      } else {
        joined.push_back(p);
      }
    }
    for (const FrameInterval& p : joined) {
      if (p.end - p.begin >= o.min_speech_frames) out.push_back(p);
    }
  }
  return out;
}

}  // namespace

VoiceActivity DetectVoice(absl::Span<const double> dbfs, const VoiceOptions& options,
                          const std::vector<FrameInterval>* voice_like) {
  VoiceActivity v;
  v.noise_floor_dbfs =
      options.noise_floor_dbfs.value_or(Percentile({dbfs.begin(), dbfs.end()},
                                                   options.noise_percentile));
  const double start_db = options.start_above_floor_db;
  const double range = Percentile({dbfs.begin(), dbfs.end()}, kRangePercentile) - v.noise_floor_dbfs;
  const double stay_db = options.stay_above_floor_db.value_or(
      std::min(start_db, std::max(kMinStayAboveFloorDb, kStayFractionOfRange * range)));
  v.start_dbfs = std::max(v.noise_floor_dbfs + start_db, options.min_speech_dbfs);
  v.stay_dbfs =
      std::max(v.noise_floor_dbfs + stay_db, options.min_speech_dbfs - (start_db - stay_db));
  v.speech = BridgeAndDrop(dbfs, Runs(dbfs, v.start_dbfs, v.stay_dbfs), options,
                           v.noise_floor_dbfs + options.pause_above_floor_db);
  if (voice_like != nullptr) {
    // After the bridging, so a pause the gate finds in music (which never falls to the room
    // noise) stays a pause.
    v.speech = GateIntervals(v.speech, *voice_like, options);
  }
  std::vector<double> speaking;
  for (const FrameInterval& i : v.speech) {
    speaking.insert(speaking.end(), dbfs.begin() + i.begin, dbfs.begin() + i.end);
  }
  v.loud_dbfs = Percentile(std::move(speaking), kLoudPercentile);
  v.follow.assign(dbfs.size(), MouthShape::kClosed);
  Follow(dbfs, options, v);
  return v;
}

}  // namespace koma
