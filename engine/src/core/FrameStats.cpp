#include "tandem/FrameStats.h"

namespace tandem {

void FrameStats::addSample(const FrameStats& s) {
  // The stages a sample runs add up over the frame's samples.
  syncMs += s.syncMs;
  shadowsMs += s.shadowsMs;
  probesMs += s.probesMs;
  rasterMs += s.rasterMs;
  readbackMs += s.readbackMs;
  raysMs += s.raysMs;
  uploadMs += s.uploadMs;
  compositeMs += s.compositeMs;
  accumulateMs += s.accumulateMs;
  bookkeepingMs += s.bookkeepingMs;
  shadowMapsMs += s.shadowMapsMs;
  probesDrawn += s.probesDrawn;
  rays += s.rays;
  // What describes the frame's ray grid and maps is the last sample's.
  rayWidth = s.rayWidth;
  rayHeight = s.rayHeight;
  threads = s.threads;
  shadowMapBytes = s.shadowMapBytes;
  probes = s.probes;
  raysReused = s.raysReused;
  denoiseMs += s.denoiseMs;
  denoised = s.denoised;
  shadowsProvedInGl = s.shadowsProvedInGl;
}

}  // namespace tandem
