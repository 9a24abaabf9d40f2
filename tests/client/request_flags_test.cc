// Every field of the three request messages is reachable from the CLI through a flag named
// after it: the test walks the proto descriptors, and for each field (nested settings
// messages walked into, repeated messages taken whole) runs the real command line parser with
// that field's kebab-case flag and checks the request the command builds has the field set to
// the value given. A field added to the proto without a flag (and not listed in kExcluded)
// fails WalksEveryField. The file-carrying fields are set by --send-file (the input file
// itself) and their csv_fps by --fps.
#include <gmock/gmock.h>
#include <google/protobuf/descriptor.h>
#include <google/protobuf/text_format.h>
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "absl/strings/str_join.h"
#include "absl/strings/str_replace.h"
#include "client/cli.h"
#include "client/curve_files.h"
#include "client/file_format.h"
#include "client/skeletal_fbx.h"
#include "client/skeletal_gltf.h"
#include "client/spine_lip_blink.h"
#include "koma/v1/retime.pb.h"
#include "tests/testing/status_matchers.h"

namespace koma::client {
namespace {

using google::protobuf::Descriptor;
using google::protobuf::FieldDescriptor;
using google::protobuf::Message;
using google::protobuf::Reflection;

const std::string kBvh = std::string(KOMA_SAMPLES_DIR) + "/pitch.bvh";  // 21 joints
const std::string kArmHead = std::string(KOMA_SAMPLES_DIR) + "/arm_head.motion3.json";
const std::string kTalk = std::string(KOMA_SAMPLES_DIR) + "/talk_blink.motion3.json";

// Fields deliberately without a flag, with the reason.
const std::map<std::string, std::string> kExcluded = {
    {"RetimeSkeletalRequest.motion", "the whole clip: the input file"},
    {"RetimeSkeletalRequest.gltf", "a glTF input file itself, always sent whole"},
    {"RetimeSkeletalRequest.fbx", "an FBX input file itself, always sent whole"},
    {"RetimeCurvesRequest.curves", "the whole curve set: the input file"},
    {"LipBlinkRequest.curves", "the whole curve set: the input file"},
    {"LipBlinkRequest.audio", "the recording's bytes: --audio FILE (tests/python/test_voice.py)"},
    {"LipBlinkRequest.spine_json",
     "a Spine skeleton IN itself, always sent whole (tests/e2e/spine_lipblink_wire_e2e_test.sh)"},
    {"LipBlinkRequest.rhubarb_cues",
     "the cue file's bytes: --rhubarb FILE (tests/python/test_voice.py)"},
    // A given timing (docs/api.md, "A given timing") is a whole timing, read from an edited
    // X-sheet or timing CSV, not a value a flag could carry.
    {"RetimeSkeletalRequest.given_timing", "a whole timing: read from a sheet (--timing-from)"},
    {"RetimeCurvesRequest.given_timings", "whole timings: read from a sheet (--timing-from)"},
    {"LipBlinkRequest.given_timing", "a whole timing: read from a sheet (--timing-from)"},
};

// The files over the wire (the oneof beside the decoded data) are set by --send-file, which
// sends the input file itself, and csv_fps by --fps with it: not a flag per field.
const std::set<std::string> kSendFileFields = {
    "RetimeSkeletalRequest.bvh_text", "RetimeCurvesRequest.motion3_json",
    "RetimeCurvesRequest.csv_text",   "RetimeCurvesRequest.csv_fps",
    "LipBlinkRequest.motion3_json",   "LipBlinkRequest.csv_text",
    "LipBlinkRequest.csv_fps",        "RetimeCurvesRequest.spine_json"};
const std::string kCsv = std::string(KOMA_TESTDATA_DIR) + "/curves_crlf.csv";
// A Spine skeleton with one animation with bone keys ("walk"), so none needs naming.
const std::string kSpine = std::string(KOMA_TESTDATA_DIR) + "/spine/hero-4.2.json";
// A Spine skeleton with mouth and eye slots (LipBlinkRequest.spine).
const std::string kHero = std::string(KOMA_SAMPLES_DIR) + "/hero.json";
const std::string kWave = std::string(KOMA_SAMPLES_DIR) + "/wave.glb";
const std::string kFbx = std::string(KOMA_SAMPLES_DIR) + "/huesitos.fbx";
constexpr char kInputFile[] = "<the input file>";

// Singular message fields whose fields are settings, each with its own flag.
const std::set<std::string> kSettingsMessages = {
    "LipBlinkRequest.mouth", "LipBlinkRequest.eyes", "EyeSettings.auto_blink",
    "LipBlinkRequest.voice_settings", "LipBlinkRequest.spine"};

struct FieldCase {
  FieldCase(std::vector<std::string> v, std::string e, std::vector<std::string> x = {},
            std::string f = "", std::string i = "")
      : values(std::move(v)),
        expected(std::move(e)),
        extra(std::move(x)),
        flag(std::move(f)),
        input(std::move(i)) {}
  std::vector<std::string> values;  // after the flag (none for a plain switch; "=V": --flag=V)
  std::string expected;             // the field's text in the built request (kInputFile: the
                                    // bytes of the input file)
  std::vector<std::string> extra;   // other flags the value needs
  std::string flag;                 // only for kSendFileFields: --send-file
  std::string input;                // another input file than the command's sample
};

std::string Ones(int n, const std::string& first) {
  std::vector<std::string> parts(n, "1");
  parts[0] = first;
  return absl::StrJoin(parts, ", ");
}

// Keyed by "Message.field" path from the request (as FieldPaths below writes them).
const std::map<std::string, FieldCase>& Cases() {
  static const auto* cases = new std::map<std::string, FieldCase>{
      // RetimeSkeletal
      {"RetimeSkeletalRequest.omissions", {{"5"}, "5"}},
      {"RetimeSkeletalRequest.holds", {{"7"}, "7"}},
      {"RetimeSkeletalRequest.max_hold", {{"2"}, "2"}},
      {"RetimeSkeletalRequest.keep_length", {{"=false"}, "false"}},
      {"RetimeSkeletalRequest.order", {{"hold-then-omit"}, "HOLD_THEN_OMIT"}},
      {"RetimeSkeletalRequest.joint_weights", {{"Hips=0.5"}, Ones(21, "0.5")}},
      {"RetimeSkeletalRequest.root_relative", {{}, "true"}},
      {"RetimeSkeletalRequest.camera",
       {{"1,0,0,0,0,2,0,0,0,0,1,0,0,0,-5,1"}, "1, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1, 0, 0, 0, -5, 1"}},
      {"RetimeSkeletalRequest.return_motion", {{"false"}, "false", {"--timing", "t.csv"}}},
      {"RetimeSkeletalRequest.timing_fps", {{"30"}, "30"}},
      {"RetimeSkeletalRequest.output_rate", {{"timing"}, "TIMING_RATE"}},
      {"RetimeSkeletalRequest.cut_neighbour_ratio", {{"0"}, "0"}},
      {"RetimeSkeletalRequest.cut_median_ratio", {{"12.5"}, "12.5"}},
      {"RetimeSkeletalRequest.omissions_per_second", {{"1.5"}, "1.5"}},
      {"RetimeSkeletalRequest.drawings_per_second", {{"8"}, "8"}},
      {"RetimeSkeletalRequest.gltf_animations", {{"Wave,0"}, "\"Wave\", \"0\"", {}, "", kWave}},
      {"RetimeSkeletalRequest.gltf_retime_none", {{}, "true", {}, "", kWave}},
      {"RetimeSkeletalRequest.gltf_source_fps", {{"24"}, "24", {}, "", kWave}},
      {"RetimeSkeletalRequest.gltf_keys", {{"linear"}, "GLTF_KEYS_LINEAR", {}, "", kWave}},
      {"RetimeSkeletalRequest.gltf_keep_original", {{}, "true", {}, "", kWave}},
      {"RetimeSkeletalRequest.fbx_take",
       {{"Armature|Action"}, "\"Armature|Action\"", {}, "", kFbx}},
      // RetimeCurves
      {"RetimeCurvesRequest.key_frames", {{"0,10,25"}, "0, 10, 25"}},
      {"RetimeCurvesRequest.frames_per_drawing", {{"2"}, "2"}},
      {"RetimeCurvesRequest.tame", {{"1.5"}, "1.5"}},
      {"RetimeCurvesRequest.tsume", {{"2.25"}, "2.25"}},
      {"RetimeCurvesRequest.curve_overrides",
       {{"ParamArmRA=2"}, "curve_id: \"ParamArmRA\" frames_per_drawing: 2"}},
      {"RetimeCurvesRequest.segment_overrides",
       {{"1:frames-per-drawing=2,tame=1.5,tsume=2"},
        "segment: 1 frames_per_drawing: 2 tame: 1.5 tsume: 2"}},
      {"RetimeCurvesRequest.timing_fps", {{"12"}, "12"}},
      // --animation, a Spine skeleton's animation: sent by name with the file.
      {"RetimeCurvesRequest.spine_animation", {{"walk"}, "\"walk\"", {"--send-file"}, "", kSpine}},
      {"RetimeCurvesRequest.merge_key_poses", {{"=false"}, "false"}},
      {"RetimeCurvesRequest.timing_groups",
       {{"face=ParamMouth*,ParamEye?Open:on=2,tame=1.25,tsume=1.5,keys=0/10/20,mode=lipblink,"
         "mouth=ParamMouthOpenY,mouth-mode=follow,eyes=ParamEyeLOpen/ParamEyeROpen,seed=7"},
        "name: \"face\" ids: \"ParamMouth*\" ids: \"ParamEye?Open\" frames_per_drawing: 2 "
        "tame: 1.25 tsume: 1.5 key_frames: 0 key_frames: 10 key_frames: 20 mode: GROUP_LIP_BLINK "
        "mouth { ids: \"ParamMouthOpenY\" mode: MOUTH_FOLLOW } eyes { ids: \"ParamEyeLOpen\" "
        "ids: \"ParamEyeROpen\" } seed: 7"}},
      {"RetimeCurvesRequest.default_timing_groups", {{"=false"}, "false"}},
      // LipBlink
      {"LipBlinkRequest.mouth.ids",
       {{"ParamMouthOpenY,ParamMouthForm"}, "\"ParamMouthOpenY\", \"ParamMouthForm\""}},
      {"LipBlinkRequest.mouth.mode", {{"follow"}, "MOUTH_FOLLOW"}},
      {"LipBlinkRequest.mouth.frames_per_shape", {{"2"}, "2"}},
      {"LipBlinkRequest.mouth.mid_ratio", {{"0.4"}, "0.4"}},
      {"LipBlinkRequest.mouth.min", {{"0.05"}, "0.05"}},
      {"LipBlinkRequest.mouth.max", {{"0.9"}, "0.9"}},
      {"LipBlinkRequest.mouth.speech", {{"10-40,50-70"}, "begin: 10 end: 40, begin: 50 end: 70"}},
      {"LipBlinkRequest.eyes.ids", {{"ParamEyeLOpen"}, "\"ParamEyeLOpen\""}},
      {"LipBlinkRequest.eyes.mid_ratio", {{"0.6"}, "0.6"}},
      {"LipBlinkRequest.eyes.threshold", {{"0.2"}, "0.2"}},
      {"LipBlinkRequest.eyes.min", {{"0.1"}, "0.1"}},
      {"LipBlinkRequest.eyes.max", {{"0.95"}, "0.95"}},
      {"LipBlinkRequest.eyes.linked", {{"false"}, "false"}},
      {"LipBlinkRequest.eyes.auto_blink.enabled", {{"true"}, "true"}},
      {"LipBlinkRequest.eyes.auto_blink.mean_interval_s", {{"3"}, "3"}},
      {"LipBlinkRequest.eyes.auto_blink.spread_s", {{"0.5"}, "0.5"}},
      {"LipBlinkRequest.eyes.auto_blink.hold", {{"3"}, "3"}},
      {"LipBlinkRequest.eyes.auto_blink.keep", {{"5-10"}, "begin: 5 end: 10"}},
      {"LipBlinkRequest.seed", {{"18446744073709551615"}, "18446744073709551615"}},
      {"LipBlinkRequest.timing_fps", {{"0"}, "0"}},
      // A Spine skeleton IN's animation and slots (aliases --animation, --mouth-slot, ...).
      {"LipBlinkRequest.spine.animation", {{"talk"}, "\"talk\"", {}, "", kHero}},
      {"LipBlinkRequest.spine.mouth_slot", {{"mouth"}, "\"mouth\"", {}, "", kHero}},
      {"LipBlinkRequest.spine.mouth_attachments",
       {{"a,b,c"}, "\"a\", \"b\", \"c\"", {}, "", kHero}},
      {"LipBlinkRequest.spine.eye_slots", {{"eyes,head"}, "\"eyes\", \"head\"", {}, "", kHero}},
      {"LipBlinkRequest.spine.eye_attachments", {{"o,h,c"}, "\"o\", \"h\", \"c\"", {}, "", kHero}},
      {"LipBlinkRequest.voice_settings.noise_floor_dbfs", {{"=-60"}, "-60"}},
      {"LipBlinkRequest.voice_settings.noise_percentile", {{"5"}, "5"}},
      {"LipBlinkRequest.voice_settings.start_above_floor_db", {{"12"}, "12"}},
      {"LipBlinkRequest.voice_settings.stay_above_floor_db", {{"3"}, "3"}},
      {"LipBlinkRequest.voice_settings.min_speech_dbfs", {{"=-50"}, "-50"}},
      {"LipBlinkRequest.voice_settings.bridge_gap_frames", {{"4"}, "4"}},
      {"LipBlinkRequest.voice_settings.faint_gap_frames", {{"5"}, "5"}},
      {"LipBlinkRequest.voice_settings.pause_above_floor_db", {{"2.5"}, "2.5"}},
      {"LipBlinkRequest.voice_settings.any_sound", {{}, "true"}},
      {"LipBlinkRequest.voice_settings.min_speech_frames", {{"3"}, "3"}},
      {"LipBlinkRequest.voice_settings.open_below_peak_db", {{"5"}, "5"}},
      {"LipBlinkRequest.voice_settings.closed_below_peak_db", {{"20"}, "20"}},
      {"LipBlinkRequest.voice_settings.hysteresis_db", {{"1"}, "1"}},
      {"LipBlinkRequest.voice_motion_fps", {{"25"}, "25"}},
      {"LipBlinkRequest.voice_output", {{"csv"}, "VOICE_OUTPUT_CSV"}},
      // Files over the wire, through --send-file.
      {"RetimeSkeletalRequest.bvh_text", {{}, kInputFile, {}, "--send-file"}},
      {"RetimeCurvesRequest.motion3_json", {{}, kInputFile, {}, "--send-file"}},
      {"RetimeCurvesRequest.csv_text", {{}, kInputFile, {}, "--send-file", kCsv}},
      {"RetimeCurvesRequest.csv_fps", {{}, "24", {"--fps", "24"}, "--send-file", kCsv}},
      {"RetimeCurvesRequest.spine_json", {{}, kInputFile, {}, "--send-file", kSpine}},
      {"LipBlinkRequest.motion3_json", {{}, kInputFile, {}, "--send-file"}},
      {"LipBlinkRequest.csv_text", {{}, kInputFile, {}, "--send-file", kCsv}},
      {"LipBlinkRequest.csv_fps", {{}, "12.5", {"--fps", "12.5"}, "--send-file", kCsv}},
  };
  return *cases;
}

struct FieldPath {
  std::string key;                             // "LipBlinkRequest.eyes.auto_blink.hold"
  std::vector<const FieldDescriptor*> fields;  // from the request down
};

void Walk(const Descriptor* message, const std::string& prefix,
          std::vector<const FieldDescriptor*> above, std::vector<FieldPath>* out) {
  for (int i = 0; i < message->field_count(); ++i) {
    const FieldDescriptor* field = message->field(i);
    const std::string key = prefix + "." + field->name();
    std::vector<const FieldDescriptor*> path = above;
    path.push_back(field);
    const std::string own = message->name() + "." + field->name();  // "EyeSettings.auto_blink"
    if (kExcluded.count(key)) continue;
    if (!field->is_repeated() && field->type() == FieldDescriptor::TYPE_MESSAGE &&
        (kSettingsMessages.count(key) || kSettingsMessages.count(own))) {
      Walk(field->message_type(), key, path, out);
      continue;
    }
    out->push_back({key, path});
  }
}

std::vector<FieldPath> FieldPaths() {
  std::vector<FieldPath> paths;
  for (const Descriptor* request :
       {v1::RetimeSkeletalRequest::descriptor(), v1::RetimeCurvesRequest::descriptor(),
        v1::LipBlinkRequest::descriptor()}) {
    Walk(request, request->name(), {}, &paths);
  }
  return paths;
}

// "--" + the kebab-case name: the field's own name, after its settings message's field
// ("mouth", "eyes", "auto-blink") for nested ones.
std::string FlagName(const FieldPath& path) {
  std::string name;
  if (path.fields.size() >= 2) name = path.fields[path.fields.size() - 2]->name() + "-";
  name += path.fields.back()->name();
  return "--" + absl::StrReplaceAll(name, {{"_", "-"}});
}

std::string ValueText(const Message& message, const FieldDescriptor* field, int index) {
  if (field->type() == FieldDescriptor::TYPE_MESSAGE) {
    const Message& sub = index < 0
                             ? message.GetReflection()->GetMessage(message, field)
                             : message.GetReflection()->GetRepeatedMessage(message, field, index);
    return sub.ShortDebugString();
  }
  std::string text;
  google::protobuf::TextFormat::PrintFieldValueToString(message, field, index, &text);
  return text;
}

// The field's value in `request` as text: "<unset>" when a field with presence is unset,
// repeated values joined by ", ".
std::string FieldText(const Message& request, const FieldPath& path) {
  const Message* message = &request;
  for (size_t i = 0; i + 1 < path.fields.size(); ++i) {
    message = &message->GetReflection()->GetMessage(*message, path.fields[i]);
  }
  const FieldDescriptor* field = path.fields.back();
  const Reflection* reflection = message->GetReflection();
  if (field->is_repeated()) {
    std::vector<std::string> parts;
    for (int i = 0; i < reflection->FieldSize(*message, field); ++i) {
      parts.push_back(ValueText(*message, field, i));
    }
    return parts.empty() ? "<empty>" : absl::StrJoin(parts, ", ");
  }
  if (field->has_presence() && !reflection->HasField(*message, field)) return "<unset>";
  return ValueText(*message, field, -1);
}

std::string FileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The request `koma COMMAND INPUT -o OUT <flags>` sends, through the real parser and the
// commands' own builders (input: the command's sample unless given).
absl::StatusOr<std::unique_ptr<Message>> BuildFromCommandLine(const std::string& request_name,
                                                              const std::vector<std::string>& flags,
                                                              const std::string& input = "") {
  std::vector<std::string> argv{"koma"};
  if (request_name == "RetimeSkeletalRequest") argv.insert(argv.end(), {"skeletal", kBvh});
  if (request_name == "RetimeCurvesRequest") argv.insert(argv.end(), {"curves", kArmHead});
  if (request_name == "LipBlinkRequest") argv.insert(argv.end(), {"lipblink", kTalk});
  if (!input.empty()) argv.back() = input;
  argv.insert(argv.end(), flags.begin(), flags.end());
  KomaCommandLine line;
  if (const int code = ParseCommandLine(argv, &line); code != -1) {
    return absl::InvalidArgumentError("parse exit code " + std::to_string(code) + " for " +
                                      absl::StrJoin(argv, " "));
  }
  if (line.command == "skeletal" && FormatFromName(line.skeletal.input) == FormatId::kGltf) {
    absl::StatusOr<v1::RetimeSkeletalRequest> r =
        BuildGltfRequest(line.skeletal, FileBytes(line.skeletal.input));
    if (!r.ok()) return r.status();
    return std::unique_ptr<Message>(new v1::RetimeSkeletalRequest(*r));
  }
  if (line.command == "skeletal" && FormatFromName(line.skeletal.input) == FormatId::kFbx) {
    absl::StatusOr<v1::RetimeSkeletalRequest> r =
        BuildFbxRequest(line.skeletal, FileBytes(line.skeletal.input));
    if (!r.ok()) return r.status();
    return std::unique_ptr<Message>(new v1::RetimeSkeletalRequest(*r));
  }
  if (line.command == "skeletal") {
    absl::StatusOr<SkeletalInput> file = ReadSkeletalFile(line.skeletal.input);
    if (!file.ok()) return file.status();
    absl::StatusOr<v1::RetimeSkeletalRequest> r = BuildSkeletalFileRequest(line.skeletal, *file);
    if (!r.ok()) return r.status();
    return std::unique_ptr<Message>(new v1::RetimeSkeletalRequest(*r));
  }
  if (line.command == "curves") {
    absl::StatusOr<CurveInput> file =
        ReadCurveInput(line.curves.input, line.curves.csv_fps, CurveFormat::kAuto, "curves");
    if (!file.ok()) return file.status();
    absl::StatusOr<v1::RetimeCurvesRequest> r = BuildCurvesFileRequest(line.curves, *file);
    if (!r.ok()) return r.status();
    return std::unique_ptr<Message>(new v1::RetimeCurvesRequest(*r));
  }
  absl::StatusOr<CurveInput> file = ReadCurveInput(line.lip_blink.input, line.lip_blink.csv_fps,
                                                   CurveFormat::kAuto, kLipBlinkSpineCommand);
  if (!file.ok()) return file.status();
  if (file->spine) {  // the skeleton goes whole, the slots in LipBlinkRequest.spine
    return std::unique_ptr<Message>(
        new v1::LipBlinkRequest(BuildSpineLipBlinkRequest(line.lip_blink, file->text, "")));
  }
  return std::unique_ptr<Message>(
      new v1::LipBlinkRequest(BuildLipBlinkFileRequest(line.lip_blink, *file)));
}

// A bytes field's value, as is.
std::string RawBytes(const Message& message, const FieldDescriptor* field) {
  return message.GetReflection()->GetString(message, field);
}

TEST(RequestFlagsTest, WalksEveryField) {
  const std::vector<FieldPath> paths = FieldPaths();
  std::set<std::string> walked;
  for (const FieldPath& path : paths) {
    walked.insert(path.key);
    EXPECT_TRUE(Cases().count(path.key))
        << path.key << " has no CLI flag case: add a flag " << FlagName(path)
        << " and a case here, or list it in kExcluded with the reason";
  }
  for (const auto& [key, unused] : Cases()) {
    EXPECT_TRUE(walked.count(key)) << key << ": a case for a field the proto does not have";
  }
  // 22 + 15 + 43 fields today (kExcluded ones are not walked); the count catches a settings
  // message walked wrongly.
  EXPECT_EQ(paths.size(), 80u);
}

TEST(RequestFlagsTest, EachFieldIsSetThroughItsKebabCaseFlag) {
  for (const FieldPath& path : FieldPaths()) {
    SCOPED_TRACE(path.key);
    const auto it = Cases().find(path.key);
    if (it == Cases().end()) continue;  // WalksEveryField reports it
    const FieldCase& c = it->second;
    const std::string request_name = path.fields.front()->containing_type()->name();
    std::vector<std::string> flags;
    const std::string flag = c.flag.empty() ? FlagName(path) : c.flag;
    EXPECT_EQ(!c.flag.empty(), kSendFileFields.count(path.key) > 0)
        << "only the file fields are set by another flag than their kebab-case name";
    if (!c.values.empty() && c.values[0][0] == '=') {
      flags.push_back(flag + c.values[0]);
    } else {
      flags.push_back(flag);
      flags.insert(flags.end(), c.values.begin(), c.values.end());
    }
    flags.insert(flags.end(), c.extra.begin(), c.extra.end());
    flags.insert(flags.end(), {"-o", "out"});
    absl::StatusOr<std::unique_ptr<Message>> with =
        BuildFromCommandLine(request_name, flags, c.input);
    ASSERT_THAT(with, koma::testing::IsOk()) << absl::StrJoin(flags, " ");
    absl::StatusOr<std::unique_ptr<Message>> without =
        BuildFromCommandLine(request_name, {"-o", "out"}, c.input);
    ASSERT_THAT(without, koma::testing::IsOk());
    if (c.expected == kInputFile) {
      const std::string file = c.input.empty() ? (request_name == "RetimeSkeletalRequest" ? kBvh
                                                  : request_name == "RetimeCurvesRequest" ? kArmHead
                                                                                          : kTalk)
                                               : c.input;
      ASSERT_FALSE(FileBytes(file).empty());
      EXPECT_EQ(RawBytes(**with, path.fields.back()), FileBytes(file));
      EXPECT_EQ(FieldText(**without, path), "<unset>");
      continue;
    }
    EXPECT_EQ(FieldText(**with, path), c.expected) << absl::StrJoin(flags, " ");
    EXPECT_NE(FieldText(**without, path), c.expected)
        << "the case's value is the default, so it proves nothing";
    // A repeated message is set whole: every one of its fields through the one flag.
    const FieldDescriptor* field = path.fields.back();
    if (field->is_repeated() && field->type() == FieldDescriptor::TYPE_MESSAGE) {
      for (int i = 0; i < field->message_type()->field_count(); ++i) {
        const FieldDescriptor* sub = field->message_type()->field(i);
        // Text format: "name: value", and "name { ... }" for a message.
        EXPECT_THAT(c.expected,
                    ::testing::HasSubstr(
                        sub->name() + (sub->type() == FieldDescriptor::TYPE_MESSAGE ? " {" : ":")))
            << "the case leaves " << sub->name() << " unset";
      }
    }
  }
}

// The short names of earlier versions still reach the same fields.
TEST(RequestFlagsTest, AliasesSetTheSameFields) {
  struct Alias {
    std::string request;
    std::vector<std::string> short_form;
    std::vector<std::string> long_form;
  };
  const std::vector<Alias> aliases = {
      {"RetimeSkeletalRequest",
       {"--omit", "5", "--hold", "7", "--hold-first", "--no-keep-length"},
       {"--omissions", "5", "--holds", "7", "--order", "hold-then-omit", "--keep-length=false"}},
      {"RetimeCurvesRequest",
       {"--on", "2", "--keys", "0,10", "--curve-on", "ParamArmRA=1"},
       {"--frames-per-drawing", "2", "--key-frames", "0,10", "--curve-overrides", "ParamArmRA=1"}},
      {"LipBlinkRequest",
       {"--mouth", "ParamMouthOpenY", "--eyes", "ParamEyeLOpen", "--mode", "follow", "--on", "2",
        "--unlinked-eyes", "--auto-blink", "3", "--speech", "1-5"},
       {"--mouth-ids", "ParamMouthOpenY", "--eyes-ids", "ParamEyeLOpen", "--mouth-mode", "follow",
        "--mouth-frames-per-shape", "2", "--eyes-linked", "false", "--auto-blink-mean-interval-s",
        "3", "--mouth-speech", "1-5"}},
  };
  for (const Alias& alias : aliases) {
    std::vector<std::string> a = alias.short_form;
    std::vector<std::string> b = alias.long_form;
    a.insert(a.end(), {"-o", "out"});
    b.insert(b.end(), {"-o", "out"});
    absl::StatusOr<std::unique_ptr<Message>> short_request = BuildFromCommandLine(alias.request, a);
    absl::StatusOr<std::unique_ptr<Message>> long_request = BuildFromCommandLine(alias.request, b);
    ASSERT_THAT(short_request, koma::testing::IsOk());
    ASSERT_THAT(long_request, koma::testing::IsOk());
    EXPECT_EQ((*short_request)->SerializeAsString(), (*long_request)->SerializeAsString())
        << alias.request;
  }
}

TEST(RequestFlagsTest, JointWeightsByPositionAndErrors) {
  std::vector<std::string> weights(21, "1");
  weights[3] = "0.25";
  absl::StatusOr<std::unique_ptr<Message>> r = BuildFromCommandLine(
      "RetimeSkeletalRequest", {"--joint-weights", absl::StrJoin(weights, ","), "-o", "out"});
  ASSERT_THAT(r, koma::testing::IsOk());
  const auto& request = static_cast<const v1::RetimeSkeletalRequest&>(**r);
  ASSERT_EQ(request.joint_weights_size(), 21);
  EXPECT_EQ(request.joint_weights(3), 0.25);
  EXPECT_THAT(
      BuildFromCommandLine("RetimeSkeletalRequest", {"--joint-weights", "1,2", "-o", "o"}),
      koma::testing::StatusIs(absl::StatusCode::kInvalidArgument,
                              ::testing::HasSubstr("--joint-weights: 2 weights for 21 joints")));
  EXPECT_THAT(
      BuildFromCommandLine("RetimeSkeletalRequest", {"--joint-weights", "Hip=2", "-o", "o"}),
      koma::testing::StatusIs(absl::StatusCode::kInvalidArgument,
                              ::testing::HasSubstr("no joint \"Hip\"; did you mean \"Hips\"?")));
}

}  // namespace
}  // namespace koma::client
