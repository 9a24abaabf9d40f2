// LipBlink from a voice (docs/semantics.md, "LipBlink from a voice"): one minute of 48 kHz
// stereo 16-bit WAV through the whole RPC (an in-process koma server: the request's bytes,
// decoding, the analysis, the mouth, the motion3.json and cues written, the response's bytes),
// and the core analysis alone on the decoded samples (loudness, voice features, speech gate).
// Results: docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/voice_activity.h"
#include "core/voice_features.h"
#include "core/voice_gate.h"
#include "koma/v1/retime.grpc.pb.h"
#include "server/server.h"
#include "tests/testing/wav_bytes.h"

namespace koma {
namespace {

constexpr int kRate = 48000;
constexpr int kSeconds = 60;

// Speech-like: 1.5-4 s bursts of a 150-300 Hz tone with a syllable envelope, 0.3-1.2 s pauses,
// over -60 dBFS noise; interleaved stereo.
std::vector<double> Minute() {
  std::vector<double> out;
  out.reserve(static_cast<size_t>(kRate) * kSeconds * 2);
  uint64_t state = 7;
  const auto unit = [&state] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) * 0x1.0p-53;
  };
  int64_t i = 0;
  while (i < int64_t{kRate} * kSeconds) {
    const int64_t burst = static_cast<int64_t>((1.5 + 2.5 * unit()) * kRate);
    const int64_t pause = static_cast<int64_t>((0.3 + 0.9 * unit()) * kRate);
    const double pitch = 150 + 150 * unit();
    for (int64_t k = 0; k < burst + pause && i < int64_t{kRate} * kSeconds; ++k, ++i) {
      double x = 0.001 * (2 * unit() - 1);
      if (k < burst) {
        const double t = static_cast<double>(k) / kRate;
        x += 0.3 * std::fabs(std::sin(3.14159 * 4 * t)) * std::sin(2 * 3.14159 * pitch * t);
      }
      out.push_back(x);
      out.push_back(x);
    }
  }
  return out;
}

void BM_VoiceRpcMinuteStereo48k(benchmark::State& state) {
  testing::WavHeader h;
  h.sample_rate = kRate;
  h.channels = 2;
  v1::LipBlinkRequest request;
  request.set_audio(testing::WavBytes(h, Minute()));
  server::ServerConfig config;
  config.address = "";
  config.limits.max_file_bytes = 64 << 20;
  std::unique_ptr<server::KomaServer> server = server::KomaServer::Start(config).value();
  std::unique_ptr<v1::Retime::Stub> stub = v1::Retime::NewStub(server->InProcessChannel());
  for (auto _ : state) {
    grpc::ClientContext context;
    v1::LipBlinkResponse response;
    const grpc::Status status = stub->LipBlink(&context, request, &response);
    if (!status.ok()) {
      state.SkipWithError(status.error_message().c_str());
      break;
    }
    benchmark::DoNotOptimize(response.motion3_json().data());
  }
  state.counters["x_real_time"] = benchmark::Counter(
      kSeconds * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) *
                          static_cast<int64_t>(request.audio().size()));
}
// Time: wall clock per call. CPU: the whole process's CPU time per call (the client's and the
// in-process server's threads), the cost a busy shared host cannot inflate.
BENCHMARK(BM_VoiceRpcMinuteStereo48k)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

void BM_VoiceCoreMinute48k(benchmark::State& state) {
  const std::vector<double> stereo = Minute();
  std::vector<float> mono;
  for (size_t i = 0; i < stereo.size(); i += 2) mono.push_back(static_cast<float>(stereo[i]));
  for (auto _ : state) {
    // What server/lip_blink_voice.cc runs: the loudness and the voice features (issue 44's
    // speech gate) over the same blocks, then the stretches and the speech.
    FrameLoudness loudness(kRate, 24.0);
    VoiceFeatures features(kRate, 24.0);
    for (size_t i = 0; i < mono.size(); i += 4096) {
      const auto block =
          absl::MakeConstSpan(mono.data() + i, std::min<size_t>(4096, mono.size() - i));
      loudness.Add(block);
      features.Add(block);
    }
    features.Finish();
    const VoiceOptions options;
    const std::vector<FrameInterval> voice_like = VoiceLikeStretches(features, 24.0, options.gate);
    const VoiceActivity v =
        DetectVoice(loudness.Dbfs(loudness.frames_touched()), options, &voice_like);
    benchmark::DoNotOptimize(v.speech.data());
  }
  state.counters["x_real_time"] = benchmark::Counter(
      kSeconds * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_VoiceCoreMinute48k)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace koma
