// glibc malloc settings for a server whose messages run from kilobytes to hundreds of
// megabytes. koma_server calls this first thing in main(); so does koma_echo_server, so the
// transport baseline it is compared with allocates the same way.
#ifndef KOMA_PLATFORM_MALLOC_TUNING_H_
#define KOMA_PLATFORM_MALLOC_TUNING_H_

#include <malloc.h>

#include <cstdint>

#include "platform/huge_page_pool.h"

namespace koma::platform {

// glibc raises its mmap threshold (up to 32 MiB) each time a large block is freed, after
// which blocks of a large call's size come from the heap and stay resident when freed: RSS
// grew from call to call on 100,000-frame clips. Fixed thresholds instead: blocks of 1 MiB
// or more (a large clip's arrays) are mmap'd and returned to the system when freed; smaller
// ones come from the heap, which keeps up to 16 MiB of free space instead of returning it at
// once, so mid-size calls (LipBlink's 800 KB curves) reuse memory rather than fault in fresh
// pages every call. Measured (2026-11-21, load matrix): 256 KiB / 1 MiB kept the 100k-frame peak
// lowest but made LipBlink 3x100k ~1.7x slower (page faults); 2 MiB / 16 MiB and up made
// it fastest but the 100k-frame peak ~1.6x higher.
//
// One malloc arena for all threads: by default glibc gives threads arenas of their own (up to 8
// per core), and gRPC receives a large message's pieces on whichever thread reads the socket,
// so a 73 MB request left up to ~130 MB of freed pieces resident across two or more arenas,
// where the next call's pieces, read on another thread, did not reuse them. With one arena
// the 100,000-frame RetimeSkeletal peak went from 320-380 to 240-255 MiB and stopped growing
// from run to run; RetimeCurves 500 x 10k from 330-440 to ~215 MiB; LipBlink 3 x 100k at c=16
// from ~195 to ~168 MiB. Throughput at Pitch size with 16 calls in flight was the same within
// the noise (two cores, so little lock contention). Lower thresholds (512 or 256 KiB, trim at
// 2-4 MiB) took LipBlink's peak down only 5-15 % more but cost it 30-40 % of its throughput.
inline void TuneMallocForLargeMessages() {
  mallopt(M_MMAP_THRESHOLD, 1024 * 1024);
  mallopt(M_TRIM_THRESHOLD, 16 * 1024 * 1024);
  mallopt(M_ARENA_MAX, 1);
}

// Arrays of 4 MiB and more (a large call's request and response blocks, forward kinematics'
// output, RetimeSkeletal's working arrays) are huge-page mappings; up to `megabytes` of released
// ones stay mapped for the next large call, which then skips the page faults and the kernel's
// page clearing (platform/huge_page_pool.h). Resident memory can exceed what is in use by that
// much. Both servers take it from --huge_page_cache_mb.
inline void SetHugePageCache(int64_t megabytes) {
  SetHugePageCacheLimit(static_cast<size_t>(megabytes < 0 ? 0 : megabytes) << 20);
}

}  // namespace koma::platform

#endif  // KOMA_PLATFORM_MALLOC_TUNING_H_
