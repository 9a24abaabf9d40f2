#include "client/spine_lip_blink.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "client/channel.h"
#include "client/curves_convert.h"
#include "client/files.h"
#include "client/retime_call.h"
#include "client/xdts_sheets.h"
#include "formats/xdts.h"
#include "core/film_grid.h"
#include "core/lip_blink.h"
#include "formats/error_text.h"
#include "koma/v1/retime.grpc.pb.h"

namespace koma::client {
namespace {

// An eye drawing as a level of the eye curve sent to LipBlink (EyeSettings min 0, max 1, mid
// ratio 0.5 by default): closed 0 is a blink, half 0.5 is not.
constexpr double kEyeOpen = 1.0, kEyeHalf = 0.5, kEyeClosed = 0.0;

// The three names for `slot`: `given`, or the slot name with the default suffixes; each an
// attachment of the slot in some skin.
absl::StatusOr<std::vector<std::string>> ThreeNames(const formats::SpineFile& file,
                                                    const std::string& slot_flag,
                                                    const std::string& slot,
                                                    const std::string& names_flag,
                                                    const std::vector<std::string>& given,
                                                    const char* const (&suffixes)[3]) {
  absl::StatusOr<std::vector<std::string>> has = formats::SpineSlotAttachments(file, slot);
  if (!has.ok()) {
    return absl::InvalidArgumentError(absl::StrCat(slot_flag, " ", has.status().message()));
  }
  std::vector<std::string> names = given;
  if (names.empty()) {
    for (const char* suffix : suffixes) names.push_back(absl::StrCat(slot, "_", suffix));
  } else if (names.size() != 3) {
    return absl::InvalidArgumentError(absl::StrCat(
        names_flag, ": expected three attachment names (", suffixes[0], ",", suffixes[1], ",",
        suffixes[2], "), got ", names.size(), ": ", absl::StrJoin(names, ",")));
  }
  for (const std::string& name : names) {
    if (std::find(has->begin(), has->end(), name) == has->end()) {
      return absl::InvalidArgumentError(absl::StrCat(
          names_flag, ": ", formats::QuoteForError(name), " is not an attachment of slot \"",
          slot, "\" in any skin (it has ", has->empty() ? "none" : absl::StrJoin(*has, ", "),
          ")", given.empty() ? "; name the three with " + names_flag : ""));
    }
  }
  return names;
}

// A stepped curve from (frame, value) keys, frames 0 .. frame_count - 1.
Curve SteppedCurve(const std::string& id, double first, const std::vector<CurvePoint>& keys,
                   int frame_count) {
  Curve curve;
  curve.id = id;
  curve.start = {0.0, first};
  const double last = frame_count - 1;
  double value = first;
  for (const CurvePoint& key : keys) {
    if (!(key.frame > curve.start.frame) || key.frame > last) continue;
    if (!curve.segments.empty() && !(key.frame > curve.segments.back().end.frame)) continue;
    CurveSegment segment;
    segment.type = SegmentType::kStepped;
    segment.end = key;
    curve.segments.push_back(segment);
    value = key.value;
  }
  if (curve.segments.empty() || curve.segments.back().end.frame < last) {
    CurveSegment segment;
    segment.type = SegmentType::kStepped;
    segment.end = {last, value};
    curve.segments.push_back(segment);
  }
  return curve;
}

double EyeLevel(const std::string& name, const std::vector<std::string>& names) {
  if (name == names[1]) return kEyeHalf;
  if (name == names[2]) return kEyeClosed;
  return kEyeOpen;  // open, or any other drawing
}

// The eye slot's attachment timeline in the animation as an eye curve at `fps`.
absl::StatusOr<Curve> EyeCurve(const formats::SpineFile& file, const SpineLipBlinkSlots& slots,
                               size_t e, double fps, int frame_count) {
  const std::string& slot = slots.eyes[e];
  const std::vector<std::string>& names = slots.eye_names[e];
  absl::StatusOr<std::vector<formats::SpineAttachmentKey>> keys =
      formats::SpineAttachmentKeys(file, slots.animation, slot);
  if (!keys.ok()) return keys.status();
  double first = EyeLevel(formats::SpineSetupAttachment(file, slot), names);
  std::vector<CurvePoint> points;
  for (const formats::SpineAttachmentKey& key : *keys) {
    const double level = EyeLevel(key.name, names);
    if (key.time <= 0) {
      first = level;
    } else {
      points.push_back({key.time * fps, level});
    }
  }
  return SteppedCurve(slot, first, points, frame_count);
}

// One key at frame 0 and one wherever the drawing changes, at frame / rate seconds.
std::vector<formats::SpineAttachmentKey> KeysOf(const std::vector<MouthShape>& drawings,
                                                const std::vector<std::string>& names,
                                                bool eye, double rate) {
  std::vector<formats::SpineAttachmentKey> keys;
  for (size_t g = 0; g < drawings.size(); ++g) {
    if (g > 0 && drawings[g] == drawings[g - 1]) continue;
    // Mouth names: closed, mid, open; eye names: open, half, closed.
    const int index = static_cast<int>(drawings[g]);
    keys.push_back({static_cast<double>(g) / rate, names[eye ? 2 - index : index]});
  }
  return keys;
}

std::vector<MouthHold> HoldsOf(const v1::MouthTrack& track) {
  std::vector<MouthHold> holds;
  for (const v1::MouthHold& h : track.holds()) {
    const MouthShape shape = h.shape() == v1::MOUTH_OPEN  ? MouthShape::kOpen
                             : h.shape() == v1::MOUTH_MID ? MouthShape::kMid
                                                          : MouthShape::kClosed;
    holds.push_back({h.begin(), h.length(), shape});
  }
  return holds;
}

std::vector<Blink> BlinksOf(const v1::EyeTrack& track) {
  std::vector<Blink> blinks;
  for (const v1::Blink& b : track.blinks()) {
    Blink blink;
    blink.closing_begin = b.closing_begin();
    blink.closed_begin = b.closed_begin();
    blink.closed_end = b.closed_end();
    blink.open_span = b.open_span();
    blink.hold = b.hold();
    blink.automatic = b.automatic();
    blinks.push_back(blink);
  }
  return blinks;
}

}  // namespace

absl::StatusOr<SpineLipBlinkSlots> SpineLipBlinkSlotsOf(const LipBlinkArgs& args,
                                                        const formats::SpineFile& file) {
  SpineLipBlinkSlots slots;
  if (args.spine_animation.empty()) {
    return absl::InvalidArgumentError(
        "--animation NAME: the Spine animation to write the mouth and eyes into is required");
  }
  slots.animation = args.spine_animation;
  slots.existing = formats::FindSpineAnimation(file, args.spine_animation).ok();
  if (args.mouth_slot.empty() && args.eye_slots.empty()) {
    return absl::InvalidArgumentError(
        "--mouth-slot SLOT and/or --eye-slot SLOT: a Spine skeleton needs the slots to key");
  }
  if (!args.mouth_slot.empty()) {
    static constexpr const char* kMouth[3] = {"closed", "mid", "open"};
    absl::StatusOr<std::vector<std::string>> names =
        ThreeNames(file, "--mouth-slot", args.mouth_slot, "--mouth-attachments",
                   args.mouth_attachments, kMouth);
    if (!names.ok()) return names.status();
    slots.mouth = args.mouth_slot;
    slots.mouth_names = *std::move(names);
    if (!HasVoice(args) && args.speech.empty()) {
      return absl::InvalidArgumentError(absl::StrCat(
          "--mouth-slot ", args.mouth_slot,
          ": the mouth needs a voice (--audio FILE, --rhubarb FILE) or --speech intervals"));
    }
  } else if (!args.mouth_attachments.empty()) {
    return absl::InvalidArgumentError("--mouth-attachments: needs --mouth-slot SLOT");
  }
  if (args.eye_slots.empty() && !args.eye_attachments.empty()) {
    return absl::InvalidArgumentError("--eye-attachments: needs --eye-slot SLOT");
  }
  for (const std::string& eye : args.eye_slots) {
    static constexpr const char* kEyes[3] = {"open", "half", "closed"};
    absl::StatusOr<std::vector<std::string>> names =
        ThreeNames(file, "--eye-slot", eye, "--eye-attachments", args.eye_attachments, kEyes);
    if (!names.ok()) return names.status();
    if (eye == slots.mouth || std::count(args.eye_slots.begin(), args.eye_slots.end(), eye) > 1) {
      return absl::InvalidArgumentError(
          absl::StrCat("--eye-slot: \"", eye, "\" is named twice (or is the mouth slot)"));
    }
    slots.eye_names.push_back(*std::move(names));
    slots.eyes.push_back(eye);
  }
  if (!slots.existing && !HasVoice(args) && args.speech.empty()) {
    return absl::InvalidArgumentError(absl::StrCat(
        "--animation ", formats::QuoteForError(args.spine_animation),
        ": not an animation of the skeleton; a new one takes its length from a voice "
        "(--audio, --rhubarb) or --speech"));
  }
  return slots;
}

absl::StatusOr<v1::LipBlinkRequest> BuildSpineLipBlinkRequest(const LipBlinkArgs& args,
                                                              const formats::SpineFile& file,
                                                              const SpineLipBlinkSlots& slots,
                                                              std::string voice) {
  const double fps = file.fps;
  int frames = 0;
  if (slots.existing) {
    absl::StatusOr<int> index = formats::FindSpineAnimation(file, slots.animation);
    if (!index.ok()) return index.status();
    frames = static_cast<int>(std::lround(file.animations[*index].duration * fps)) + 1;
  } else if (!HasVoice(args)) {
    for (const FlagInterval& i : args.speech) frames = std::max(frames, i.end + 1);
  }
  CurveSet set;
  set.fps = fps;
  set.frame_count = std::max(frames, 2);
  const bool voice_only = !slots.existing && HasVoice(args);
  if (!voice_only) {
    if (!slots.mouth.empty()) set.curves.push_back(SteppedCurve(slots.mouth, 0.0, {}, set.frame_count));
    for (size_t e = 0; e < slots.eyes.size(); ++e) {
      absl::StatusOr<Curve> curve = EyeCurve(file, slots, e, fps, set.frame_count);
      if (!curve.ok()) return curve.status();
      set.curves.push_back(*std::move(curve));
    }
  }
  v1::LipBlinkRequest request = BuildLipBlinkRequest(args, set);
  v1::MouthSettings* mouth = request.mutable_mouth();
  mouth->clear_ids();
  if (!slots.mouth.empty()) mouth->add_ids(slots.mouth);
  mouth->set_min(0.0);
  mouth->set_max(1.0);
  v1::EyeSettings* eyes = request.mutable_eyes();
  eyes->clear_ids();
  // A new animation's eyes exist only with auto-blink (the server adds them, open).
  if (!voice_only || eyes->auto_blink().enabled()) {
    for (const std::string& eye : slots.eyes) eyes->add_ids(eye);
  }
  eyes->set_min(kEyeClosed);
  eyes->set_max(kEyeOpen);
  if (HasVoice(args)) {
    if (voice_only) {
      request.clear_curves();
      request.set_voice_motion_fps(fps);
      request.set_voice_output(v1::VOICE_OUTPUT_MOTION3_JSON);
    }
    if (!args.audio.empty()) {
      request.set_audio(std::move(voice));
    } else {
      request.set_rhubarb_cues(std::move(voice));
      if (args.mode.empty()) request.mutable_mouth()->clear_mode();
    }
  }
  return request;
}

absl::StatusOr<std::vector<formats::SpineAttachmentTimeline>> SpineTimelinesOf(
    const formats::SpineFile& file, const SpineLipBlinkSlots& slots,
    const v1::LipBlinkResponse& response) {
  if (response.curves().empty()) return absl::InternalError("the answer has no curves");
  const int source_frames = response.curves(0).values_size();
  const double timing = response.timing_fps();
  std::optional<FilmGrid> grid;
  if (timing > 0) grid = FilmGrid::Make(file.fps, timing);
  const int frames = grid ? grid->GridFrameCount(source_frames) : source_frames;
  const double rate = grid ? timing : file.fps;
  std::vector<formats::SpineAttachmentTimeline> timelines;
  for (const v1::MouthTrack& track : response.mouths()) {
    if (track.id() != slots.mouth) continue;
    timelines.push_back(
        {slots.mouth, KeysOf(MouthDrawings(HoldsOf(track), frames), slots.mouth_names, false, rate)});
  }
  for (const v1::EyeTrack& track : response.eyes()) {
    const auto it = std::find(slots.eyes.begin(), slots.eyes.end(), track.id());
    if (it == slots.eyes.end()) continue;
    const std::vector<std::string>& names = slots.eye_names[it - slots.eyes.begin()];
    timelines.push_back(
        {track.id(), KeysOf(BlinkDrawings(BlinksOf(track), frames), names, true, rate)});
  }
  return timelines;
}

int RunLipBlinkSpine(const LipBlinkArgs& args, const CommandOutput& out, const CurveInput& input) {
  if (args.send_file || !args.report.empty() || !args.motion.empty() ||
      args.voice_motion_fps || !args.voice_output.empty()) {
    return out.UsageFailure(absl::InvalidArgumentError(
        "--send-file, --report, --motion, --voice-motion-fps, --voice-output: not for a Spine "
        "skeleton (IN is the motion; its fps is the skeleton's)"));
  }
  if (absl::Status s = CheckWritable({args.output, args.cues, args.xdts}); !s.ok()) {
    return out.Failure(s);
  }
  const formats::SpineFile& file = *input.spine;
  absl::StatusOr<SpineLipBlinkSlots> slots = SpineLipBlinkSlotsOf(args, file);
  if (!slots.ok()) return out.UsageFailure(slots.status());
  std::string voice;
  if (HasVoice(args)) {
    absl::StatusOr<std::string> read = ReadFile(args.audio.empty() ? args.rhubarb : args.audio);
    if (!read.ok()) return out.Failure(read.status());
    voice = *std::move(read);
  }
  absl::StatusOr<v1::LipBlinkRequest> request =
      BuildSpineLipBlinkRequest(args, file, *slots, std::move(voice));
  if (!request.ok()) return out.Failure(request.status());
  v1::LipBlinkResponse response;
  if (int code = CallRetime(args, out, &v1::Retime::Stub::LipBlink, *request, &response);
      code >= 0) {
    return code;
  }
  absl::StatusOr<std::vector<formats::SpineAttachmentTimeline>> timelines =
      SpineTimelinesOf(file, *slots, response);
  if (!timelines.ok()) return out.Failure(timelines.status());
  absl::StatusOr<std::string> text =
      formats::WriteSpineAttachments(file, slots->animation, *timelines);
  if (!text.ok()) return out.Failure(text.status());
  if (absl::Status s = WriteFile(args.output, *text); !s.ok()) return out.Failure(s);
  if (!args.xdts.empty()) {  // the exposure sheet of the same answer, as for a motion3.json
    absl::StatusOr<formats::XdtsSheet> sheet =
        LipBlinkXdtsSheet(response, file.fps, XdtsClipName(args.input, args.xdts));
    if (!sheet.ok()) return out.Failure(sheet.status());
    if (absl::Status s = WriteFile(args.xdts, formats::WriteXdts(*sheet)); !s.ok()) {
      return out.Failure(s);
    }
  }
  if (!args.cues.empty() && HasVoice(args)) {
    const bool tsv = args.cues.size() >= 4 && args.cues.substr(args.cues.size() - 4) == ".tsv";
    if (absl::Status s = WriteFile(args.cues, tsv ? response.rhubarb_tsv() : response.rhubarb_json());
        !s.ok()) {
      return out.Failure(s);
    }
  }
  std::string text_summary = absl::StrCat(OutputName(args.output), ": animation \"",
                                          slots->animation, "\"", slots->existing ? "" : " (new)");
  nlohmann::json summary = {{"output", args.output}, {"animation", slots->animation},
                            {"new_animation", !slots->existing},
                            {"timing_fps", response.timing_fps()}};
  nlohmann::json slot_list = nlohmann::json::array();
  for (const formats::SpineAttachmentTimeline& t : *timelines) {
    absl::StrAppend(&text_summary, ", slot ", t.slot, " ", t.keys.size(), " keys");
    nlohmann::json keys = nlohmann::json::array();
    for (const formats::SpineAttachmentKey& k : t.keys) keys.push_back({{"time", k.time}, {"name", k.name}});
    slot_list.push_back({{"slot", t.slot}, {"keys", std::move(keys)}});
  }
  summary["slots"] = std::move(slot_list);
  out.Success(text_summary + "\n" + XdtsLine(args.xdts), summary,
              IsStdio(args.output) || IsStdio(args.cues) || IsStdio(args.xdts));
  return kExitOk;
}

}  // namespace koma::client
