#include "client/lip_blink_summary.h"

#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "client/files.h"
#include "convert/curve_text.h"
#include "convert/curves_convert.h"

namespace koma::client {
namespace {

// --mode as the server applies it: unset is random, or follow for Rhubarb cues.
std::string MouthModeName(const LipBlinkArgs& args) {
  if (!args.mode.empty()) return args.mode;
  return args.rhubarb.empty() ? "random" : "follow";
}

// Frame numbers of the response: the curves' frames, or film-grid frames (timing_fps > 0),
// which the summary also gives in seconds.
struct Frames {
  double grid_fps = 0;
  const char* noun() const { return grid_fps > 0 ? "grid frames" : "frames"; }
  const char* one() const { return grid_fps > 0 ? "grid frame" : "frame"; }
  std::string Range(int first, int last) const {
    std::string text = absl::StrCat(first, "-", last);
    if (grid_fps > 0) {
      absl::StrAppend(&text,
                      absl::StrFormat(" (%.2f-%.2f s)", first / grid_fps, (last + 1) / grid_fps));
    }
    return text;
  }
  std::string At(int frame) const {
    return grid_fps > 0 ? absl::StrFormat("%d (%.2f s)", frame, frame / grid_fps)
                        : absl::StrCat(frame);
  }
};

std::string MouthLine(const v1::MouthTrack& mouth, const Frames& frames) {
  std::vector<std::string> speech;
  for (const v1::FrameInterval& i : mouth.speech()) {
    speech.push_back(frames.Range(i.begin(), i.end() - 1));
  }
  std::vector<std::string> shapes;
  for (const v1::MouthHold& hold : mouth.holds()) shapes.push_back(convert::MouthShapeName(hold.shape()));
  return absl::StrFormat("  mouth %s: speech at %s %s; %d holds: %s\n", mouth.id(), frames.noun(),
                         speech.empty() ? "none" : absl::StrJoin(speech, ", "), mouth.holds_size(),
                         absl::StrJoin(shapes, " "));
}

std::string EyeLine(const v1::EyeTrack& eye, const Frames& frames) {
  std::vector<std::string> blinks;
  for (const v1::Blink& b : eye.blinks()) {
    blinks.push_back(absl::StrCat(frames.one(), " ", frames.At(b.closed_begin()), " (hold ",
                                  b.hold(), b.automatic() ? ", auto)" : ")"));
  }
  return absl::StrFormat("  eye %s: %d blinks%s%s\n", eye.id(), eye.blinks_size(),
                         blinks.empty() ? "" : ": ", absl::StrJoin(blinks, ", "));
}

nlohmann::json Intervals(const google::protobuf::RepeatedPtrField<v1::FrameInterval>& list) {
  nlohmann::json out = nlohmann::json::array();
  for (const v1::FrameInterval& i : list) out.push_back({{"begin", i.begin()}, {"end", i.end()}});
  return out;
}

}  // namespace

std::string LipBlinkSummaryText(const LipBlinkArgs& args, const CurveSet& curves,
                                const v1::LipBlinkResponse& response) {
  std::string text = absl::StrFormat("%s: %d frames at %.4g fps -> %s (seed %d, %s mouth)\n",
                                     InputName(args.input), curves.frame_count, curves.fps,
                                     OutputName(args.output), response.seed(), MouthModeName(args));
  const Frames frames{response.timing_fps()};
  if (frames.grid_fps > 0) {
    absl::StrAppendFormat(
        &text,
        "  on the %.4g fps film grid: holds and frames below are its frames (%.1f ms each)\n",
        frames.grid_fps, 1000.0 / frames.grid_fps);
  }
  for (const v1::MouthTrack& mouth : response.mouths()) text += MouthLine(mouth, frames);
  for (const v1::EyeTrack& eye : response.eyes()) text += EyeLine(eye, frames);
  return text;
}

nlohmann::json LipBlinkSummaryJson(const LipBlinkArgs& args, const CurveSet& curves,
                                   const v1::LipBlinkResponse& response) {
  nlohmann::json j;
  j["input"] = args.input;
  j["outputs"] = {{"curves", args.output}};
  if (!args.report.empty()) j["outputs"]["report"] = args.report;
  if (!args.xdts.empty()) j["outputs"]["xdts"] = args.xdts;
  j["frames"] = curves.frame_count;
  j["fps"] = curves.fps;
  j["seed"] = response.seed();
  j["mouth_mode"] = MouthModeName(args);
  j["timing_fps"] = response.timing_fps();
  j["mouths"] = nlohmann::json::array();
  for (const v1::MouthTrack& mouth : response.mouths()) {
    nlohmann::json holds = nlohmann::json::array();
    for (const v1::MouthHold& h : mouth.holds()) {
      holds.push_back(
          {{"begin", h.begin()}, {"length", h.length()}, {"shape", convert::MouthShapeName(h.shape())}});
    }
    j["mouths"].push_back({{"id", mouth.id()},
                           {"speech", Intervals(mouth.speech())},
                           {"holds", holds},
                           {"closed_level", mouth.closed_level()},
                           {"mid_level", mouth.mid_level()},
                           {"open_level", mouth.open_level()}});
  }
  j["eyes"] = nlohmann::json::array();
  for (const v1::EyeTrack& eye : response.eyes()) {
    nlohmann::json blinks = nlohmann::json::array();
    for (const v1::Blink& b : eye.blinks()) {
      blinks.push_back({{"closing_begin", b.closing_begin()},
                        {"closed_begin", b.closed_begin()},
                        {"closed_end", b.closed_end()},
                        {"open_span", b.open_span()},
                        {"hold", b.hold()},
                        {"automatic", b.automatic()}});
    }
    j["eyes"].push_back({{"id", eye.id()},
                         {"blinks", blinks},
                         {"closed_level", eye.closed_level()},
                         {"mid_level", eye.mid_level()},
                         {"open_level", eye.open_level()}});
  }
  return j;
}

namespace {

// The motion the server wrote (for its frame count and rate).
CurveSet WrittenCurves(const LipBlinkArgs& args, const v1::LipBlinkResponse& response) {
  const bool csv = response.has_csv_text();
  absl::StatusOr<convert::CurveInput> input = convert::ParseCurveText(
      csv ? response.csv_text() : response.motion3_json(), csv, args.csv_fps);
  return input.ok() ? input->curves : CurveSet{};
}

LipBlinkArgs VoiceArgs(const LipBlinkArgs& args) {
  LipBlinkArgs named = args;
  named.input = args.audio.empty() ? args.rhubarb : args.audio;
  return named;
}

}  // namespace

std::string LipBlinkVoiceSummaryText(const LipBlinkArgs& args,
                                     const v1::LipBlinkResponse& response) {
  const v1::LipBlinkVoiceAnalysis& v = response.voice();
  std::string text;
  if (!args.audio.empty()) {
    absl::StrAppendFormat(&text, "%s: %.3f s, %d Hz, %d channel%s", InputName(args.audio),
                          v.duration_s(), v.sample_rate(), v.channels(),
                          v.channels() == 1 ? "" : "s");
  } else {
    absl::StrAppendFormat(&text, "%s: %.3f s of Rhubarb cues", InputName(args.rhubarb),
                          v.duration_s());
  }
  const std::string& motion = args.motion.empty() ? args.input : args.motion;
  absl::StrAppend(&text, motion.empty() ? ", a new motion\n"
                                        : absl::StrCat(", into ", InputName(motion), "\n"));
  if (!args.audio.empty()) {
    absl::StrAppendFormat(&text,
                          "  loudness: noise floor %.1f dBFS; speech starts above %.1f dBFS, "
                          "stays above %.1f dBFS; loud %.1f dBFS\n",
                          v.noise_floor_dbfs(), v.start_dbfs(), v.stay_dbfs(), v.loud_dbfs());
  }
  text += LipBlinkSummaryText(VoiceArgs(args), WrittenCurves(args, response), response);
  if (!args.cues.empty()) absl::StrAppend(&text, "  cues: ", OutputName(args.cues), "\n");
  return text;
}

nlohmann::json LipBlinkVoiceSummaryJson(const LipBlinkArgs& args,
                                        const v1::LipBlinkResponse& response) {
  nlohmann::json j =
      LipBlinkSummaryJson(VoiceArgs(args), WrittenCurves(args, response), response);
  if (!args.cues.empty()) j["outputs"]["cues"] = args.cues;
  const v1::LipBlinkVoiceAnalysis& v = response.voice();
  j["voice"] = {{"kind", args.audio.empty() ? "rhubarb" : "audio"},
                {"sample_rate", v.sample_rate()},
                {"channels", v.channels()},
                {"duration_s", v.duration_s()},
                {"frame_fps", v.frame_fps()},
                {"noise_floor_dbfs", v.noise_floor_dbfs()},
                {"start_dbfs", v.start_dbfs()},
                {"stay_dbfs", v.stay_dbfs()},
                {"loud_dbfs", v.loud_dbfs()},
                {"speech", Intervals(v.speech())}};
  const std::string& motion = args.motion.empty() ? args.input : args.motion;
  if (!motion.empty()) j["voice"]["motion"] = motion;
  return j;
}

}  // namespace koma::client
