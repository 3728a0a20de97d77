#!/bin/sh
# tandem-render RENDER OUTDIR: with no --preset (and a scene without render.preset) tandem-render renders
# the named default preset, hybrid-full, says so, and traces exactly the rays --preset hybrid-full traces
# (it used to render every effect by rays at depth 5, which matches no preset).
set -u
render="$1"
out="$2"
"$render" --size 64x36 -o "$out/cli-default-preset.png" --stats "$out/cli-default-preset.json" >"$out/cli-default-preset.out" || exit 1
"$render" --size 64x36 -o "$out/cli-hybrid-full.png" --preset hybrid-full >"$out/cli-hybrid-full.out" || exit 1
status=0
if ! head -n 1 "$out/cli-default-preset.out" | grep -q "preset hybrid-full (the default)"; then
  echo "the summary does not name the default preset:"
  head -n 1 "$out/cli-default-preset.out"
  status=1
fi
if ! grep -q '"preset": "hybrid-full"' "$out/cli-default-preset.json"; then
  echo "--stats does not name the preset"
  status=1
fi
a=$(grep 'rays/frame' "$out/cli-default-preset.out")
b=$(grep 'rays/frame' "$out/cli-hybrid-full.out")
if [ -z "$a" ] || [ "$a" != "$b" ]; then
  echo "default and --preset hybrid-full trace different rays:"
  echo "  default:             $a"
  echo "  --preset hybrid-full: $b"
  status=1
fi
# --preset replaces the default, and the summary says where the preset came from.
"$render" --size 64x36 -o "$out/cli-raster.png" --preset raster --depth 3 >"$out/cli-raster.out" || exit 1
if ! head -n 1 "$out/cli-raster.out" | grep -q "preset raster (--preset), changed by --depth"; then
  echo "the summary does not name --preset raster and the --depth override:"
  head -n 1 "$out/cli-raster.out"
  status=1
fi
# A raster frame runs no ray pass: the summary says so instead of "ray pass 0x0".
if grep -q "ray pass 0x0" "$out/cli-raster.out" || ! grep -q "; no ray pass" "$out/cli-raster.out"; then
  echo "the raster summary does not say 'no ray pass':"
  cat "$out/cli-raster.out"
  status=1
fi
exit $status
