// LipBlink's film-grid pieces (core/lip_blink_grid.h), on hand-worked cases: sampling a curve
// at grid times, speech/keep intervals snapped to their nearest grid frames (ties to the
// earlier, empty ones dropped), the repaint masks, and the expansion back to the source rate
// (grid values in repainted stretches and the grid frame before each, input elsewhere; steps
// at exact grid times there and on source frames elsewhere).
#include "core/lip_blink_grid.h"

#include <gtest/gtest.h>

#include <optional>
#include <vector>

#include "core/curves.h"
#include "core/film_grid.h"
#include "core/lip_blink.h"

namespace koma {
namespace {

FilmGrid Grid(double source_fps) { return *FilmGrid::Make(source_fps, 24.0); }

std::vector<bool> Bits(int n, std::vector<int> on) {
  std::vector<bool> out(static_cast<size_t>(n), false);
  for (int i : on) out[static_cast<size_t>(i)] = true;
  return out;
}

TEST(LipBlinkGridTest, SampleOnGridEvaluatesAtEachGridTime) {
  const FilmGrid grid = Grid(30.0);  // grid frame g at source frame 1.25 g
  Curve keys;
  keys.id = "k";
  keys.start = {0.0, 0.0};
  CurveSegment linear;
  linear.type = SegmentType::kLinear;
  linear.end = {10.0, 20.0};
  keys.segments.push_back(linear);
  CurveSegment stepped;
  stepped.type = SegmentType::kStepped;
  stepped.end = {12.5, -4.0};  // jumps at source frame 12.5 = grid frame 10
  keys.segments.push_back(stepped);
  const std::vector<double> v = SampleOnGrid(keys, grid, 12, true);
  ASSERT_EQ(v.size(), 12u);
  for (int g = 0; g <= 8; ++g) EXPECT_DOUBLE_EQ(v[g], 2.0 * 1.25 * g) << g;  // 2 per frame
  EXPECT_EQ(v[9], 20.0);   // 11.25: held at the linear end's value
  EXPECT_EQ(v[10], -4.0);  // 12.5: the step's own time shows its end value
  EXPECT_EQ(v[11], -4.0);
  Curve dense;
  dense.id = "d";
  dense.samples = {0.0, 4.0, 8.0, 0.0, 0.0, 1.0};
  const std::vector<double> d = SampleOnGrid(dense, grid, 5, false);
  EXPECT_EQ(d, (std::vector<double>{0.0, 5.0, 4.0, 0.0, 1.0}));  // 0, 1.25, 2.5, 3.75, 5
}

TEST(LipBlinkGridTest, IntervalsSnapToNearestGridFramesAndEmptyOnesGo) {
  const FilmGrid at120 = Grid(120.0);  // source frame k at grid frame k / 5
  EXPECT_EQ(IntervalsOnGrid({{11, 13}, {60, 61}, {100, 120}, {130, 131}, {236, 241}}, at120, 49),
            (std::vector<FrameInterval>{{2, 3}, {20, 24}, {47, 48}}));
  // The end may be the clip's frame count: it snaps to at most the grid's.
  EXPECT_EQ(IntervalsOnGrid({{0, 240}}, at120, 48), (std::vector<FrameInterval>{{0, 48}}));
  // At 48 fps an odd frame lies half-way between two grid frames: it goes to the earlier one.
  const FilmGrid at48 = Grid(48.0);
  EXPECT_EQ(IntervalsOnGrid({{1, 3}, {5, 6}, {9, 12}}, at48, 20),
            (std::vector<FrameInterval>{{0, 1}, {2, 3}, {4, 6}}));
  // Finer than the source (12 fps: grid frame 2k at source frame k).
  const FilmGrid at12 = Grid(12.0);
  EXPECT_EQ(IntervalsOnGrid({{1, 2}, {3, 5}}, at12, 9),
            (std::vector<FrameInterval>{{2, 4}, {6, 9}}));
  EXPECT_TRUE(IntervalsOnGrid({}, at120, 10).empty());
}

TEST(LipBlinkGridTest, MasksCoverSpeechAndEachBlinksRepaint) {
  EXPECT_EQ(SpeechMask({{1, 3}, {5, 6}}, 8), Bits(8, {1, 2, 5}));
  EXPECT_EQ(SpeechMask({}, 3), Bits(3, {}));
  // Closed 4..5, k = 2: closed through max(5, 4 + 1) = 5, half-open 6..7; open span 3 ends at
  // 8: the repaint is 2 .. 8 (closing from 2), clipped at the next blink's closing_begin.
  Blink a;
  a.closing_begin = 2;
  a.closed_begin = 4;
  a.closed_end = 5;
  a.open_span = 3;
  a.hold = 2;
  EXPECT_EQ(BlinkMask({a}, 12), Bits(12, {2, 3, 4, 5, 6, 7, 8}));
  Blink b = a;
  b.closing_begin = 7;
  b.closed_begin = 8;
  b.closed_end = 8;
  b.open_span = 5;  // to 13, past the clip
  b.hold = 3;
  EXPECT_EQ(BlinkMask({a, b}, 12), Bits(12, {2, 3, 4, 5, 6, 7, 8, 9, 10, 11}));
  // A blink that stays shut shorter than k: closed through C_start + k - 1, then k half-open.
  Blink c;
  c.closing_begin = 0;
  c.closed_begin = 0;
  c.closed_end = 0;
  c.open_span = 0;
  c.hold = 3;
  EXPECT_EQ(BlinkMask({c}, 10), Bits(10, {0, 1, 2, 3, 4, 5}));
}

// 10 source frames at 30 fps: grid frames 0..7 at source frames 0, 1.25, 2.5, 3.75, 5, 6.25,
// 7.5, 8.75; source frame k falls in grid frame floor(4k / 5): 0 0 1 2 3 4 4 5 6 7.
TEST(LipBlinkGridTest, ExpandConvertedShowsGridValuesInRepaintedStretchesOnly) {
  const FilmGrid grid = Grid(30.0);
  const std::vector<double> grid_values = {0, 10, 20, 30, 40, 50, 60, 70};
  std::vector<double> source;
  for (int k = 0; k < 10; ++k) source.push_back(100.0 + k);
  // Grid frames 4 and 5 repainted: 3, just before them, shows its grid value too.
  const SourceRateCurve out = ExpandConverted(grid_values, Bits(8, {4, 5}), source, grid);
  EXPECT_EQ(out.values, (std::vector<double>{100, 101, 102, 103, 30, 40, 40, 50, 108, 109}));
  const std::vector<CurvePoint> want = {{0, 100}, {1, 101},  {2, 102},    {3, 103},
                                        {3.75, 30}, {5, 40}, {6.25, 50}, {8, 108}, {9, 109}};
  ASSERT_EQ(out.steps.size(), want.size());
  for (size_t i = 0; i < want.size(); ++i) {
    EXPECT_EQ(out.steps[i].frame, want[i].frame) << i;
    EXPECT_EQ(out.steps[i].value, want[i].value) << i;
  }
}

TEST(LipBlinkGridTest, ExpandConvertedAtTheClipsEdgesAndWithNothingRepainted) {
  const FilmGrid grid = Grid(30.0);
  const std::vector<double> grid_values = {7, 7, 7, 9, 9, 9, 9, 5};
  const std::vector<double> source(10, 1.0);
  // Nothing repainted: the input, as stepped keys at its first and last frame.
  SourceRateCurve out = ExpandConverted(grid_values, Bits(8, {}), source, grid);
  EXPECT_EQ(out.values, source);
  ASSERT_EQ(out.steps.size(), 2u);
  EXPECT_EQ(out.steps[0].frame, 0.0);
  EXPECT_EQ(out.steps[1].frame, 9.0);
  EXPECT_EQ(out.steps[1].value, 1.0);
  // From grid frame 0 and the last grid frame: equal neighbours make one step.
  out = ExpandConverted(grid_values, Bits(8, {0, 1, 7}), source, grid);
  EXPECT_EQ(out.values, (std::vector<double>{7, 7, 7, 1, 1, 1, 1, 1, 9, 5}));
  const std::vector<CurvePoint> want = {{0, 7}, {3, 1}, {7.5, 9}, {8.75, 5}, {9, 5}};
  ASSERT_EQ(out.steps.size(), want.size());
  for (size_t i = 0; i < want.size(); ++i) {
    EXPECT_EQ(out.steps[i].frame, want[i].frame) << i;
    EXPECT_EQ(out.steps[i].value, want[i].value) << i;
  }
}

}  // namespace
}  // namespace koma
