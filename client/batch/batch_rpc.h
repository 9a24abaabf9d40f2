// The three RPCs as `koma batch` drives them: read and parse one input into its request,
// start the call, write the outputs from the answer. The request building and the output
// writing are the single-file commands' own functions, so a batch writes the same bytes.
#ifndef KOMA_CLIENT_BATCH_BATCH_RPC_H_
#define KOMA_CLIENT_BATCH_BATCH_RPC_H_

#include <grpcpp/grpcpp.h>

#include <functional>
#include <memory>
#include <string>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "client/batch/batch_inputs.h"
#include "client/curves_command.h"
#include "client/lip_blink_command.h"
#include "client/skeletal_command.h"
#include "koma/v1/retime.grpc.pb.h"

namespace koma::client::batch {

// One parsed clip with its request and (after a call) its answer.
class Clip {
 public:
  virtual ~Clip() = default;
  // Starts the call; `done` runs once, on a gRPC thread, when it ends. Clears any earlier
  // answer first (a retry).
  virtual void Start(v1::Retime::Stub& stub, grpc::ClientContext* context,
                     std::function<void(grpc::Status)> done) = 0;
  // Writes item.output (and item.timing, item.report when set) from the answer, atomically,
  // as the single-file command writes -o, --timing and --report.
  virtual absl::Status Write(const BatchItem& item) = 0;
};

// Reads clips of one RPC with the options of the batch.
class Rpc {
 public:
  virtual ~Rpc() = default;
  // The file read and parsed, the request built (as the single-file command builds it).
  // Errors name the file.
  virtual absl::StatusOr<std::unique_ptr<Clip>> Read(const BatchItem& item) const = 0;
};

std::unique_ptr<Rpc> MakeSkeletalRpc(const SkeletalArgs& args);
std::unique_ptr<Rpc> MakeCurvesRpc(const CurvesArgs& args);
std::unique_ptr<Rpc> MakeLipBlinkRpc(const LipBlinkArgs& args);

}  // namespace koma::client::batch

#endif  // KOMA_CLIENT_BATCH_BATCH_RPC_H_
