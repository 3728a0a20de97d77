#!/bin/sh
# tandem-render RENDER OUTDIR: every invalid value (including those that used to render with exit 0:
# --depth -1, --spp 0, --scale 0, --exposure 0 and inf, --spp without the reference preset; a
# --trace-pixel outside the frame) exits
# non-zero before rendering, with exactly one line on stderr naming the flag and nothing on stdout.
set -u
render="$1"
out="$2"
status=0
check() {  # FLAG ARGS...: ARGS must be refused with a message naming FLAG
  flag="$1"
  shift
  rm -f "$out/cli-reject.png"
  if "$render" --size 32x18 -o "$out/cli-reject.png" "$@" >"$out/cli-reject.out" 2>"$out/cli-reject.err"; then
    echo "accepted with exit 0: $*"
    status=1
    return
  fi
  lines=$(wc -l <"$out/cli-reject.err")
  if [ "$lines" -ne 1 ]; then
    echo "$lines lines on stderr for: $*"
    cat "$out/cli-reject.err"
    status=1
  fi
  if ! grep -q -- "^tandem-render: .*$flag" "$out/cli-reject.err"; then
    echo "error does not name $flag for: $*: $(cat "$out/cli-reject.err")"
    status=1
  fi
  if [ -s "$out/cli-reject.out" ] || [ -e "$out/cli-reject.png" ]; then
    echo "rendered or printed a summary for: $*"
    status=1
  fi
}
check --depth --depth -1
check --depth --depth 65
check --depth --depth abc
check --spp --preset reference --spp 0
check --spp --preset reference --spp 65
check --spp --spp 4
check --spp --preset hybrid-fast --spp 2
check --probe-limit --preset raster --probe-limit 0
check --probe-limit --preset raster --probe-limit 5000
check --probe-limit --probe-limit 8
check --probe-limit --preset reference --probe-limit 8
check --probe-size --preset raster --probe-size 100
check --probe-size --preset raster --probe-size 8
check --probe-size --preset hybrid-full --probe-size 64
check --probes-per-frame --preset raster --probes-per-frame -1
check --probes-per-frame --preset raster --probes-per-frame 5000
check --probes-per-frame --preset hybrid-full --probes-per-frame 2
check --environment --environment "$out/no-such-environment.hdr"
check --environment --environment "$0"
check --environment-intensity --environment-intensity 2
check --environment-intensity --environment none --environment-intensity 2
check --environment-intensity --environment sky --environment-intensity -1
check --environment-rotation --environment sky --environment-rotation inf
check --environment-rotation --environment-rotation 90
check --scale --scale 0
check --scale --scale 3
check --scale --preset reference --scale 2
check --exposure --exposure 0
check --exposure --exposure -1
check --exposure --exposure inf
check --exposure --exposure nan
check --size --size 0x0
check --preset --preset fast
check --shadows --shadows on
check --tonemap --tonemap filmic
check --frames --frames 0
check --threads --threads -1
check --context --context x11
check -o -o "$out/cli-reject.tga"
check --trace-pixel --trace-pixel 32,0
check --trace-pixel --trace-pixel 0,18
check --trace-pixel --trace-pixel 5
check --trace-pixel --trace-pixel -1,5
check --aa --aa smooth
check --denoise --denoise maybe
check --denoise --denoise on --aa ssaa 4
check --denoise --denoise on --preset reference
check --aa --aa ssaa 0
check --aa --aa ssaa 257
check --aa --aa ssaa four
check --aa --aa off 4
check --aa --aa ssaa 4 --preset reference
check --aa --aa adaptive --target-fps 30
check --aa-threshold --aa-threshold 0.1
check --aa-threshold --aa adaptive --aa-threshold 2
check --aa-threshold --aa adaptive --aa-threshold nan
check --accumulate --accumulate -1
check --accumulate --accumulate 65537
check --accumulate --accumulate 8 --target-fps 30
check --light-samples --light-samples 0
check --light-samples --light-samples 33
check --light-samples --light-samples many
check --gloss-samples --gloss-samples 0
check --gloss-samples --gloss-samples 33
check --aperture --aperture -0.5
check --aperture --aperture nan
check --focus-distance --focus-distance 0
check --focus-distance --focus-distance inf
check --shutter --shutter -0.1
check --shutter --shutter inf
check --gi --gi radiosity --preset reference
check --gi --gi path
check --trace-pixel --preset reference --gi path --trace-pixel 1,1
check --radiosity --radiosity maybe
check --radiosity --preset reference --gi path --radiosity on
check --radiosity-error --radiosity on --radiosity-error 1.5
check --radiosity-error --radiosity on --radiosity-error nan
check --radiosity-error --radiosity-error 0.1
check --radiosity-shots --radiosity on --radiosity-shots 0
check --radiosity-patches --radiosity on --radiosity-patches 8
check --radiosity-patches --radiosity-patches 512
check --radiosity-refine --radiosity on --radiosity-refine maybe
check --radiosity-refine --radiosity-refine off
exit $status
