#pragma once
// Runs body(begin, end) over fixed chunks of [0, count) on `threads`
// workers. Chunk boundaries do not depend on the thread count, and each
// chunk writes only its own outputs, so results are identical for any count.

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

namespace svit::baker {

inline int resolveThreads(int requested) {
  if (requested > 0) return requested;
  return std::max(1, int(std::thread::hardware_concurrency()));
}

template <typename Body>
void parallelFor(size_t count, size_t chunk, int threads, const Body& body) {
  const size_t chunks = (count + chunk - 1) / chunk;
  if (threads <= 1 || chunks <= 1) {
    for (size_t c = 0; c < chunks; ++c) body(c * chunk, std::min(count, (c + 1) * chunk));
    return;
  }
  std::atomic<size_t> next{0};
  auto worker = [&] {
    for (size_t c = next++; c < chunks; c = next++)
      body(c * chunk, std::min(count, (c + 1) * chunk));
  };
  std::vector<std::thread> pool;
  const int extra = int(std::min<size_t>(size_t(threads), chunks)) - 1;
  for (int i = 0; i < extra; ++i) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
}

}  // namespace svit::baker
