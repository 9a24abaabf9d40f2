// What `koma curves` tells about a retiming: the human summary and the --json summary
// (schema: docs/summary.schema.json, "curves").
#ifndef KOMA_CLIENT_CURVES_SUMMARY_H_
#define KOMA_CLIENT_CURVES_SUMMARY_H_

#include <nlohmann/json.hpp>
#include <string>

#include "client/curves_command.h"
#include "core/curves.h"
#include "koma/v1/retime.pb.h"

namespace koma::client {

// `request` is what was asked (the timing groups' modes are read from it).
std::string CurvesSummaryText(const CurvesArgs& args, const CurveSet& curves,
                              const v1::RetimeCurvesRequest& request,
                              const v1::RetimeCurvesResponse& response);

nlohmann::json CurvesSummaryJson(const CurvesArgs& args, const CurveSet& curves,
                                 const v1::RetimeCurvesRequest& request,
                                 const v1::RetimeCurvesResponse& response);

}  // namespace koma::client

#endif  // KOMA_CLIENT_CURVES_SUMMARY_H_
