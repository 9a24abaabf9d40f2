// `koma lipblink hero.json --animation talk --audio voice.flac --mouth-slot mouth
//  --eye-slot eyes -o out.json`: LipBlink into a Spine skeleton. The skeleton goes over the
// wire (LipBlinkRequest.spine_json, the slots in LipBlinkRequest.spine) and the server writes
// the slots' attachment timelines (convert/spine_lip_blink.h); the CLI checks the slots first
// so its errors name its flags, and rebuilds the decoded request the server answered for
// --report.
#ifndef KOMA_CLIENT_SPINE_LIP_BLINK_H_
#define KOMA_CLIENT_SPINE_LIP_BLINK_H_

#include <string>

#include "absl/status/statusor.h"
#include "client/command_output.h"
#include "client/curve_files.h"
#include "client/lip_blink_command.h"
#include "convert/spine_lip_blink.h"
#include "koma/v1/retime.pb.h"

namespace koma::client {

// --animation, --mouth-slot, --mouth-attachments, --eye-slot, --eye-attachments.
v1::SpineLipBlinkSettings SpineSettingsOf(const LipBlinkArgs& args);

// The slots checked against the skeleton, errors naming the flags (`--mouth-slot no slot
// named "nose" (the skeleton has ...)`).
absl::StatusOr<convert::SpineLipBlinkSlots> CheckSpineSlots(const LipBlinkArgs& args,
                                                           const formats::SpineFile& file);

// The request for the skeleton's text `skeleton` and the voice's bytes (empty: none).
v1::LipBlinkRequest BuildSpineLipBlinkRequest(const LipBlinkArgs& args, std::string skeleton,
                                              std::string voice);

// `input`: IN as read (input.spine set).
int RunLipBlinkSpine(const LipBlinkArgs& args, const CommandOutput& out, const CurveInput& input);

}  // namespace koma::client

#endif  // KOMA_CLIENT_SPINE_LIP_BLINK_H_
