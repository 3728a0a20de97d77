// The one translation unit that compiles stb_image and stb_image_write (Debian's libstb-dev ships
// headers only for these). Everything else includes the headers without the implementation macros.
// stb_image allocates through StbAllocator so StbMemoryCap (StbGuard.h) can bound what a decode holds.
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "core/StbGuard.h"

namespace tandem {

namespace {
thread_local StbMemoryCap* tCap = nullptr;
// Each block carries its size in front, so frees and reallocs can be accounted. 16 bytes keep the
// pointer handed to stb aligned as malloc's is.
constexpr std::size_t kHeader = 16;
}  // namespace

StbMemoryCap::StbMemoryCap(std::uint64_t maxLiveBytes) : max_(maxLiveBytes), outer_(tCap) { tCap = this; }
StbMemoryCap::~StbMemoryCap() { tCap = outer_; }

struct StbAllocator {
  static void* allocate(void* old, std::size_t n) {
    std::size_t oldSize = 0;
    char* base = nullptr;
    if (old) {
      base = static_cast<char*>(old) - kHeader;
      std::memcpy(&oldSize, base, sizeof oldSize);
    }
    StbMemoryCap* cap = tCap;
    if (cap) {
      const std::uint64_t live = cap->live_ - std::min<std::uint64_t>(cap->live_, oldSize);
      if (n > cap->max_ || live > cap->max_ - n) {
        cap->refused_ = true;
        return nullptr;  // stb frees nothing on a failed realloc: the old block stays valid and accounted
      }
    }
    if (n > SIZE_MAX - kHeader) return nullptr;
    char* p = static_cast<char*>(std::realloc(base, n + kHeader));
    if (!p) return nullptr;
    std::memcpy(p, &n, sizeof n);
    if (cap) {
      cap->live_ = cap->live_ - std::min<std::uint64_t>(cap->live_, oldSize) + n;
      cap->peak_ = std::max(cap->peak_, cap->live_);
    }
    return p + kHeader;
  }
  static void release(void* p) {
    if (!p) return;
    char* base = static_cast<char*>(p) - kHeader;
    std::size_t size = 0;
    std::memcpy(&size, base, sizeof size);
    // A block allocated under an outer cap (or none) and freed under this one only lowers this count to 0.
    if (StbMemoryCap* cap = tCap) cap->live_ -= std::min<std::uint64_t>(cap->live_, size);
    std::free(base);
  }
};

}  // namespace tandem

static void* tandemStbMalloc(std::size_t n) { return tandem::StbAllocator::allocate(nullptr, n); }
static void* tandemStbRealloc(void* p, std::size_t n) { return tandem::StbAllocator::allocate(p, n); }
static void tandemStbFree(void* p) { tandem::StbAllocator::release(p); }

#define STBI_MALLOC(sz) tandemStbMalloc(sz)
#define STBI_REALLOC(p, newsz) tandemStbRealloc(p, newsz)
#define STBI_FREE(p) tandemStbFree(p)
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_WRITE_IMPLEMENTATION
// (Radiance .hdr environment images are read by core/Image.cpp's own decoder: readHdr says why.)
#define STBI_NO_HDR
#define STBI_NO_LINEAR
// The allocator macros are ours, so stb's casts around them count as our code: silence what it does.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wold-style-cast"
#include <stb_image.h>
#include <stb_image_write.h>
#pragma GCC diagnostic pop
