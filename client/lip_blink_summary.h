// What `koma lipblink` tells: the human summary and the --json summary (schema:
// docs/summary.schema.json, "lipblink").
#ifndef KOMA_CLIENT_LIP_BLINK_SUMMARY_H_
#define KOMA_CLIENT_LIP_BLINK_SUMMARY_H_

#include <nlohmann/json.hpp>
#include <string>

#include "client/lip_blink_command.h"
#include "core/curves.h"
#include "koma/v1/retime.pb.h"

namespace koma::client {

std::string LipBlinkSummaryText(const LipBlinkArgs& args, const CurveSet& curves,
                                const v1::LipBlinkResponse& response);

nlohmann::json LipBlinkSummaryJson(const LipBlinkArgs& args, const CurveSet& curves,
                                   const v1::LipBlinkResponse& response);

// A voice request's (--audio / --rhubarb): the recording, its analysis and the written
// motion's frames, then the lines and fields of the two above; the JSON adds "voice".
std::string LipBlinkVoiceSummaryText(const LipBlinkArgs& args,
                                     const v1::LipBlinkResponse& response);
nlohmann::json LipBlinkVoiceSummaryJson(const LipBlinkArgs& args,
                                        const v1::LipBlinkResponse& response);

}  // namespace koma::client

#endif  // KOMA_CLIENT_LIP_BLINK_SUMMARY_H_
