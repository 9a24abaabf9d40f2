// What `koma batch` does per clip besides the call, on the Pitch sample (129 frames, 20
// joints, 8,580 channel values, 66 KB of text): read the file, parse the BVH, build the
// request; turn the answer back into a clip and write it. The load generator (koma_load)
// does none of this (it builds its request once), so this is the client-side cost between a
// batch's clips/s and the load generator's calls/s. Results: docs/benchmarks.md ("koma batch").
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "client/files.h"
#include "client/skeletal_command.h"
#include "client/skeletal_convert.h"
#include "formats/bvh.h"

namespace koma {
namespace {

std::string PitchText() {
  static const std::string text = *client::ReadFile(KOMA_PITCH_BVH);
  return text;
}

void BM_ReadFile(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(client::ReadFile(KOMA_PITCH_BVH));
}
BENCHMARK(BM_ReadFile);

void BM_ParseBvh(benchmark::State& state) {
  const std::string text = PitchText();
  for (auto _ : state) benchmark::DoNotOptimize(formats::ParseBvh(text));
}
BENCHMARK(BM_ParseBvh);

void BM_BuildRequest(benchmark::State& state) {
  const SkeletalClip clip = *formats::ParseBvh(PitchText());
  const client::SkeletalArgs args;
  for (auto _ : state) benchmark::DoNotOptimize(client::BuildSkeletalRequest(args, clip));
}
BENCHMARK(BM_BuildRequest);

void BM_WriteBvh(benchmark::State& state) {
  const SkeletalClip clip = *formats::ParseBvh(PitchText());
  for (auto _ : state) benchmark::DoNotOptimize(formats::WriteBvh(clip));
}
BENCHMARK(BM_WriteBvh);

// Read and parse (as the batch does, ReadSkeletalInput), request; then the answer (here: the request's motion, same size) back to a
// clip, formatted and written through a temporary file and a rename, as WriteFile does.
void BM_ClientWorkPerClip(benchmark::State& state) {
  const client::SkeletalArgs args;
  const std::string out = (std::filesystem::temp_directory_path() /
                           ("koma_batch_client_benchmark_" + std::to_string(getpid()) + ".bvh"))
                              .string();
  for (auto _ : state) {
    const SkeletalClip clip = *client::ReadSkeletalInput(KOMA_PITCH_BVH);
    v1::RetimeSkeletalResponse response;
    *response.mutable_motion() = client::BuildSkeletalRequest(args, clip)->motion();
    const SkeletalClip answer = *client::ClipFromResponse(response, clip.skeleton);
    benchmark::DoNotOptimize(client::WriteFile(out, formats::WriteBvh(answer)));
  }
  std::remove(out.c_str());
}
BENCHMARK(BM_ClientWorkPerClip);

}  // namespace
}  // namespace koma
