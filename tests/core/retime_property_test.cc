// RetimeNaive (the literal reference) and RetimeFast must agree field by field on thousands
// of random clips, including exact ties and static stretches; the fast result must also
// satisfy the invariants of docs/semantics.md, "RetimeSkeletal".
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "core/distance.h"
#include "core/retime.h"
#include "core/retime_internal.h"
#include "core/split_mix64.h"
#include "tests/testing/status_matchers.h"

namespace koma {
namespace {

constexpr int kClipCount = 3000;

enum class ClipStyle { kContinuous, kTinyIntegers, kStaticStretches, kIntegerWalk, kStill };

// frame_count x joint_count x 3 positions in one of the styles above.
std::vector<double> RandomPositions(SplitMix64& rng, int frames, int joints, ClipStyle style) {
  std::vector<double> p(static_cast<size_t>(frames) * joints * 3, 0.0);
  const size_t stride = static_cast<size_t>(joints) * 3;
  for (int f = 0; f < frames; ++f) {
    double* frame = p.data() + f * stride;
    const double* prev = f > 0 ? frame - stride : nullptr;
    const bool repeat = prev != nullptr && (style == ClipStyle::kStill ||
                                            (style == ClipStyle::kStaticStretches && rng.OneIn(2)));
    for (size_t c = 0; c < stride; ++c) {
      if (repeat) {
        frame[c] = prev[c];
      } else if (style == ClipStyle::kContinuous || style == ClipStyle::kStaticStretches) {
        frame[c] = rng.Unit() * 2.0 - 1.0;
      } else if (style == ClipStyle::kTinyIntegers) {
        frame[c] = rng.Int(0, 2);  // many exact ties, many zero SSDs
      } else {                     // integer walk; kStill's first frame too
        frame[c] = (prev != nullptr ? prev[c] : 0.0) + rng.Int(-1, 1);
      }
    }
  }
  return p;
}

DistanceOptions RandomDistanceOptions(SplitMix64& rng, int joints) {
  DistanceOptions options;
  if (rng.OneIn(3)) {
    for (int j = 0; j < joints; ++j) options.weights.push_back(rng.Int(0, 2));  // 0 allowed
  }
  options.root_relative = rng.OneIn(4);
  return options;
}

RetimeOptions RandomRetimeOptions(SplitMix64& rng, int frames) {
  RetimeOptions options;
  options.omissions = frames >= 3 ? rng.Int(0, frames - 3) : 0;
  options.holds = rng.Int(0, frames);
  options.max_hold = rng.Int(1, 5);
  options.keep_length = !rng.OneIn(3);
  options.order = rng.OneIn(3) ? StepOrder::kHoldThenOmit : StepOrder::kOmitThenHold;
  return options;
}

char KindLetter(FrameKind kind) {
  switch (kind) {
    case FrameKind::kOriginal:
      return 'o';
    case FrameKind::kDuplicate:
      return 'd';
    case FrameKind::kHeld:
      return 'h';
  }
  return '?';
}

// "0o 1o 1d 3o ..." plus the gone frames and counts.
std::string Describe(const TimingMap& map) {
  std::ostringstream out;
  out << "source_frames:";
  for (size_t t = 0; t < map.source_frames.size(); ++t) {
    out << " " << map.source_frames[t] << KindLetter(map.kinds[t]);
  }
  out << "\n  deleted:";
  for (int32_t f : map.deleted) out << " " << f;
  out << "\n  hidden:";
  for (int32_t f : map.hidden) out << " " << f;
  out << "\n  omissions " << map.omissions_applied << ", duplicates " << map.duplicates_applied
      << " (skipped " << map.duplicates_skipped << ", later omitted " << map.duplicates_omitted
      << ", later held " << map.duplicates_held << "), holds " << map.holds_applied;
  return out.str();
}

std::string Describe(const RetimeOptions& o) {
  std::ostringstream out;
  out << "omissions=" << o.omissions << " holds=" << o.holds << " max_hold=" << o.max_hold
      << " keep_length=" << o.keep_length
      << " order=" << (o.order == StepOrder::kOmitThenHold ? "omit,hold" : "hold,omit");
  return out.str();
}

// Invariants any correct result has; returns "" or the first violation.
std::string CheckInvariants(const TimingMap& map, const FrameDistance& distance,
                            const RetimeOptions& options) {
  const int n = distance.frame_count();
  const int len = static_cast<int>(map.source_frames.size());
  const int expected_len =
      options.keep_length ? n - map.duplicates_skipped : n - map.omissions_applied;
  if (len != expected_len || map.kinds.size() != map.source_frames.size()) {
    return "length " + std::to_string(len) + ", expected " + std::to_string(expected_len);
  }
  if (map.source_frames.front() != 0 || map.source_frames.back() != n - 1) {
    return "first or last pose lost";
  }
  if (map.omissions_applied > options.omissions || map.holds_applied > options.holds) {
    return "more steps applied than asked";
  }
  const int dup_total = map.duplicates_applied + map.duplicates_skipped;
  if (dup_total != (options.keep_length ? map.omissions_applied : 0)) {
    return "duplicates applied + skipped != deletes";
  }
  // Every duplicate is still a kDuplicate frame, or a later step omitted or held it.
  const int still_duplicates = static_cast<int>(
      std::count(map.kinds.begin(), map.kinds.end(), FrameKind::kDuplicate));
  if (still_duplicates + map.duplicates_omitted + map.duplicates_held != map.duplicates_applied) {
    return "kDuplicate frames + duplicates omitted + held != duplicates applied";
  }
  if (options.order == StepOrder::kHoldThenOmit && map.duplicates_held != 0) {
    return "a duplicate held before any was made";
  }
  std::vector<int> shown(n, 0);  // output frames per source frame
  std::vector<int> gone(n, 0);   // entries in deleted + hidden
  int run = 0;
  for (int t = 0; t < len; ++t) {
    const bool continues = t > 0 && map.source_frames[t] == map.source_frames[t - 1];
    if (t > 0 && map.source_frames[t] < map.source_frames[t - 1]) return "order broken";
    run = continues ? run + 1 : 1;
    if (run > options.max_hold) return "run longer than max_hold at t=" + std::to_string(t);
    if (continues && map.kinds[t] == FrameKind::kOriginal) return "kOriginal inside a run";
    ++shown[map.source_frames[t]];
  }
  for (int32_t f : map.deleted) ++gone[f];
  for (int32_t f : map.hidden) ++gone[f];
  for (int f = 0; f < n; ++f) {
    if ((shown[f] > 0) == (gone[f] > 0) || gone[f] > 1) {
      return "frame " + std::to_string(f) + " must be either shown or gone once";
    }
  }
  if (!std::is_sorted(map.deleted.begin(), map.deleted.end()) ||
      !std::is_sorted(map.hidden.begin(), map.hidden.end())) {
    return "deleted/hidden not ascending";
  }
  // When the last step stopped early, its stop condition must hold on the final sequence.
  const bool holds_last = options.order == StepOrder::kOmitThenHold;
  if (holds_last && map.holds_applied < options.holds) {
    for (int t = 1; t + 1 < len; ++t) {
      if (map.source_frames[t] == map.source_frames[t - 1]) continue;
      int prev_run = 1;
      while (t - prev_run - 1 >= 0 &&
             map.source_frames[t - prev_run - 1] == map.source_frames[t - 1]) {
        ++prev_run;
      }
      if (prev_run + 1 <= options.max_hold) return "holds stopped with a candidate left";
    }
  }
  if (!holds_last && map.omissions_applied < options.omissions) {
    for (int t = 1; t + 1 < len; ++t) {
      if (distance(map.source_frames[t - 1], map.source_frames[t]) != 0.0) {
        return "omissions stopped while something moves";
      }
    }
  }
  return "";
}

TEST(RetimePropertyTest, NaiveAndFastAgreeOnRandomClips) {
  int failures = 0;
  int with_held_duplicates = 0;     // clips where a later step changed a duplicate:
  int with_omitted_duplicates = 0;  // the invariant above must not hold vacuously
  for (uint64_t seed = 1; seed <= kClipCount && failures < 5; ++seed) {
    SplitMix64 rng(seed);
    const int frames = rng.Int(2, 60);
    const int joints = rng.Int(1, 4);
    const auto style = static_cast<ClipStyle>(rng.Int(0, 4));
    const std::vector<double> positions = RandomPositions(rng, frames, joints, style);
    const DistanceOptions distance_options = RandomDistanceOptions(rng, joints);
    const RetimeOptions options = RandomRetimeOptions(rng, frames);
    ASSERT_OK_AND_ASSIGN(const FrameDistance distance,
                         FrameDistance::Create(positions, frames, joints, distance_options));
    ASSERT_THAT(ValidateRetimeOptions(options, frames), testing::IsOk());
    const TimingMap naive = RetimeNaive(distance, options);
    std::vector<double> input_ssd;
    // Every other clip reads step B's unlink distances from the tables, as clips of
    // kTableMinFrames and more do (when holds >= N / 4); every third of the others is given
    // its input SSD, as the server's cut search hands it over.
    const TimingMap fast =
        seed % 2 == 1 ? retime_internal::RetimeFastWithTablesFrom(distance, options, &input_ssd, 0)
        : seed % 3 == 0
            ? RetimeFastWithInputSsd(distance, options, RetimeInputSsd(distance), &input_ssd)
            : RetimeFast(distance, options, &input_ssd);
    const std::vector<double> want_ssd = distance.InputSsd();
    ASSERT_EQ(input_ssd.size(), want_ssd.size());
    ASSERT_EQ(std::memcmp(input_ssd.data(), want_ssd.data(), sizeof(double) * want_ssd.size()), 0)
        << "RetimeFast's input_ssd differs from InputSsd()";
    const std::string context = "seed " + std::to_string(seed) + ": " + std::to_string(frames) +
                                " frames, " + std::to_string(joints) + " joints, style " +
                                std::to_string(static_cast<int>(style)) + ", " + Describe(options);
    if (!(naive == fast)) {
      ++failures;
      ADD_FAILURE() << context << "\nnaive " << Describe(naive) << "\nfast  " << Describe(fast);
      continue;
    }
    with_held_duplicates += fast.duplicates_held > 0;
    with_omitted_duplicates += fast.duplicates_omitted > 0;
    const std::string violation = CheckInvariants(fast, distance, options);
    if (!violation.empty()) {
      ++failures;
      ADD_FAILURE() << context << ": " << violation << "\n" << Describe(fast);
    }
  }
  EXPECT_GT(with_held_duplicates, 10);
  EXPECT_GT(with_omitted_duplicates, 10);
}

}  // namespace
}  // namespace koma
