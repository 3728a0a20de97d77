#include "render/Adaptive.h"

#include <algorithm>
#include <cmath>

#include "core/Shading.h"

namespace tandem {

float displayLuminance(glm::vec3 linear, const FrameSettings& s) {
  const float y = s.exposure * glm::dot(linear, glm::vec3(0.2126f, 0.7152f, 0.0722f));
  return std::sqrt(shading::tdToneMap(glm::vec3(y), shading::toneMapOp(s.toneMap)).x);
}

void dilate(std::vector<std::uint8_t>& mask, int width, int height, int radius) {
  // Separable: a max filter along rows, then along columns.
  std::vector<std::uint8_t> rows(mask.size(), 0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      if (mask[static_cast<std::size_t>(y) * width + x])
        for (int dx = std::max(0, x - radius); dx <= std::min(width - 1, x + radius); ++dx)
          rows[static_cast<std::size_t>(y) * width + dx] = 1;
  std::fill(mask.begin(), mask.end(), 0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      if (rows[static_cast<std::size_t>(y) * width + x])
        for (int dy = std::max(0, y - radius); dy <= std::min(height - 1, y + radius); ++dy)
          mask[static_cast<std::size_t>(dy) * width + x] = 1;
}

bool adaptiveRound(const std::vector<float>& lo, const std::vector<float>& hi, const std::vector<std::uint32_t>& count,
                   int width, int height, float threshold, int rayScale, std::vector<std::uint8_t>& refine,
                   std::vector<std::uint8_t>& traced) {
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  refine.assign(n, 0);
  bool any = false;
  for (std::size_t i = 0; i < n; ++i)
    if (count[i] > 0 && hi[i] - lo[i] > threshold) refine[i] = 1, any = true;
  if (!any) {
    traced.assign(n, 0);
    return false;
  }
  dilate(refine, width, height, 1);
  traced = refine;
  if (rayScale > 1) dilate(traced, width, height, 2 * rayScale);
  return true;
}

}  // namespace tandem
