#!/usr/bin/env python3
"""render-stats.py RENDER OUTDIR: tandem-render on the embedded default scene writes the image it was asked for and
--stats JSON that holds what the frame did, checked against counts made independently:
- the PNG has the requested size (its IHDR), the summary names the preset, the exit status is 0;
- every stage has min <= median <= max, all finite and >= 0, and the settings and preset are those asked for;
  every frame's stages make its total within 2 % (what is left is `untimed`), for every preset, in one of
  three draws (a preemption between two stages is the machine's time); the GL stages carry their GPU time;
- hybrid-full's primary rays equal the pixels the frame shows a surface at (the instance-id view's non-black
  pixels, decoded here), at --scale 2 the grid pixels whose stand-in pixel shows one; the reference's are
  width x height x spp^2; the raster preset traces nothing; without shadows no shadow ray, with depth 0 no
  reflection or refraction ray;
- --pipeline on gives the image and rays of --pipeline off, and both report the interval between frames.
"""
import json
import math
import os
import struct
import subprocess
import sys
import zlib

render, out = sys.argv[1], sys.argv[2]
W, H = 96, 54
fail = []


def run(name, *args):
    png = os.path.join(out, f"cli-stats-{name}.png")
    stats = os.path.join(out, f"cli-stats-{name}.json")
    p = subprocess.run([render, "--size", f"{W}x{H}", "-o", png, "--stats", stats, *args], capture_output=True, text=True)
    if p.returncode != 0:
        fail.append(f"{name}: exit {p.returncode}: {p.stderr.strip()}")
        return None, None, ""
    with open(stats) as f:
        return png, json.load(f), p.stdout


def read_png(path):
    """8-bit RGBA or RGB PNG → (width, height, rows of bytes), with the five row filters undone."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    pos, idat, ihdr = 8, b"", None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            ihdr = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    w, h, depth, colour = ihdr[0], ihdr[1], ihdr[2], ihdr[3]
    assert depth == 8 and colour in (2, 6), f"unexpected PNG format {depth}/{colour}"
    bpp = 4 if colour == 6 else 3
    raw = zlib.decompress(idat)
    rows, prev, stride = [], bytearray(w * bpp), w * bpp
    for y in range(h):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        prev = line
    return w, h, bpp, rows


png, full, summary = run("hybrid-full", "--preset", "hybrid-full")
if full:
    w, h, _, _ = read_png(png)
    if (w, h) != (W, H):
        fail.append(f"the image is {w}x{h}, not {W}x{H}")
    if "preset hybrid-full" not in summary.splitlines()[0]:
        fail.append("the summary does not name the preset: " + summary.splitlines()[0])
    if full.get("preset") != "hybrid-full" or full.get("width") != W or full.get("height") != H:
        fail.append(f"--stats says preset {full.get('preset')} at {full.get('width')}x{full.get('height')}")
STAGES = ("plan", "prepare", "sync", "shadows", "probes", "raster", "readback", "rays", "upload", "composite",
          "accumulate", "bookkeeping", "present")
GPU_STAGES = ("shadows", "probes", "raster", "upload", "composite", "accumulate")


def untimed_share(stats):
    """What of the frame's total lies outside its stages, as a fraction of the total."""
    stages = stats.get("stages_ms", {})
    total = stages.get("total", {}).get("median", 0.0)
    summed = sum(stages[s]["median"] for s in STAGES if s in stages)
    return abs(total - summed) / total if total > 0 else 0.0


def check_stages(name, stats, args):
    # A frame whose stages leave more than 2 % untimed is drawn again, twice at most: on 2 cores shared with
    # other tests the scheduler can take the render thread between two stages for a time slice (14 ms of a
    # 98 ms frame seen in CI), which is the machine's time, not the frame's; work done outside the stages
    # leaves the same gap every time it is drawn.
    for attempt in range(2):
        if untimed_share(stats) <= 0.02:
            break
        print(f"{name}: {untimed_share(stats):.1%} of the frame untimed, drawn again")
        _, again, _ = run(f"{name}-again{attempt}", *args)
        if again is None:
            return
        stats = again
    for stage in STAGES + ("total",):
        s = stats["stages_ms"].get(stage)
        if s is None:
            fail.append(f"{name}: --stats lacks stage {stage}")
            continue
        if not all(math.isfinite(s[k]) and s[k] >= 0 for k in ("min", "median", "max")) or not s["min"] <= s["median"] <= s["max"]:
            fail.append(f"{name}: stage {stage}: min/median/max {s}")
    # One frame: its median is the frame. The stages make the total but for the timers' own microseconds.
    total = stats["stages_ms"]["total"]["median"]
    summed = sum(stats["stages_ms"][s]["median"] for s in STAGES if s in stats["stages_ms"])
    if abs(total - summed) > 0.02 * total:
        fail.append(f"{name}: the stages add up to {summed:.3f} ms of a {total:.3f} ms frame")
    if abs(stats["stages_ms"]["untimed"]["median"] - (total - summed)) > 1e-3 * total + 1e-3:
        fail.append(f"{name}: untimed is not what the stages leave of the total")
    for stage in GPU_STAGES:
        g = stats.get("gpu_ms", {}).get(stage)
        if g is None or not (math.isfinite(g["median"]) and g["median"] >= 0):
            fail.append(f"{name}: no GPU time for stage {stage}: {g}")


if full:
    check_stages("hybrid-full", full, ("--preset", "hybrid-full"))

# What the frame shows, independently: the instance-id view's pixels (black is the sky).
png, ids, _ = run("ids", "--preset", "hybrid-full", "--debug-view", "instance")
if ids and full:
    _, _, bpp, rows = read_png(png)
    surface = [[any(rows[y][x * bpp:x * bpp + 3]) for x in range(W)] for y in range(H)]
    covered = sum(sum(r) for r in surface)
    if not 0 < covered < W * H:
        fail.append(f"the id view shows {covered} surface pixels of {W * H}")
    if full["rays"]["primary"] != covered:
        fail.append(f"hybrid-full: {full['rays']['primary']} primary rays, {covered} pixels show a surface")
    for k in ("shadow", "reflection", "refraction"):
        if full["rays"][k] <= 0:
            fail.append(f"hybrid-full on the Whitted scene traced no {k} ray")
    # --scale 2: grid pixel (gx, gy) stands for (min(2gx + 1, W - 1), min(2gy + 1, H - 1)).
    _, half, _ = run("half", "--preset", "hybrid-full", "--scale", "2")
    if half:
        want = sum(surface[min(2 * gy + 1, H - 1)][min(2 * gx + 1, W - 1)]
                   for gy in range((H + 1) // 2) for gx in range((W + 1) // 2))
        if half["rays"]["primary"] != want:
            fail.append(f"--scale 2: {half['rays']['primary']} primary rays, {want} grid pixels show a surface")

_, ref, _ = run("reference", "--preset", "reference", "--spp", "2")
if ref and ref["rays"]["primary"] != W * H * 4:
    fail.append(f"reference --spp 2: {ref['rays']['primary']} primary rays, not {W * H * 4}")
_, raster, _ = run("raster", "--preset", "raster")
if raster:
    check_stages("raster", raster, ("--preset", "raster"))
if ref:
    check_stages("reference", ref, ("--preset", "reference", "--spp", "2"))
if raster and any(raster["rays"][k] for k in ("primary", "shadow", "reflection", "refraction", "resolved")):
    fail.append(f"the raster preset traced rays: {raster['rays']}")
_, noshadow, _ = run("noshadow", "--preset", "hybrid-full", "--shadows", "off")
if noshadow and full and (noshadow["rays"]["shadow"] != 0 or noshadow["rays"]["primary"] != full["rays"]["primary"]):
    fail.append(f"--shadows off: {noshadow['rays']}")
_, flat, _ = run("depth0", "--preset", "hybrid-full", "--depth", "0")
if flat and full and (flat["rays"]["reflection"] or flat["rays"]["refraction"] or flat["rays"]["shadow"] > full["rays"]["shadow"]):
    fail.append(f"--depth 0: {flat['rays']}")

# Throughput mode: the same image and rays as latency mode over --frames 3 (each call shows the frame before;
# the last is shown by finish()), every frame's stats, the interval between frames, no drain (nothing changed).
png_off, off, _ = run("latency", "--preset", "hybrid-full", "--frames", "3")
png_on, on, summary_on = run("throughput", "--preset", "hybrid-full", "--frames", "3", "--pipeline", "on")
if off and on:
    if open(png_off, "rb").read() != open(png_on, "rb").read():
        fail.append("--pipeline on: the image differs from --pipeline off's")
    if on["rays"] != off["rays"]:
        fail.append(f"--pipeline on: rays {on['rays']} against {off['rays']}")
    if on.get("pipelined") is not True or off.get("pipelined") is not False:
        fail.append(f"--stats pipelined: {on.get('pipelined')} / {off.get('pipelined')}")
    for name, j in (("latency", off), ("throughput", on)):
        iv = j.get("interval_ms", {})
        if not (0 < iv.get("min", 0) <= iv.get("median", 0) <= iv.get("max", 0)):
            fail.append(f"{name}: interval_ms {iv}")
    if on.get("pipeline", {}).get("drained_frames") != 0:
        fail.append(f"--pipeline on: {on.get('pipeline')} (nothing changed: no frame should drain)")
    if "throughput mode" not in summary_on:
        fail.append("--pipeline on: the summary does not say the total is each frame's latency")

for f in fail:
    print(f)
sys.exit(1 if fail else 0)
