// Per-call protobuf arenas for the callback service (gRPC's MessageAllocator hook).
//
// Without it gRPC parses every request into heap-allocated messages, one malloc per curve
// point and segment, and frees them one by one: profiled on RetimeCurves (60 curves x 300
// frames), malloc and free took about a quarter of the server's CPU. On an arena the request
// and the response are carved out of a few large blocks and freed in one go.
//
// Request and response get an arena each, so FreeRequest() can drop the request (for a
// 100,000-frame clip ~77 MB) as soon as the handler has read it, before the response is
// serialised; it lowers the peak memory of a large call by the size of its request.
//
// RetimeSkeletal does not use it: its requests are a few huge packed arrays, which the parser
// grows chunk by chunk as the bytes arrive (on an arena every outgrown copy stays until the
// call ends); the service parses those itself, each array allocated once (skeletal_parse.h).
#ifndef KOMA_SERVER_ARENA_ALLOCATOR_H_
#define KOMA_SERVER_ARENA_ALLOCATOR_H_

#include <google/protobuf/arena.h>
#include <grpcpp/support/message_allocator.h>

#include <cstddef>
#include <memory>

#include "platform/huge_page_memory.h"

namespace koma::server {

// Arena blocks of 4 MiB or more (a large call's big arrays, each in a block of its own) come
// from huge pages (platform/huge_page_memory.h): ~18,000 fewer page faults for a 100k-frame
// clip's 74 MB response array. protobuf hands a block back with the size it asked for.
inline void* AllocateArenaBlock(size_t bytes) { return platform::AllocateBlock(bytes); }
inline void FreeArenaBlock(void* block, size_t bytes) { platform::FreeBlock(block, bytes); }

// Blocks grow from 8 KiB (a small call stays in one or two) to 1 MiB; a field larger than a
// block gets a block of its own, so big packed arrays are not split.
inline google::protobuf::ArenaOptions CallArenaOptions() {
  google::protobuf::ArenaOptions options;
  options.start_block_size = 8 * 1024;
  options.max_block_size = 1024 * 1024;
  options.block_alloc = AllocateArenaBlock;
  options.block_dealloc = FreeArenaBlock;
  return options;
}

template <typename Request, typename Response>
class ArenaMessageAllocator final : public grpc::MessageAllocator<Request, Response> {
 public:
  grpc::MessageHolder<Request, Response>* AllocateMessages() override { return new Holder; }

 private:
  class Holder final : public grpc::MessageHolder<Request, Response> {
   public:
    Holder()
        : request_arena_(std::make_unique<google::protobuf::Arena>(CallArenaOptions())),
          response_arena_(CallArenaOptions()) {
      this->set_request(google::protobuf::Arena::CreateMessage<Request>(request_arena_.get()));
      this->set_response(google::protobuf::Arena::CreateMessage<Response>(&response_arena_));
    }

    // gRPC calls this once the call is over (response sent or the call failed).
    void Release() override { delete this; }

    // The request and everything it owns is gone after this; request() is null.
    void FreeRequest() override {
      request_arena_.reset();
      this->set_request(nullptr);
    }

   private:
    std::unique_ptr<google::protobuf::Arena> request_arena_;
    google::protobuf::Arena response_arena_;
  };
};

}  // namespace koma::server

#endif  // KOMA_SERVER_ARENA_ALLOCATOR_H_
