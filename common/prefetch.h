#pragma once

namespace agv {

// Asks the processor to bring the cache line holding p nearer. GCC removes a loop of
// __builtin_prefetch calls as a loop without effects (agv bench: none were left in the edge
// scan); an asm statement it keeps.
inline void prefetch(const void* p) {
#if defined(__GNUC__) && defined(__x86_64__)
  asm volatile("prefetcht0 %0" : : "m"(*static_cast<const char*>(p)));
#else
  __builtin_prefetch(p);
#endif
}

}  // namespace agv
