// `koma live`'s own logic (client/live_*.h): the setup every flag builds, the usage errors, a
// frame's JSON line, the --record motion3.json read back by formats/motion3, and a recording
// cut into 10 ms chunks of its own samples. The stream itself: tests/e2e/live_e2e_test.sh.
#include <gmock/gmock.h>
#include <google/protobuf/text_format.h>
#include <google/protobuf/util/message_differencer.h>
#include <gtest/gtest.h>

#include <cstring>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "client/cli.h"
#include "client/files.h"
#include "client/live_audio_source.h"
#include "client/live_command.h"
#include "client/live_output.h"
#include "client/live_record.h"
#include "formats/audio_reader.h"
#include "formats/motion3.h"
#include "tests/testing/status_matchers.h"

namespace koma::client {
namespace {

using ::koma::testing::StatusIs;

const std::string kVoice = std::string(KOMA_SAMPLES_DIR) + "/voice.flac";  // 16 kHz mono

LiveArgs Parse(std::vector<std::string> flags) {
  std::vector<std::string> line{"koma", "live"};
  line.insert(line.end(), flags.begin(), flags.end());
  KomaCommandLine parsed;
  EXPECT_EQ(ParseCommandLine(line, &parsed), -1);
  EXPECT_EQ(parsed.command, "live");
  return parsed.live;
}

v1::LiveLipBlinkSetup SetupOf(const std::string& text) {
  v1::LiveLipBlinkSetup setup;
  EXPECT_TRUE(google::protobuf::TextFormat::ParseFromString(text, &setup)) << text;
  return setup;
}

LiveAudioFormat Format16k() {
  LiveAudioFormat format;
  format.sample_rate = 16000;
  format.channels = 1;
  format.sample_format = v1::LIVE_SAMPLE_S16LE;
  return format;
}

TEST(LiveSetupTest, DefaultsLeaveTheServersDefaults) {
  const v1::LiveLipBlinkSetup setup = BuildLiveSetup(Parse({}), Format16k());
  EXPECT_TRUE(google::protobuf::util::MessageDifferencer::Equals(
      setup, SetupOf("sample_rate: 16000 channels: 1 sample_format: LIVE_SAMPLE_S16LE "
                   "mouth { mode: MOUTH_RANDOM }")))
      << setup.DebugString();
}

TEST(LiveSetupTest, EveryFlagReachesItsField) {
  const LiveArgs args = Parse(
      {"--mode", "follow", "--on", "2", "--mouth-mid-ratio", "0.4", "--mouth-min", "0.1",
       "--mouth-max", "0.9", "--eyes-mid-ratio", "0.3", "--eyes-min", "0.05", "--eyes-max",
       "0.95", "--auto-blink", "3", "--auto-blink-spread-s", "0.5", "--auto-blink-hold", "3",
       "--voice-settings-noise-floor-dbfs", "-60", "--voice-settings-noise-percentile", "20",
       "--voice-settings-start-above-floor-db", "8", "--voice-settings-stay-above-floor-db", "4",
       "--voice-settings-min-speech-dbfs", "-50", "--voice-settings-bridge-gap-frames", "2",
       "--voice-settings-faint-gap-frames", "5", "--voice-settings-pause-above-floor-db", "2",
       "--voice-settings-min-speech-frames", "3", "--voice-settings-open-below-peak-db", "5",
       "--voice-settings-closed-below-peak-db", "14", "--voice-settings-hysteresis-db", "2",
       "--voice-settings-any-sound", "--lookahead", "3", "--seed", "42", "--timing-fps", "12"});
  const v1::LiveLipBlinkSetup setup = BuildLiveSetup(args, Format16k());
  const v1::LiveLipBlinkSetup want = SetupOf(R"pb(
    sample_rate: 16000 channels: 1 sample_format: LIVE_SAMPLE_S16LE
    mouth { mode: MOUTH_FOLLOW frames_per_shape: 2 mid_ratio: 0.4 min: 0.1 max: 0.9 }
    eyes {
      mid_ratio: 0.3 min: 0.05 max: 0.95
      auto_blink { enabled: true mean_interval_s: 3 spread_s: 0.5 hold: 3 }
    }
    voice_settings {
      noise_floor_dbfs: -60 noise_percentile: 20 start_above_floor_db: 8
      stay_above_floor_db: 4 min_speech_dbfs: -50 bridge_gap_frames: 2 faint_gap_frames: 5
      pause_above_floor_db: 2 min_speech_frames: 3 open_below_peak_db: 5
      closed_below_peak_db: 14 hysteresis_db: 2 any_sound: true
    }
    lookahead_frames: 3 seed: 42 timing_fps: 12
  )pb");
  EXPECT_TRUE(google::protobuf::util::MessageDifferencer::Equals(setup, want))
      << setup.DebugString();
}

TEST(LiveSetupTest, TheConnectionAndAudioFlags) {
  const LiveArgs args = Parse({"--input", "x.wav", "--speed", "0", "--seconds", "2.5",
                               "--record", "out.motion3.json", "--json", "--server", "h:1",
                               "--deadline", "30"});
  EXPECT_EQ(args.input, "x.wav");
  EXPECT_EQ(args.speed, 0.0);
  EXPECT_EQ(args.seconds, 2.5);
  EXPECT_EQ(args.record, "out.motion3.json");
  EXPECT_TRUE(args.json);
  EXPECT_EQ(args.server, "h:1");
  EXPECT_EQ(args.deadline_seconds, 30.0);
  EXPECT_EQ(Parse({}).deadline_seconds, 0.0);  // a live stream has no deadline by default
  EXPECT_TRUE(CheckLiveFlags(args).ok());
}

TEST(LiveSetupTest, TheAvatarFlagsGivenAreKnownAfterTheParse) {
  // AvatarSinkFlags keeps the parser's CLI::Option pointers: the line keeps the parser alive
  // (it was freed with the parse, and an Ogg recording's decoding reused its memory: --vts was
  // "given" and koma live tried to reach VTube Studio).
  KomaCommandLine parsed;
  ASSERT_EQ(ParseCommandLine({"koma", "live", "--input", kVoice, "--vmc"}, &parsed), -1);
  std::vector<std::string> filler(10000, std::string(64, 'x'));  // reuse freed memory, if any
  ASSERT_NE(parsed.live.avatar.vmc, nullptr);
  ASSERT_NE(parsed.live.avatar.vts, nullptr);
  EXPECT_EQ(parsed.live.avatar.vmc->count(), 1u);
  EXPECT_EQ(parsed.live.avatar.vts->count(), 0u);
}

TEST(LiveSetupTest, UsageErrors) {
  KomaCommandLine parsed;
  EXPECT_EQ(ParseCommandLine({"koma", "live", "--speed", "-1"}, &parsed), 2);
  EXPECT_EQ(ParseCommandLine({"koma", "live", "--seconds", "0"}, &parsed), 2);
  EXPECT_EQ(ParseCommandLine({"koma", "live", "--mouth"}, &parsed), 2);  // lipblink's, not live's
  EXPECT_THAT(CheckLiveFlags(Parse({"--input", "a.wav", "--device", "null"})),
              StatusIs(absl::StatusCode::kInvalidArgument, ::testing::HasSubstr("one audio source")));
  EXPECT_THAT(CheckLiveFlags(Parse({"--speed", "2"})),
              StatusIs(absl::StatusCode::kInvalidArgument, ::testing::HasSubstr("--speed")));
  EXPECT_THAT(CheckLiveFlags(Parse({"--input", "a.wav", "--record", "-", "--json"})),
              StatusIs(absl::StatusCode::kInvalidArgument, ::testing::HasSubstr("standard output")));
}

TEST(LiveOutputTest, AFramesJsonLine) {
  v1::LiveLipBlinkFrame frame;
  ASSERT_TRUE(google::protobuf::TextFormat::ParseFromString(
      "grid_frame: 5 time_s: 0.20833333333333334 speech: true mouth: MOUTH_MID mouth_level: 0.5 "
      "new_drawing: true hold_start: true eyes: MOUTH_CLOSED eye_level: 0 blink_start: true "
      "late_ms: 83.3125 loudness_dbfs: -20.5 noise_floor_dbfs: -70",
      &frame));
  LiveFrameTiming timing;
  timing.wall_late_ms = 91.23456;
  timing.wall_s = 1.5;
  const nlohmann::json j = nlohmann::json::parse(LiveFrameJson(frame, timing));
  EXPECT_EQ(j, nlohmann::json::parse(R"({
    "grid_frame": 5, "time_s": 0.20833333333333334, "speech": true, "mouth": "half",
    "mouth_level": 0.5, "new_drawing": true, "hold_start": true, "eyes": "closed", "blink": true,
    "blink_start": true, "eye_level": 0.0, "loudness_dbfs": -20.5, "noise_floor_dbfs": -70.0,
    "late_ms": 83.3125, "wall_late_ms": 91.235, "wall_s": 1.5})"));
  frame.set_eyes(v1::MOUTH_OPEN);
  frame.set_mouth(v1::MOUTH_OPEN);
  const nlohmann::json open = nlohmann::json::parse(LiveFrameJson(frame, timing));
  EXPECT_EQ(open["blink"], false);
  EXPECT_EQ(open["mouth"], "open");
  EXPECT_EQ(std::string(LiveShapeName(v1::MOUTH_CLOSED)), "closed");
}

TEST(LiveRecordTest, SteppedKeysReadBackAsTheStreamedLevels) {
  const std::vector<double> mouth{0, 0, 0.5, 0.5, 0.5, 1, 1, 0};
  const std::vector<double> eyes{1, 1, 1, 0, 0.5, 1, 1, 1};
  ASSERT_OK_AND_ASSIGN(const std::string text, LiveMotion3(24.0, mouth, eyes));
  ASSERT_OK_AND_ASSIGN(const formats::Motion3File file, formats::ParseMotion3(text));
  EXPECT_EQ(file.curves.fps, 24.0);
  EXPECT_EQ(file.curves.frame_count, 9);  // frames 0 .. 8: the last drawing held to 8 / 24 s
  EXPECT_EQ(file.document["Meta"]["Duration"], 8.0 / 24.0);
  ASSERT_EQ(file.curves.curves.size(), 3u);
  EXPECT_EQ(file.curves.curves[0].id, "ParamMouthOpenY");
  EXPECT_EQ(file.curves.curves[1].id, "ParamEyeLOpen");
  EXPECT_EQ(file.curves.curves[2].id, "ParamEyeROpen");
  ASSERT_OK_AND_ASSIGN(const formats::Motion3Counts counts, formats::CountMotion3(file.document));
  EXPECT_EQ(file.document["Meta"]["TotalSegmentCount"], counts.total_segment_count);
  // A key where the level changes (stepped), and the end.
  const Curve& m = file.curves.curves[0];
  EXPECT_EQ(m.start.frame, 0.0);
  std::vector<std::pair<double, double>> keys;
  for (const CurveSegment& s : m.segments) {
    EXPECT_EQ(s.type, SegmentType::kStepped);
    keys.push_back({s.end.frame, s.end.value});
  }
  EXPECT_EQ(keys, (std::vector<std::pair<double, double>>{{2, 0.5}, {5, 1}, {7, 0}, {8, 0}}));
  EXPECT_EQ(file.curves.curves[1].segments.size(), 4u);  // 0 at 3, 0.5 at 4, 1 at 5, the end
}

TEST(LiveRecordTest, NothingStreamedIsAnError) {
  EXPECT_THAT(LiveMotion3(24.0, {}, {}),
              StatusIs(absl::StatusCode::kInvalidArgument, ::testing::HasSubstr("no frame")));
}

TEST(LiveAudioSourceTest, ARecordingIn10MsChunksOfItsOwnSamples) {
  ASSERT_OK_AND_ASSIGN(std::unique_ptr<LiveAudioSource> source, OpenLiveFile(kVoice));
  EXPECT_EQ(source->format().sample_rate, 16000);
  EXPECT_EQ(source->format().channels, 1);
  EXPECT_EQ(source->format().sample_format, v1::LIVE_SAMPLE_S16LE);  // 16-bit FLAC
  EXPECT_FALSE(source->real_time());  // paced by the command
  // The decoder's mono samples, for comparison.
  ASSERT_OK_AND_ASSIGN(const std::string bytes, ReadFile(kVoice));
  ASSERT_OK_AND_ASSIGN(auto decoder, formats::AudioDecoder::Open(bytes, {}));
  std::vector<float> decoded;
  for (;;) {
    ASSERT_OK_AND_ASSIGN(absl::Span<const float> block, decoder->Next());
    if (block.empty()) break;
    decoded.insert(decoded.end(), block.begin(), block.end());
  }
  std::vector<float> streamed;
  std::string chunk;
  int chunks = 0;
  for (;;) {
    ASSERT_OK_AND_ASSIGN(const bool more, source->Next(&chunk));
    if (!more) break;
    ++chunks;
    ASSERT_EQ(chunk.size() % 2, 0u);
    if (streamed.size() + 160 <= decoded.size()) {
      ASSERT_EQ(chunk.size(), 320u) << "chunk " << chunks;  // 160 samples: 10 ms
    }
    for (size_t i = 0; i < chunk.size(); i += 2) {
      int16_t s;
      std::memcpy(&s, chunk.data() + i, 2);
      streamed.push_back(static_cast<float>(s) / 32768.0f);
    }
  }
  EXPECT_EQ(streamed, decoded);  // S16LE holds a 16-bit recording's samples exactly
  EXPECT_EQ(chunks, static_cast<int>((decoded.size() + 159) / 160));
}

TEST(LiveAudioSourceTest, ErrorsNameTheFileOrDevice) {
  EXPECT_THAT(OpenLiveFile("/no/such.wav"),
              StatusIs(absl::StatusCode::kNotFound, ::testing::HasSubstr("--input /no/such.wav")));
  EXPECT_THAT(OpenLiveDevice("no_such_device"),
              StatusIs(absl::StatusCode::kUnavailable,
                       ::testing::HasSubstr("--device no_such_device: cannot open it")));
}

TEST(LiveAudioSourceTest, AlsasNullDeviceGivesSilence) {
  ASSERT_OK_AND_ASSIGN(std::unique_ptr<LiveAudioSource> source, OpenLiveDevice("null"));
  EXPECT_EQ(source->format().sample_rate, 48000);
  EXPECT_EQ(source->format().channels, 1);
  EXPECT_FALSE(source->real_time());  // it answers at once: paced by the command
  std::string chunk;
  ASSERT_OK_AND_ASSIGN(const bool more, source->Next(&chunk));
  EXPECT_TRUE(more);
  EXPECT_EQ(chunk.size(), 960u);  // 480 frames: 10 ms
}

}  // namespace
}  // namespace koma::client
