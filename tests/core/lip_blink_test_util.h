// Helpers for the ConvertEyes tests: eye curves written as letters, random eyes with known
// closed runs, and the anime-blink invariants (docs/semantics.md, "LipBlink") checked frame by
// frame.
#ifndef KOMA_TESTS_CORE_LIP_BLINK_TEST_UTIL_H_
#define KOMA_TESTS_CORE_LIP_BLINK_TEST_UTIL_H_

#include <gtest/gtest.h>

#include <algorithm>
#include <ostream>
#include <string>
#include <vector>

#include "core/lip_blink.h"
#include "core/split_mix64.h"

namespace koma {

inline bool operator==(const Blink& a, const Blink& b) {
  return a.closing_begin == b.closing_begin && a.closed_begin == b.closed_begin &&
         a.closed_end == b.closed_end && a.open_span == b.open_span && a.hold == b.hold &&
         a.automatic == b.automatic;
}

inline void PrintTo(const Blink& b, std::ostream* os) {
  *os << "{closing " << b.closing_begin << ", closed " << b.closed_begin << ".." << b.closed_end
      << ", open_span " << b.open_span << ", k " << b.hold << (b.automatic ? ", auto}" : "}");
}

// Letters <-> values with levels 0 (closed) and 1 (open), delta 0.1: O 1 and o 0.95 are open,
// C 0 and c 0.05 closed, h 0.7, m 0.5 (E_mid) and q 0.3 half-shut.
inline double EyeValue(char letter) {
  switch (letter) {
    case 'O':
      return 1.0;
    case 'o':
      return 0.95;
    case 'h':
      return 0.7;
    case 'q':
      return 0.3;
    case 'C':
      return 0.0;
    case 'c':
      return 0.05;
    case 'm':
      return 0.5;
  }
  ADD_FAILURE() << "no eye letter '" << letter << "'";
  return -1.0;
}

inline std::vector<double> Eye(const std::string& letters) {
  std::vector<double> values;
  for (char c : letters) values.push_back(EyeValue(c));
  return values;
}

inline std::string Letters(const std::vector<double>& values) {
  std::string s;
  for (double v : values) {
    s += v == 1.0    ? 'O'
         : v == 0.95 ? 'o'
         : v == 0.7  ? 'h'
         : v == 0.3  ? 'q'
         : v == 0.0  ? 'C'
         : v == 0.05 ? 'c'
         : v == 0.5  ? 'm'
                     : '?';
  }
  return s;
}

// Levels given (0 and 1), so that every letter curve draws at the same levels.
inline EyeOptions LetterOptions() {
  EyeOptions options;
  options.min = 0.0;
  options.max = 1.0;
  return options;
}

struct RandomEye {
  std::vector<double> values;
  std::vector<FrameInterval> closed;  // the closed runs, as generated
};

// Open stretches (values in [0.9, 1], min_open to 30 frames) separating blinks (0-3
// half-shut frames, 1-10 closed ones in [0, 0.1), 0-8 half-shut) and squints (1-4 half-shut
// frames), cut at frame_count.
inline RandomEye MakeRandomEye(SplitMix64& rng, int frame_count, int min_open) {
  RandomEye eye;
  std::vector<double>& v = eye.values;
  const auto half = [&](int count) {
    for (int i = 0; i < count; ++i) v.push_back(0.15 + 0.7 * rng.Unit());
  };
  while (static_cast<int>(v.size()) < frame_count) {
    for (int i = rng.Int(min_open, 30); i > 0; --i) v.push_back(0.9 + 0.1 * rng.Unit());
    if (rng.OneIn(6)) {
      half(rng.Int(1, 4));
      continue;
    }
    half(rng.Int(0, 3));
    const int begin = static_cast<int>(v.size());
    for (int i = rng.Int(1, 10); i > 0; --i) v.push_back(0.1 * rng.Unit());
    eye.closed.push_back({begin, static_cast<int>(v.size())});
    half(rng.Int(0, 8));
  }
  v.resize(static_cast<size_t>(frame_count));
  while (!eye.closed.empty() && eye.closed.back().begin >= frame_count) eye.closed.pop_back();
  if (!eye.closed.empty()) eye.closed.back().end = std::min(eye.closed.back().end, frame_count);
  return eye;
}

// One past the last frame blink i repaints: its opening span, or further when its closed run
// (stretched to k) plus k half-open frames outlast it; never past the clip or the next blink.
inline int SpanEnd(const std::vector<Blink>& blinks, size_t i, int frame_count) {
  const Blink& b = blinks[i];
  const int closed_last = std::max(b.closed_end, b.closed_begin + b.hold - 1);
  const int end = std::max(b.closed_end + 1 + b.open_span, closed_last + 1 + b.hold);
  const int limit = i + 1 < blinks.size() ? blinks[i + 1].closing_begin : frame_count;
  return std::min(end, limit);
}

struct EyeLevels {
  double closed, mid, open;
};

// The drawing is the input with each blink painted open (closing phase), closed (C_start
// through max(C_end, C_start + k - 1)), k frames E_mid, then open to the end of the opening
// span, all cut at the clip's end and at the next blink's closing_begin. `separated`: open
// stretches of at least 3 frames separate the blinks, so no blink may need cutting by the
// next one, and the frame before a detected closed run is open (an auto-blink's may be
// half-shut input: its guard frame is only outside other blinks and keep intervals).
inline void ExpectAnimeBlinks(const std::vector<double>& input, const std::vector<double>& drawn,
                              const std::vector<Blink>& blinks, EyeLevels l, bool separated) {
  const int frame_count = static_cast<int>(input.size());
  std::vector<double> expected = input;
  for (size_t i = 0; i < blinks.size(); ++i) {
    const Blink& b = blinks[i];
    const int limit = i + 1 < blinks.size() ? blinks[i + 1].closing_begin : frame_count;
    const auto paint = [&](int from, int to, double level) {
      for (int f = from; f < std::min(to, limit); ++f) expected[f] = level;
    };
    const int closed_stop = std::max(b.closed_end, b.closed_begin + b.hold - 1) + 1;
    paint(b.closing_begin, b.closed_begin, l.open);
    paint(b.closed_begin, closed_stop, l.closed);
    paint(closed_stop, closed_stop + b.hold, l.mid);
    paint(closed_stop + b.hold, b.closed_end + 1 + b.open_span, l.open);
    if (separated && i + 1 < blinks.size()) {
      EXPECT_LE(std::max(closed_stop + b.hold, b.closed_end + 1 + b.open_span), limit)
          << "blink " << i << " needed cutting";
    }
  }
  ASSERT_EQ(drawn.size(), expected.size());
  for (int f = 0; f < frame_count; ++f) ASSERT_EQ(drawn[f], expected[f]) << "frame " << f;
  const double open_at_least = l.open - 0.1 * (l.open - l.closed);  // delta 0.1
  for (const Blink& b : blinks) {
    if (separated && b.closed_begin > 0 && !b.automatic) {
      EXPECT_GE(drawn[b.closed_begin - 1], open_at_least) << b.closed_begin;
    }
  }
}

}  // namespace koma

#endif  // KOMA_TESTS_CORE_LIP_BLINK_TEST_UTIL_H_
