#!/bin/sh
# tandem-render RENDER OUTDIR: a frame size the GL cannot hold exits non-zero with one line on stderr
# naming what refused it, and writes no image (it used to write a black one and exit 0). The size is
# 16384x16384, the largest --size takes: within llvmpipe's size limits (16384), but its 4 GiB RGBA32F
# radiance target is over the 2 GiB llvmpipe allocates for one texture, which it refuses before
# allocating anything. Elsewhere such a frame may fit (a GPU with the memory would render it, slowly), so
# the test runs on llvmpipe only and is skipped (77) on other drivers. Sizes over a driver's queried
# limits are the gl test FrameLimitsGLTest.ResizeBeyondTheDriverLimitNamesIt.
set -u
render="$1"
out="$2"
"$render" --preset raster --size 16x16 -o "$out/cli-size-probe.png" >"$out/cli-size-probe.out" 2>&1 || {
  echo "a 16x16 frame failed:"; cat "$out/cli-size-probe.out"; exit 1; }
if ! grep -q llvmpipe "$out/cli-size-probe.out"; then
  echo "skipped: needs llvmpipe's 2 GiB cap on one texture; the context here is:"
  sed -n 2p "$out/cli-size-probe.out"
  exit 77
fi
rm -f "$out/cli-size-limit.png"
if "$render" --preset raster --size 16384x16384 -o "$out/cli-size-limit.png" \
  >"$out/cli-size-limit.out" 2>"$out/cli-size-limit.err"; then
  echo "exit 0 for a frame llvmpipe cannot hold"
  exit 1
fi
status=0
if [ "$(wc -l <"$out/cli-size-limit.err")" -ne 1 ]; then
  echo "expected one line on stderr, got:"
  cat "$out/cli-size-limit.err"
  status=1
fi
if ! grep -q "^tandem-render: --size 16384x16384: the frame's GL targets need 8192.0 MiB; GL texture 'linear radiance' (16384x16384 GL_RGBA32F, 4096.0 MiB): glTextureStorage2D failed with GL_OUT_OF_MEMORY$" "$out/cli-size-limit.err"; then
  echo "the error does not name the size, the texture and GL_OUT_OF_MEMORY:"
  cat "$out/cli-size-limit.err"
  status=1
fi
if [ -e "$out/cli-size-limit.png" ]; then
  echo "an image was written"
  status=1
fi
exit $status
