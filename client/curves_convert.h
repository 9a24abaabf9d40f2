// The CLI's names for convert/curves_convert.h (shared with the server's file requests).
#ifndef KOMA_CLIENT_CURVES_CONVERT_H_
#define KOMA_CLIENT_CURVES_CONVERT_H_

#include "convert/curves_convert.h"

namespace koma::client {
using convert::CurveSetToProto;
using convert::StepsFromProto;
using convert::TimingFromProto;
}  // namespace koma::client

#endif  // KOMA_CLIENT_CURVES_CONVERT_H_
