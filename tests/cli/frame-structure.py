#!/usr/bin/env python3
"""The frame keeps the shape docs/architecture.md describes, so it can be double-buffered and overlapped:
- Renderer::render and Renderer::Impl::drawSample read as stage calls, under 80 lines together, and
  render/Renderer.cpp holds the frame only (under 500 lines);
- shade.frag's shadePixel is a thin main (under 80 lines) over the shade_*.glsl steps;
- the shade pass (shade.frag and the shade_*.glsl it includes) skips features with plain ifs on the
  variant's typed constants: at most 10 #if / #ifdef / #elif, kept where a declaration differs;
- every TD_ flag the shade pass tests has a typed constant or is one of the named non-boolean ones.
Usage: frame-structure.py REPO_ROOT"""
import os
import re
import sys

root = sys.argv[1]
fail = []


def body_lines(path, signature):
    """Lines from the line that starts with `signature` to the first line that is "}" alone."""
    lines = open(path).read().split("\n")
    for i, line in enumerate(lines):
        if line.startswith(signature):
            for j in range(i, len(lines)):
                if lines[j] == "}":
                    return j - i + 1
            break
    fail.append(f"{path}: no function starting with {signature!r}")
    return 0


renderer = os.path.join(root, "engine", "src", "render", "Renderer.cpp")
render = body_lines(renderer, "FrameStats Renderer::render(")
draw_sample = body_lines(renderer, "bool Renderer::Impl::drawSample(")
if render + draw_sample >= 80:
    fail.append(f"{renderer}: render ({render} lines) + drawSample ({draw_sample}) should be under 80 together")
total = len(open(renderer).read().split("\n"))
if total >= 500:
    fail.append(f"{renderer}: {total} lines; the frame only should stay under 500")

shaders = os.path.join(root, "shaders")
frag = os.path.join(shaders, "shade.frag")
shade_pixel = body_lines(frag, "void shadePixel()")
if shade_pixel >= 80:
    fail.append(f"{frag}: shadePixel is {shade_pixel} lines; under 80 calling the shade_*.glsl steps")

pass_files = [frag] + sorted(os.path.join(shaders, f) for f in os.listdir(shaders) if re.match(r"shade_\w+\.glsl$", f))
conditionals = []
for path in pass_files:
    for n, line in enumerate(open(path), 1):
        if re.match(r"\s*#\s*(if|ifdef|elif)\b", line):
            conditionals.append(f"{os.path.basename(path)}:{n}: {line.strip()}")
if len(conditionals) > 10:
    fail.append(f"the shade pass has {len(conditionals)} #if / #ifdef / #elif (at most 10):\n  " +
                "\n  ".join(conditionals))

# A flag tested in code (not in its own default or constant) goes through its typed constant, so a
# feature check cannot quietly be written as an #if again or against a misspelt macro.
text = open(frag).read()
constants = set(re.findall(r"^const bool k\w+ = \(?(TD_\w+)", text, re.M))
defaults = set(re.findall(r"^#ifndef (TD_\w+)", text, re.M))
not_boolean = {"TD_LIGHT_COUNT", "TD_UNIFORM_MATERIALS", "TD_LIGHT_KINDS", "TD_DEBUG_VIEW", "TD_RAY_INPUTS"}
for flag in sorted(defaults - constants - not_boolean):
    fail.append(f"{frag}: the variant flag {flag} has a default and no typed constant (const bool k... = {flag} ...)")
for path in pass_files:
    for n, line in enumerate(open(path), 1):
        code = line.split("//")[0]
        if code.lstrip().startswith("#") or code.lstrip().startswith("const bool k"):
            continue
        for flag in re.findall(r"\b(TD_\w+)\s*[!=]=\s*0", code):
            if flag in constants:
                fail.append(f"{path}:{n}: {flag} tested by hand; use its typed constant")

for f in fail:
    print(f)
sys.exit(1 if fail else 0)
