#include "server/status_mapping.h"

#include <string>

namespace koma::server {

grpc::Status ToGrpcStatus(const absl::Status& status) {
  if (status.ok()) return grpc::Status::OK;
  // absl::StatusCode mirrors the canonical gRPC codes 0..16 one to one.
  const int code = static_cast<int>(status.code());
  const grpc::StatusCode grpc_code = (code >= 0 && code <= 16)
                                         ? static_cast<grpc::StatusCode>(code)
                                         : grpc::StatusCode::UNKNOWN;
  return grpc::Status(grpc_code, std::string(status.message()));
}

std::string GrpcCodeName(grpc::StatusCode code) {
  // absl's canonical code names are gRPC's ("INVALID_ARGUMENT", ...).
  return absl::StatusCodeToString(static_cast<absl::StatusCode>(code));
}

}  // namespace koma::server
