// The live voice analysis (core/live_voice.h) against the offline one (the whole recording at
// once), on samples/voice.flac and on generated music and noise: the speech frames agree after
// the first second within one grid frame at each boundary, music and noise keep the mouth
// closed, the drawing rules hold, any split of the audio into blocks gives the same frames,
// and with the same speech the mouth and the blinks are the offline ones, draw for draw.
#include "core/live_voice.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <malloc.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "core/lip_blink.h"
#include "core/split_mix64.h"
#include "formats/audio_reader.h"
#include "tests/core/live_voice_check.h"

namespace koma {
namespace {

using testing::BoundaryError;
using testing::CheckDrawingRules;
using testing::OfflineSpeech;
using testing::RunLive;

constexpr double kFps = 24.0;
constexpr int kFirstSecond = 24;  // grid frames the running noise floor may take to settle

struct Recording {
  std::vector<float> mono;
  int rate = 0;
};

Recording Decode(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto decoder = formats::AudioDecoder::Open(bytes, formats::AudioLimits{});
  EXPECT_TRUE(decoder.ok()) << path;
  Recording r;
  r.rate = (*decoder)->info().sample_rate;
  for (;;) {
    auto block = (*decoder)->Next();
    EXPECT_TRUE(block.ok());
    if (!block.ok() || block->empty()) break;
    r.mono.insert(r.mono.end(), block->begin(), block->end());
  }
  return r;
}

const Recording& Voice() {
  static const Recording* voice = new Recording(Decode(KOMA_SAMPLES_DIR "/voice.flac"));
  return *voice;
}

LiveVoiceOptions Options(int rate, int lookahead) {
  LiveVoiceOptions o;
  o.sample_rate = rate;
  o.frame_fps = kFps;
  o.lookahead_frames = lookahead;
  o.seed = 7;
  o.eyes.auto_blink.enabled = true;
  return o;
}

std::vector<bool> SpeechOf(const std::vector<LiveFrame>& frames) {
  std::vector<bool> speech;
  for (const LiveFrame& f : frames) speech.push_back(f.speech);
  return speech;
}

// Music and noise at 16 kHz after 2 s of -70 dBFS room noise: 6 s of triangle chords with a
// 4 Hz tremolo, 6 s of white noise, 6 s of brown noise, each -12 to -20 dBFS, so loudness alone
// calls most of it speech. (A synthetic sawtooth melody is voice-like enough for the offline
// gate; tests/python/test_live_voice.py has sox's music.)
Recording MusicAndNoise() {
  Recording r;
  r.rate = 16000;
  const double pi = 3.14159265358979323846;
  SplitMix64 rng(3);
  const auto white = [&rng] { return 2.0 * rng.Unit() - 1.0; };
  double brown = 0.0;
  for (int i = 0; i < r.rate * 20; ++i) {
    const double t = static_cast<double>(i) / r.rate - 2.0;
    double x = 0.0003 * white();
    if (t < 0.0) {
    } else if (t < 6.0) {
      const double tremolo = 0.75 + 0.25 * std::sin(2 * pi * 4.0 * t);
      for (const double f : {196.0, 247.0, 294.0}) {
        const double p = f * t - std::floor(f * t);
        x += 0.08 * tremolo * (4.0 * std::fabs(p - 0.5) - 1.0);
      }
    } else if (t < 12.0) {
      x += 0.15 * white();
    } else {
      brown = 0.995 * brown + 0.05 * white();
      x += 0.3 * brown;
    }
    r.mono.push_back(static_cast<float>(x));
  }
  return r;
}

TEST(LiveVoiceTest, AgreesWithTheOfflineAnalysisOnVoiceFlac) {
  const Recording& voice = Voice();
  ASSERT_GT(voice.mono.size(), static_cast<size_t>(voice.rate) * 3);
  const std::vector<bool> offline = OfflineSpeech(voice.mono, voice.rate, kFps, VoiceOptions{});
  for (int lookahead = 0; lookahead <= kMaxLookaheadFrames; ++lookahead) {
    const LiveVoiceOptions o = Options(voice.rate, lookahead);
    const std::vector<LiveFrame> live = RunLive(voice.mono, o, {4096});
    ASSERT_EQ(live.size(), offline.size());
    EXPECT_EQ(CheckDrawingRules(live, o, static_cast<int64_t>(voice.mono.size())), "");
    const int error = BoundaryError(SpeechOf(live), offline, kFirstSecond);

    RecordProperty(absl::StrCat("boundary_error_lookahead_", lookahead), error);
    // Lookahead 2 and 3: the acceptance (docs/semantics.md has the figures for 0 and 1).
    if (lookahead >= 2) {
      EXPECT_GE(error, 0) << "lookahead " << lookahead << ": the speech runs differ";
      EXPECT_LE(error, 1) << "lookahead " << lookahead;
    }
  }
}

TEST(LiveVoiceTest, MusicAndNoiseKeepTheMouthClosedAsOffline) {
  const Recording r = MusicAndNoise();
  const std::vector<bool> offline = OfflineSpeech(r.mono, r.rate, kFps, VoiceOptions{});
  VoiceOptions any_sound;
  any_sound.gate.enabled = false;
  const std::vector<bool> loud = OfflineSpeech(r.mono, r.rate, kFps, any_sound);
  // The recording is loud: without the gate most of it is "speech".
  EXPECT_GT(std::count(loud.begin(), loud.end(), true), static_cast<int>(loud.size()) / 2);
  EXPECT_EQ(std::count(offline.begin(), offline.end(), true), 0);
  for (int lookahead = 0; lookahead <= kMaxLookaheadFrames; ++lookahead) {
    const LiveVoiceOptions o = Options(r.rate, lookahead);
    const std::vector<LiveFrame> live = RunLive(r.mono, o, {1000});
    EXPECT_EQ(CheckDrawingRules(live, o, static_cast<int64_t>(r.mono.size())), "");
    int open = 0;
    for (const LiveFrame& f : live) open += f.mouth != MouthShape::kClosed;
    EXPECT_LE(open, static_cast<int>(live.size()) / 50) << "lookahead " << lookahead;
  }
}

TEST(LiveVoiceTest, AnyBlockSplitGivesTheSameFrames) {
  const Recording& voice = Voice();
  // Ten seconds: the voice and the start of the music.
  std::vector<float> mono(voice.mono.begin(),
                          voice.mono.begin() + std::min<size_t>(voice.mono.size(), voice.rate * 8));
  const Recording music = MusicAndNoise();
  mono.insert(mono.end(), music.mono.begin(), music.mono.begin() + music.rate * 2);
  SplitMix64 rng(11);
  for (int round = 0; round < 6; ++round) {
    LiveVoiceOptions o = Options(voice.rate, round % 4);
    o.mouth.mode = round % 2 ? MouthMode::kFollow : MouthMode::kRandom;
    const std::vector<LiveFrame> whole = RunLive(mono, o, {mono.size()});
    std::vector<size_t> blocks;
    for (int i = 0; i < 64; ++i) {
      // Single samples, sub-frame and multi-frame blocks.
      const int kind = rng.Int(0, 2);
      blocks.push_back(kind == 0 ? 1 : kind == 1 ? rng.Int(2, 2000) : rng.Int(2000, 20000));
    }
    const std::vector<LiveFrame> split = RunLive(mono, o, blocks);
    ASSERT_EQ(split.size(), whole.size());
    for (size_t i = 0; i < whole.size(); ++i) {
      SCOPED_TRACE(absl::StrCat("round ", round, " frame ", i));
      EXPECT_EQ(std::memcmp(&split[i].dbfs, &whole[i].dbfs, sizeof(double)), 0);
      EXPECT_EQ(split[i].speech, whole[i].speech);
      EXPECT_EQ(split[i].mouth, whole[i].mouth);
      EXPECT_EQ(split[i].hold_start, whole[i].hold_start);
      EXPECT_EQ(split[i].eye, whole[i].eye);
      EXPECT_EQ(split[i].late_samples, whole[i].late_samples);
    }
    EXPECT_EQ(CheckDrawingRules(split, o, static_cast<int64_t>(mono.size())), "");
  }
}

// With the same speech and seed, RANDOM's holds are ConvertMouth's draw for draw (one draw per
// hold in time order), and the auto-blinks are ConvertEyes' on an eye that never moves.
TEST(LiveVoiceTest, TheMouthAndBlinksAreTheOfflineOnesForTheSameSpeech) {
  const Recording& voice = Voice();
  std::vector<float> thrice;  // 12 s
  for (int i = 0; i < 3; ++i) thrice.insert(thrice.end(), voice.mono.begin(), voice.mono.end());
  LiveVoiceOptions o = Options(voice.rate, 2);
  o.seed = 1234;
  o.eyes.auto_blink.mean_interval_s = 1.0;
  o.eyes.auto_blink.spread_s = 0.5;
  const std::vector<LiveFrame> live = RunLive(thrice, o, {777});
  const int frames = static_cast<int>(live.size());
  MouthOptions mouth = o.mouth;
  mouth.speech = testing::Runs(SpeechOf(live), 0);
  mouth.detect_speech = false;
  mouth.min = 0.0;
  mouth.max = 1.0;
  ASSERT_FALSE(mouth.speech.empty());
  const MouthResult offline = ConvertMouth(std::vector<double>(frames, 0.0), mouth, o.seed);
  const std::vector<MouthShape> drawings = MouthDrawings(offline.holds, frames);
  EyeOptions eyes = o.eyes;
  eyes.fps = kFps;
  eyes.min = 0.0;
  eyes.max = 1.0;
  const std::vector<double> open(frames, 1.0);
  const EyeResult offline_eyes = ConvertEyes({open}, eyes, o.seed);
  ASSERT_GT(offline_eyes.blinks[0].size(), 3u);
  // The offline walk stops before a blink that would not end inside the clip; the live one
  // does not know where the clip ends.
  const int fits = offline_eyes.blinks[0].back().closed_begin + 2 * eyes.auto_blink.hold;
  for (int g = 0; g < frames; ++g) {
    ASSERT_EQ(live[g].mouth, drawings[g]) << "frame " << g;
    ASSERT_EQ(live[g].mouth_level, offline.values[g]) << "frame " << g;
    if (g < fits) {
      ASSERT_EQ(live[g].eye_level, offline_eyes.values[0][g]) << "frame " << g;
    }
  }
}

TEST(LiveVoiceTest, DecidesEachFrameTheLookaheadAfterItsEnd) {
  // 1 kHz tone bursts at 48 kHz: frame g is popped once the sample `lookahead` frames after
  // its end has arrived, not before.
  for (int lookahead = 0; lookahead <= kMaxLookaheadFrames; ++lookahead) {
    LiveVoice live(Options(48000, lookahead));
    const GridSamples grid(48000, kFps);
    std::vector<float> one(1, 0.0f);
    int64_t popped = 0;
    LiveFrame f;
    for (int64_t i = 0; i < 48000; ++i) {
      one[0] = static_cast<float>(0.1 * std::sin(i * 0.13) * ((i / 9000) % 2));
      live.Add(one);
      while (live.Pop(&f)) {
        ASSERT_EQ(f.frame, popped);
        EXPECT_EQ(i + 1, grid.FirstSample(f.frame + 1 + lookahead));
        EXPECT_EQ(f.late_samples, grid.FirstSample(f.frame + 1 + lookahead) -
                                      grid.FirstSample(f.frame + 1));
        ++popped;
      }
    }
    EXPECT_EQ(popped, 24 - lookahead);
    live.Finish();
    while (live.Pop(&f)) ++popped;
    EXPECT_EQ(popped, 24);
    live.Add(one);  // after the end: nothing
    EXPECT_FALSE(live.Pop(&f));
    EXPECT_EQ(live.samples(), 48000);
  }
}

// The running noise floor (a histogram of the last kLiveHistorySeconds) against the naive
// percentile of the exact loudness of the same frames, over 75 s so frames leave the history:
// within half a 0.1 dB bin.
TEST(LiveVoiceTest, TheRunningFloorIsTheNaivePercentileOfTheHistory) {
  const int rate = 8000;
  const GridSamples grid(rate, kFps);
  LiveVoiceOptions o = Options(rate, 1);
  o.voice.noise_percentile = 25.0;
  LiveVoice live(o);
  SplitMix64 rng(5);
  const int64_t history = static_cast<int64_t>(kLiveHistorySeconds * kFps);
  struct Seen {
    int64_t first, last;  // the frames the decision's history held
    double floor;
  };
  std::vector<Seen> seen;
  std::vector<double> dbfs;  // every frame's, from the popped frames
  LiveFrame f;
  for (int64_t g = 0; g < 75 * 24; ++g) {
    // One frame of noise at a level that wanders between -80 and -10 dBFS: the frame's last
    // sample completes it and decides frame g - 1 (lookahead 1) on frames 0 .. g.
    const double amplitude = std::pow(10.0, (-80.0 + 70.0 * rng.Unit()) / 20.0);
    std::vector<float> frame(static_cast<size_t>(grid.FirstSample(g + 1) - grid.FirstSample(g)));
    for (float& x : frame) x = static_cast<float>(amplitude * (2.0 * rng.Unit() - 1.0));
    live.Add(frame);
    if (g >= 1) seen.push_back({std::max<int64_t>(0, g - history + 1), g, live.noise_floor_dbfs()});
    while (live.Pop(&f)) dbfs.push_back(f.dbfs);
  }
  live.Finish();
  while (live.Pop(&f)) dbfs.push_back(f.dbfs);
  ASSERT_EQ(dbfs.size(), 75u * 24u);
  for (const Seen& s : seen) {
    const double naive = Percentile({dbfs.begin() + s.first, dbfs.begin() + s.last + 1}, 25.0);
    ASSERT_NEAR(s.floor, naive, 0.05 + 1e-9) << "frames " << s.first << ".." << s.last;
  }
}

// Bounded state: after the first two minutes (the 60 s history full, every ring and scratch
// buffer grown), eight more minutes of talk and pauses allocate nothing that stays. glibc's
// count of the heap's bytes in use, which only this thread moves between the two readings.
TEST(LiveVoiceTest, TheStateStaysBoundedOverTenMinutes) {
  const int rate = 8000;
  LiveVoice live(Options(rate, 3));
  std::vector<float> block(static_cast<size_t>(rate / 50));  // 20 ms
  LiveFrame f;
  int64_t i = 0, speech = 0;
  const auto feed = [&](int seconds) {
    for (int b = 0; b < seconds * 50; ++b) {
      for (float& x : block) {
        const double t = static_cast<double>(i++) / rate;
        // 1.3 s of a 4 Hz-modulated 180 Hz vowel-like tone in every 2 s.
        x = static_cast<float>(std::fmod(t, 2.0) < 1.3
                                   ? 0.3 * std::sin(2 * 3.14159 * 180 * t *
                                                    (1 + 0.05 * std::sin(2 * 3.14159 * 4 * t)))
                                   : 0.0003 * std::sin(i * 1.7));
      }
      live.Add(block);
      while (live.Pop(&f)) speech += f.speech;
    }
  };
  feed(120);
  const size_t before = mallinfo2().uordblks;
  feed(480);
  const size_t after = mallinfo2().uordblks;
  EXPECT_LE(after, before) << "grew by " << after - before << " bytes";
  EXPECT_GT(speech, 0);
}

TEST(LiveVoiceTest, ValidatesItsOptions) {
  LiveVoiceOptions o;
  EXPECT_TRUE(ValidateLiveVoiceOptions(o).ok());
  o.lookahead_frames = 4;
  EXPECT_THAT(std::string(ValidateLiveVoiceOptions(o).message()),
              ::testing::HasSubstr("lookahead_frames: 4 must be in [0, 3]"));
  o = LiveVoiceOptions{};
  o.sample_rate = 0;
  EXPECT_THAT(std::string(ValidateLiveVoiceOptions(o).message()),
              ::testing::HasSubstr("sample_rate: 0"));
  o = LiveVoiceOptions{};
  o.mouth.frames_per_shape = 0;
  EXPECT_THAT(std::string(ValidateLiveVoiceOptions(o).message()),
              ::testing::HasSubstr("frames_per_shape"));
  o = LiveVoiceOptions{};
  o.voice.noise_percentile = 100.0;
  EXPECT_THAT(std::string(ValidateLiveVoiceOptions(o).message()),
              ::testing::HasSubstr("noise_percentile"));
}

}  // namespace
}  // namespace koma
