// `koma lipblink hero.json --animation talk --audio voice.flac --mouth-slot mouth
//  --eye-slot eyes -o out.json`: LipBlink into a Spine skeleton. The mouth and eye slots become
// curves of the skeleton's fps (mouth: closed; eyes: the animation's eye attachment timeline as
// open 1 / half 0.5 / closed 0, so its closed keys are blinks), the ordinary LipBlink RPC
// converts them (the voice, --speech or auto-blink as for a motion3.json), and the answer's
// mouth holds and blinks, on the film grid, become the slots' attachment timelines in the
// named animation (formats/spine_attachments.h): one key where the drawing changes, at the
// grid frame's exact time in seconds. Everything else in the file is kept.
#ifndef KOMA_CLIENT_SPINE_LIP_BLINK_H_
#define KOMA_CLIENT_SPINE_LIP_BLINK_H_

#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "client/command_output.h"
#include "client/curve_files.h"
#include "client/lip_blink_command.h"
#include "formats/spine.h"
#include "formats/spine_attachments.h"
#include "koma/v1/retime.pb.h"

namespace koma::client {

// The slots and their three attachment names, checked against the skeleton.
struct SpineLipBlinkSlots {
  std::string animation;
  bool existing = false;  // the animation is in the file (else it is added)
  std::string mouth;      // empty: no mouth
  std::vector<std::string> mouth_names;  // closed, mid, open
  std::vector<std::string> eyes;
  std::vector<std::vector<std::string>> eye_names;  // per eye slot: open, half, closed
};

// INVALID_ARGUMENT naming the flag and the value: no --animation, no slot, a slot the skeleton
// lacks, not three attachments, an attachment the slot has in no skin, a mouth without a voice
// or --speech. Unset attachment names default to <slot>_closed,<slot>_mid,<slot>_open and
// <slot>_open,<slot>_half,<slot>_closed.
absl::StatusOr<SpineLipBlinkSlots> SpineLipBlinkSlotsOf(const LipBlinkArgs& args,
                                                        const formats::SpineFile& file);

// The LipBlink request for the skeleton: curves at skeleton.fps over the animation (or, for a
// new animation with a voice, none: the server's motion covers the recording), the voice.
absl::StatusOr<v1::LipBlinkRequest> BuildSpineLipBlinkRequest(const LipBlinkArgs& args,
                                                              const formats::SpineFile& file,
                                                              const SpineLipBlinkSlots& slots,
                                                              std::string voice);

// The slots' attachment timelines from the answer (mouths[0], eyes[i]), keyed on the grid.
absl::StatusOr<std::vector<formats::SpineAttachmentTimeline>> SpineTimelinesOf(
    const formats::SpineFile& file, const SpineLipBlinkSlots& slots,
    const v1::LipBlinkResponse& response);

// `input`: IN as read (input.spine set).
int RunLipBlinkSpine(const LipBlinkArgs& args, const CommandOutput& out, const CurveInput& input);

}  // namespace koma::client

#endif  // KOMA_CLIENT_SPINE_LIP_BLINK_H_
