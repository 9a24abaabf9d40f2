// live_voice_compare FILE: the live voice analysis (core/live_voice.h) of a recording against
// the offline one, for tests/python/test_live_voice.py's espeak-ng and sox recordings. Prints
// one JSON line per lookahead (0 .. 3): the frames, both speech tracks as [begin, end)
// intervals, the largest boundary difference from the first second on (-1: the intervals do
// not pair up), the frames whose mouth is not closed, and the first broken drawing rule ("" for
// none), and the noise floors (offline: the whole file's; live: the least and most the
// decisions used after the first second). The audio goes in blocks of 1,000 samples and then
// of 333 samples, which must give the same frames.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "formats/audio_reader.h"
#include "tests/core/live_voice_check.h"

namespace {

std::string Intervals(const std::vector<bool>& speech) {
  std::vector<std::string> parts;
  for (const koma::FrameInterval& i : koma::testing::Runs(speech, 0)) {
    parts.push_back(absl::StrCat("[", i.begin, ",", i.end, "]"));
  }
  return absl::StrCat("[", absl::StrJoin(parts, ","), "]");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: live_voice_compare FILE\n");
    return 2;
  }
  std::ifstream in(argv[1], std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto decoder = koma::formats::AudioDecoder::Open(bytes, koma::formats::AudioLimits{});
  if (!decoder.ok()) {
    std::fprintf(stderr, "%s\n", std::string(decoder.status().message()).c_str());
    return 1;
  }
  const int rate = (*decoder)->info().sample_rate;
  std::vector<float> mono;
  for (;;) {
    auto block = (*decoder)->Next();
    if (!block.ok()) return 1;
    if (block->empty()) break;
    mono.insert(mono.end(), block->begin(), block->end());
  }
  constexpr double kFps = 24.0;
  const std::vector<bool> offline = koma::testing::OfflineSpeech(mono, rate, kFps, {});
  koma::FrameLoudness loudness(rate, kFps);
  loudness.Add(mono);
  const double offline_floor =
      koma::Percentile(loudness.Dbfs(loudness.frames_touched()), koma::VoiceOptions{}.noise_percentile);
  for (int lookahead = 0; lookahead <= koma::kMaxLookaheadFrames; ++lookahead) {
    koma::LiveVoiceOptions o;
    o.sample_rate = rate;
    o.frame_fps = kFps;
    o.lookahead_frames = lookahead;
    o.eyes.auto_blink.enabled = true;
    const std::vector<koma::LiveFrame> live = koma::testing::RunLive(mono, o, {1000});
    const std::vector<koma::LiveFrame> again = koma::testing::RunLive(mono, o, {333});
    std::vector<bool> speech;
    int open = 0;
    double floor_min = 0.0, floor_max = koma::kSilenceDbfs;  // after the first second
    bool same = again.size() == live.size();
    for (size_t i = 0; i < live.size(); ++i) {
      speech.push_back(live[i].speech);
      open += live[i].mouth != koma::MouthShape::kClosed;
      if (i >= 24) {
        floor_min = std::min(floor_min, live[i].noise_floor_dbfs);
        floor_max = std::max(floor_max, live[i].noise_floor_dbfs);
      }
      same = same && again[i].speech == live[i].speech && again[i].mouth == live[i].mouth;
    }
    std::string rules = koma::testing::CheckDrawingRules(live, o, static_cast<int64_t>(mono.size()));
    if (!same) rules = "another block size gives other frames";
    std::printf(
        "{\"lookahead\": %d, \"rate\": %d, \"frames\": %zu, \"offline\": %s, \"live\": %s, "
        "\"boundary_error\": %d, \"open_frames\": %d, \"offline_floor\": %.2f, "
        "\"live_floor\": [%.2f, %.2f], \"rules\": \"%s\"}\n",
        lookahead, rate, live.size(), Intervals(offline).c_str(), Intervals(speech).c_str(),
        koma::testing::BoundaryError(speech, offline, 24), open, offline_floor, floor_min,
        floor_max, rules.c_str());
  }
  return 0;
}
