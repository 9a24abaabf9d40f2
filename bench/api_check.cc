// koma_api_check TARGET TARGET...: sends the same few koma.v1.Retime calls (koma_load's
// synthetic requests, small sizes, plus one invalid request) to every target and checks that
// each answers with the status and serialized response of the first. Used by
// bench/api_smoke_test.sh to keep koma_api_server's variants answering like koma_server.
#include <grpcpp/grpcpp.h>

#include <chrono>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "bench/load/load_request.h"
#include "koma/v1/retime.grpc.pb.h"

namespace {

using Stub = koma::v1::Retime::Stub;

// One call's outcome as text: "OK" or "CODE message", and the response's bytes (deterministic
// serialization, so equal messages give equal bytes).
struct Answer {
  std::string status;
  std::string bytes;
};

template <typename Request, typename Response>
using Method = grpc::Status (Stub::*)(grpc::ClientContext*, const Request&, Response*);

template <typename Request, typename Response>
std::function<Answer(Stub&)> Call(Method<Request, Response> method, Request request) {
  return [method, request](Stub& stub) {
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(10));
    Response response;
    const grpc::Status status = (stub.*method)(&context, request, &response);
    Answer answer{
        status.ok() ? "OK" : absl::StrCat(status.error_code(), " ", status.error_message()), ""};
    google::protobuf::io::StringOutputStream stream(&answer.bytes);
    google::protobuf::io::CodedOutputStream coded(&stream);
    coded.SetSerializationDeterministic(true);
    response.SerializeToCodedStream(&coded);
    return answer;
  };
}

struct Case {
  std::string name;
  bool expect_ok;
  std::function<Answer(Stub&)> call;
};

std::vector<Case> Cases() {
  using koma::load::SyntheticCurves;
  using koma::load::SyntheticLipBlink;
  using koma::load::SyntheticSkeletal;
  koma::v1::RetimeCurvesRequest invalid = SyntheticCurves(2, 30, 1);
  invalid.mutable_curves()->set_frame_count(0);
  return {
      {"RetimeSkeletal positions 129x31", true,
       Call(&Stub::RetimeSkeletal, SyntheticSkeletal(129, 31, /*positions=*/true, 1))},
      {"RetimeSkeletal channels 129x31", true,
       Call(&Stub::RetimeSkeletal, SyntheticSkeletal(129, 31, /*positions=*/false, 1))},
      {"RetimeCurves 60x300", true, Call(&Stub::RetimeCurves, SyntheticCurves(60, 300, 1))},
      {"LipBlink 3x1000", true, Call(&Stub::LipBlink, SyntheticLipBlink(3, 1000, 1))},
      {"RetimeCurves invalid (frame_count 0)", false, Call(&Stub::RetimeCurves, invalid)},
  };
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: koma_api_check HOST:PORT HOST:PORT...\n");
    return 2;
  }
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(256 * 1024 * 1024);
  std::vector<std::unique_ptr<Stub>> stubs;
  for (int i = 1; i < argc; ++i) {
    stubs.push_back(koma::v1::Retime::NewStub(
        grpc::CreateCustomChannel(argv[i], grpc::InsecureChannelCredentials(), args)));
  }
  int mismatches = 0;
  for (const Case& c : Cases()) {
    const int before = mismatches;
    const Answer first = c.call(*stubs[0]);
    if ((first.status == "OK") != c.expect_ok) {
      std::fprintf(stderr, "UNEXPECTED %s: %s answered [%s]\n", c.name.c_str(), argv[1],
                   first.status.c_str());
      ++mismatches;
    }
    for (size_t i = 1; i < stubs.size(); ++i) {
      const Answer other = c.call(*stubs[i]);
      if (other.status != first.status || other.bytes != first.bytes) {
        std::fprintf(stderr,
                     "MISMATCH %s: %s answered [%s] %zu bytes, %s answered [%s] %zu bytes\n",
                     c.name.c_str(), argv[1], first.status.c_str(), first.bytes.size(), argv[i + 1],
                     other.status.c_str(), other.bytes.size());
        ++mismatches;
      }
    }
    std::printf("%s: [%s] %zu bytes from %zu targets%s\n", c.name.c_str(), first.status.c_str(),
                first.bytes.size(), stubs.size(), mismatches == before ? "" : " (see mismatches)");
  }
  return mismatches == 0 ? 0 : 1;
}
