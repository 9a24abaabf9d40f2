// FrameLoudness, MeanSquareToDbfs and DetectVoice against hand-worked cases and a naive
// reference (per-sample frame lookup, std::log10, the rules written out frame by frame).
#include "core/voice_activity.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/split_mix64.h"

namespace koma {
namespace {

TEST(MeanSquareToDbfsTest, MatchesLog10WithinATrillionth) {
  SplitMix64 rng(7);
  for (int i = 0; i < 20000; ++i) {
    const double ms = std::ldexp(rng.Unit() + 1e-3, -rng.Int(0, 40));  // >= 9e-16
    if (ms <= 1e-15) continue;
    EXPECT_NEAR(MeanSquareToDbfs(ms), 10.0 * std::log10(ms), 1e-12) << ms;
  }
  EXPECT_EQ(MeanSquareToDbfs(1.0), 0.0);
  EXPECT_NEAR(MeanSquareToDbfs(0.5), -3.0102999566398120, 1e-13);  // a full-scale sine
  EXPECT_EQ(MeanSquareToDbfs(0.0), kSilenceDbfs);
  EXPECT_EQ(MeanSquareToDbfs(1e-16), kSilenceDbfs);
  EXPECT_EQ(MeanSquareToDbfs(std::nan("")), kSilenceDbfs);
}

// The reference: sample i is in frame floor(i * fps / rate) (exact for these integer rates).
std::vector<double> NaiveDbfs(const std::vector<float>& x, int rate, int fps, int frames) {
  std::vector<double> sum(frames, 0.0);
  std::vector<int> count(frames, 0);
  for (size_t i = 0; i < x.size(); ++i) {
    const int64_t g = static_cast<int64_t>(i) * fps / rate;
    if (g < frames) {
      sum[g] += static_cast<double>(x[i]) * x[i];
      ++count[g];
    }
  }
  std::vector<double> out(frames, kSilenceDbfs);
  for (int g = 0; g < frames; ++g) {
    if (count[g] > 0 && sum[g] / count[g] > 1e-15) out[g] = 10 * std::log10(sum[g] / count[g]);
  }
  return out;
}

TEST(FrameLoudnessTest, AnyBlockSplitMatchesTheNaiveFrames) {
  SplitMix64 rng(11);
  for (int trial = 0; trial < 200; ++trial) {
    const int rates[] = {8000, 11025, 16000, 22050, 44100, 48000, 7, 96001};
    const int rate = rates[rng.Int(0, 7)];
    const int fps = rng.Int(1, 60);
    const int n = rng.Int(0, 5000);
    std::vector<float> x(n);
    for (float& v : x) v = static_cast<float>(rng.Unit() * 2 - 1) * (rng.Int(0, 3) == 0 ? 0 : 1);
    FrameLoudness loudness(rate, fps);
    for (int i = 0; i < n;) {  // blocks of random sizes, as the decoder's
      const int take = std::min(n - i, rng.Int(1, 700));
      loudness.Add(absl::MakeConstSpan(x.data() + i, take));
      i += take;
    }
    const int frames = loudness.frames_touched() + 2;
    const std::vector<double> got = loudness.Dbfs(frames);
    const std::vector<double> want = NaiveDbfs(x, rate, fps, frames);
    ASSERT_EQ(loudness.samples(), n);
    ASSERT_EQ(loudness.frames_touched(), n == 0 ? 0 : static_cast<int>((int64_t{n} - 1) * fps / rate) + 1)
        << rate << " " << fps << " " << n;
    for (int g = 0; g < frames; ++g) ASSERT_NEAR(got[g], want[g], 1e-9) << g;
  }
}

TEST(FrameLoudnessTest, FullScaleSquareIsZeroDbfsAndHalfIsMinusSix) {
  FrameLoudness loudness(48000, 24);  // 2000 samples per frame
  std::vector<float> x(4000);
  for (int i = 0; i < 2000; ++i) x[i] = (i % 2) ? 1.0f : -1.0f;
  for (int i = 2000; i < 4000; ++i) x[i] = (i % 2) ? 0.5f : -0.5f;
  loudness.Add(x);
  const std::vector<double> db = loudness.Dbfs(3);
  EXPECT_EQ(db[0], 0.0);
  EXPECT_NEAR(db[1], -6.0205999132796239, 1e-12);
  EXPECT_EQ(db[2], kSilenceDbfs);  // past the recording
}

// The rules written out directly: per frame speech if in a run >= stay holding a frame >= start;
// then gaps <= bridge merged, and gaps <= faint whose every frame is above `pause`; then short
// runs dropped.
std::vector<FrameInterval> NaiveSpeech(const std::vector<double>& db, double start, double stay,
                                       int bridge, int min_len, int faint = 0,
                                       double pause = 0.0) {
  const int n = static_cast<int>(db.size());
  std::vector<bool> on(n, false);
  for (int f = 0; f < n; ++f) {
    if (db[f] < start) continue;
    for (int g = f; g >= 0 && db[g] >= stay; --g) on[g] = true;
    for (int g = f; g < n && db[g] >= stay; ++g) on[g] = true;
  }
  std::vector<FrameInterval> runs;
  for (int f = 0; f < n; ++f) {
    if (!on[f]) continue;
    int e = f;
    while (e < n && on[e]) ++e;
    runs.push_back({f, e});
    f = e;
  }
  std::vector<FrameInterval> merged;
  for (const FrameInterval& r : runs) {
    bool faint_gap = false;
    if (!merged.empty() && r.begin - merged.back().end <= faint) {
      faint_gap = true;
      for (int f = merged.back().end; f < r.begin; ++f) faint_gap = faint_gap && db[f] > pause;
    }
    if (!merged.empty() && (r.begin - merged.back().end <= bridge || faint_gap)) {
      merged.back().end = r.end;
    } else {
      merged.push_back(r);
    }
  }
  std::vector<FrameInterval> out;
  for (const FrameInterval& r : merged) {
    if (r.end - r.begin >= min_len) out.push_back(r);
  }
  return out;
}

TEST(DetectVoiceTest, MatchesTheNaiveRulesOnRandomLoudness) {
  SplitMix64 rng(3);
  for (int trial = 0; trial < 2000; ++trial) {
    const int n = rng.Int(1, 120);
    std::vector<double> db(n);
    double level = -60;
    for (double& v : db) {
      if (rng.Int(0, 4) == 0) level = rng.Int(0, 1) ? -60 : -20;
      v = level + rng.Int(-8, 8);
    }
    VoiceOptions o;
    o.bridge_gap_frames = rng.Int(0, 4);
    o.faint_gap_frames = rng.Int(0, 6);
    o.pause_above_floor_db = rng.Int(0, 6);
    o.min_speech_frames = rng.Int(1, 4);
    const VoiceActivity v = DetectVoice(db, o);
    const double floor = Percentile(db, 10);
    EXPECT_EQ(v.noise_floor_dbfs, floor);
    EXPECT_EQ(v.start_dbfs, std::max(floor + 9, -55.0));
    const double stay_db =
        std::min(9.0, std::max(2.0, 0.2 * (Percentile(db, 90) - floor)));
    EXPECT_EQ(v.stay_dbfs, std::max(floor + stay_db, -55.0 - (9 - stay_db)));
    const std::vector<FrameInterval> want =
        NaiveSpeech(db, v.start_dbfs, v.stay_dbfs, o.bridge_gap_frames, o.min_speech_frames,
                    o.faint_gap_frames, floor + o.pause_above_floor_db);
    ASSERT_EQ(v.speech.size(), want.size()) << trial;
    for (size_t i = 0; i < want.size(); ++i) EXPECT_EQ(v.speech[i], want[i]) << trial;
    ASSERT_EQ(v.follow.size(), db.size());
    for (int f = 0; f < n; ++f) {
      bool inside = false;
      for (const FrameInterval& i : v.speech) inside |= f >= i.begin && f < i.end;
      if (!inside) {
        EXPECT_EQ(v.follow[f], MouthShape::kClosed);
      }
    }
  }
}

TEST(DetectVoiceTest, HandWorkedSpeechAndFollow) {
  // Floor -60 (10th percentile), start -51, stay -52 (a fifth of the 40 dB range); loud = 90th percentile of speech = -20:
  // open above -26 (+1.5 to enter), closed below -35.
  std::vector<double> db(40, -60.0);
  for (int f = 5; f < 15; ++f) db[f] = -20;  // a word
  db[15] = -59.5;                            // a 1-frame stop closure: bridged
  for (int f = 16; f < 20; ++f) db[f] = -30;  // quieter: mid
  db[30] = -20;                               // a click: dropped (1 frame)
  const VoiceActivity v = DetectVoice(db, VoiceOptions{});
  EXPECT_EQ(v.noise_floor_dbfs, -60);
  ASSERT_EQ(v.speech.size(), 1u);
  EXPECT_EQ(v.speech[0], (FrameInterval{5, 20}));
  EXPECT_EQ(v.loud_dbfs, -20);
  EXPECT_EQ(v.follow[5], MouthShape::kOpen);
  EXPECT_EQ(v.follow[15], MouthShape::kClosed);  // -59.5 < -35 - 1.5
  EXPECT_EQ(v.follow[16], MouthShape::kMid);
  EXPECT_EQ(v.follow[30], MouthShape::kClosed);
}

TEST(DetectVoiceTest, AFaintGapIsBridgedAPauseIsNot) {
  // Floor -60; a word, a 4-frame gap, a word, a 4-frame gap, a word. The first gap stays
  // 3-5 dB above the floor (a fricative lost in a narrow band): bridged. The second touches
  // the floor once (a pause): kept. 3-frame gaps are bridged whatever their level.
  std::vector<double> db(60, -60.0);
  for (int f = 5; f < 15; ++f) db[f] = -20;
  for (int f = 15; f < 19; ++f) db[f] = f == 16 ? -55 : -57;  // faint
  for (int f = 19; f < 29; ++f) db[f] = -20;
  for (int f = 29; f < 33; ++f) db[f] = f == 31 ? -59.5 : -56;  // reaches floor + 1
  for (int f = 33; f < 43; ++f) db[f] = -20;
  VoiceActivity v = DetectVoice(db, VoiceOptions{});
  EXPECT_EQ(v.noise_floor_dbfs, -60);
  ASSERT_EQ(v.speech.size(), 2u);
  EXPECT_EQ(v.speech[0], (FrameInterval{5, 29}));
  EXPECT_EQ(v.speech[1], (FrameInterval{33, 43}));
  VoiceOptions no_faint;
  no_faint.faint_gap_frames = 3;
  EXPECT_EQ(DetectVoice(db, no_faint).speech.size(), 3u);
  VoiceOptions looser;
  looser.pause_above_floor_db = 0.25;  // -59.5 is now above the pause level
  EXPECT_EQ(DetectVoice(db, looser).speech.size(), 1u);
  VoiceOptions old_default;
  old_default.bridge_gap_frames = 4;  // before the faint-gap rule: both bridged
  EXPECT_EQ(DetectVoice(db, old_default).speech.size(), 1u);
}

TEST(DetectVoiceTest, HysteresisHoldsTheDrawingNearABoundary) {
  std::vector<double> db(30, -60.0);
  // Loud level -20 (90th percentile of speech), open boundary -26: values hovering within
  // +-1 dB of it never flip the drawing once it is open.
  for (int f = 2; f < 28; ++f) db[f] = f < 10 ? -20 : ((f % 2) ? -25.2 : -26.8);
  const VoiceActivity v = DetectVoice(db, VoiceOptions{});
  ASSERT_EQ(v.speech.size(), 1u);
  for (int f = 2; f < 28; ++f) EXPECT_EQ(v.follow[f], MouthShape::kOpen) << f;
  VoiceOptions none;
  none.hysteresis_db = 0;
  const VoiceActivity chatter = DetectVoice(db, none);
  int changes = 0;
  for (int f = 6; f < 28; ++f) changes += chatter.follow[f] != chatter.follow[f - 1];
  EXPECT_GT(changes, 10);
}

TEST(DetectVoiceTest, CleanRecordingSilenceIsNotSpeech) {
  // Digital silence (-150) with a breath at -70: the floor is -150, but min_speech_dbfs keeps
  // the breath out.
  std::vector<double> db(50, kSilenceDbfs);
  for (int f = 10; f < 20; ++f) db[f] = -70;
  for (int f = 25; f < 35; ++f) db[f] = -25;
  const VoiceActivity v = DetectVoice(db, VoiceOptions{});
  ASSERT_EQ(v.speech.size(), 1u);
  EXPECT_EQ(v.speech[0], (FrameInterval{25, 35}));
}

TEST(ValidateVoiceOptionsTest, NamesTheOption) {
  VoiceOptions o;
  o.stay_above_floor_db = 12.0;
  EXPECT_EQ(ValidateVoiceOptions(o).message(),
            "stay_above_floor_db: 12 must be in (0, start_above_floor_db = 9] dB");
  o = {};
  o.noise_percentile = 100;
  EXPECT_EQ(ValidateVoiceOptions(o).message(), "noise_percentile: 100 must be in (0, 100)");
  o = {};
  o.closed_below_peak_db = 5;
  EXPECT_EQ(ValidateVoiceOptions(o).message(),
            "closed_below_peak_db: 5 must be in (open_below_peak_db = 6, 200] dB");
  o = {};
  o.faint_gap_frames = -1;
  EXPECT_EQ(ValidateVoiceOptions(o).message(), "faint_gap_frames: -1 must be >= 0");
  o = {};
  o.pause_above_floor_db = -0.5;
  EXPECT_EQ(ValidateVoiceOptions(o).message(),
            "pause_above_floor_db: -0.5 must be in [0, 200] dB");
  o = {};
  o.min_speech_frames = 0;
  EXPECT_EQ(ValidateVoiceOptions(o).message(), "min_speech_frames: 0 must be >= 1");
  o = {};
  o.noise_floor_dbfs = 3;
  EXPECT_EQ(ValidateVoiceOptions(o).message(), "noise_floor_dbfs: 3 must be finite and <= 0 dBFS");
  EXPECT_TRUE(ValidateVoiceOptions(VoiceOptions{}).ok());
}

}  // namespace
}  // namespace koma
