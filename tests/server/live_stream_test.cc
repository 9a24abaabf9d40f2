// LiveLipBlink through the real service (in-process channel): a whole stream of a known voice
// (samples/voice.flac) gives frames 0..N-1 in order, byte for byte the same however the audio
// is cut, in S16 or F32, stereo with equal channels or mono, and the same as core's LiveVoice
// fed directly; setup and audio errors name the field or the message; every limit
// (--live_max_message_bytes, --live_max_seconds, --live_max_streams, --live_idle_seconds,
// --live_max_queued_frames) and a shutdown end a stream with their status, after the frames
// they promise; many streams at once, cut differently, agree (run under TSan too).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/time/time.h"
#include "core/live_voice.h"
#include "formats/audio_reader.h"
#include "koma/v1/retime.grpc.pb.h"
#include "server/live_lip_blink.h"
#include "tests/server/in_process_server.h"

namespace koma::server {
namespace {

using ::koma::testing::InProcessServer;
using ::koma::testing::SetTestDeadline;
using ::testing::HasSubstr;
using Clock = std::chrono::steady_clock;
using Request = v1::LiveLipBlinkRequest;
using Frame = v1::LiveLipBlinkFrame;

double SecondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// samples/voice.flac: 3.82 s of 16 kHz 16-bit speech, mono.
const std::vector<float>& Voice() {
  static const std::vector<float>* voice = [] {
    std::ifstream in(KOMA_SAMPLES_DIR "/voice.flac", std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)),
                            std::istreambuf_iterator<char>());
    auto decoder = formats::AudioDecoder::Open(bytes, formats::AudioLimits{});
    auto* out = new std::vector<float>;
    if (!decoder.ok()) return out;
    EXPECT_EQ((*decoder)->info().sample_rate, 16000);
    for (;;) {
      auto block = (*decoder)->Next();
      if (!block.ok() || block->empty()) break;
      out->insert(out->end(), block->begin(), block->end());
    }
    return out;
  }();
  return *voice;
}
constexpr int kRate = 16000;

v1::LiveLipBlinkSetup LiveSetup(int channels = 1, v1::LiveSampleFormat format = v1::LIVE_SAMPLE_S16LE) {
  v1::LiveLipBlinkSetup s;
  s.set_sample_rate(kRate);
  s.set_channels(channels);
  s.set_sample_format(format);
  s.set_lookahead_frames(2);
  s.set_seed(7);
  s.mutable_eyes()->mutable_auto_blink()->set_enabled(true);
  return s;
}

// The samples as interleaved bytes, each sample repeated on every channel. voice.flac is 16-bit,
// so its samples are exact in S16 and the two formats carry the same values.
std::string Bytes(absl::Span<const float> mono, int channels, v1::LiveSampleFormat format) {
  std::string out;
  for (float x : mono) {
    for (int c = 0; c < channels; ++c) {
      if (format == v1::LIVE_SAMPLE_S16LE) {
        const auto v = static_cast<int16_t>(std::lround(static_cast<double>(x) * 32768.0));
        out.append(reinterpret_cast<const char*>(&v), 2);
      } else {
        out.append(reinterpret_cast<const char*>(&x), 4);
      }
    }
  }
  return out;
}

Request SetupMessage(const v1::LiveLipBlinkSetup& setup) {
  Request r;
  *r.mutable_setup() = setup;
  return r;
}
Request Audio(std::string bytes) {
  Request r;
  r.set_audio(std::move(bytes));
  return r;
}

// The setup, then `bytes` in messages of `message_bytes`.
std::vector<Request> Messages(const v1::LiveLipBlinkSetup& setup, const std::string& bytes,
                              size_t message_bytes) {
  std::vector<Request> out = {SetupMessage(setup)};
  for (size_t at = 0; at < bytes.size(); at += message_bytes) {
    out.push_back(Audio(bytes.substr(at, message_bytes)));
  }
  return out;
}

struct StreamResult {
  grpc::Status status;
  std::vector<Frame> frames;
  double seconds = 0;
};

// One stream: a writer thread sends `messages` (then half-closes unless `half_close` is false,
// when it just stops), this thread reads every frame.
StreamResult RunStream(v1::Retime::Stub& stub, const std::vector<Request>& messages,
                       bool half_close = true) {
  grpc::ClientContext context;
  SetTestDeadline(context, 60);
  const Clock::time_point start = Clock::now();
  auto stream = stub.LiveLipBlink(&context);
  std::thread writer([&] {
    for (const Request& m : messages) {
      if (!stream->Write(m)) break;
    }
    if (half_close) stream->WritesDone();
  });
  StreamResult result;
  Frame f;
  while (stream->Read(&f)) result.frames.push_back(f);
  if (!half_close) context.TryCancel();
  writer.join();
  result.status = stream->Finish();
  result.seconds = SecondsSince(start);
  return result;
}

// core's LiveVoice fed `mono` directly, its frames as the server writes them.
std::vector<Frame> Reference(const v1::LiveLipBlinkSetup& setup, absl::Span<const float> mono) {
  absl::StatusOr<LiveVoiceOptions> options = LiveOptionsFromSetup(setup, RequestLimits{});
  EXPECT_TRUE(options.ok()) << options.status();
  LiveVoice live(*options);
  live.Add(mono);
  live.Finish();
  std::vector<Frame> out;
  LiveFrame f;
  while (live.Pop(&f)) LiveFrameToProto(f, setup.sample_rate(), &out.emplace_back());
  return out;
}

// Byte-identical messages; the first difference is reported.
void ExpectSameFrames(const std::vector<Frame>& got, const std::vector<Frame>& want,
                      const std::string& what) {
  EXPECT_EQ(got.size(), want.size()) << what;
  for (size_t i = 0; i < std::min(got.size(), want.size()); ++i) {
    if (got[i].SerializeAsString() != want[i].SerializeAsString()) {
      ADD_FAILURE() << what << ": frame " << i << " differs:\n"
                    << got[i].DebugString() << "want\n"
                    << want[i].DebugString();
      return;
    }
  }
}

void ExpectInOrder(const std::vector<Frame>& frames) {
  for (size_t i = 0; i < frames.size(); ++i) {
    ASSERT_EQ(frames[i].grid_frame(), static_cast<int64_t>(i));
  }
}

server::ServerConfig Config() {
  server::ServerConfig config;
  config.worker_threads = 2;
  return config;
}

class LiveStreamTest : public ::testing::Test {
 protected:
  v1::Retime::Stub& stub() { return server_->stub(); }
  void Restart(const server::ServerConfig& config) {
    server_.reset();
    server_ = std::make_unique<InProcessServer>(config);
  }
  int InFlight() { return server_->server().live_streams_in_flight(); }
  // Waits up to `seconds` for the server's stream count to reach `n`.
  bool WaitInFlight(int n, double seconds = 2.0) {
    const Clock::time_point start = Clock::now();
    while (InFlight() != n) {
      if (SecondsSince(start) > seconds) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return true;
  }
  std::unique_ptr<InProcessServer> server_ = std::make_unique<InProcessServer>(Config());
};

TEST_F(LiveStreamTest, AWholeVoiceGivesEveryGridFrameInOrderAsLiveVoiceDoes) {
  const std::vector<float>& voice = Voice();
  ASSERT_EQ(voice.size(), 61191u);
  const std::vector<Frame> want = Reference(LiveSetup(), voice);
  // 61,191 samples at 16 kHz on the 24 fps grid: 91.8 frames, the last partial.
  ASSERT_EQ(want.size(), 92u);
  int speech = 0;
  for (const Frame& f : want) speech += f.speech();
  EXPECT_GT(speech, 20);  // a voice: its speech is found
  EXPECT_LT(speech, 92);

  const StreamResult r =
      RunStream(stub(), Messages(LiveSetup(), Bytes(voice, 1, v1::LIVE_SAMPLE_S16LE), 320));
  ASSERT_TRUE(r.status.ok()) << r.status.error_message();
  ExpectInOrder(r.frames);
  ExpectSameFrames(r.frames, want, "10 ms messages");
  EXPECT_DOUBLE_EQ(r.frames[5].time_s(), 5 / 24.0);
  // The lookahead, 2 grid frames, in whole samples past the frame's end.
  EXPECT_NEAR(r.frames[5].late_ms(), 2000.0 / 24.0, 1000.0 / kRate);
  EXPECT_LT(r.frames.back().late_ms(), 2000.0 / 24.0);     // the end: what there was
  EXPECT_TRUE(WaitInFlight(0));
}

TEST_F(LiveStreamTest, TheSameFramesHoweverTheAudioIsCutEncodedOrMixed) {
  const std::vector<float>& voice = Voice();
  const std::vector<Frame> want = Reference(LiveSetup(), voice);
  struct Case {
    int channels;
    v1::LiveSampleFormat format;
    size_t samples_per_message;
  };
  const Case cases[] = {
      {1, v1::LIVE_SAMPLE_S16LE, 1},     {1, v1::LIVE_SAMPLE_S16LE, 160},
      {1, v1::LIVE_SAMPLE_S16LE, 16000}, {1, v1::LIVE_SAMPLE_S16LE, 1 << 20},
      {1, v1::LIVE_SAMPLE_F32LE, 160},   {1, v1::LIVE_SAMPLE_F32LE, 16000},
      {2, v1::LIVE_SAMPLE_S16LE, 160},   {2, v1::LIVE_SAMPLE_F32LE, 16000},
      {2, v1::LIVE_SAMPLE_F32LE, 1},     {8, v1::LIVE_SAMPLE_F32LE, 441},
  };
  for (const Case& c : cases) {
    const int sample_bytes = c.format == v1::LIVE_SAMPLE_S16LE ? 2 : 4;
    const std::string bytes = Bytes(voice, c.channels, c.format);
    const size_t message_bytes =
        std::min(bytes.size(), c.samples_per_message * c.channels * sample_bytes);
    const StreamResult r =
        RunStream(stub(), Messages(LiveSetup(c.channels, c.format), bytes, message_bytes));
    const std::string what = absl::StrCat(c.channels, " channels, format ", c.format, ", ",
                                          c.samples_per_message, " samples a message");
    ASSERT_TRUE(r.status.ok()) << what << ": " << r.status.error_message();
    ExpectSameFrames(r.frames, want, what);
  }
}

TEST_F(LiveStreamTest, IrregularAndEmptyMessagesGiveTheSameFrames) {
  const std::vector<float>& voice = Voice();
  const std::string bytes = Bytes(voice, 1, v1::LIVE_SAMPLE_S16LE);
  std::vector<Request> messages = {SetupMessage(LiveSetup())};
  const size_t sizes[] = {0, 2, 998, 6, 4000, 0, 17 * 2, 32000};
  size_t at = 0;
  for (int i = 0; at < bytes.size(); ++i) {
    const size_t n = std::min(bytes.size() - at, sizes[i % 8]);
    messages.push_back(Audio(bytes.substr(at, n)));
    at += n;
  }
  const StreamResult r = RunStream(stub(), messages);
  ASSERT_TRUE(r.status.ok()) << r.status.error_message();
  ExpectSameFrames(r.frames, Reference(LiveSetup(), voice), "irregular messages");
}

// --live_max_queued_frames counts the frames a client left unread, not those one message
// decides at once: 3.8 s in one message is 92 frames, more than 10, for a client that reads.
TEST_F(LiveStreamTest, OneMessageMayDecideMoreFramesThanMayWait) {
  server::ServerConfig config = Config();
  config.limits.live_max_queued_frames = 30;  // a message may hold 4 x 30 = 120 frames
  Restart(config);
  const std::vector<float>& voice = Voice();  // 92 grid frames
  const std::string bytes = Bytes(voice, 1, v1::LIVE_SAMPLE_S16LE);
  const StreamResult r = RunStream(stub(), Messages(LiveSetup(), bytes, bytes.size()));
  ASSERT_TRUE(r.status.ok()) << r.status.error_message();
  ExpectSameFrames(r.frames, Reference(LiveSetup(), voice), "one message");
}

TEST_F(LiveStreamTest, AMessageOfMoreThanFourQueuesOfFramesIsRefused) {
  server::ServerConfig config = Config();
  config.limits.live_max_queued_frames = 10;  // at most 40 frames of audio a message
  Restart(config);
  const std::string bytes = Bytes(Voice(), 1, v1::LIVE_SAMPLE_S16LE);
  const StreamResult r = RunStream(stub(), Messages(LiveSetup(), bytes, bytes.size()));
  EXPECT_EQ(r.status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(r.status.error_message(),
              ::testing::HasSubstr("audio (message 1): " + std::to_string(bytes.size()) +
                                   " bytes hold 91 grid frames of audio, over 40 (4 x "
                                   "--live_max_queued_frames); send smaller pieces"));
  EXPECT_TRUE(r.frames.empty());
}

TEST_F(LiveStreamTest, NoAudioGivesNoFramesAndOk) {
  const StreamResult r = RunStream(stub(), {SetupMessage(LiveSetup())});
  EXPECT_TRUE(r.status.ok()) << r.status.error_message();
  EXPECT_TRUE(r.frames.empty());
}

struct BadSetup {
  std::string name;
  std::function<void(v1::LiveLipBlinkSetup&)> change;
  std::string message;
};

TEST_F(LiveStreamTest, BadSetupsAreRefusedNamingTheField) {
  server::ServerConfig config = Config();
  config.limits.max_audio_channels = 8;
  Restart(config);
  const std::vector<BadSetup> cases = {
      {"rate 0", [](auto& s) { s.set_sample_rate(0); },
       "setup.sample_rate: 0 must be in [1000, 384000] samples per second"},
      {"rate 400000", [](auto& s) { s.set_sample_rate(400000); },
       "setup.sample_rate: 400000 must be in [1000, 384000]"},
      {"channels 0", [](auto& s) { s.set_channels(0); }, "setup.channels: 0 must be at least 1"},
      {"channels 9", [](auto& s) { s.set_channels(9); },
       "setup.channels: 9 exceeds the server limit --max_audio_channels=8"},
      {"format unset", [](auto& s) { s.clear_sample_format(); },
       "setup.sample_format: 0 is not a sample format"},
      {"lookahead 4", [](auto& s) { s.set_lookahead_frames(4); },
       "setup.lookahead_frames: 4 must be in [0, 3] grid frames"},
      {"lookahead -1", [](auto& s) { s.set_lookahead_frames(-1); }, "setup.lookahead_frames: -1"},
      {"mouth.ids", [](auto& s) { s.mutable_mouth()->add_ids("ParamMouthOpenY"); },
       "setup.mouth.ids: must be unset"},
      {"eyes.threshold", [](auto& s) { s.mutable_eyes()->set_threshold(0.5); },
       "setup.eyes.threshold: must be unset"},
      {"timing_fps 0", [](auto& s) { s.set_timing_fps(0); }, "setup.timing_fps: 0"},
      {"timing_fps NaN",
       [](auto& s) { s.set_timing_fps(std::numeric_limits<double>::quiet_NaN()); },
       "setup.timing_fps: nan"},
  };
  for (const BadSetup& c : cases) {
    v1::LiveLipBlinkSetup setup = LiveSetup();
    c.change(setup);
    const StreamResult r =
        RunStream(stub(), {SetupMessage(setup), Audio(std::string(640, '\0'))});
    EXPECT_EQ(r.status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << c.name;
    EXPECT_THAT(r.status.error_message(), HasSubstr(c.message)) << c.name;
    EXPECT_TRUE(r.frames.empty()) << c.name;
  }
  EXPECT_TRUE(WaitInFlight(0));
}

TEST_F(LiveStreamTest, MessagesOutOfOrderAreRefused) {
  const std::string second = std::string(3200, '\0');
  struct Case {
    std::string name;
    std::vector<Request> messages;
    std::string message;
    size_t frames;
  };
  const std::vector<Case> cases = {
      {"audio first", {Audio(second)}, "setup: the first message must be the setup", 0},
      {"nothing set first", {Request()}, "setup: the first message must be the setup", 0},
      {"closed before any message", {}, "setup: the stream ended before its first message", 0},
      {"a second setup",
       {SetupMessage(LiveSetup()), Audio(second), SetupMessage(LiveSetup())},
       "setup: message 2 is a second setup",
       0},
      {"neither setup nor audio",
       {SetupMessage(LiveSetup()), Audio(second), Request()},
       "message 2 has neither setup nor audio",
       0},
      {"an odd byte count for S16",
       {SetupMessage(LiveSetup()), Audio(second), Audio(std::string(1001, '\0'))},
       "audio (message 2): 1001 bytes is not a whole number of sample frames (1 channel x 2 "
       "bytes = 2 bytes each)",
       0},
  };
  for (const Case& c : cases) {
    const StreamResult r = RunStream(stub(), c.messages);
    EXPECT_EQ(r.status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << c.name;
    EXPECT_THAT(r.status.error_message(), HasSubstr(c.message)) << c.name;
  }
  // Stereo F32: 8 bytes a sample frame.
  const StreamResult r = RunStream(
      stub(), {SetupMessage(LiveSetup(2, v1::LIVE_SAMPLE_F32LE)), Audio(std::string(12, '\0'))});
  EXPECT_EQ(r.status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(r.status.error_message(),
              HasSubstr("audio (message 1): 12 bytes is not a whole number of sample frames "
                        "(2 channels x 4 bytes = 8 bytes each)"));
  EXPECT_TRUE(WaitInFlight(0));
}

TEST_F(LiveStreamTest, SamplesThatAreNotFiniteAreRefused) {
  for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                    -std::numeric_limits<float>::infinity()}) {
    std::vector<float> samples(800, 0.1f);
    samples[500] = bad;
    const StreamResult r =
        RunStream(stub(), {SetupMessage(LiveSetup(1, v1::LIVE_SAMPLE_F32LE)),
                           Audio(Bytes(std::vector<float>(1600, 0.1f), 1, v1::LIVE_SAMPLE_F32LE)),
                           Audio(Bytes(samples, 1, v1::LIVE_SAMPLE_F32LE))});
    EXPECT_EQ(r.status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << bad;
    EXPECT_THAT(r.status.error_message(),
                HasSubstr("audio (message 2): sample frame 500 is not a finite number"))
        << bad;
  }
}

TEST_F(LiveStreamTest, AMessageOverTheLimitIsRefusedNamingIt) {
  server::ServerConfig config = Config();
  config.limits.live_max_message_bytes = 1000;
  Restart(config);
  const StreamResult ok = RunStream(
      stub(), {SetupMessage(LiveSetup()), Audio(std::string(1000, '\0')), Audio(std::string(1000, '\0'))});
  EXPECT_TRUE(ok.status.ok()) << ok.status.error_message();
  const StreamResult r = RunStream(stub(), {SetupMessage(LiveSetup()), Audio(std::string(1000, '\0')),
                                            Audio(std::string(1002, '\0'))});
  EXPECT_EQ(r.status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(r.status.error_message(),
              HasSubstr("audio (message 2): 1002 bytes exceeds the server limit "
                        "--live_max_message_bytes=1000"));
}

TEST_F(LiveStreamTest, AudioPastTheLongestEndsAfterItsFrames) {
  server::ServerConfig config = Config();
  config.limits.live_max_seconds = 2.0;
  Restart(config);
  const std::vector<float>& voice = Voice();
  // 3.8 s in 10 ms messages: the stream ends at 2 s, with every frame of the first 2 s.
  const StreamResult r =
      RunStream(stub(), Messages(LiveSetup(), Bytes(voice, 1, v1::LIVE_SAMPLE_S16LE), 320));
  EXPECT_EQ(r.status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_THAT(r.status.error_message(),
              HasSubstr("audio: the stream reached 2 s of audio, the server limit "
                        "--live_max_seconds"));
  const std::vector<float> first(voice.begin(), voice.begin() + 2 * kRate);
  ExpectSameFrames(r.frames, Reference(LiveSetup(), first), "the first 2 s");
  EXPECT_EQ(r.frames.size(), 48u);
  EXPECT_TRUE(WaitInFlight(0));
}

// A stream that has sent its setup and some audio and read its first frame: the server has it.
struct OpenStream {
  grpc::ClientContext context;
  std::unique_ptr<grpc::ClientReaderWriter<Request, Frame>> stream;
  grpc::Status Open(v1::Retime::Stub& stub) {
    SetTestDeadline(context, 60);
    stream = stub.LiveLipBlink(&context);
    stream->Write(SetupMessage(LiveSetup()));
    stream->Write(Audio(Bytes(std::vector<float>(3200, 0.0f), 1, v1::LIVE_SAMPLE_S16LE)));
    Frame f;
    if (stream->Read(&f)) return grpc::Status::OK;
    return stream->Finish();
  }
  grpc::Status Close() {
    stream->WritesDone();
    Frame f;
    while (stream->Read(&f)) {
    }
    return stream->Finish();
  }
};

TEST_F(LiveStreamTest, MoreStreamsThanTheLimitAreRefusedAndASlotFreesWhenOneEnds) {
  server::ServerConfig config = Config();
  config.limits.live_max_streams = 3;
  Restart(config);
  OpenStream a, b, c, d;
  ASSERT_TRUE(a.Open(stub()).ok());
  ASSERT_TRUE(b.Open(stub()).ok());
  ASSERT_TRUE(c.Open(stub()).ok());
  EXPECT_EQ(InFlight(), 3);
  const grpc::Status refused = d.Open(stub());
  EXPECT_EQ(refused.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_THAT(refused.error_message(),
              HasSubstr("3 live streams are in flight, the server limit --live_max_streams"));
  EXPECT_TRUE(WaitInFlight(3));  // the refused one is gone
  EXPECT_TRUE(b.Close().ok());
  // The slot frees once the server is done with the stream: a new one is accepted within 1 s.
  const Clock::time_point start = Clock::now();
  grpc::Status status;
  for (int tries = 0; tries < 100 && SecondsSince(start) < 1.0; ++tries) {
    OpenStream e;
    status = e.Open(stub());
    if (status.ok()) {
      EXPECT_TRUE(e.Close().ok());
      break;
    }
    EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_TRUE(status.ok()) << status.error_message();
  EXPECT_TRUE(a.Close().ok());
  EXPECT_TRUE(c.Close().ok());
  EXPECT_TRUE(WaitInFlight(0));
}

TEST_F(LiveStreamTest, StreamsOpenedTogetherNeverPassTheLimit) {
  server::ServerConfig config = Config();
  config.limits.live_max_streams = 4;
  Restart(config);
  constexpr int kClients = 16;
  std::vector<OpenStream> streams(kClients);
  std::vector<grpc::Status> opened(kClients);
  std::vector<std::thread> clients;
  for (int i = 0; i < kClients; ++i) {
    clients.emplace_back([&, i] { opened[i] = streams[i].Open(stub()); });
  }
  for (std::thread& t : clients) t.join();
  int accepted = 0;
  for (const grpc::Status& s : opened) {
    if (s.ok()) {
      ++accepted;
    } else {
      EXPECT_EQ(s.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << s.error_message();
    }
  }
  EXPECT_EQ(accepted, 4);
  EXPECT_EQ(InFlight(), 4);
  for (int i = 0; i < kClients; ++i) {
    if (opened[i].ok()) {
      EXPECT_TRUE(streams[i].Close().ok());
    }
  }
  EXPECT_TRUE(WaitInFlight(0));
}

TEST_F(LiveStreamTest, ZeroStreamsRefusesEvery) {
  server::ServerConfig config = Config();
  config.limits.live_max_streams = 0;
  Restart(config);
  const StreamResult r = RunStream(stub(), {SetupMessage(LiveSetup())});
  EXPECT_EQ(r.status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_TRUE(WaitInFlight(0));
}

TEST_F(LiveStreamTest, AStreamWithoutAMessageForTheIdleLimitEnds) {
  server::ServerConfig config = Config();
  config.limits.live_idle_seconds = 0.5;
  Restart(config);
  for (bool setup_sent : {false, true}) {
    grpc::ClientContext context;
    SetTestDeadline(context, 30);
    const Clock::time_point start = Clock::now();
    auto stream = stub().LiveLipBlink(&context);
    if (setup_sent) {
      stream->Write(SetupMessage(LiveSetup()));
      stream->Write(Audio(Bytes(std::vector<float>(8000, 0.0f), 1, v1::LIVE_SAMPLE_S16LE)));
    }
    Frame f;
    int frames = 0;
    while (stream->Read(&f)) ++frames;
    const grpc::Status status = stream->Finish();
    const double seconds = SecondsSince(start);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::DEADLINE_EXCEEDED) << setup_sent;
    EXPECT_THAT(status.error_message(),
                HasSubstr("no message for 0.5 s (the server limit --live_idle_seconds)"));
    EXPECT_GE(seconds, 0.5);
    EXPECT_LT(seconds, 2.0);  // one tick (0.25 s) after the limit, and margin
    if (setup_sent) {
      EXPECT_LE(frames, 10);  // 0.5 s: at most 12 frames, 2 of them undecided
    }
  }
  EXPECT_TRUE(WaitInFlight(0));
}

TEST_F(LiveStreamTest, AClientThatReadsNothingIsEndedAndItsSlotFrees) {
  server::ServerConfig config = Config();
  config.limits.live_max_queued_frames = 10;
  Restart(config);
  grpc::ClientContext context;
  SetTestDeadline(context, 30);
  auto stream = stub().LiveLipBlink(&context);
  const Clock::time_point start = Clock::now();
  stream->Write(SetupMessage(LiveSetup()));
  // 60 s of audio at most, 0.1 s a message, read by no one: Write blocks once the server stops
  // reading (it ended the stream); the writer gives up then.
  std::atomic<int> sent{0};
  std::thread writer([&] {
    const std::string tenth = Bytes(Voice(), 1, v1::LIVE_SAMPLE_S16LE).substr(0, 3200);
    for (int i = 0; i < 600 && stream->Write(Audio(tenth)); ++i) ++sent;
  });
  writer.join();
  const double writes_seconds = SecondsSince(start);
  Frame f;
  int frames = 0;
  while (stream->Read(&f)) ++frames;
  const grpc::Status status = stream->Finish();
  // Either the status arrives (RESOURCE_EXHAUSTED), or the server cancelled the call 5 s after
  // ending it.
  EXPECT_TRUE(status.error_code() == grpc::StatusCode::RESOURCE_EXHAUSTED ||
              status.error_code() == grpc::StatusCode::CANCELLED)
      << status.error_code() << " " << status.error_message();
  if (status.error_code() == grpc::StatusCode::RESOURCE_EXHAUSTED) {
    EXPECT_THAT(status.error_message(),
                HasSubstr("the client read none of the last 10 frames (the server limit "
                          "--live_max_queued_frames)"));
  }
  EXPECT_LT(sent.load(), 600);
  EXPECT_LT(writes_seconds, 10.0);
  EXPECT_LE(frames, 12);
  EXPECT_TRUE(WaitInFlight(0, 7.0));
  std::printf("reads nothing: %d messages sent in %.2f s, then %d frames and %s\n", sent.load(),
              writes_seconds, frames, status.error_message().c_str());
}

// A client that half-closes at once and then reads a frame every 70 ms: its 92 frames take
// 6.4 s to drain (in process, a write completes when the client reads it), longer than the 5 s
// without progress after which an ended stream is cancelled; it is not cut.
TEST_F(LiveStreamTest, ASlowReaderIsNotCutWhileItsLastFramesDrain) {
  const std::vector<float>& voice = Voice();
  grpc::ClientContext context;
  SetTestDeadline(context, 30);
  auto stream = stub().LiveLipBlink(&context);
  for (const Request& m : Messages(LiveSetup(), Bytes(voice, 1, v1::LIVE_SAMPLE_S16LE), 32000)) {
    ASSERT_TRUE(stream->Write(m));
  }
  stream->WritesDone();
  std::vector<Frame> frames;
  Frame f;
  while (stream->Read(&f)) {
    frames.push_back(f);
    std::this_thread::sleep_for(std::chrono::milliseconds(70));
  }
  const grpc::Status status = stream->Finish();
  EXPECT_TRUE(status.ok()) << status.error_code() << " " << status.error_message();
  ExpectSameFrames(frames, Reference(LiveSetup(), voice), "read slowly");
}

// Streams sending faster than real time when the server shuts down: each ends UNAVAILABLE
// after the frames decided so far (the first frames of the whole voice's), at once, not after
// the grace. Over a loopback port: the in-process transport closes under the client's reads
// at shutdown ("Transport closed"), TCP delivers what was sent.
TEST_F(LiveStreamTest, ShutdownEndsStreamsUnavailableAfterTheirFramesPromptly) {
  server::ServerConfig config = Config();
  config.address = "127.0.0.1:0";
  std::unique_ptr<server::KomaServer> server = server::KomaServer::Start(config).value();
  std::unique_ptr<v1::Retime::Stub> tcp = v1::Retime::NewStub(grpc::CreateChannel(
      absl::StrCat("127.0.0.1:", server->port()), grpc::InsecureChannelCredentials()));
  auto stub = [&]() -> v1::Retime::Stub& { return *tcp; };
  const std::vector<float>& voice = Voice();
  const std::string bytes = Bytes(voice, 1, v1::LIVE_SAMPLE_S16LE);
  const std::vector<Frame> want = Reference(LiveSetup(), voice);
  constexpr int kStreams = 6;
  std::vector<StreamResult> results(kStreams);
  std::vector<std::thread> clients;
  std::atomic<int> reading{0};
  for (int s = 0; s < kStreams; ++s) {
    clients.emplace_back([&, s] {
      grpc::ClientContext context;
      SetTestDeadline(context, 60);
      auto stream = stub().LiveLipBlink(&context);
      std::thread writer([&] {
        if (!stream->Write(SetupMessage(LiveSetup()))) return;
        // The voice over and over in 20 ms messages, 5 ms apart, for at most 20 s.
        const Clock::time_point start = Clock::now();
        for (size_t at = 0; SecondsSince(start) < 20; at = (at + 640) % (bytes.size() - 640)) {
          if (!stream->Write(Audio(bytes.substr(at, 640)))) break;
          std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        stream->WritesDone();
      });
      Frame f;
      while (stream->Read(&f)) {
        results[s].frames.push_back(f);
        if (results[s].frames.size() == 12) ++reading;
      }
      writer.join();
      results[s].status = stream->Finish();
    });
  }
  // Until every stream has 12 frames (0.5 s of audio; sanitizer builds are slower).
  const Clock::time_point wait = Clock::now();
  while (reading.load() < kStreams && SecondsSince(wait) < 20) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_EQ(reading.load(), kStreams);
  const Clock::time_point start = Clock::now();
  server->Shutdown(absl::Seconds(20));
  const double shutdown_seconds = SecondsSince(start);
  for (std::thread& t : clients) t.join();
  EXPECT_LT(shutdown_seconds, 2.0);
  for (int s = 0; s < kStreams; ++s) {
    EXPECT_EQ(results[s].status.error_code(), grpc::StatusCode::UNAVAILABLE) << s;
    EXPECT_THAT(results[s].status.error_message(), HasSubstr("the server is shutting down"));
    ASSERT_GT(results[s].frames.size(), 10u) << s;
    ExpectInOrder(results[s].frames);
    // The voice's first 3.8 s were sent first: those frames are the whole voice's.
    const size_t n = std::min<size_t>(results[s].frames.size(), 88);
    ExpectSameFrames(std::vector<Frame>(results[s].frames.begin(), results[s].frames.begin() + n),
                     std::vector<Frame>(want.begin(), want.begin() + n), "before the shutdown");
  }
  // New streams are refused now.
  const StreamResult late = RunStream(stub(), {SetupMessage(LiveSetup())});
  EXPECT_NE(late.status.error_code(), grpc::StatusCode::OK);
}

// The ticker (idle ends), the shutdown's EndAll and the reactions of busy streams end streams
// at the same moments, five times over: every stream ends with one of the two statuses, the
// shutdown is prompt, nothing crashes (the sanitizer builds run this too).
TEST_F(LiveStreamTest, ShutdownTickerAndReactionsRace) {
  const std::string bytes = Bytes(Voice(), 1, v1::LIVE_SAMPLE_S16LE);
  for (int round = 0; round < 5; ++round) {
    server::ServerConfig config = Config();
    config.address = "127.0.0.1:0";
    config.limits.live_idle_seconds = 0.3;
    std::unique_ptr<server::KomaServer> server = server::KomaServer::Start(config).value();
    std::unique_ptr<v1::Retime::Stub> tcp = v1::Retime::NewStub(grpc::CreateChannel(
        absl::StrCat("127.0.0.1:", server->port()), grpc::InsecureChannelCredentials()));
    constexpr int kStreams = 8;
    std::vector<grpc::Status> statuses(kStreams);
    std::vector<std::thread> clients;
    for (int s = 0; s < kStreams; ++s) {
      clients.emplace_back([&, s] {
        grpc::ClientContext context;
        SetTestDeadline(context, 30);
        auto stream = tcp->LiveLipBlink(&context);
        std::thread writer([&] {
          if (!stream->Write(SetupMessage(LiveSetup()))) return;
          // Odd streams go quiet at once (the ticker ends them); even ones send 2 ms messages.
          const Clock::time_point start = Clock::now();
          for (size_t at = 0; s % 2 == 0 && SecondsSince(start) < 10;
               at = (at + 64) % (bytes.size() - 64)) {
            if (!stream->Write(Audio(bytes.substr(at, 64)))) break;
          }
        });
        Frame f;
        while (stream->Read(&f)) {
        }
        writer.join();  // its Write fails once the stream has ended
        statuses[s] = stream->Finish();
      });
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(300 + 60 * round));  // idle ends: 0.3-0.55 s
    const Clock::time_point start = Clock::now();
    server->Shutdown(absl::Seconds(20));
    EXPECT_LT(SecondsSince(start), 2.0);
    for (std::thread& t : clients) t.join();
    for (const grpc::Status& status : statuses) {
      EXPECT_TRUE(status.error_code() == grpc::StatusCode::UNAVAILABLE ||
                  status.error_code() == grpc::StatusCode::DEADLINE_EXCEEDED)
          << status.error_code() << " " << status.error_message();
    }
  }
}

// Many streams at once, each cut differently, some cancelled by their clients midway: every
// finished one has the reference frames, and the count goes back to 0.
TEST_F(LiveStreamTest, ManyStreamsAtOnceAgreeAndCancelledOnesGo) {
  const std::vector<float>& voice = Voice();
  const std::string bytes = Bytes(voice, 1, v1::LIVE_SAMPLE_S16LE);
  const std::vector<Frame> want = Reference(LiveSetup(), voice);
  constexpr int kStreams = 24;
  std::vector<std::thread> clients;
  std::atomic<int> same{0}, cancelled{0};
  for (int s = 0; s < kStreams; ++s) {
    clients.emplace_back([&, s] {
      if (s % 4 == 3) {  // cancelled after a few frames
        grpc::ClientContext context;
        SetTestDeadline(context, 60);
        auto stream = stub().LiveLipBlink(&context);
        stream->Write(SetupMessage(LiveSetup()));
        stream->Write(Audio(bytes.substr(0, 32000)));
        Frame f;
        for (int i = 0; i < 3 && stream->Read(&f); ++i) {
        }
        context.TryCancel();
        while (stream->Read(&f)) {
        }
        if (stream->Finish().error_code() == grpc::StatusCode::CANCELLED) ++cancelled;
        return;
      }
      const StreamResult r =
          RunStream(stub(), Messages(LiveSetup(), bytes, static_cast<size_t>(2 * (37 + 191 * s))));
      bool ok = r.status.ok() && r.frames.size() == want.size();
      for (size_t i = 0; ok && i < want.size(); ++i) {
        ok = r.frames[i].SerializeAsString() == want[i].SerializeAsString();
      }
      if (ok) ++same;
    });
  }
  for (std::thread& t : clients) t.join();
  EXPECT_EQ(same.load(), kStreams - kStreams / 4);
  EXPECT_EQ(cancelled.load(), kStreams / 4);
  EXPECT_TRUE(WaitInFlight(0));
}

}  // namespace
}  // namespace koma::server
