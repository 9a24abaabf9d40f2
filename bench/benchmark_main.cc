// main() of every Google Benchmark binary here: glibc malloc and core's large arrays set up as
// in koma_server first (platform/malloc_tuning.h, platform/huge_page_memory.h). With glibc's
// defaults a benchmark that frees a few hundred KB per iteration hands it back to the kernel
// and faults it in again on the next one: RetimeFast on a Pitch-size clip measured 24-29 us
// that way against 11 us with the servers' settings, which is what a call sees in koma_server.
#include <benchmark/benchmark.h>

#include "platform/huge_page_memory.h"
#include "platform/malloc_tuning.h"

int main(int argc, char** argv) {
  koma::platform::TuneMallocForLargeMessages();
  koma::platform::UseHugePagesForLargeArrays();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
