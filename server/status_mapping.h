// The one place where absl::Status becomes grpc::Status.
#ifndef KOMA_SERVER_STATUS_MAPPING_H_
#define KOMA_SERVER_STATUS_MAPPING_H_

#include <grpcpp/support/status.h>

#include <string>

#include "absl/status/status.h"

namespace koma::server {

// Same code (the numeric values of absl::StatusCode and grpc::StatusCode agree), same
// message.
grpc::Status ToGrpcStatus(const absl::Status& status);

// "INVALID_ARGUMENT" etc., for logs and metrics.
std::string GrpcCodeName(grpc::StatusCode code);

}  // namespace koma::server

#endif  // KOMA_SERVER_STATUS_MAPPING_H_
