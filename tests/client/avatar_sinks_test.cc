// koma live's avatar links without a network: the 0..1 values of each drawing, the VMC
// bundle's OSC bytes (decoded here by the OSC 1.0 layout, independently of liblo), the VTube
// Studio requests' JSON, the flags' parsing and the token file.
#include <sys/stat.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "client/avatar_levels.h"
#include "client/avatar_sink_flags.h"
#include "client/vmc_sink.h"
#include "client/vtube_studio_sink.h"
#include "client/vts_messages.h"
#include "client/websocket_client.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace koma::client {
namespace {

using ::testing::HasSubstr;

v1::LiveLipBlinkFrame FrameWith(double mouth_level, double eye_level) {
  v1::LiveLipBlinkFrame frame;
  frame.set_mouth_level(mouth_level);
  frame.set_eye_level(eye_level);
  return frame;
}

TEST(AvatarLevelsTest, DefaultsAreTheServers) {
  const AvatarLevels levels = AvatarLevelsOf(v1::LiveLipBlinkSetup());
  EXPECT_EQ(levels.mouth.min, 0.0);
  EXPECT_EQ(levels.mouth.max, 1.0);
  EXPECT_EQ(levels.eyes.min, 0.0);
  EXPECT_EQ(levels.eyes.max, 1.0);
  v1::LiveLipBlinkSetup setup;
  setup.mutable_mouth()->set_min(2.0);  // max unset: max(1, min + 1) = 3
  setup.mutable_eyes()->set_max(30.0);
  const AvatarLevels set = AvatarLevelsOf(setup);
  EXPECT_EQ(set.mouth.min, 2.0);
  EXPECT_EQ(set.mouth.max, 3.0);
  EXPECT_EQ(set.eyes.max, 30.0);
}

TEST(AvatarLevelsTest, ThreeDrawingsAreThreeSteps) {
  // Mouth levels 10 (closed), 12.5 (mid, mid_ratio 0.25), 20 (open); eyes 0, 0.5, 1.
  AvatarLevels levels;
  levels.mouth = {10.0, 20.0};
  EXPECT_EQ(MouthOpenness(FrameWith(10.0, 1.0), levels), 0.0);
  EXPECT_EQ(MouthOpenness(FrameWith(12.5, 1.0), levels), 0.25);
  EXPECT_EQ(MouthOpenness(FrameWith(20.0, 1.0), levels), 1.0);
  EXPECT_EQ(EyeOpenness(FrameWith(10.0, 0.5), levels), 0.5);
  // Outside the range: clamped. No range: 0.
  EXPECT_EQ(Normalised(-1.0, {0.0, 1.0}), 0.0);
  EXPECT_EQ(Normalised(7.0, {0.0, 1.0}), 1.0);
  EXPECT_EQ(Normalised(1.0, {1.0, 1.0}), 0.0);
}

TEST(VmcTest, BlendsAreMouthThenOneMinusEyes) {
  VmcOptions options;
  const AvatarLevels levels;
  const std::vector<VmcBlend> blends = VmcBlendsOf(FrameWith(0.5, 0.0), levels, options);
  ASSERT_EQ(blends.size(), 2u);
  EXPECT_EQ(blends[0].clip, "A");
  EXPECT_EQ(blends[0].value, 0.5f);
  EXPECT_EQ(blends[1].clip, "Blink");
  EXPECT_EQ(blends[1].value, 1.0f);  // eyes shut: the blink clip full
  options.mouth_clip = "aa";
  options.blink_clip = "blink";
  const std::vector<VmcBlend> vrm1 = VmcBlendsOf(FrameWith(1.0, 1.0), levels, options);
  EXPECT_EQ(vrm1[0].clip, "aa");
  EXPECT_EQ(vrm1[0].value, 1.0f);
  EXPECT_EQ(vrm1[1].clip, "blink");
  EXPECT_EQ(vrm1[1].value, 0.0f);
}

// A reader of OSC 1.0 bytes: strings NUL-terminated and padded to 4 bytes, big-endian int32
// and float32.
class OscReader {
 public:
  explicit OscReader(std::string bytes) : bytes_(std::move(bytes)) {}
  bool done() const { return at_ >= bytes_.size(); }
  size_t at() const { return at_; }
  std::string String() {
    const size_t end = bytes_.find('\0', at_);
    std::string text = bytes_.substr(at_, end - at_);
    at_ = (end + 4) & ~size_t{3};  // past the NUL, to the next multiple of 4
    return text;
  }
  uint32_t U32() {
    uint32_t value = 0;
    for (int i = 0; i < 4; ++i) value = (value << 8) | static_cast<uint8_t>(bytes_[at_ + i]);
    at_ += 4;
    return value;
  }
  uint64_t U64() {
    const uint64_t high = U32();
    return (high << 32) | U32();
  }
  float Float() {
    const uint32_t bits = U32();
    float value;
    std::memcpy(&value, &bits, sizeof(value));
    return value;
  }

 private:
  std::string bytes_;
  size_t at_ = 0;
};

TEST(VmcTest, BundleBytesAreOscOneZero) {
  const std::string bytes = VmcBundleBytes({{"A", 0.5f}, {"Blink", 0.25f}});
  ASSERT_EQ(bytes.size() % 4, 0u);
  OscReader osc(bytes);
  EXPECT_EQ(osc.String(), "#bundle");
  EXPECT_EQ(osc.U64(), 1u);  // the time tag "immediately"
  struct Message {
    std::string address, tags, clip;
    float value = -1.0f;
  };
  std::vector<Message> messages;
  while (!osc.done()) {
    const uint32_t size = osc.U32();
    const size_t end = osc.at() + size;
    Message message;
    message.address = osc.String();
    message.tags = osc.String();
    if (message.tags == ",sf") {
      message.clip = osc.String();
      message.value = osc.Float();
    }
    EXPECT_EQ(osc.at(), end) << message.address;
    messages.push_back(message);
  }
  ASSERT_EQ(messages.size(), 3u);
  EXPECT_EQ(messages[0].address, "/VMC/Ext/Blend/Val");
  EXPECT_EQ(messages[0].tags, ",sf");
  EXPECT_EQ(messages[0].clip, "A");
  EXPECT_EQ(messages[0].value, 0.5f);
  EXPECT_EQ(messages[1].clip, "Blink");
  EXPECT_EQ(messages[1].value, 0.25f);
  EXPECT_EQ(messages[2].address, "/VMC/Ext/Blend/Apply");
  EXPECT_EQ(messages[2].tags, ",");
}

TEST(VmcTest, TargetParsing) {
  VmcOptions options;
  ASSERT_TRUE(ParseVmcTarget("", "--vmc", options).ok());
  EXPECT_EQ(options.host, "127.0.0.1");
  EXPECT_EQ(options.port, "39539");
  ASSERT_TRUE(ParseVmcTarget("192.168.1.20:39540", "--vmc", options).ok());
  EXPECT_EQ(options.host, "192.168.1.20");
  EXPECT_EQ(options.port, "39540");
  ASSERT_TRUE(ParseVmcTarget("[::1]:9000", "--vmc", options).ok());
  EXPECT_EQ(options.host, "::1");
  EXPECT_EQ(options.port, "9000");
  for (const char* bad : {"localhost", ":39539", "h:0", "h:65536", "h:x", "h:+1", "[::1]9000",
                          "a:b:c"}) {
    const absl::Status status = ParseVmcTarget(bad, "--vmc", options);
    EXPECT_TRUE(absl::IsInvalidArgument(status)) << bad;
    EXPECT_THAT(std::string(status.message()), HasSubstr("--vmc")) << bad;
  }
}

TEST(VtsMessagesTest, RequestsHaveTheDocumentedShape) {
  const nlohmann::json token = nlohmann::json::parse(VtsTokenRequest(VtsPlugin(), "id-1"));
  EXPECT_EQ(token["apiName"], "VTubeStudioPublicAPI");
  EXPECT_EQ(token["apiVersion"], "1.0");
  EXPECT_EQ(token["requestID"], "id-1");
  EXPECT_EQ(token["messageType"], "AuthenticationTokenRequest");
  EXPECT_EQ(token["data"]["pluginName"], "koma");
  EXPECT_EQ(token["data"]["pluginDeveloper"], "koma contributors");
  EXPECT_FALSE(token["data"].contains("pluginIcon"));  // optional, omitted

  const nlohmann::json auth =
      nlohmann::json::parse(VtsAuthenticationRequest(VtsPlugin(), "tok", "id-2"));
  EXPECT_EQ(auth["messageType"], "AuthenticationRequest");
  EXPECT_EQ(auth["data"]["authenticationToken"], "tok");
  EXPECT_EQ(auth["data"]["pluginName"], "koma");

  const nlohmann::json inject = nlohmann::json::parse(
      VtsInjectRequest({{"MouthOpen", 0.5}, {"EyeOpenLeft", 1.0}}, "id-3"));
  EXPECT_EQ(inject["messageType"], "InjectParameterDataRequest");
  EXPECT_EQ(inject["data"]["faceFound"], false);
  EXPECT_EQ(inject["data"]["mode"], "set");
  ASSERT_EQ(inject["data"]["parameterValues"].size(), 2u);
  EXPECT_EQ(inject["data"]["parameterValues"][0]["id"], "MouthOpen");
  EXPECT_EQ(inject["data"]["parameterValues"][0]["value"], 0.5);
  EXPECT_FALSE(inject["data"]["parameterValues"][0].contains("weight"));  // 1: set outright
}

TEST(VtsMessagesTest, ValuesAreMouthAndBothEyes) {
  VtsOptions options;
  const std::vector<VtsParameterValue> values =
      VtsValuesOf(FrameWith(0.5, 0.0), AvatarLevels(), options);
  ASSERT_EQ(values.size(), 3u);
  EXPECT_EQ(values[0].id, "MouthOpen");
  EXPECT_EQ(values[0].value, 0.5);
  EXPECT_EQ(values[1].id, "EyeOpenLeft");
  EXPECT_EQ(values[1].value, 0.0);
  EXPECT_EQ(values[2].id, "EyeOpenRight");
  EXPECT_EQ(values[2].value, 0.0);
}

TEST(VtsMessagesTest, ResponsesAndErrors) {
  absl::StatusOr<VtsResponse> error = ParseVtsResponse(
      R"({"apiName":"VTubeStudioPublicAPI","apiVersion":"1.0","timestamp":1,"requestID":"r",
          "messageType":"APIError","data":{"errorID":50,"message":"denied"}})");
  ASSERT_TRUE(error.ok()) << error.status();
  EXPECT_TRUE(error->is_error());
  EXPECT_EQ(error->request_id, "r");
  EXPECT_EQ(error->error_id(), 50);
  EXPECT_EQ(error->error_message(), "denied");

  absl::StatusOr<VtsResponse> no_data = ParseVtsResponse(R"({"messageType":"X"})");
  ASSERT_TRUE(no_data.ok());
  EXPECT_TRUE(no_data->data.is_object());
  EXPECT_EQ(no_data->error_id(), -1);

  for (const char* bad : {"", "[1]", "{", R"({"data":{}})", R"({"messageType":1})",
                          R"({"messageType":"X","data":[1]})"}) {
    EXPECT_TRUE(absl::IsInvalidArgument(ParseVtsResponse(bad).status())) << bad;
  }
}

TEST(WebSocketUrlTest, Parsing) {
  absl::StatusOr<WebSocketUrl> url = ParseWebSocketUrl("ws://localhost:8001");
  ASSERT_TRUE(url.ok());
  EXPECT_EQ(url->host, "localhost");
  EXPECT_EQ(url->port, 8001);
  EXPECT_EQ(url->path, "/");
  url = ParseWebSocketUrl("ws://[::1]:9/api");
  ASSERT_TRUE(url.ok());
  EXPECT_EQ(url->host, "::1");
  EXPECT_EQ(url->port, 9);
  EXPECT_EQ(url->path, "/api");
  url = ParseWebSocketUrl("192.168.0.5:8001");
  ASSERT_TRUE(url.ok());
  EXPECT_EQ(url->host, "192.168.0.5");
  url = ParseWebSocketUrl("ws://host");
  ASSERT_TRUE(url.ok());
  EXPECT_EQ(url->port, 80);
  for (const char* bad : {"wss://h:1", "ws://:8001", "h", "ws://h:", "h:", "ws://h:0", "ws://h:x", "ws://[::1"}) {
    EXPECT_TRUE(absl::IsInvalidArgument(ParseWebSocketUrl(bad).status())) << bad;
  }
}

TEST(VtsTokenTest, SavedOwnerOnlyAndReadBack) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("koma_vts_token_" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  const std::string path = (dir / "koma" / "vts-token").string();
  EXPECT_TRUE(absl::IsNotFound(ReadVtsToken(path).status()));
  ASSERT_TRUE(WriteVtsToken(path, "abc-123").ok());
  struct stat info {};
  ASSERT_EQ(stat(path.c_str(), &info), 0);
  EXPECT_EQ(info.st_mode & 0777, 0600u);
  absl::StatusOr<std::string> token = ReadVtsToken(path);
  ASSERT_TRUE(token.ok());
  EXPECT_EQ(*token, "abc-123");
  ASSERT_TRUE(WriteVtsToken(path, "second").ok());  // replaced
  EXPECT_EQ(*ReadVtsToken(path), "second");
  std::filesystem::remove_all(dir);
}

TEST(VtsTokenTest, DefaultPathFollowsXdg) {
  const char* saved_xdg = std::getenv("XDG_CONFIG_HOME");
  const std::string xdg = saved_xdg ? saved_xdg : "";
  setenv("XDG_CONFIG_HOME", "/x/config", 1);
  EXPECT_EQ(DefaultVtsTokenFile(), "/x/config/koma/vts-token");
  unsetenv("XDG_CONFIG_HOME");
  const char* home = std::getenv("HOME");
  if (home != nullptr && home[0] != '\0') {
    EXPECT_EQ(DefaultVtsTokenFile(), std::string(home) + "/.config/koma/vts-token");
  }
  if (saved_xdg != nullptr) setenv("XDG_CONFIG_HOME", xdg.c_str(), 1);
}

// Parses `args` as a command's flags; the sinks they ask for, or the error.
absl::StatusOr<std::vector<std::unique_ptr<LiveSink>>> SinksOf(std::vector<std::string> args) {
  CLI::App command;
  AvatarSinkFlags flags;
  AddAvatarSinkFlags(command, flags);
  std::reverse(args.begin(), args.end());  // CLI11 takes them last first
  try {
    command.parse(args);
  } catch (const CLI::ParseError& e) {
    return absl::InvalidArgumentError(e.what());
  }
  std::vector<std::unique_ptr<LiveSink>> sinks;
  if (absl::Status s = AddAvatarSinks(flags, sinks); !s.ok()) return s;
  return sinks;
}

TEST(AvatarSinkFlagsTest, EachFlagItsSink) {
  absl::StatusOr<std::vector<std::unique_ptr<LiveSink>>> none = SinksOf({});
  ASSERT_TRUE(none.ok());
  EXPECT_TRUE(none->empty());
  absl::StatusOr<std::vector<std::unique_ptr<LiveSink>>> both =
      SinksOf({"--vmc", "--vts", "--vmc-mouth-clip", "aa"});
  ASSERT_TRUE(both.ok()) << both.status();
  ASSERT_EQ(both->size(), 2u);
  EXPECT_NE(dynamic_cast<VmcSink*>((*both)[0].get()), nullptr);
  EXPECT_NE(dynamic_cast<VtubeStudioSink*>((*both)[1].get()), nullptr);
  absl::StatusOr<std::vector<std::unique_ptr<LiveSink>>> with_values =
      SinksOf({"--vmc", "192.168.1.20:39540", "--vts", "ws://127.0.0.1:8001"});
  ASSERT_TRUE(with_values.ok()) << with_values.status();
  EXPECT_EQ(with_values->size(), 2u);
}

TEST(AvatarSinkFlagsTest, BadValuesAreRefusedAtParse) {
  for (const std::vector<std::string>& args :
       std::vector<std::vector<std::string>>{{"--vmc", "localhost"},
                                             {"--vmc", "h:0"},
                                             {"--vts", "wss://h:1"},
                                             {"--vmc-blink-clip", ""},
                                             {"--vts-eye-right-param", ""}}) {
    const absl::Status status = SinksOf(args).status();
    EXPECT_TRUE(absl::IsInvalidArgument(status)) << args[0] << " " << args[1];
    EXPECT_THAT(std::string(status.message()), HasSubstr(args[0])) << status;
  }
}

}  // namespace
}  // namespace koma::client
