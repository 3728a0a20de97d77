#!/usr/bin/env python3
"""The frame channels are declared once (shaders/bindings.glsl, TD_CHANNEL_* / TD_SAMPLER_* / TD_OUTPUT_*):
- every channel's GL internal format is the one docs/gbuffer.md gives its row;
- the passes that make or move those channels name no GL format or pixel-transfer enum of their own;
- every shader declares a channel's texture unit with the channel's sampler type, and its outputs with
  the table's output types.
Usage: channel-table.py REPO_ROOT"""
import os
import re
import sys

root = sys.argv[1]
fail = []

table = open(os.path.join(root, "shaders", "bindings.glsl")).read()
channels = dict(re.findall(r"^#define TD_CHANNEL_(\w+) (GL_\w+), GL_\w+, GL_\w+", table, re.M))
samplers = dict(re.findall(r"^#define TD_SAMPLER_(\w+) (\w+)", table, re.M))
if len(channels) < 9:
    fail.append(f"bindings.glsl: expected the frame channels, found {sorted(channels)}")

# docs/gbuffer.md: the first cell names the channel, the second its format.
doc_rows = {}
for line in open(os.path.join(root, "docs", "gbuffer.md")):
    cells = [c.strip() for c in line.strip().strip("|").split("|")]
    if len(cells) >= 2:
        doc_rows[cells[0]] = cells[1]
doc_name = {"IDS": "ids", "DEPTH": "depth", "LIGHT_MASK": "light mask", "REFLECTED": "reflected",
            "TRANSMITTED": "transmitted", "LINEAR": "linear radiance", "DISPLAY": "display",
            "PROBES": "reflection probes", "SHADOW_MAPS": "shadow maps", "AREA_SAMPLES": "area-light samples",
            "EXACT_HITS": "exact hits", "SHADOW_MASK": "shadow mask", "SHADOW_PROOFS": "shadow proofs",
            "DENOISE_NOISY": "denoise: noisy", "DENOISE_GUIDE": "denoise: guide", "DENOISE_MOTION": "denoise: motion",
            "DENOISE_EXACT": "denoise: exact", "DENOISE_TEXEL": "denoise: texels", "DENOISE_MOMENTS": "denoise: moments",
            "DENOISE_RADIANCE": "denoise: radiance"}
for name, fmt in channels.items():
    row = doc_name.get(name)
    if row is None:
        fail.append(f"bindings.glsl: TD_CHANNEL_{name} has no docs/gbuffer.md row in this check's list")
    elif row not in doc_rows:
        fail.append(f"docs/gbuffer.md: no row '{row}' for TD_CHANNEL_{name}")
    elif f"`{fmt[3:]}`" not in doc_rows[row]:
        fail.append(f"docs/gbuffer.md: row '{row}' says {doc_rows[row]!r}, bindings.glsl says {fmt}")

# The passes that own the channels take every format from the table.
# Internal formats and the pixel transfer formats and types of CPU copies; a static_assert that pins a
# channel's transfer to the C++ type it is read into is the one place such a name may appear.
literal = re.compile(r"\bGL_(RG32UI|R16UI|R32UI|RGBA32F|RGBA16F|RGBA16|RGBA8|DEPTH_COMPONENT32F|RG_INTEGER|RED_INTEGER|RGBA|"
                     r"FLOAT|HALF_FLOAT|UNSIGNED_BYTE|UNSIGNED_SHORT|UNSIGNED_INT|DEPTH_COMPONENT)\b")
for f in ["VisibilityPass.cpp", "ShadePass.cpp", "OutputPass.cpp", "ReflectionProbes.cpp", "RasterEffects.cpp",
          "RayChannels.h", "ShadowProofPass.cpp", "DenoisePass.cpp"]:
    path = os.path.join(root, "engine", "src", "gl", f)
    in_assert = False
    for n, line in enumerate(open(path), 1):
        code = line.split("//")[0]
        in_assert = in_assert or "static_assert" in code
        if not in_assert and literal.search(code):
            fail.append(f"{path}:{n}: a channel format written by hand: {line.strip()}")
        if in_assert and ";" in code:
            in_assert = False

# Shaders: a unit that is a channel is declared with the channel's sampler type, and every fragment
# output with a TD_OUTPUT_ type.
unit_decl = re.compile(r"layout\s*\(\s*binding\s*=\s*TD_UNIT_(\w+)\s*\)\s*uniform\s+(\w+)\s")
out_decl = re.compile(r"layout\s*\(\s*location\s*=\s*\d+\s*\)\s*out\s+(\w+)\s")
for f in sorted(os.listdir(os.path.join(root, "shaders"))):
    path = os.path.join(root, "shaders", f)
    for n, line in enumerate(open(path), 1):
        m = unit_decl.search(line)
        if m and m.group(1) in samplers and m.group(2) != f"TD_SAMPLER_{m.group(1)}":
            fail.append(f"{path}:{n}: TD_UNIT_{m.group(1)} declared as {m.group(2)}, not TD_SAMPLER_{m.group(1)}")
        o = out_decl.search(line)
        if o and not o.group(1).startswith("TD_OUTPUT_"):
            fail.append(f"{path}:{n}: a fragment output typed by hand ({o.group(1)}), not by a TD_OUTPUT_ of bindings.glsl")

for f in fail:
    print(f)
sys.exit(1 if fail else 0)
