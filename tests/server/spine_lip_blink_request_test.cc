// LipBlink into a Spine skeleton over the wire (LipBlinkRequest.spine_json / spine): the
// answer is the decoded request's answer (the slots as curves at skeleton.fps) plus the
// skeleton with the slots' attachment timelines written; every refusal names its field.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "convert/spine_lip_blink.h"
#include "formats/spine.h"
#include "formats/spine_attachments.h"
#include "tests/formats/test_files.h"
#include "tests/server/in_process_server.h"
#include "tests/testing/status_matchers.h"

namespace koma::testing {
namespace {

std::string SpineText(const std::string& name) {
  return name == "hero.json" ? formats::ReadTestFile(KOMA_SAMPLES_DIR "/hero.json")
                             : formats::ReadTestFile(KOMA_TESTDATA_DIR "/spine/" + name);
}

grpc::Status Call(InProcessServer& server, const v1::LipBlinkRequest& request,
                  v1::LipBlinkResponse* response) {
  grpc::ClientContext context;
  SetTestDeadline(context);
  return server.stub().LipBlink(&context, request, response);
}

struct SpineCase {
  std::string file;
  std::string animation;
  std::string mouth;            // empty: none
  std::vector<std::string> mouth_names;  // empty: the defaults
  bool eyes = false;            // the "eyes" slot
  int speech_end = 0;           // mouth.speech 3..speech_end (skeleton frames); 0: none
  bool auto_blink = false;
};

v1::LipBlinkRequest RequestFor(const SpineCase& c) {
  v1::LipBlinkRequest request;
  request.set_spine_json(SpineText(c.file));
  request.mutable_spine()->set_animation(c.animation);
  request.mutable_spine()->set_mouth_slot(c.mouth);
  for (const std::string& name : c.mouth_names) request.mutable_spine()->add_mouth_attachments(name);
  if (c.eyes) request.mutable_spine()->add_eye_slots("eyes");
  if (c.speech_end > 0) {
    v1::FrameInterval* speech = request.mutable_mouth()->add_speech();
    speech->set_begin(3);
    speech->set_end(c.speech_end);
  }
  if (c.auto_blink) {
    request.mutable_eyes()->mutable_auto_blink()->set_enabled(true);
    request.mutable_eyes()->mutable_auto_blink()->set_mean_interval_s(1.5);
  }
  return request;
}

// The document without animations.<name>.slots.<slot>.attachment of the keyed slots (and
// without the animation when it was added), to compare with the input.
nlohmann::ordered_json WithoutKeys(nlohmann::ordered_json doc, const std::string& animation,
                           const std::vector<std::string>& slots, bool added) {
  if (added) {
    doc["animations"].erase(animation);
    return doc;
  }
  nlohmann::ordered_json& anim = doc["animations"][animation];
  for (const std::string& slot : slots) {
    if (!anim.contains("slots") || !anim["slots"].contains(slot)) continue;
    anim["slots"][slot].erase("attachment");
    if (anim["slots"][slot].empty()) anim["slots"].erase(slot);
  }
  if (anim.contains("slots") && anim["slots"].empty()) anim.erase("slots");
  return doc;
}

TEST(SpineLipBlinkRequestTest, AnswersTheDecodedRequestAndWritesTheSlots) {
  InProcessServer server;
  const SpineCase kCases[] = {
      {"hero.json", "talk", "mouth", {}, true, 40, true},
      {"hero-4.1.json", "walk", "mouth", {}, true, 20, false},
      {"hero-4.2.json", "walk", "", {}, true, 0, true},
      {"hero-3.8.json", "blink", "mouth", {}, true, 12, false},
      {"matt-3.7.json", "shake_head", "mouth", {"mouth_a", "mouth_c", "mouth_d"}, false, 15, false},
  };
  for (const SpineCase& c : kCases) {
    SCOPED_TRACE(c.file + " " + c.animation);
    const v1::LipBlinkRequest request = RequestFor(c);
    v1::LipBlinkResponse response;
    const grpc::Status status = Call(server, request, &response);
    ASSERT_TRUE(status.ok()) << status.error_message();
    ASSERT_EQ(response.output_case(), v1::LipBlinkResponse::kSpineJson);

    // The decoded request the skeleton stands for, answered on its own: the same answer.
    ASSERT_OK_AND_ASSIGN(const formats::SpineFile file, formats::ParseSpine(request.spine_json()));
    ASSERT_OK_AND_ASSIGN(const convert::SpineLipBlinkSlots slots,
                         convert::SpineLipBlinkSlotsOf(request.spine(), file, false,
                                                       c.speech_end > 0,
                                                       convert::ProtoSpineLipBlinkNames()));
    ASSERT_OK_AND_ASSIGN(const v1::LipBlinkRequest decoded,
                         convert::DecodedSpineLipBlinkRequest(request, file, slots));
    EXPECT_EQ(decoded.input_case(), v1::LipBlinkRequest::kCurves);
    v1::LipBlinkResponse decoded_response;
    ASSERT_TRUE(Call(server, decoded, &decoded_response).ok());
    v1::LipBlinkResponse rest = response;
    rest.clear_output();
    EXPECT_EQ(rest.spine_new_animation(), !formats::FindSpineAnimation(file, c.animation).ok());
    rest.clear_spine_new_animation();
    EXPECT_EQ(rest.SerializeAsString(), decoded_response.SerializeAsString());

    // The written skeleton: same version, the slots keyed on the 24 fps grid with their
    // three names, everything else as it was.
    ASSERT_OK_AND_ASSIGN(const formats::SpineFile written,
                         formats::ParseSpine(response.spine_json()));
    EXPECT_EQ(written.document["skeleton"]["spine"], file.document["skeleton"]["spine"]);
    std::vector<std::string> keyed;
    if (!c.mouth.empty()) keyed.push_back(c.mouth);
    if (c.eyes) keyed.push_back("eyes");
    for (size_t s = 0; s < keyed.size(); ++s) {
      const std::string& slot = keyed[s];
      SCOPED_TRACE(slot);
      ASSERT_OK_AND_ASSIGN(const std::vector<formats::SpineAttachmentKey> keys,
                           formats::SpineAttachmentKeys(written, c.animation, slot));
      ASSERT_FALSE(keys.empty());
      const std::vector<std::string>& names =
          slot == c.mouth ? slots.mouth_names : slots.eye_names[0];
      const std::set<std::string> allowed(names.begin(), names.end());
      EXPECT_EQ(keys[0].time, 0.0);
      for (size_t k = 0; k < keys.size(); ++k) {
        EXPECT_TRUE(allowed.count(keys[k].name)) << keys[k].name;
        const double grid = keys[k].time * 24.0;
        EXPECT_NEAR(grid, std::round(grid), 1e-9) << keys[k].time;
        if (k > 0) {
          EXPECT_GT(keys[k].time, keys[k - 1].time);
          EXPECT_NE(keys[k].name, keys[k - 1].name);
        }
      }
      if (slot == c.mouth) {
        // Open or mid only inside the speech: skeleton frames 3 .. speech_end at its fps,
        // snapped to the grid (a grid frame is speech when its time is).
        const double fps = file.fps;
        bool spoke = false;
        for (size_t k = 0; k < keys.size(); ++k) {
          if (keys[k].name == names[0]) continue;
          spoke = true;
          EXPECT_GE(keys[k].time, 3 / fps - 1 / 24.0 - 1e-9);
          const double until = k + 1 < keys.size() ? keys[k + 1].time : 1e9;
          EXPECT_LE(until, (c.speech_end + 1) / fps + 1 / 24.0 + 1e-9);
        }
        EXPECT_TRUE(spoke);
        EXPECT_EQ(keys.back().name, names[0]);  // closed after the speech
      }
    }
    EXPECT_EQ(WithoutKeys(written.document, c.animation, keyed, !slots.existing),
              WithoutKeys(file.document, c.animation, keyed, !slots.existing));
  }
}

TEST(SpineLipBlinkRequestTest, TheExistingBlinkIsKeptOnTheGrid) {
  // hero-4.1 walk: eyes_closed at 0.8 s, eyes_open at 0.9 s -> one blink whose closed drawing
  // starts at grid frame 20 (0.8333 s): closed, then half, then open.
  InProcessServer server;
  v1::LipBlinkResponse response;
  const grpc::Status status =
      Call(server, RequestFor({"hero-4.1.json", "walk", "", {}, true, 0, false}), &response);
  ASSERT_TRUE(status.ok()) << status.error_message();
  ASSERT_OK_AND_ASSIGN(const formats::SpineFile written, formats::ParseSpine(response.spine_json()));
  ASSERT_OK_AND_ASSIGN(const std::vector<formats::SpineAttachmentKey> keys,
                       formats::SpineAttachmentKeys(written, "walk", "eyes"));
  ASSERT_EQ(keys.size(), 4u);
  EXPECT_EQ(keys[0], (formats::SpineAttachmentKey{0.0, "eyes_open"}));
  EXPECT_EQ(keys[1].name, "eyes_closed");
  EXPECT_NEAR(keys[1].time, 20 / 24.0, 1e-12);
  EXPECT_EQ(keys[2].name, "eyes_half");
  EXPECT_EQ(keys[3].name, "eyes_open");
  EXPECT_FALSE(response.spine_new_animation());
}

TEST(SpineLipBlinkRequestTest, AVoiceWritesANewAnimationAsLongAsTheCues) {
  InProcessServer server;
  v1::LipBlinkRequest request = RequestFor({"hero.json", "talk", "mouth", {}, true, 0, true});
  // Rhubarb TSV: X (closed) then D (open) from 0.5 s, B (closed) from 1.0 s, X from 1.5 s.
  request.set_rhubarb_cues("0.00\tX\n0.50\tD\n1.00\tB\n1.50\tX\n2.00\tX\n");
  v1::LipBlinkResponse response;
  const grpc::Status status = Call(server, request, &response);
  ASSERT_TRUE(status.ok()) << status.error_message();
  ASSERT_EQ(response.output_case(), v1::LipBlinkResponse::kSpineJson);
  EXPECT_TRUE(response.spine_new_animation());
  EXPECT_FALSE(response.rhubarb_json().empty());
  ASSERT_OK_AND_ASSIGN(const formats::SpineFile written, formats::ParseSpine(response.spine_json()));
  ASSERT_OK_AND_ASSIGN(const std::vector<formats::SpineAttachmentKey> keys,
                       formats::SpineAttachmentKeys(written, "talk", "mouth"));
  // The same cues as an ordinary voice request (a new motion at the skeleton's 30 fps): the
  // same mouth holds.
  v1::LipBlinkRequest plain;
  plain.set_rhubarb_cues(request.rhubarb_cues());
  plain.set_voice_motion_fps(30);
  plain.mutable_mouth()->add_ids("mouth");
  v1::LipBlinkResponse plain_response;
  ASSERT_TRUE(Call(server, plain, &plain_response).ok());
  ASSERT_EQ(response.mouths_size(), 1);
  ASSERT_EQ(plain_response.mouths_size(), 1);
  EXPECT_EQ(response.mouths(0).SerializeAsString(), plain_response.mouths(0).SerializeAsString());
  // At every grid frame the attachment shown (the last key at or before it) is the hold's
  // drawing; closed outside the speech [0.5, 1.5) s.
  const char* const kNames[] = {"", "mouth_closed", "mouth_mid", "mouth_open"};
  ASSERT_FALSE(keys.empty());
  for (int g = 0; g < 48; ++g) {
    std::string shown;
    for (const formats::SpineAttachmentKey& key : keys) {
      if (key.time <= g / 24.0 + 1e-12) shown = key.name;
    }
    std::string drawn = "mouth_closed";
    for (const v1::MouthHold& hold : response.mouths(0).holds()) {
      if (g >= hold.begin() && g < hold.begin() + hold.length()) drawn = kNames[hold.shape()];
    }
    EXPECT_EQ(shown, drawn) << "grid frame " << g;
    if (g < 12 || g >= 36) {
      EXPECT_EQ(shown, "mouth_closed") << "grid frame " << g;
    }
  }
  EXPECT_GT(keys.size(), 3u);  // the mouth flaps inside the speech
  // The same request, the same bytes.
  v1::LipBlinkResponse again;
  ASSERT_TRUE(Call(server, request, &again).ok());
  EXPECT_EQ(again.SerializeAsString(), response.SerializeAsString());
}

struct Refusal {
  std::string what;
  grpc::StatusCode code;
  std::string message;  // a part of the message
};

TEST(SpineLipBlinkRequestTest, EveryRefusalNamesItsField) {
  server::ServerConfig config;
  config.limits.max_file_bytes = 1 << 20;
  InProcessServer server(config);
  const SpineCase base = {"hero.json", "walk", "mouth", {}, true, 20, false};
  const auto with = [&](auto change) {
    v1::LipBlinkRequest request = RequestFor(base);
    change(request);
    return request;
  };
  using R = v1::LipBlinkRequest;
  const std::vector<std::pair<R, Refusal>> kCases = {
      {with([](R& r) { r.mutable_spine()->clear_animation(); }),
       {"no animation", grpc::INVALID_ARGUMENT, "spine.animation: the Spine animation"}},
      {with([](R& r) { r.mutable_spine()->set_mouth_slot("nose"); }),
       {"unknown mouth slot", grpc::INVALID_ARGUMENT,
        "spine.mouth_slot no slot named \"nose\" (the skeleton has torso, head, mouth, eyes)"}},
      {with([](R& r) {
         r.mutable_spine()->clear_mouth_slot();
         r.mutable_spine()->clear_eye_slots();
       }),
       {"no slot", grpc::INVALID_ARGUMENT, "spine.mouth_slot and/or spine.eye_slots"}},
      {with([](R& r) { r.mutable_spine()->add_mouth_attachments("mouth_closed"); }),
       {"one name", grpc::INVALID_ARGUMENT,
        "spine.mouth_attachments: expected three attachment names (closed,mid,open), got 1"}},
      {with([](R& r) {
         for (const char* n : {"mouth_closed", "mouth_wide", "mouth_open"}) {
           r.mutable_spine()->add_mouth_attachments(n);
         }
       }),
       {"unknown attachment", grpc::INVALID_ARGUMENT,
        "spine.mouth_attachments: \"mouth_wide\" is not an attachment of slot \"mouth\" in any "
        "skin (it has mouth_closed, mouth_mid, mouth_open)"}},
      {with([](R& r) { r.mutable_spine()->add_eye_slots("ears"); }),
       {"unknown eye slot", grpc::INVALID_ARGUMENT, "spine.eye_slots no slot named \"ears\""}},
      {with([](R& r) { r.mutable_spine()->add_eye_slots("eyes"); }),
       {"eye slot twice", grpc::INVALID_ARGUMENT,
        "spine.eye_slots: \"eyes\" is named twice (or is the mouth slot)"}},
      {with([](R& r) {
         r.mutable_spine()->clear_eye_slots();
         r.mutable_spine()->add_eye_attachments("a");
       }),
       {"eye names without eyes", grpc::INVALID_ARGUMENT,
        "spine.eye_attachments: needs spine.eye_slots"}},
      {with([](R& r) { r.mutable_mouth()->clear_speech(); }),
       {"mouth without voice", grpc::INVALID_ARGUMENT,
        "spine.mouth_slot mouth: the mouth needs a voice (audio, rhubarb_cues) or mouth.speech"}},
      {with([](R& r) {
         r.mutable_spine()->set_animation("run");
         r.mutable_spine()->clear_mouth_slot();
         r.mutable_mouth()->clear_speech();
       }),
       {"new animation without length", grpc::INVALID_ARGUMENT,
        "spine.animation \"run\": not an animation of the skeleton"}},
      {with([](R& r) {
         r.mutable_spine()->set_animation("run");
         r.mutable_mouth()->mutable_speech(0)->set_end(2147483647);
       }),
       {"a new animation as long as INT32_MAX frames", grpc::RESOURCE_EXHAUSTED,
        "spine_json: the slots as curves: 2 curves x 2147483647 frames"}},
      {with([](R& r) { r.mutable_mouth()->add_ids("ParamMouthOpenY"); }),
       {"mouth.ids", grpc::INVALID_ARGUMENT,
        "mouth.ids: ParamMouthOpenY is not for spine_json"}},
      {with([](R& r) { r.mutable_eyes()->add_ids("ParamEyeLOpen"); }),
       {"eyes.ids", grpc::INVALID_ARGUMENT, "eyes.ids: ParamEyeLOpen is not for spine_json"}},
      {with([](R& r) { r.mutable_mouth()->set_min(0.2); }),
       {"mouth.min", grpc::INVALID_ARGUMENT, "mouth.min: 0.2 is not for spine_json"}},
      {with([](R& r) { r.mutable_eyes()->set_max(2); }),
       {"eyes.max", grpc::INVALID_ARGUMENT, "eyes.max: 2 is not for spine_json"}},
      {with([](R& r) { r.set_voice_motion_fps(24); }),
       {"voice_motion_fps", grpc::INVALID_ARGUMENT, "voice_motion_fps: 24 is not for spine_json"}},
      {with([](R& r) { r.set_voice_output(v1::VOICE_OUTPUT_CSV); }),
       {"voice_output", grpc::INVALID_ARGUMENT,
        "voice_output: VOICE_OUTPUT_CSV is not for spine_json"}},
      {with([](R& r) { r.set_csv_fps(30); }),
       {"csv_fps", grpc::INVALID_ARGUMENT, "csv_fps: 30 is not for spine_json"}},
      {with([](R& r) { r.set_spine_json("{\"skeleton\": {\"spine\": \"4.1.24\"}, \"slots\": 3}"); }),
       {"bad skeleton", grpc::INVALID_ARGUMENT, "spine_json: "}},
      {with([](R& r) { r.set_spine_json(std::string((1 << 20) + 1, ' ')); }),
       {"too big", grpc::RESOURCE_EXHAUSTED, "spine_json: 1048577 bytes exceeds the server limit --max_file_bytes=1048576"}},
      {with([](R& r) { r.set_spine_json("{\"skeleton\": {\"spine\": \"4.1.24\"}, \"slots\": 3}"); r.set_rhubarb_cues("0.00\tX\n"); }),
       {"bad skeleton with a voice", grpc::INVALID_ARGUMENT, "spine_json: "}},
      {with([](R& r) {
         r.mutable_curves()->set_fps(30);
         r.mutable_curves()->set_frame_count(2);
       }),
       {"spine without spine_json", grpc::INVALID_ARGUMENT,
        "spine: only with spine_json"}},
  };
  for (const auto& [request, refusal] : kCases) {
    SCOPED_TRACE(refusal.what);
    v1::LipBlinkResponse response;
    const grpc::Status status = Call(server, request, &response);
    EXPECT_EQ(status.error_code(), refusal.code) << status.error_message();
    EXPECT_NE(status.error_message().find(refusal.message), std::string::npos)
        << status.error_message();
  }
}

// The memory budget sizes a skeleton's call by what it decodes to: a new animation whose
// speech runs to frame 1,000,000 (two slot curves of a million frames) is refused naming the
// budget although the request is a few KB; a short one fits, and the reservation is released.
TEST(SpineLipBlinkRequestTest, TheMemoryBudgetSizesTheDecodedCall) {
  server::ServerConfig config = InProcessServer::Config(2, 20'000'000);
  config.max_memory_mb = 24;  // 12 MiB of it for calls
  InProcessServer server(config);
  ASSERT_NE(server.server().memory_budget(), nullptr);
  v1::LipBlinkRequest request = RequestFor({"hero.json", "long", "mouth", {}, true, 1'000'000, false});
  v1::LipBlinkResponse response;
  grpc::Status status = Call(server, request, &response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << status.error_message();
  EXPECT_NE(status.error_message().find("memory budget (--max_memory_mb=24"), std::string::npos)
      << status.error_message();
  EXPECT_NE(status.error_message().find("this file request (the parsed file"), std::string::npos)
      << status.error_message();
  request = RequestFor({"hero.json", "long", "mouth", {}, true, 40, false});
  status = Call(server, request, &response);
  EXPECT_TRUE(status.ok()) << status.error_message();
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (server.server().memory_budget()->in_use() != 0 &&
         std::chrono::steady_clock::now() < give_up) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  EXPECT_EQ(server.server().memory_budget()->in_use(), 0);
}

}  // namespace
}  // namespace koma::testing
