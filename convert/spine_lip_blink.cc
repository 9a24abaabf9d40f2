#include "convert/spine_lip_blink.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "convert/curves_convert.h"
#include "core/curves.h"
#include "core/film_grid.h"
#include "core/lip_blink.h"
#include "formats/error_text.h"

namespace koma::convert {
namespace {

// An eye drawing as a level of the eye curve LipBlink converts (levels 0 .. 1, mid ratio 0.5
// by default): closed 0 is a blink, half 0.5 is not.
constexpr double kEyeOpen = 1.0, kEyeHalf = 0.5, kEyeClosed = 0.0;

// The three names for `slot`: `given`, or the slot name with the default suffixes; each an
// attachment of the slot in some skin.
absl::StatusOr<std::vector<std::string>> ThreeNames(const formats::SpineFile& file,
                                                    const std::string& slot_name,
                                                    const std::string& slot,
                                                    const std::string& names_name,
                                                    const std::vector<std::string>& given,
                                                    const char* const (&suffixes)[3]) {
  absl::StatusOr<std::vector<std::string>> has = formats::SpineSlotAttachments(file, slot);
  if (!has.ok()) {
    return absl::InvalidArgumentError(absl::StrCat(slot_name, " ", has.status().message()));
  }
  std::vector<std::string> names = given;
  if (names.empty()) {
    for (const char* suffix : suffixes) names.push_back(absl::StrCat(slot, "_", suffix));
  } else if (names.size() != 3) {
    return absl::InvalidArgumentError(absl::StrCat(
        names_name, ": expected three attachment names (", suffixes[0], ",", suffixes[1], ",",
        suffixes[2], "), got ", names.size(), ": ", absl::StrJoin(names, ",")));
  }
  for (const std::string& name : names) {
    if (std::find(has->begin(), has->end(), name) == has->end()) {
      return absl::InvalidArgumentError(absl::StrCat(
          names_name, ": ", formats::QuoteForError(name), " is not an attachment of slot \"",
          slot, "\" in any skin (it has ", has->empty() ? "none" : absl::StrJoin(*has, ", "),
          ")", given.empty() ? "; name the three with " + names_name : ""));
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

std::vector<std::string> Strings(const google::protobuf::RepeatedPtrField<std::string>& in) {
  return {in.begin(), in.end()};
}

}  // namespace

const SpineLipBlinkNames& ProtoSpineLipBlinkNames() {
  static const SpineLipBlinkNames* const names = new SpineLipBlinkNames{
      "spine.animation",
      "spine.mouth_slot",
      "spine.mouth_attachments",
      "spine.eye_slots",
      "spine.eye_attachments",
      "a voice (audio, rhubarb_cues) or mouth.speech intervals",
      "a voice (audio, rhubarb_cues) or mouth.speech"};
  return *names;
}

absl::StatusOr<SpineLipBlinkSlots> SpineLipBlinkSlotsOf(const v1::SpineLipBlinkSettings& settings,
                                                        const formats::SpineFile& file,
                                                        bool has_voice, bool has_speech,
                                                        const SpineLipBlinkNames& names) {
  SpineLipBlinkSlots slots;
  if (settings.animation().empty()) {
    return absl::InvalidArgumentError(absl::StrCat(
        names.animation, ": the Spine animation to write the mouth and eyes into is required"));
  }
  slots.animation = settings.animation();
  slots.existing = formats::FindSpineAnimation(file, settings.animation()).ok();
  if (settings.mouth_slot().empty() && settings.eye_slots().empty()) {
    return absl::InvalidArgumentError(absl::StrCat(
        names.mouth_slot, " and/or ", names.eye_slots,
        ": a Spine skeleton needs the slots to key"));
  }
  const std::vector<std::string> mouth_given = Strings(settings.mouth_attachments());
  const std::vector<std::string> eye_given = Strings(settings.eye_attachments());
  if (!settings.mouth_slot().empty()) {
    static constexpr const char* kMouth[3] = {"closed", "mid", "open"};
    absl::StatusOr<std::vector<std::string>> three =
        ThreeNames(file, names.mouth_slot, settings.mouth_slot(), names.mouth_attachments,
                   mouth_given, kMouth);
    if (!three.ok()) return three.status();
    slots.mouth = settings.mouth_slot();
    slots.mouth_names = *std::move(three);
    if (!has_voice && !has_speech) {
      return absl::InvalidArgumentError(absl::StrCat(names.mouth_slot, " ", settings.mouth_slot(),
                                                     ": the mouth needs ", names.voice));
    }
  } else if (!mouth_given.empty()) {
    return absl::InvalidArgumentError(
        absl::StrCat(names.mouth_attachments, ": needs ", names.mouth_slot));
  }
  if (settings.eye_slots().empty() && !eye_given.empty()) {
    return absl::InvalidArgumentError(
        absl::StrCat(names.eye_attachments, ": needs ", names.eye_slots));
  }
  for (const std::string& eye : settings.eye_slots()) {
    static constexpr const char* kEyes[3] = {"open", "half", "closed"};
    absl::StatusOr<std::vector<std::string>> three =
        ThreeNames(file, names.eye_slots, eye, names.eye_attachments, eye_given, kEyes);
    if (!three.ok()) return three.status();
    if (eye == slots.mouth ||
        std::count(settings.eye_slots().begin(), settings.eye_slots().end(), eye) > 1) {
      return absl::InvalidArgumentError(absl::StrCat(
          names.eye_slots, ": \"", eye, "\" is named twice (or is the mouth slot)"));
    }
    slots.eye_names.push_back(*std::move(three));
    slots.eyes.push_back(eye);
  }
  if (!slots.existing && !has_voice && !has_speech) {
    return absl::InvalidArgumentError(absl::StrCat(
        names.animation, " ", formats::QuoteForError(settings.animation()),
        ": not an animation of the skeleton; a new one takes its length from ",
        names.new_animation));
  }
  return slots;
}

absl::StatusOr<v1::LipBlinkRequest> DecodedSpineLipBlinkRequest(const v1::LipBlinkRequest& request,
                                                                const formats::SpineFile& file,
                                                                const SpineLipBlinkSlots& slots) {
  const double fps = file.fps;
  const bool has_voice = request.voice_case() != v1::LipBlinkRequest::VOICE_NOT_SET;
  // Frames as a double, saturated at INT32_MAX: a huge duration or interval end is then
  // refused by the decoded request's frame_count limit (--max_values), never overflows.
  double frames = 0;
  if (slots.existing) {
    absl::StatusOr<int> index = formats::FindSpineAnimation(file, slots.animation);
    if (!index.ok()) return index.status();
    frames = std::round(file.animations[*index].duration * fps) + 1;
  } else if (!has_voice) {
    for (const v1::FrameInterval& i : request.mouth().speech()) {
      frames = std::max(frames, static_cast<double>(i.end()) + 1);
    }
  }
  constexpr double kMaxFrames = 2147483647.0;
  CurveSet set;
  set.fps = fps;
  set.frame_count = !(frames < kMaxFrames) ? static_cast<int>(kMaxFrames)
                                           : std::max(static_cast<int>(frames), 2);
  const bool voice_only = !slots.existing && has_voice;
  if (!voice_only) {
    if (!slots.mouth.empty()) {
      set.curves.push_back(SteppedCurve(slots.mouth, 0.0, {}, set.frame_count));
    }
    for (size_t e = 0; e < slots.eyes.size(); ++e) {
      absl::StatusOr<Curve> curve = EyeCurve(file, slots, e, fps, set.frame_count);
      if (!curve.ok()) return curve.status();
      set.curves.push_back(*std::move(curve));
    }
  }
  v1::LipBlinkRequest decoded = request;
  decoded.clear_spine();
  if (voice_only) {
    decoded.clear_input();
    decoded.set_voice_motion_fps(fps);
    decoded.set_voice_output(v1::VOICE_OUTPUT_MOTION3_JSON);
  } else {
    *decoded.mutable_curves() = CurveSetToProto(set);  // replaces spine_json
  }
  v1::MouthSettings* mouth = decoded.mutable_mouth();
  mouth->clear_ids();
  if (!slots.mouth.empty()) mouth->add_ids(slots.mouth);
  mouth->set_min(0.0);
  mouth->set_max(1.0);
  v1::EyeSettings* eyes = decoded.mutable_eyes();
  eyes->clear_ids();
  // A new animation's eyes exist only with auto-blink (the voice's motion adds them, open).
  if (!voice_only || eyes->auto_blink().enabled()) {
    for (const std::string& eye : slots.eyes) eyes->add_ids(eye);
  }
  eyes->set_min(kEyeClosed);
  eyes->set_max(kEyeOpen);
  return decoded;
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

}  // namespace koma::convert
