#!/bin/sh
# tandem-render RENDER OUTDIR: --trace-pixel X,Y prints that pixel's ray tree after the frame. The pixel is
# one of the embedded Whitted scene's glass sphere at 320x180 (tests/rt/PixelTraceTest.cpp traces it too):
# the primary ray hits the glass, which spawns a reflection and a refraction ray, every light gets a line,
# and the pixel's sum closes the tree. Under --quiet the tree is all stdout holds. A pixel outside the frame
# is refused with one line naming the flag, before anything renders.
set -u
render="$1"
out="$2"
status=0
expect() {  # FILE PATTERN WHAT: FILE must hold a line matching the extended regex PATTERN
  if ! grep -qE -- "$2" "$1"; then
    echo "no $3 (/$2/) in:"
    cat "$1"
    status=1
  fi
}
if ! "$render" --size 320x180 --trace-pixel 132,87 -o "$out/cli-trace.png" >"$out/cli-trace.out" 2>"$out/cli-trace.err"; then
  echo "--trace-pixel 132,87 failed:"
  cat "$out/cli-trace.err"
  exit 1
fi
expect "$out/cli-trace.out" '^  rays/frame: ' "frame summary before the tree"
expect "$out/cli-trace.out" '^pixel \(132, 87\) of 320x180, hybrid ray pass, ray grid 1/1 pixel \(132, 87\)' "header"
expect "$out/cli-trace.out" '^primary ray, depth 0$' "primary ray"
expect "$out/cli-trace.out" '^  hit glass-sphere \(instance 2\), triangle [0-9]+, t [0-9.]+, front face, material glass' "primary hit on the glass"
expect "$out/cli-trace.out" '^  light 0 key: (unoccluded|occluded) \(shadow ray origin ' "key light's shadow ray"
expect "$out/cli-trace.out" '^  light 1 spot: ' "spot light's line"
expect "$out/cli-trace.out" '^  sum: kr 0\.1, kt 0\.9, F 0\.0[0-9]+, wR 0\.1[0-9]+, wT 0\.8[0-9]+$' "glass's Whitted weights"
expect "$out/cli-trace.out" '^  reflection ray, depth 1, weight 0\.1[0-9]+, throughput ' "reflection child"
expect "$out/cli-trace.out" '^  refraction ray, depth 1, weight 0\.8[0-9]+, throughput ' "refraction child"
expect "$out/cli-trace.out" '^    hit glass-sphere \(instance 2\), .*back face' "refracted ray leaving the glass"
expect "$out/cli-trace.out" '^pixel = local \(.*\) \+ reflected \(.*\) \+ transmitted \(.*\) = \(' "pixel sum"
expect "$out/cli-trace.out" '^light mask 0b[01]{2}; rays: 1 primary, [0-9]+ shadow, [0-9]+ reflection, [0-9]+ refraction$' "ray counts"
# The tree is the last thing printed, and with --quiet the only thing.
"$render" --size 320x180 --trace-pixel 132,87 -q -o "$out/cli-trace-q.png" >"$out/cli-trace-q.out" 2>&1 || status=1
if ! head -n 1 "$out/cli-trace-q.out" | grep -q '^pixel (132, 87) of 320x180'; then
  echo "--quiet --trace-pixel does not print the tree alone:"
  head -n 3 "$out/cli-trace-q.out"
  status=1
fi
# Outside the frame: one line naming the flag and the frame, nothing rendered or printed.
rm -f "$out/cli-trace-bad.png"
if "$render" --size 320x180 --trace-pixel 320,87 -o "$out/cli-trace-bad.png" >"$out/cli-trace-bad.out" 2>"$out/cli-trace-bad.err"; then
  echo "--trace-pixel 320,87 accepted for a 320x180 frame"
  status=1
fi
if [ "$(wc -l <"$out/cli-trace-bad.err")" -ne 1 ] ||
  ! grep -q -- '^tandem-render: --trace-pixel: pixel (320, 87) is outside the 320x180 frame' "$out/cli-trace-bad.err"; then
  echo "not one line naming --trace-pixel and the frame:"
  cat "$out/cli-trace-bad.err"
  status=1
fi
if [ -s "$out/cli-trace-bad.out" ] || [ -e "$out/cli-trace-bad.png" ]; then
  echo "rendered or printed for a pixel outside the frame"
  status=1
fi
exit $status
