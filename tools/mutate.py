#!/usr/bin/env python3
"""Mutation testing (docs/testing.md): each mutation below is a one-line bug a reviewer could plausibly write; the
suite must catch every one. For each: copy the pristine file into a scratch tree, apply the mutation, rebuild the
test binary that should catch it there, run its tests, and expect a failure. A mutation the tests pass is a
survivor: a hole in the tests. A mutation whose text is no longer in its file is stale: update it.

  tools/mutate.py [--build DIR] [--only ID[,ID...]] [--list]

The scratch tree is DIR/src (the working tree copied, build folders and .git left out, refreshed each run) with
its own Release build in DIR/build (default DIR: build/mutation). The first run builds everything the listed
tests need (about as long as a full build); each mutation then rebuilds only what its file touches.
Exit status: 0 when every mutation was killed, 1 otherwise.

Adding a feature adds its mutations here: one per formula, decision or check it introduces, each naming the
test binary and the gtest filter of the fast test that kills it.
"""
import argparse
import os
import shutil
import subprocess
import sys
import time

# id, file, original text (must occur exactly once), mutated text, test binary target, gtest filter
MUTATIONS = [
    # Shading formulas (shaders/shading.glsl is compiled as C++ too: the oracles see it).
    ("schlick-fourth-power", "shaders/shading.glsl",
     "return r0 + (1.0f - r0) * k * k * k * k * k;", "return r0 + (1.0f - r0) * k * k * k * k;",
     "tandem-numerics-tests", "Oracles.*"),
    ("fresnel-drops-s-polarisation", "shaders/shading.glsl",
     "return 0.5f * (rPar * rPar + rPerp * rPerp);", "return 0.5f * (rPar * rPar + rPar * rPar);",
     "tandem-numerics-tests", "Oracles.*"),
    ("phong-exponent-halved", "shaders/shading.glsl",
     "return rv > 0.0f ? pow(rv, ns) : 0.0f;", "return rv > 0.0f ? pow(rv, 0.5f * ns) : 0.0f;",
     "tandem-numerics-tests", "Oracles.*"),
    ("aces-curve-constant", "shaders/shading.glsl",
     "vec3 num = c * (2.51f * c + vec3(0.03f));", "vec3 num = c * (2.41f * c + vec3(0.03f));",
     "tandem-gl-tests", "Golden.*"),
    # Rays: media, Snell, offsets, shadow-ray sides.
    ("inside-outside-ignored", "engine/src/rt/Whitted.cpp",
     "float etaI = hit.backFace ? ior : 1.0f;\n    float etaT = hit.backFace ? 1.0f : ior;",
     "float etaI = 1.0f;\n    float etaT = ior;",
     "tandem-numerics-tests", "Oracles.*"),
    ("snell-ratio-inverted", "engine/src/rt/RayMath.h",
     "float eta = etaI / etaT;", "float eta = etaT / etaI;",
     "tandem-numerics-tests", "Oracles.*"),
    ("shadow-origin-always-front", "engine/src/rt/Whitted.cpp",
     "r.originW = origins.towards(hit, glm::dot(toLight, hit.geomNormalW) >= 0.0f);",
     "r.originW = origins.towards(hit, true);",
     "tandem-numerics-tests", "Oracles.*"),
    ("offset-without-error-bound", "engine/src/rt/RayMath.h",
     "float d = kUlp * (kErrUlps * glm::dot(an, magnitude) + kMinUlps * maxMag);",
     "float d = 0.0f * kUlp * (kErrUlps * glm::dot(an, magnitude) + kMinUlps * maxMag);",
     "tandem-rt-tests", "OriginOffset.*"),
    # Exact solids and their frame.
    ("resolve-keeps-the-proxy-id", "engine/src/rt/RayTracer.cpp",
     "r.id.y = hit.triangle;", "r.id.y = r.id.y;",
     "tandem-rt-tests", "ResolveExact.*"),
    ("proxy-triangles-block-shadows", "engine/src/rt/ShadowCertainty.cpp",
     "bool blocks = !embree.letsRaysThrough(i) && !mesh.exact;", "bool blocks = !embree.letsRaysThrough(i);",
     "tandem-rt-tests", "ResolveExact.*"),
    ("torus-proxy-not-widened", "engine/src/io/SolidProxy.cpp",
     "const double rt = r + widened;", "const double rt = r;",
     "tandem-unit-tests", "SolidProxy.*"),
    # Procedural textures.
    ("noise-fade-derivative-dropped", "shaders/procedural.glsl",
     "vec3 du = 30.0f * f * f * (f * (f - vec3(2.0f)) + vec3(1.0f));", "vec3 du = vec3(0.0f);",
     "tandem-unit-tests", "Procedural.*"),
    ("bump-bends-the-wrong-way", "shaders/procedural.glsl",
     "vec3 n = N - amplitude * (gradW - dot(gradW, N) * N);", "vec3 n = N + amplitude * (gradW - dot(gradW, N) * N);",
     "tandem-unit-tests", "Procedural.*"),
    # Loaders.
    ("gltf-folder-by-string-prefix", "engine/src/io/GltfFs.cpp",
     "if (!isInside(c.root, canon))", "if (canon.string().rfind(c.root.string(), 0) != 0)",
     "tandem-unit-tests", "GltfConfinement.*:GltfHardening.*"),
    ("scene-file-unknown-keys-allowed", "engine/src/io/SceneJson.h",
     "if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;", "continue;",
     "tandem-unit-tests", "SceneFile*"),
    # Metrics.
    ("flip-colour-exponent", "engine/src/core/ImageMetrics.cpp",
     "constexpr float kQc = 0.7f;", "constexpr float kQc = 0.6f;",
     "tandem-unit-tests", "ImageMetrics*:Flip*"),
    # Counts.
    ("stats-primary-is-the-grid-shadow-doubled", "engine/src/render/Renderer.cpp",
     "    stats.rays = rays.counts;\n",
     "    stats.rays = rays.counts;\n    stats.rays.primary = static_cast<std::uint64_t>(rays.width) * rays.height;\n"
     "    stats.rays.shadow *= 2;\n",
     "tandem-gl-tests", "FrameCountsGL.*"),
    # The game.
    ("game-no-wall-bounce", "samples/game/logic/Game.cpp",
     "vel_ -= (1.0f + tuning_.restitution) * vn * c->normal;", "vel_ -= vn * c->normal;",
     "tandem-game-unit-tests", "GamePhysics.*:Game.*"),
    ("game-damping-per-step-not-substep", "samples/game/logic/Game.cpp",
     "vel_ *= std::exp(-damping * h);", "vel_ *= std::exp(-damping * dt);",
     "tandem-game-unit-tests", "GamePhysics.*:Game.*"),
    ("game-gem-reach-without-the-marble", "samples/game/logic/Game.cpp",
     "const float reach = level_.marbleRadius + level_.gemRadius;", "const float reach = level_.gemRadius;",
     "tandem-game-unit-tests", "GamePhysics.*:Game.*"),
    ("game-clock-runs-after-a-win", "samples/game/logic/Game.cpp",
     "const double t = outcome_ == Outcome::Playing ? time_ : endTime_;", "const double t = time_;",
     "tandem-game-unit-tests", "GamePhysics.*:Game.*"),
]


def run(cmd, cwd=None, timeout=None):
    return subprocess.run(cmd, cwd=cwd, timeout=timeout, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(root, "build", "mutation"))
    ap.add_argument("--only", default="")
    ap.add_argument("--list", action="store_true")
    a = ap.parse_args()
    chosen = [m for m in MUTATIONS if not a.only or m[0] in a.only.split(",")]
    if a.list:
        for m in chosen:
            print(f"{m[0]:45s} {m[1]:40s} {m[4]} --gtest_filter={m[5]}")
        return 0
    if not chosen:
        print("mutate: no mutation by that id")
        return 1
    src, build = os.path.join(a.build, "src"), os.path.join(a.build, "build")
    os.makedirs(src, exist_ok=True)
    # The scratch tree: the working tree as it is (uncommitted changes too), without build folders and .git.
    skip = {".git", "out"}
    for name in os.listdir(root):
        if name in skip or name.startswith("build"):
            continue
        s, d = os.path.join(root, name), os.path.join(src, name)
        if os.path.isdir(s):
            r = run(["cp", "-a", "--update", "--no-target-directory", s, d])
        else:
            r = run(["cp", "-a", "--update", s, d])
        if r.returncode != 0:
            print(r.stdout)
            return 1
    # ../shared beside the scratch tree, as beside the real one (tests look for ../shared/assets).
    shared = os.path.join(os.path.dirname(root), "shared")
    if os.path.isdir(shared) and not os.path.exists(os.path.join(a.build, "shared")):
        os.symlink(shared, os.path.join(a.build, "shared"))
    jobs = str(os.cpu_count() or 2)
    if not os.path.exists(os.path.join(build, "CMakeCache.txt")):
        r = run(["cmake", "-S", src, "-B", build, "-DCMAKE_BUILD_TYPE=Release", "-DTANDEM_BUILD_BENCH=OFF"])
        if r.returncode != 0:
            print(r.stdout)
            return 1
    survivors, stale, broken = [], [], []
    for mid, rel, old, new, target, gfilter in chosen:
        path = os.path.join(src, rel)
        pristine = open(os.path.join(root, rel)).read()
        if pristine.count(old) != 1:
            stale.append(mid)
            print(f"{mid}: STALE ({pristine.count(old)} occurrences of its text in {rel})")
            continue
        t0 = time.time()
        try:
            with open(path, "w") as f:
                f.write(pristine.replace(old, new))
            b = run(["cmake", "--build", build, "-j", jobs, "--target", target])
            if b.returncode != 0:
                broken.append(mid)
                print(f"{mid}: does not build (fix the mutation):\n{b.stdout[-2000:]}")
                continue
            exe = os.path.join(build, "bin", target)
            try:
                t = run([exe, f"--gtest_filter={gfilter}", "--gtest_brief=1"], cwd=src, timeout=1200)
                killed = t.returncode != 0
                detail = next((l for l in t.stdout.splitlines() if l.startswith("[  FAILED  ]")), "")
            except subprocess.TimeoutExpired:
                killed, detail = True, "(timed out)"
            print(f"{mid}: {'killed' if killed else 'SURVIVED'} in {time.time() - t0:.0f} s {detail}", flush=True)
            if not killed:
                survivors.append(mid)
        finally:
            with open(path, "w") as f:
                f.write(pristine)
    # The scratch tree left pristine and built, ready for the next run.
    total = len(chosen)
    print(f"mutate: {total - len(survivors) - len(stale) - len(broken)} of {total} killed; survivors: "
          f"{', '.join(survivors) or 'none'}; stale: {', '.join(stale) or 'none'}; not building: {', '.join(broken) or 'none'}")
    return 0 if not survivors and not stale and not broken else 1


if __name__ == "__main__":
    sys.exit(main())
