#pragma once
// Runs body(i) for i in [begin, end) on all hardware threads, indices handed out one at a time.
// Plain std::thread rather than OpenMP: OpenMP's idle threads spin between parallel regions,
// which on a two-core machine shared with the SLAM threads burns the other core.
#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

namespace pf2 {
namespace synth {

template <typename Body>
void parallelFor(int begin, int end, bool parallel, const Body& body) {
  const int count = end - begin;
  const int threads = parallel ? std::min<int>(count, std::max(1u, std::thread::hardware_concurrency())) : 1;
  if (threads <= 1) {
    for (int i = begin; i < end; ++i) body(i);
    return;
  }
  std::atomic<int> next(begin);
  const auto work = [&]() {
    for (int i = next++; i < end; i = next++) body(i);
  };
  std::vector<std::thread> helpers;
  for (int t = 1; t < threads; ++t) helpers.emplace_back(work);
  work();
  for (std::thread& helper : helpers) helper.join();
}

}  // namespace synth
}  // namespace pf2
