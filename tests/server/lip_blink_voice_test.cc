// LipBlink from a voice through the real service (in-process channel): speech found at the
// known times of generated recordings, the mouth drawn only there, the same answer for every
// encoding of one recording, merging into a sent motion, cues in and out, and a table of bad
// voices refused with the field and the reason.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "formats/rhubarb_cues.h"
#include "koma/v1/retime.grpc.pb.h"
#include "tests/server/bad_request_table.h"
#include "tests/server/in_process_server.h"
#include "tests/testing/wav_bytes.h"

namespace koma::server {
namespace {

using ::koma::testing::CallRpc;
using ::koma::testing::InProcessServer;
using ::koma::testing::ToneAndSilence;
using ::koma::testing::VoiceLikeAndSilence;
using ::koma::testing::WavBytes;
using ::koma::testing::WavHeader;
using ::testing::HasSubstr;

// Silence 0.5 s, voice 0.5 s, silence 0.5 s, voice 0.75 s, silence 0.25 s (2.5 s): speech at
// 24 fps grid frames [12, 24) and [36, 54). Voice-like (VoiceLikeAndSilence), not a held tone,
// which is music since issue 44 (AHeldToneIsMusicNotSpeech).
std::string Recording(WavHeader h = {}, double noise = 0.0) {
  std::vector<double> mono = VoiceLikeAndSilence(
      h.sample_rate, {{0.5, 0.0}, {0.5, 0.5}, {0.5, 0.0}, {0.75, 0.5}, {0.25, 0.0}});
  uint64_t state = 12345;
  for (double& x : mono) {  // white noise from a fixed LCG: the same every run
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    x += noise * (static_cast<double>(state >> 11) * 0x1.0p-53 * 2 - 1);
  }
  std::vector<double> interleaved;
  for (double x : mono) {
    for (int c = 0; c < h.channels; ++c) interleaved.push_back(x);
  }
  return WavBytes(h, interleaved);
}

v1::LipBlinkRequest VoiceRequest(std::string audio) {
  v1::LipBlinkRequest request;
  request.set_audio(std::move(audio));
  return request;
}

std::vector<std::pair<int, int>> Speech(const v1::LipBlinkResponse& r) {
  std::vector<std::pair<int, int>> out;
  for (const v1::FrameInterval& i : r.voice().speech()) out.emplace_back(i.begin(), i.end());
  return out;
}

class LipBlinkVoiceTest : public ::testing::Test {
 protected:
  InProcessServer server_;
  v1::LipBlinkResponse Call(const v1::LipBlinkRequest& request) {
    v1::LipBlinkResponse response;
    const grpc::Status status = CallRpc(server_.stub(), request, &response);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return response;
  }
};

TEST_F(LipBlinkVoiceTest, AudioAloneGivesATalkingMotion) {
  const v1::LipBlinkResponse r = Call(VoiceRequest(Recording()));
  EXPECT_EQ(Speech(r), (std::vector<std::pair<int, int>>{{12, 24}, {36, 54}}));
  EXPECT_EQ(r.voice().sample_rate(), 16000);
  EXPECT_EQ(r.voice().channels(), 1);
  EXPECT_DOUBLE_EQ(r.voice().duration_s(), 2.5);
  EXPECT_EQ(r.voice().loudness_dbfs_size(), 60);
  EXPECT_EQ(r.timing_fps(), 24);
  ASSERT_EQ(r.mouths_size(), 1);
  const v1::MouthTrack& mouth = r.mouths(0);
  EXPECT_EQ(mouth.id(), "ParamMouthOpenY");
  EXPECT_EQ(mouth.closed_level(), 0);
  EXPECT_EQ(mouth.open_level(), 1);
  v1::MouthShape previous = v1::MOUTH_CLOSED;
  int previous_end = -1;
  for (const v1::MouthHold& h : mouth.holds()) {
    EXPECT_GE(h.length(), 1);
    EXPECT_LE(h.length(), 3);
    if (h.begin() == previous_end) {
      EXPECT_NE(h.shape(), previous) << "the same drawing twice at grid frame " << h.begin();
    }
    previous = h.shape();
    previous_end = h.begin() + h.length();
  }
  // The motion: 2.5 s at 30 fps = frames 0..75; the mouth is closed outside speech, so never
  // moves in the silences (all of them 250 ms or more).
  ASSERT_TRUE(r.has_motion3_json());
  const nlohmann::json doc = nlohmann::json::parse(r.motion3_json());
  EXPECT_EQ(doc["Meta"]["Fps"], 30);
  EXPECT_EQ(doc["Meta"]["Duration"], 2.5);
  EXPECT_EQ(doc["Meta"]["CurveCount"], 1);
  ASSERT_EQ(r.curves_size(), 1);
  const auto& values = r.curves(0).values();
  ASSERT_EQ(values.size(), 76);
  for (int k = 0; k < 76; ++k) {
    const double t = k / 30.0;
    const bool silent = t < 0.5 - 1.0 / 24 || (t >= 1.0 + 1.0 / 24 && t < 1.5 - 1.0 / 24) ||
                        t >= 2.25 + 1.0 / 24;
    if (silent) {
      EXPECT_EQ(values[k], 0.0) << "frame " << k;
    }
  }
  // Cues: JSON and TSV of the same holds.
  absl::StatusOr<std::vector<MouthCue>> json = formats::ParseRhubarbCues(r.rhubarb_json());
  absl::StatusOr<std::vector<MouthCue>> tsv = formats::ParseRhubarbCues(r.rhubarb_tsv());
  ASSERT_TRUE(json.ok() && tsv.ok());
  EXPECT_EQ(json->size() + 1, tsv->size());  // the TSV's closing X line
  EXPECT_EQ(json->front().shape, 'X');
  EXPECT_EQ(json->front().end_s, 0.5);
  EXPECT_EQ(json->back().end_s, 2.5);
}

TEST_F(LipBlinkVoiceTest, AHeldToneIsMusicNotSpeech) {
  // The same parts as Recording() with a 220 Hz tone: loud, but a held note, not a voice
  // (before issue 44 it was found as speech at [12, 24) and [36, 54)); the mouth stays closed.
  WavHeader h;
  const v1::LipBlinkResponse r = Call(VoiceRequest(WavBytes(
      h, ToneAndSilence(16000, {{0.5, 0.0}, {0.5, 0.5}, {0.5, 0.0}, {0.75, 0.5}, {0.25, 0.0}}))));
  EXPECT_TRUE(Speech(r).empty());
  for (const v1::MouthHold& hold : r.mouths(0).holds()) {
    EXPECT_EQ(hold.shape(), v1::MOUTH_CLOSED) << hold.begin();
  }
  // any_sound: loudness alone, as before issue 44 (a singer): the tone is speech again.
  v1::LipBlinkRequest any_sound = VoiceRequest(WavBytes(
      h, ToneAndSilence(16000, {{0.5, 0.0}, {0.5, 0.5}, {0.5, 0.0}, {0.75, 0.5}, {0.25, 0.0}})));
  any_sound.mutable_voice_settings()->set_any_sound(true);
  EXPECT_EQ(Speech(Call(any_sound)), (std::vector<std::pair<int, int>>{{12, 24}, {36, 54}}));
  any_sound.mutable_voice_settings()->set_any_sound(false);  // said, as unset
  EXPECT_TRUE(Speech(Call(any_sound)).empty());
}

TEST_F(LipBlinkVoiceTest, SameRequestSameBytes) {
  v1::LipBlinkRequest request = VoiceRequest(Recording(WavHeader{}, 0.01));
  request.mutable_eyes()->mutable_auto_blink()->set_enabled(true);
  const std::string a = Call(request).SerializeAsString();
  const std::string b = Call(request).SerializeAsString();
  EXPECT_EQ(a, b);
}

TEST_F(LipBlinkVoiceTest, EveryEncodingGivesTheSameSpeech) {
  const std::vector<std::pair<int, int>> want = {{12, 24}, {36, 54}};
  for (int rate : {8000, 16000, 22050, 44100, 48000}) {
    for (int channels : {1, 2}) {
      for (const auto& [bits, is_float] :
           std::vector<std::pair<int, bool>>{{16, false}, {24, false}, {32, true}}) {
        WavHeader h;
        h.sample_rate = rate;
        h.channels = channels;
        h.bits = bits;
        h.float_samples = is_float;
        const v1::LipBlinkResponse r = Call(VoiceRequest(Recording(h, 0.005)));
        EXPECT_EQ(Speech(r), want) << rate << " Hz, " << channels << " ch, " << bits << " bits";
      }
    }
  }
}

TEST_F(LipBlinkVoiceTest, AutoBlinkAddsBlinkingEyes) {
  v1::LipBlinkRequest request = VoiceRequest(Recording());
  request.mutable_eyes()->mutable_auto_blink()->set_enabled(true);
  request.mutable_eyes()->mutable_auto_blink()->set_mean_interval_s(0.8);
  const v1::LipBlinkResponse r = Call(request);
  ASSERT_EQ(r.eyes_size(), 2);
  EXPECT_GT(r.eyes(0).blinks_size(), 0);
  EXPECT_TRUE(r.eyes(0).blinks(0).automatic());
  const nlohmann::json doc = nlohmann::json::parse(r.motion3_json());
  EXPECT_EQ(doc["Meta"]["CurveCount"], 3);
}

TEST_F(LipBlinkVoiceTest, MergesIntoASentMotionKeepingEveryOtherCurve) {
  // A body motion without a mouth: 3 s at 30 fps, one curve.
  const std::string body =
      R"({"Version": 3, "Meta": {"Duration": 3, "Fps": 30, "Loop": true, "AreBeziersRestricted": true, "CurveCount": 1, "TotalSegmentCount": 1, "TotalPointCount": 2, "UserDataCount": 0, "TotalUserDataSize": 0}, "Curves": [{"Target": "Parameter", "Id": "ParamAngleX", "Segments": [0, 0, 0, 3, 30]}]})";
  v1::LipBlinkRequest request = VoiceRequest(Recording());
  request.set_motion3_json(body);
  const v1::LipBlinkResponse r = Call(request);
  const nlohmann::json doc = nlohmann::json::parse(r.motion3_json());
  ASSERT_EQ(doc["Curves"].size(), 2u);
  EXPECT_EQ(doc["Curves"][0], nlohmann::json::parse(body)["Curves"][0]);  // untouched
  EXPECT_EQ(doc["Curves"][1]["Id"], "ParamMouthOpenY");
  EXPECT_EQ(doc["Meta"]["Loop"], true);
  EXPECT_EQ(doc["Meta"]["CurveCount"], 2);
  EXPECT_EQ(Speech(r), (std::vector<std::pair<int, int>>{{12, 24}, {36, 54}}));
  // A sent motion shorter than the recording cuts it: 1.2 s holds the first word only.
  request.set_motion3_json(R"({"Version": 3, "Meta": {"Duration": 1.2, "Fps": 30}, "Curves": [{"Target": "Parameter", "Id": "ParamMouthOpenY", "Segments": [0, 0.3, 0, 1.2, 0.3]}]})");
  const v1::LipBlinkResponse cut = Call(request);
  EXPECT_EQ(Speech(cut), (std::vector<std::pair<int, int>>{{12, 24}}));
  // The sent mouth curve is replaced (closed, 0) outside speech, not kept at 0.3.
  EXPECT_EQ(cut.curves(0).values(0), 0.0);
}

TEST_F(LipBlinkVoiceTest, FollowOpensOnLoudAndHalfOpensOnQuiet) {
  // Loud 0.5 s, then 0.5 s 10 dB quieter (between 6 and 15 dB below the loud level: mid).
  WavHeader h;
  const std::vector<double> x =
      VoiceLikeAndSilence(16000, {{0.5, 0.0}, {0.5, 0.6}, {0.5, 0.19}, {0.5, 0.0}});
  v1::LipBlinkRequest request = VoiceRequest(WavBytes(h, x));
  request.mutable_mouth()->set_mode(v1::MOUTH_FOLLOW);
  const v1::LipBlinkResponse r = Call(request);
  EXPECT_EQ(Speech(r), (std::vector<std::pair<int, int>>{{12, 36}}));
  for (const v1::MouthHold& hold : r.mouths(0).holds()) {
    if (hold.begin() < 24) {
      // Open asked throughout: open, then (never twice) mid, open, mid ...
      EXPECT_NE(hold.shape(), v1::MOUTH_CLOSED) << hold.begin();
    } else if (hold.begin() >= 25) {
      // Mid asked: mid and, between, the nearer of closed / open: closed (ties go closed).
      EXPECT_NE(hold.shape(), v1::MOUTH_OPEN) << hold.begin();
    }
  }
}

TEST_F(LipBlinkVoiceTest, RhubarbCuesDriveTheMouth) {
  v1::LipBlinkRequest request;
  request.set_rhubarb_cues("0.00\tX\n0.50\tD\n0.75\tB\n1.00\tX\n2.00\tX\n");
  const v1::LipBlinkResponse r = Call(request);
  EXPECT_EQ(Speech(r), (std::vector<std::pair<int, int>>{{12, 24}}));
  ASSERT_EQ(r.mouths(0).holds_size(), 4);  // frames 12-14 open, 15-17 mid, 18-20 closed...
  EXPECT_EQ(r.mouths(0).holds(0).shape(), v1::MOUTH_OPEN);  // D, followed
  EXPECT_EQ(r.mouths(0).holds(2).shape(), v1::MOUTH_CLOSED);  // B
  EXPECT_EQ(r.voice().sample_rate(), 0);
  EXPECT_DOUBLE_EQ(r.voice().duration_s(), 2.0);
}

TEST_F(LipBlinkVoiceTest, CsvOutputOnRequest) {
  v1::LipBlinkRequest request = VoiceRequest(Recording());
  request.set_voice_output(v1::VOICE_OUTPUT_CSV);
  request.set_voice_motion_fps(24);
  const v1::LipBlinkResponse r = Call(request);
  ASSERT_TRUE(r.has_csv_text());
  EXPECT_EQ(r.csv_text().substr(0, 22), "frame,ParamMouthOpenY\n");
  EXPECT_EQ(r.timing_fps(), 0);  // 24 fps motion on the 24 fps grid: source frames
  EXPECT_EQ(Speech(r), (std::vector<std::pair<int, int>>{{12, 24}, {36, 54}}));
}

using BadVoice = ::koma::testing::BadRequest<v1::LipBlinkRequest>;

std::vector<BadVoice> BadVoices() {
  using C = grpc::StatusCode;
  const C kInvalid = C::INVALID_ARGUMENT;
  return {
      {"EmptyAudio", [](auto& r) { r.set_audio(""); }, kInvalid, "audio: empty"},
      {"TextAudio", [](auto& r) { r.set_audio("this is not a recording\n"); }, kInvalid,
       "audio: not a recording libsndfile can read"},
      {"TruncatedHeader", [](auto& r) { r.set_audio(r.audio().substr(0, 20)); }, kInvalid,
       "audio: not a recording"},
      {"ZeroHz",
       [](auto& r) {
         WavHeader h;
         h.sample_rate = 0;
         r.set_audio(WavBytes(h, {0.1, 0.2}));
       },
       kInvalid, "audio:"},
      {"ZeroChannels",
       [](auto& r) {
         WavHeader h;
         h.channels = 0;
         r.set_audio(WavBytes(h, {}));
       },
       kInvalid, "audio:"},
      {"ThreeHundredChannels",
       [](auto& r) {
         WavHeader h;
         h.channels = 300;
         r.set_audio(WavBytes(h, std::vector<double>(3000, 0.1)));
       },
       C::RESOURCE_EXHAUSTED, "audio: 300 channels exceeds the server limit --max_audio_channels=64"},
      {"LongerThanTheLimit",
       [](auto& r) {
         WavHeader h;
         h.sample_rate = 8000;
         r.set_audio(WavBytes(h, std::vector<double>(8000 * 11, 0.1)));
       },
       C::RESOURCE_EXHAUSTED, "--max_audio_seconds=10"},
      {"OverMaxFileBytes", [](auto& r) { r.set_audio(std::string(300'000, 'R')); },
       C::RESOURCE_EXHAUSTED, "audio: 300000 bytes exceeds the server limit --max_file_bytes=200000"},
      {"SpeechWithAudio",
       [](auto& r) {
         v1::FrameInterval* i = r.mutable_mouth()->add_speech();
         i->set_begin(0);
         i->set_end(5);
       },
       kInvalid, "mouth.speech: 1 intervals given with a voice"},
      {"BadStay", [](auto& r) { r.mutable_voice_settings()->set_stay_above_floor_db(20); },
       kInvalid, "voice_settings.stay_above_floor_db: 20 must be in (0, start_above_floor_db = 9]"},
      {"BadPercentile", [](auto& r) { r.mutable_voice_settings()->set_noise_percentile(0); },
       kInvalid, "voice_settings.noise_percentile: 0"},
      {"BadMotionFps", [](auto& r) { r.set_voice_motion_fps(-3); }, kInvalid,
       "voice_motion_fps: -3"},
      {"BadOutput", [](auto& r) { r.set_voice_output(static_cast<v1::LipBlinkVoiceOutput>(7)); },
       kInvalid, "voice_output: 7"},
      {"BadCues", [](auto& r) { r.set_rhubarb_cues("0.0\tX\n0.5\tQ\n"); }, kInvalid,
       "rhubarb_cues: line 2: \"Q\" is not one of A-H, X"},
      {"CuesOverlap",
       [](auto& r) {
         r.set_rhubarb_cues(R"({"mouthCues": [{"start": 0, "end": 1, "value": "A"},
                                               {"start": 0.5, "end": 2, "value": "D"}]})");
       },
       kInvalid, "rhubarb_cues: mouthCues[1]: starts at 0.5"},
      {"CuesTooLong", [](auto& r) { r.set_rhubarb_cues("0\tX\n0.5\tD\n11\tX\n"); },
       C::RESOURCE_EXHAUSTED, "rhubarb_cues: 11 s of cues, over the server limit --max_audio_seconds=10"},
      {"NaNSamples",
       [](auto& r) {
         WavHeader h;
         h.float_samples = true;
         h.bits = 32;
         r.set_audio(WavBytes(h, {0.1, std::numeric_limits<double>::quiet_NaN(), 0.1}));
       },
       kInvalid, "audio: sample frame 1 is not a finite number"},
      {"BadHysteresis", [](auto& r) { r.mutable_voice_settings()->set_hysteresis_db(-1); },
       kInvalid, "voice_settings.hysteresis_db: -1"},
      {"BadMinSpeech", [](auto& r) { r.mutable_voice_settings()->set_min_speech_dbfs(3); },
       kInvalid, "voice_settings.min_speech_dbfs: 3"},
      {"BadBridge", [](auto& r) { r.mutable_voice_settings()->set_bridge_gap_frames(-1); },
       kInvalid, "voice_settings.bridge_gap_frames: -1 must be >= 0"},
      {"BadPauseLevel",
       [](auto& r) { r.mutable_voice_settings()->set_pause_above_floor_db(-1); }, kInvalid,
       "voice_settings.pause_above_floor_db: -1 must be in [0, 200] dB"},
      {"BadFloor", [](auto& r) { r.mutable_voice_settings()->set_noise_floor_dbfs(1); },
       kInvalid, "voice_settings.noise_floor_dbfs: 1"},
      {"BadMotionWithAudio", [](auto& r) { r.set_motion3_json("{"); }, kInvalid,
       "motion3_json:"},
  };
}

class LipBlinkVoiceBadRequestTest
    : public koma::testing::BadRequestSuite<LipBlinkVoiceBadRequestTest, v1::LipBlinkRequest> {
 public:
  static server::ServerConfig SuiteConfig() {
    server::ServerConfig config = InProcessServer::Config(1, 50'000);
    config.limits.max_file_bytes = 200'000;
    config.limits.max_audio_seconds = 10;
    return config;
  }
  static v1::LipBlinkRequest ValidRequest() {
    WavHeader h;
    h.sample_rate = 8000;
    return VoiceRequest(WavBytes(h, ToneAndSilence(8000, {{0.5, 0.0}, {0.5, 0.5}})));
  }
};

KOMA_BAD_REQUEST_TABLE(LipBlinkVoiceBadRequestTest, LipBlinkVoiceBadRequestTableTest, BadVoices)

}  // namespace
}  // namespace koma::server
