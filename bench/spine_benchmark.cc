// A Spine skeleton through the whole RetimeCurves RPC: a 50-bone skeleton with 2,000 keys (each
// bone a rotate and a translate timeline of 20 Bezier keys, 10 s at 30 fps), on threes with
// tame and tsume on the 24 fps grid, over an in-process gRPC channel to a real KomaServer.
//   BM_SpineFileRpc:    the request carries the file (spine_json); the server parses it,
//                       retimes, writes the skeleton back; the client receives the file.
//   BM_SpineDecodedRpc: what `koma curves` does: parse locally, send the decoded curves, write
//                       the skeleton from the answer.
// Results and how to run: docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include <grpcpp/grpcpp.h>

#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "convert/curve_text.h"
#include "convert/curves_convert.h"
#include "core/split_mix64.h"
#include "koma/v1/retime.grpc.pb.h"
#include "server/logging.h"
#include "server/server.h"

namespace koma {
namespace {

constexpr int kBones = 50;
constexpr int kKeysPerTimeline = 20;  // x 2 timelines x 50 bones = 2,000 keys

// Spine 4.1 JSON: bones b0..b49, one animation "walk" keyed every 0.5 s with Bezier handles a
// third of the way in (absolute, per value).
std::string SyntheticSkeleton() {
  SplitMix64 rng(32);
  std::string bones = "{\"name\":\"root\"}";
  std::string timelines;
  for (int b = 0; b < kBones; ++b) {
    absl::StrAppend(&bones, ",{\"name\":\"b", b, "\",\"parent\":\"root\"}");
    std::string rotate, translate;
    double angle = 0, x = 0, y = 0;
    for (int k = 0; k < kKeysPerTimeline; ++k) {
      const double t = 0.5 * k;
      const double next_angle = 60 * rng.Unit() - 30, nx = 40 * rng.Unit(), ny = 40 * rng.Unit();
      const bool last = k + 1 == kKeysPerTimeline;
      const std::string sep = k == 0 ? "" : ",";
      absl::StrAppend(&rotate, sep, "{\"time\":", t, ",\"value\":", angle);
      absl::StrAppend(&translate, sep, "{\"time\":", t, ",\"x\":", x, ",\"y\":", y);
      if (!last) {
        absl::StrAppend(&rotate, ",\"curve\":[", t + 0.5 / 3, ",", angle, ",", t + 1.0 / 3, ",",
                        next_angle, "]");
        absl::StrAppend(&translate, ",\"curve\":[", t + 0.5 / 3, ",", x, ",", t + 1.0 / 3, ",", nx,
                        ",", t + 0.5 / 3, ",", y, ",", t + 1.0 / 3, ",", ny, "]");
      }
      absl::StrAppend(&rotate, "}");
      absl::StrAppend(&translate, "}");
      angle = next_angle;
      x = nx;
      y = ny;
    }
    absl::StrAppend(&timelines, b == 0 ? "" : ",", "\"b", b, "\":{\"rotate\":[", rotate,
                    "],\"translate\":[", translate, "]}");
  }
  return absl::StrCat("{\"skeleton\":{\"spine\":\"4.1.24\",\"fps\":30},\"bones\":[", bones,
                      "],\"animations\":{\"walk\":{\"bones\":{", timelines, "}}}}");
}

struct Fixture {
  Fixture() : text(SyntheticSkeleton()) {
    server::ServerConfig config;
    config.address = "";
    config.worker_threads = 1;
    // One log line per call would be measured too (and flood the output).
    if (!server::ConfigureLogging("warn", "text").ok()) std::abort();
    server = server::KomaServer::Start(config).value();
    stub = v1::Retime::NewStub(server->InProcessChannel());
  }
  std::string text;
  std::unique_ptr<server::KomaServer> server;
  std::unique_ptr<v1::Retime::Stub> stub;
};

Fixture& Shared() {
  static Fixture* fixture = new Fixture();
  return *fixture;
}

void Options(v1::RetimeCurvesRequest& request) {
  request.set_frames_per_drawing(3);
  request.set_tame(1.5);
  request.set_tsume(1.5);
}

// The request with the skeleton sent whole (RetimeCurvesRequest.spine_json), with Options.
v1::RetimeCurvesRequest FileRequest(const std::string& skeleton) {
  v1::RetimeCurvesRequest request;
  Options(request);
  request.set_spine_json(skeleton);
  request.set_spine_animation("walk");
  return request;
}

// The request the CLI sends for the skeleton: its curves decoded, with Options.
v1::RetimeCurvesRequest DecodedRequest(const convert::CurveInput& input) {
  v1::RetimeCurvesRequest request;
  Options(request);
  *request.mutable_curves() = convert::CurveSetToProto(input.curves);
  return request;
}

// The answer's curves as CurveOutputText takes them.
std::vector<std::optional<convert::CurveReplacement>> Replacements(
    const v1::RetimeCurvesResponse& response) {
  std::vector<std::optional<convert::CurveReplacement>> replacements;
  for (const v1::RetimedCurve& curve : response.curves()) {
    replacements.push_back(convert::ReplacementFromProto(curve));
  }
  return replacements;
}

void BM_SpineFileRpc(benchmark::State& state) {
  Fixture& f = Shared();
  const v1::RetimeCurvesRequest request = FileRequest(f.text);
  for (auto _ : state) {
    grpc::ClientContext context;
    v1::RetimeCurvesResponse response;
    const grpc::Status status = f.stub->RetimeCurves(&context, request, &response);
    if (!status.ok() || response.spine_json().empty()) state.SkipWithError("call");
    benchmark::DoNotOptimize(response.spine_json().data());
  }
  state.counters["keys"] = 2 * kBones * kKeysPerTimeline;
  state.counters["file_bytes"] = static_cast<double>(f.text.size());
}

void BM_SpineDecodedRpc(benchmark::State& state) {
  Fixture& f = Shared();
  for (auto _ : state) {
    absl::StatusOr<convert::CurveInput> input = convert::ParseSpineText(f.text, "walk");
    if (!input.ok()) std::abort();
    const v1::RetimeCurvesRequest request = DecodedRequest(*input);
    grpc::ClientContext context;
    v1::RetimeCurvesResponse response;
    if (!f.stub->RetimeCurves(&context, request, &response).ok()) state.SkipWithError("call");
    absl::StatusOr<std::string> written =
        convert::CurveOutputText(*input, Replacements(response), false);
    if (!written.ok()) state.SkipWithError("write");
    benchmark::DoNotOptimize(written->data());
  }
}

// The stages of one call, each alone (to see where BM_SpineFileRpc's time goes):
//   BM_SpineStageParse:    formats::ParseSpine of the file (the server's first step).
//   BM_SpineStageCurvesRpc: the RPC with the decoded curves and no file (retime, the
//                          per-curve answer, both protos' encoding and decoding, gRPC).
//   BM_SpineStageWrite:    writing the skeleton back from the retimed curves.
//   BM_SpineStageDecodeAnswer: the client decoding the file call's answer (proto bytes).
void BM_SpineStageParse(benchmark::State& state) {
  Fixture& f = Shared();
  for (auto _ : state) {
    absl::StatusOr<convert::CurveInput> input = convert::ParseSpineText(f.text, "walk");
    if (!input.ok()) std::abort();
    benchmark::DoNotOptimize(input->curves.curves.data());
  }
}

void BM_SpineStageCurvesRpc(benchmark::State& state) {
  Fixture& f = Shared();
  absl::StatusOr<convert::CurveInput> input = convert::ParseSpineText(f.text, "walk");
  if (!input.ok()) std::abort();
  const v1::RetimeCurvesRequest request = DecodedRequest(*input);
  for (auto _ : state) {
    grpc::ClientContext context;
    v1::RetimeCurvesResponse response;
    if (!f.stub->RetimeCurves(&context, request, &response).ok()) state.SkipWithError("call");
    benchmark::DoNotOptimize(response.curves().data());
  }
}

void BM_SpineStageWrite(benchmark::State& state) {
  Fixture& f = Shared();
  absl::StatusOr<convert::CurveInput> input = convert::ParseSpineText(f.text, "walk");
  if (!input.ok()) std::abort();
  grpc::ClientContext context;
  v1::RetimeCurvesResponse response;
  if (!f.stub->RetimeCurves(&context, DecodedRequest(*input), &response).ok()) std::abort();
  const std::vector<std::optional<convert::CurveReplacement>> replacements =
      Replacements(response);
  for (auto _ : state) {
    absl::StatusOr<std::string> written = convert::CurveOutputText(*input, replacements, false);
    if (!written.ok()) state.SkipWithError("write");
    benchmark::DoNotOptimize(written->data());
  }
}

void BM_SpineStageDecodeAnswer(benchmark::State& state) {
  Fixture& f = Shared();
  const v1::RetimeCurvesRequest request = FileRequest(f.text);
  grpc::ClientContext context;
  v1::RetimeCurvesResponse response;
  if (!f.stub->RetimeCurves(&context, request, &response).ok()) std::abort();
  const std::string bytes = response.SerializeAsString();
  for (auto _ : state) {
    v1::RetimeCurvesResponse decoded;
    if (!decoded.ParseFromString(bytes)) state.SkipWithError("decode");
    benchmark::DoNotOptimize(decoded.curves().data());
  }
  state.counters["answer_bytes"] = static_cast<double>(bytes.size());
  state.counters["spine_json_bytes"] = static_cast<double>(response.spine_json().size());
}

// Process CPU time (client and server threads together) beside the wall-clock time: on a shared
// machine the wall clock measures the other processes' load, the CPU time what one call costs.
BENCHMARK(BM_SpineFileRpc)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
BENCHMARK(BM_SpineDecodedRpc)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK(BM_SpineStageParse)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
BENCHMARK(BM_SpineStageCurvesRpc)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK(BM_SpineStageWrite)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
BENCHMARK(BM_SpineStageDecodeAnswer)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

}  // namespace
}  // namespace koma
