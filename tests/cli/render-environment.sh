#!/bin/sh
# tandem-render RENDER OUTDIR: --environment FILE.hdr renders the default scene under an image (a uniform
# blue-white .hdr written here), which the frame's background then shows: the image's top-left pixel differs
# from the --environment none render's and is the image's radiance as the display shows it (ACES, Narkowicz's
# fit, then sRGB, worked out here). The top-left corner is sky in the default scene.
set -eu
render="$1"
out="$2"
python3 - "$out/cli-environment.hdr" <<'PY'
import sys
w, h = 16, 8
rows = bytes([128, 128, 255, 128]) * (w * h)  # RGBE: (128, 128, 255) * 2^(128 - 136) = (0.5, 0.5, 0.996)
open(sys.argv[1], "wb").write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (h, w) + rows)
PY
"$render" --quiet --size 64x36 --preset raster --environment none -o "$out/cli-environment-none.png"
"$render" --quiet --size 64x36 --preset raster --environment "$out/cli-environment.hdr" -o "$out/cli-environment.png"
python3 - "$out/cli-environment-none.png" "$out/cli-environment.png" <<'PY'
import struct, sys, zlib
def first_pixel(path):
    data = open(path, "rb").read()
    pos, idat, width = 8, b"", 0
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            width = struct.unpack(">I", body[:4])[0]
        if kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw = zlib.decompress(idat)
    # Every PNG filter predicts the first row's first pixel from nothing (zeros): its bytes are the pixel's.
    return tuple(raw[1:4])
none, image = first_pixel(sys.argv[1]), first_pixel(sys.argv[2])
def display(x):  # exposure 1, ACES (Narkowicz 2015), sRGB encoding, 8 bits
    a = min(max(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 0.0), 1.0)
    return round(255 * (12.92 * a if a <= 0.0031308 else 1.055 * a ** (1 / 2.4) - 0.055))
want = tuple(display(c * 2.0 ** (128 - 136)) for c in (128, 128, 255))
if none == image:
    sys.exit(f"--environment FILE.hdr changed nothing: {image}")
if max(abs(a - b) for a, b in zip(image, want)) > 1:
    sys.exit(f"the image's sky is {image}, not {want}")
PY
