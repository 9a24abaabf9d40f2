// LipBlink into a Spine skeleton (LipBlinkRequest.spine_json, `koma lipblink hero.json
// --animation talk --mouth-slot mouth --eye-slot eyes`): the mouth and eye slots become
// curves of the skeleton's fps (mouth: closed; eyes: the animation's eye attachment timeline
// as open 1 / half 0.5 / closed 0, so its closed keys are blinks), the ordinary LipBlink
// request converts them (the voice, mouth.speech or auto-blink as for a motion3.json), and the
// answer's mouth holds and blinks, on the film grid, become the slots' attachment timelines in
// the named animation (formats/spine_attachments.h): one key where the drawing changes, at the
// grid frame's exact time in seconds. Everything else in the file is kept.
//
// Shared by the server (server/lip_blink_spine.h, errors naming the proto fields) and the CLI
// (which checks the slots first to name its flags).
#ifndef KOMA_CONVERT_SPINE_LIP_BLINK_H_
#define KOMA_CONVERT_SPINE_LIP_BLINK_H_

#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "formats/spine.h"
#include "formats/spine_attachments.h"
#include "koma/v1/retime.pb.h"

namespace koma::convert {

// What errors call the settings: the proto's fields, or the CLI's flags.
struct SpineLipBlinkNames {
  std::string animation;          // "spine.animation"
  std::string mouth_slot;         // "spine.mouth_slot"
  std::string mouth_attachments;  // "spine.mouth_attachments"
  std::string eye_slots;          // "spine.eye_slots"
  std::string eye_attachments;    // "spine.eye_attachments"
  std::string voice;              // "a voice (audio, rhubarb_cues) or mouth.speech intervals"
  std::string new_animation;      // "a voice (audio, rhubarb_cues) or mouth.speech"
};
const SpineLipBlinkNames& ProtoSpineLipBlinkNames();

// The slots and their three attachment names, checked against the skeleton.
struct SpineLipBlinkSlots {
  std::string animation;
  bool existing = false;  // the animation is in the file (else it is added)
  std::string mouth;      // empty: no mouth
  std::vector<std::string> mouth_names;  // closed, mid, open
  std::vector<std::string> eyes;
  std::vector<std::vector<std::string>> eye_names;  // per eye slot: open, half, closed
};

// INVALID_ARGUMENT naming the setting and the value: no animation, no slot, a slot the
// skeleton lacks, not three attachments, an attachment the slot has in no skin, a mouth
// without a voice or speech, a new animation without either. Unset attachment names default
// to <slot>_closed,<slot>_mid,<slot>_open and <slot>_open,<slot>_half,<slot>_closed.
absl::StatusOr<SpineLipBlinkSlots> SpineLipBlinkSlotsOf(const v1::SpineLipBlinkSettings& settings,
                                                        const formats::SpineFile& file,
                                                        bool has_voice, bool has_speech,
                                                        const SpineLipBlinkNames& names);

// The decoded LipBlink request for the skeleton: `request`'s settings and voice with curves at
// skeleton.fps over the animation (or, for a new animation with a voice, none: the voice's
// motion at skeleton.fps covers the recording), the slots as the mouth and eye ids, levels 0..1.
absl::StatusOr<v1::LipBlinkRequest> DecodedSpineLipBlinkRequest(const v1::LipBlinkRequest& request,
                                                                const formats::SpineFile& file,
                                                                const SpineLipBlinkSlots& slots);

// The slots' attachment timelines from the decoded request's answer, keyed on the grid.
absl::StatusOr<std::vector<formats::SpineAttachmentTimeline>> SpineTimelinesOf(
    const formats::SpineFile& file, const SpineLipBlinkSlots& slots,
    const v1::LipBlinkResponse& response);

}  // namespace koma::convert

#endif  // KOMA_CONVERT_SPINE_LIP_BLINK_H_
