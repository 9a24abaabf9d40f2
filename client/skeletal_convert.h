// The CLI's names for convert/skeletal_convert.h (shared with the server's file requests).
#ifndef KOMA_CLIENT_SKELETAL_CONVERT_H_
#define KOMA_CLIENT_SKELETAL_CONVERT_H_

#include "convert/skeletal_convert.h"

namespace koma::client {
using convert::ClipFromResponse;
using convert::TimingMapFromResponse;
using convert::ToProto;
}  // namespace koma::client

#endif  // KOMA_CLIENT_SKELETAL_CONVERT_H_
