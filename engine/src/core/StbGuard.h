#pragma once
// A cap on the memory stb_image may hold at once, for decoding untrusted images. stb_image itself bounds
// only the declared dimensions: a PNG whose zlib stream inflates far past its rows, or a file declaring
// more pixels than it holds, makes it allocate freely. Every allocation stb_image makes goes through
// StbImpl.cpp's allocator, which refuses (stb then fails with "outofmem") once the live bytes of the
// innermost cap on this thread would exceed it. Without a cap, allocation is unlimited.
#include <cstdint>

namespace tandem {

class StbMemoryCap {
 public:
  explicit StbMemoryCap(std::uint64_t maxLiveBytes);
  ~StbMemoryCap();
  StbMemoryCap(const StbMemoryCap&) = delete;
  StbMemoryCap& operator=(const StbMemoryCap&) = delete;

  /// Whether an allocation was refused while this cap was active.
  bool refused() const { return refused_; }
  std::uint64_t peakBytes() const { return peak_; }

 private:
  friend struct StbAllocator;
  std::uint64_t max_;
  std::uint64_t live_ = 0;
  std::uint64_t peak_ = 0;
  bool refused_ = false;
  StbMemoryCap* outer_;
};

}  // namespace tandem
