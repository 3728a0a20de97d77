#!/usr/bin/env python3
"""Mutation testing (docs/testing.md): each mutation below is a one-line bug a reviewer could plausibly write; the
suite must catch every one. For each: copy the pristine file into a scratch tree, apply the mutation, rebuild the
test binary that should catch it there, run its tests, and expect a failure. A mutation the tests pass is a
survivor: a hole in the tests. A mutation whose text is no longer in its file is stale: update it.

  tools/mutate.py [--build DIR] [--only ID[,ID...]] [--list] [--check-texts] [--without-goldens]

--check-texts only checks that each mutation's text occurs exactly once in its file and that its gtest filter
names some test (no build, a second; the default test run does it, so that an edit which leaves a mutation
stale fails there, not months later).

--without-goldens leaves every golden-image test out of each mutation's run (gtest filter -*Golden*): a
golden is a regression net, not an oracle, and no behaviour may be guarded by one alone (docs/testing.md).
The ctest label `mutation` runs in that mode.

The scratch tree is DIR/src (the working tree copied, build folders and .git left out, refreshed each run) with
its own Release build in DIR/build (default DIR: build/mutation). The first run builds everything the listed
tests need (about as long as a full build); each mutation then rebuilds only what its file touches.
Exit status: 0 when every mutation was killed, 1 otherwise.

Adding a feature adds its mutations here: one per formula, decision or check it introduces, each naming the
test binary and the gtest filter of the fast test that kills it.
"""
import argparse
import filecmp
import fnmatch
import os
import re
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
     "tandem-numerics-tests", "Oracles.*"),
    ("light-samples-sobol-mask-one-bit", "shaders/shading.glsl",
     "uint take = 0u - (i & 1u);", "uint take = i & 1u;",
     "tandem-unit-tests", "AreaLight.EachFramesSamplesAreStratified*:Sampling.*"),
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
    # The ray pass's inputs and batches.
    ("selection-ignored", "engine/src/rt/RayTracer.cpp",
     "        if (!only.empty() && only[pixel] == 0) continue;  // not this round's: as the background",
     "        if (!only.empty() && only[pixel] == 2) continue;  // not this round's: as the background",
     "tandem-rt-tests", "RayPassWhitted.ASelection*"),
    ("shadow-packet-bit-of-light-0", "engine/src/rt/Wavefront.cpp",
     "    const auto bit = static_cast<LightMask>(1u << j);", "    const auto bit = static_cast<LightMask>(1u);",
     "tandem-rt-tests", "RayPassWhitted.*:RayPassShadows.*"),
    ("blend-surface-spawns-nothing", "engine/src/rt/SurfaceShading.h",
     "  return !(krKtIorModel.x > 0.0f) && !(krKtIorModel.y > 0.0f) && coverage >= 1.0f;",
     "  return !(krKtIorModel.x > 0.0f) && !(krKtIorModel.y > 0.0f) && coverage >= 0.0f;",
     "tandem-rt-tests", "RayPassWhitted.*"),
    ("shadow-packet-lane-time-mid", "engine/src/rt/Wavefront.cpp",
     "        packet.time[k] = r.time;", "        packet.time[k] = 0.5f;",
     "tandem-rt-tests", "MotionBlurRays.*"),
    # Hybrid shadows proved in the GL.
    ("segment-test-crosses-outside-the-triangle", "shaders/shadow_tests.glsl",
     "  if (inside && abs(s0) > margin && endBeyond", "  if (abs(s0) > margin && endBeyond",
     "tandem-rt-tests", "HybridShadows.*"),
    ("complete-pixel-despite-a-mirror", "engine/src/render/ShadowProofs.cpp",
     "if (m.kr == 0.0f && m.kt == 0.0f && m.alphaMode", "if (m.kt == 0.0f && m.alphaMode",
     "tandem-gl-tests", "ShadowProofsGLTest.*"),
    ("complete-pixel-unlit-where-the-light-cannot-reach", "shaders/shadow_proof.frag",
     "          mask |= bit;  // no ray; the CPU leaves the bit set", "          mask |= 0u;",
     "tandem-gl-tests", "ShadowProofsGLTest.*"),
    ("complete-pixel-answers-uncounted", "engine/src/rt/RayTracer.cpp",
     "          counts.shadowByMap += static_cast<std::uint64_t>(std::popcount((proof >> kProofNeededShift) & 0xFFu));",
     "", "tandem-gl-tests", "ShadowProofsGLTest.*"),
    ("gl-proofs-at-the-wrong-stand-ins", "shaders/shadow_proof.frag",
     "* rayScale + rayScale / 2, frameSize - 1)", "* rayScale, frameSize - 1)",
     "tandem-gl-tests", "ShadowProofsGLTest.*"),
    ("gl-proof-swaps-lit-and-shadowed", "shaders/shadow_proof.frag",
     "        if (answer == 1) lit |= bit;", "        if (answer == 2) lit |= bit;",
     "tandem-gl-tests", "ShadowProofsGLTest.*"),
    ("gl-proof-lit-despite-an-unsure-candidate", "shaders/shadow_proof.frag",
     "> depth + eps) return missesAll ? 1 : 0;", "> depth + eps) return 1;",
     "tandem-gl-tests", "ShadowProofsGLTest.*"),
    ("gl-read-backs-bottom-up", "engine/src/gl/GlObjects.h",
     "  flipRows(pixels, width, height);\n}", "}",
     "tandem-gl-tests", "ShadowProofsGLTest.*"),
    ("resolved-pixels-keep-their-proofs", "engine/src/rt/RayTracer.cpp",
     "          if (r.id != id && !visibility.proofs.empty())", "          if (false && !visibility.proofs.empty())",
     "tandem-rt-tests", "ResolveExact.*"),
    ("proofs-outlive-their-frame", "engine/src/render/Renderer.cpp",
     "  into.proofs.clear();\n", "",
     "tandem-gl-tests", "ShadowProofsGLTest.*"),
    # Exact solids and their frame.
    ("resolve-keeps-the-proxy-id", "engine/src/rt/RayTracer.cpp",
     "                r.id.y = kExactTriangle;", "                r.id.y = r.id.y;",
     "tandem-rt-tests", "ResolveExact.*"),
    ("proxy-triangles-block-shadows", "engine/src/rt/ShadowCertainty.cpp",
     "bool blocks = !embree.letsRaysThrough(i) && !mesh.exact;", "bool blocks = !embree.letsRaysThrough(i);",
     "tandem-rt-tests", "ResolveExact.*"),
    ("torus-proxy-not-widened", "engine/src/io/SolidProxy.cpp",
     "const double rt = r + widened;", "const double rt = r;",
     "tandem-unit-tests", "SolidProxy.*"),
    # The frame's decisions (render/Accumulation.h, render/FrameHistory.h).
    ("accumulation-ignores-probes-catching-up", "engine/src/render/Accumulation.cpp",
     "!since.sceneChanged && since.probesCurrent &&", "!since.sceneChanged &&",
     "tandem-unit-tests", "Accumulation.*"),
    ("accumulation-restart-keeps-old-sums", "engine/src/render/Accumulation.cpp",
     "  firstUnread = firstFiltered_ = false;\n  summing_ = false;\n", "  firstUnread = firstFiltered_ = false;\n",
     "tandem-unit-tests", "Accumulation.*"),
    ("samples-catch-up-probes-one-by-one", "engine/src/render/Accumulation.h",
     "    sample.settings.probesPerFrame = 0;\n", "",
     "tandem-unit-tests", "Accumulation.*"),
    ("radiosity-ignores-static-moves", "engine/src/render/RadiosityJob.cpp",
     "if (changes.replaced || changes.staticMoved) stale_ = true;", "if (changes.replaced) stale_ = true;",
     "tandem-gl-tests", "RadiosityGL.AStaticInstanceMoved*"),
    ("radiosity-solves-dynamic-moves", "engine/src/render/RadiosityJob.cpp",
     "if (changes.replaced || changes.staticMoved) stale_ = true;",
     "if (changes.replaced || changes.instancesMoved()) stale_ = true;",
     "tandem-gl-tests", "RadiosityGL.AStaticInstanceMoved*"),
    ("history-misses-light-changes", "engine/src/render/SceneChanges.h",
     "bool any() const { return replaced || instancesMoved() || lights; }",
     "bool any() const { return replaced || instancesMoved(); }",
     "tandem-unit-tests", "SceneChanges.*"),
    ("answers-kept-just-after-motion-blur", "engine/src/render/FrameHistory.cpp",
     "  if (moving) return false;\n", "",
     "tandem-unit-tests", "FrameHistory.*"),
    # Procedural textures.
    ("noise-fade-derivative-dropped", "shaders/procedural.glsl",
     "vec3 du = 30.0f * f * f * (f * (f - vec3(2.0f)) + vec3(1.0f));", "vec3 du = vec3(0.0f);",
     "tandem-unit-tests", "Procedural.*"),
    ("marble-angle-unreduced", "shaders/procedural.glsl",
     "float angle = 3.14159265f * (s - 2.0f * floor(0.5f * s));", "float angle = 3.14159265f * s;",
     "tandem-unit-tests", "Procedural.*"),
    ("bump-bends-the-wrong-way", "shaders/procedural.glsl",
     "vec3 n = N - amplitude * (gradW - dot(gradW, N) * N);", "vec3 n = N + amplitude * (gradW - dot(gradW, N) * N);",
     "tandem-unit-tests", "Procedural.*"),
    # Loaders.
    ("gltf-folder-by-string-prefix", "engine/src/io/GltfFs.cpp",
     "if (!isInside(c.root, canon))", "if (canon.string().rfind(c.root.string(), 0) != 0)",
     "tandem-unit-tests", "GltfConfinement.*:GltfHardening.*"),
    ("gltf-required-extensions-left-to-tinygltf", "engine/src/io/GltfFs.cpp",
     "    if (!unknown.empty()) return Error{\"extensionsRequired names unsupported extensions: \" + unknown};\n",
     "", "tandem-unit-tests", "GltfHardening.*"),
    ("gltf-index-rules-inside-foreign-extensions", "engine/src/io/GltfFs.cpp",
     "!supportedExtension(std::string(key.substr(0, 64)))", "false",
     "tandem-unit-tests", "GltfHardening.*"),
    ("gltf-single-sided-ignored", "engine/src/io/GltfMaterials.cpp",
     "mat.doubleSided = g.doubleSided;", "mat.doubleSided = true;",
     "tandem-corpus-tests", "GltfAuthorsIntent.*"),
    ("raster-back-faces-never-culled", "engine/src/gl/GpuScene.cpp",
     "if (cull) glEnable(GL_CULL_FACE);", "if (cull) glDisable(GL_CULL_FACE);",
     "tandem-gl-tests", "GltfMaterialsGLTest.*"),
    ("shadow-rays-cull-as-camera-rays", "engine/src/rt/EmbreeScene.cpp",
     "(kShadow ? -along : along)", "along",
     "tandem-rt-tests", "SingleSided.*"),
    ("single-sided-mirror-sign-ignored", "engine/src/rt/EmbreeScene.cpp",
     "glm::determinant(glm::mat3(inst.worldFromObject)) < 0.0f ? std::int8_t(-1) : std::int8_t(1)", "std::int8_t(1)",
     "tandem-rt-tests", "SingleSided.*"),
    ("single-sided-glass-culled-too", "engine/include/tandem/Scene.h",
     "return !m.doubleSided && !(m.kt > 0.0f);", "return !m.doubleSided;",
     "tandem-rt-tests", "SingleSided.*"),
    ("single-sided-proves-shadows", "engine/src/rt/EmbreeScene.h",
     "(instance < cullSign_.size() && cullSign_[instance] != 0);", "false;",
     "tandem-rt-tests", "HybridShadows.*:SingleSided.*"),
    ("gltf-factor-maps-over-the-whole-atlas", "engine/src/io/GltfImport.cpp",
     "  applyFactorMaps();\n", "",
     "tandem-unit-tests", "GltfImport.*"),
    ("gltf-transmission-texture-ignored", "engine/src/io/GltfMaterials.cpp",
     "    if (maps.transmission >= 0) x.transmission *= float(mean(maps.transmission, maps.transmissionUv, maps.transmissionOnUv0).r);\n", "",
     "tandem-unit-tests", "GltfImport.*"),
    ("gltf-unposed-skins-single-sided", "engine/src/io/GltfImport.cpp",
     "      if (n.skin >= 0) inst.material = unposedMaterial(inst.material);\n", "",
     "tandem-unit-tests", "GltfImport.*"),
    ("probe-limit-ignored", "engine/src/gl/GpuScene.cpp",
     "std::min(wanting.size(), static_cast<std::size_t>(std::max(limit, 1)))", "wanting.size()",
     "tandem-gl-tests", "ReflectionProbeLayout.*:RasterEffectsGLTest.AFrameDraws*"),
    ("probe-shared-by-the-first-not-the-nearest", "engine/src/gl/GpuScene.cpp",
     "if (glm::distance(centre[k], centre[chosen[s]]) < glm::distance(centre[k], centre[chosen[best]])) best = s;",
     "if (false) best = s;",
     "tandem-gl-tests", "ReflectionProbeLayout.*"),
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
    # Radiosity (tests/rt/RadiosityTest.cpp: form factors from their definition, the Cornell box per patch
    # against a path-traced gather).
    ("radiosity-shoots-by-radiosity", "engine/src/rt/Radiosity.cpp",
     "const float power = luminance(glm::abs(unshot_[p])) * patches_[p].area;",
     "const float power = luminance(glm::abs(unshot_[p]));", "tandem-rt-tests", "Radiosity.*"),
    ("radiosity-reciprocity-direction", "engine/src/rt/Radiosity.cpp",
     "const glm::vec3 h = f * shot;", "const glm::vec3 h = f * shot * (patches_[j].area / patches_[best].area);",
     "tandem-rt-tests", "Radiosity.*"),
    ("radiosity-received-without-area", "engine/src/rt/Radiosity.cpp",
     "for (std::size_t j = 0; j < patches_.size(); ++j) received += static_cast<double>(row[j]) * patches_[j].area;",
     "for (std::size_t j = 0; j < patches_.size(); ++j) received += static_cast<double>(row[j]);",
     "tandem-rt-tests", "Radiosity.*"),
    ("radiosity-visibility-from-one-point", "engine/src/rt/Radiosity.cpp",
     "return visible(points[k % kReceiverPoints], r.normalW, to, s.normalW) ? 1 : 0;",
     "return visible(points[0], r.normalW, to, s.normalW) ? 1 : 0;", "tandem-rt-tests", "Radiosity.*"),
    ("radiosity-any-visible-is-all", "engine/src/rt/Radiosity.cpp",
     "return static_cast<float>(f * seen / traced);", "return static_cast<float>(seen > 0 ? f : 0.0);",
     "tandem-rt-tests", "Radiosity.*"),
    ("radiosity-four-rays-for-large-pairs", "engine/src/rt/Radiosity.cpp",
     "const int first = f > 1.0 / 64.0 ? more : 4;", "const int first = 4;", "tandem-rt-tests", "Radiosity.*"),
    ("radiosity-near-subdivision-weight", "engine/src/rt/Radiosity.cpp",
     "    return 0.25 * (meanOverTriangle(a, ab, ca, n, shooter, shooterRadius, sc, sn, depth + 1) +",
     "    return 0.5 * (meanOverTriangle(a, ab, ca, n, shooter, shooterRadius, sc, sn, depth + 1) +",
     "tandem-rt-tests", "Radiosity.*"),
    ("radiosity-visibility-ignored", "engine/src/rt/Radiosity.cpp",
     "  return ray.tfar >= 0.0f;  // Embree sets tfar to -inf when something is in the way", "  return true;",
     "tandem-rt-tests", "Radiosity.*"),
    ("radiosity-direct-light-cosine-unclamped", "engine/src/rt/Radiosity.cpp",
     "const float cosine = glm::dot(patch.normalW, toLight);",
     "const float cosine = std::abs(glm::dot(patch.normalW, toLight));", "tandem-rt-tests", "Radiosity.*"),
    ("radiosity-overshoot-not-scaled", "engine/src/rt/Radiosity.cpp",
     "      if (received > patches_[best].area) {", "      if (received > 2.0 * patches_[best].area) {",
     "tandem-rt-tests", "Radiosity.*"),
    ("radiosity-weld-across-creases", "engine/src/rt/Radiosity.cpp",
     "const float cosWeld = std::cos(glm::radians(25.0f));", "const float cosWeld = std::cos(glm::radians(95.0f));",
     "tandem-rt-tests", "Radiosity.*"),
    # Hybrid shadows' proofs (tests/rt/HybridShadowsTest.cpp: every map answer against Embree's ray at large
    # magnitudes, the all-rays mask on hostile scenes).
    ("shadow-proof-object-space-and-translation-ignored", "engine/src/rt/ShadowCertainty.cpp",
     "        tests_.back().magnitude = std::max(tests_.back().magnitude, scale * std::max(p.x, std::max(p.y, p.z)));\n"
     "      }\n"
     "      tests_.back().magnitude = std::max(tests_.back().magnitude, translation);",
     "        (void)p;\n"
     "      }\n"
     "      (void)translation;", "tandem-rt-tests", "HybridShadows.*"),
    ("shadow-proof-margin-of-the-ray-only", "engine/src/rt/ShadowCertainty.cpp",
     "kRelativeMargin * std::max(magnitude, tri.magnitude)", "kRelativeMargin * magnitude",
     "tandem-rt-tests", "HybridShadows.*"),
    ("shadow-proof-rest-ignored", "engine/src/rt/ShadowCertainty.cpp",
     "if (missesAll && t.restDepth > depth + eps) return ShadowAnswer::Lit;", "if (missesAll) return ShadowAnswer::Lit;",
     "tandem-rt-tests", "HybridShadows.*"),
    ("shadow-map-far-triangles-placed-exactly", "engine/src/rt/ShadowCertainty.cpp",
     "tris.back().slack = kRelativeRounding * tests_.back().magnitude;", "tris.back().slack = 0.0f;",
     "tandem-rt-tests", "HybridShadows.*"),
    # The load budget (tests/unit/LoadBudgetTest.cpp: each charge against what the load kept).
    ("budget-texels-by-file-channels", "engine/src/io/GltfMaterials.cpp",
     "if (!budget_.charge(pixels * 4)) {", "if (!budget_.charge(pixels * u64(comp))) {", "tandem-unit-tests", "LoadBudget*"),
    ("budget-colours-by-components", "engine/src/io/GltfMeshes.cpp",
     "charge(id + \" colours\", u64(n) * sizeof(glm::vec4))", "charge(id + \" colours\", u64(n) * nc * sizeof(float))",
     "tandem-unit-tests", "LoadBudget*"),
    ("budget-uvs-as-floats", "engine/src/io/GltfMeshes.cpp",
     "charge(id + \" uvs\", u64(n) * sizeof(glm::vec2))", "charge(id + \" uvs\", u64(n) * sizeof(float))",
     "tandem-unit-tests", "LoadBudget*"),
    ("budget-tangents-never-charge-zero-uvs", "engine/src/io/GltfMeshes.cpp",
     "(zeroUvs ? sizeof(glm::vec2) : 0)", "0", "tandem-unit-tests", "LoadBudget*"),
    ("budget-scene-mesh-one-index-a-triangle", "engine/src/io/SceneFile.cpp",
     "vertices * vertexBytes + triangles * 3 * sizeof(std::uint32_t)", "vertices * vertexBytes + triangles * sizeof(std::uint32_t)",
     "tandem-unit-tests", "LoadBudget*"),
    # Adaptive anti-aliasing (tests/unit/AdaptiveTest.cpp; tests/gl/AntiAliasGLTest.cpp's thin line).
    ("adaptive-no-neighbours", "engine/src/render/Adaptive.cpp",
     "  dilate(refine, width, height, 1);", "  dilate(refine, width, height, 0);", "tandem-unit-tests", "Adaptive*"),
    ("adaptive-threshold-inclusive", "engine/src/render/Adaptive.cpp",
     "hi[i] - lo[i] > threshold", "hi[i] - lo[i] >= threshold", "tandem-unit-tests", "Adaptive*"),
    ("adaptive-rays-not-grown-enough", "engine/src/render/Adaptive.cpp",
     "dilate(traced, width, height, 2 * rayScale);", "dilate(traced, width, height, rayScale);",
     "tandem-unit-tests", "Adaptive*"),
    ("adaptive-unsampled-pixels-count", "engine/src/render/Adaptive.cpp",
     "if (count[i] > 0 && hi[i] - lo[i] > threshold)", "if (hi[i] - lo[i] > threshold)", "tandem-unit-tests", "Adaptive*"),
    ("adaptive-no-neighbours-in-the-frame", "engine/src/render/Adaptive.cpp",
     "  dilate(refine, width, height, 1);", "  dilate(refine, width, height, 0);", "tandem-gl-tests", "AntiAlias.*"),
    # The frame-time budget (tests/unit/FrameBudgetTest.cpp: scripted frame times).
    ("frame-budget-no-smoothing", "engine/src/render/FrameBudget.cpp",
     "meanMs_ = framesOnCurrent_ == 0 ? shown : 0.5 * meanMs_ + 0.5 * shown;", "meanMs_ = shown;",
     "tandem-unit-tests", "FrameBudget*"),
    ("frame-budget-pipelined-sums", "engine/src/render/FrameBudget.cpp",
     "  return std::max(fixed, rayMs - transfers) + transfers;", "  return fixed + rayMs;",
     "tandem-unit-tests", "FrameBudget*"),
    ("frame-budget-pipelined-by-latency", "engine/src/render/FrameBudget.cpp",
     "double shown = frame.pipelined && !frame.pipelineDrained && frame.intervalMs > 0 ? frame.intervalMs : total;",
     "double shown = total;", "tandem-unit-tests", "FrameBudget*"),
    ("frame-budget-switch-frame-taken-as-its-cost", "engine/src/render/FrameBudget.cpp",
     "    if (!std::isnan(steady)) shown = std::min(shown, steady);", "", "tandem-unit-tests", "FrameBudget*"),
    ("frame-budget-switch-frame-by-the-model-alone", "engine/src/render/FrameBudget.cpp",
     "const double steady = traced ? costMs(current_, rayMs) : predictMs(current_);",
     "const double steady = predictMs(current_);", "tandem-unit-tests", "FrameBudget*"),
    ("readback-rows-bottom-up", "engine/src/gl/PixelReadback.h",
     "static_cast<std::size_t>(height_ - 1 - y) * static_cast<std::size_t>(width_)",
     "static_cast<std::size_t>(y) * static_cast<std::size_t>(width_)", "tandem-gl-tests", "GBufferGLTest.*"),
    ("frame-budget-learns-from-a-left-choice", "engine/src/render/FrameBudget.cpp",
     "  if (frame.budget.active && frame.budget.step != current_) return;", "",
     "tandem-unit-tests", "FrameBudget*"),
    # The motion view (docs/motion.md): closed forms in tests/gl/MotionGLTest.cpp.
    ("motion-depth-ignored", "shaders/shade_debug.glsl",
     "    seen = seen && abs(depthThen - before.z) <= 0.02 * before.z;", "", "tandem-gl-tests", "MotionGLTest.*"),
    ("motion-instances-stand-still", "engine/src/render/Motion.cpp",
     "      previousFromCurrent = glm::mat4(d);", "", "tandem-gl-tests", "MotionGLTest.*"),
    ("motion-anchor-dropped", "engine/src/render/Motion.cpp",
     "      const glm::dmat4 d = glm::translate(glm::dmat4(1.0), -a) * before.worldFromObject[i] *",
     "      const glm::dmat4 d = glm::dmat4(1.0) * before.worldFromObject[i] *", "tandem-gl-tests", "MotionGLTest.*"),
    ("motion-history-across-scenes", "engine/src/render/Motion.cpp",
     "  const bool history = before.held && before.sceneGeneration == now.sceneGeneration &&",
     "  const bool history = before.held &&", "tandem-gl-tests", "MotionGLTest.*"),
    ("motion-history-width-only", "engine/src/render/Motion.cpp",
     "                       before.width == now.width && before.height == now.height &&",
     "                       before.width == now.width &&", "tandem-gl-tests", "MotionGLTest.ANewSceneSize*"),
    ("motion-samples-move-from-each-other", "engine/src/render/Motion.cpp",
     "  if (motionNext.held && motionNext.call != calls) {", "  if (motionNext.held) {", "tandem-gl-tests",
     "MotionGLTest.*"),
    # The spatiotemporal filter (docs/denoise.md): tests/gl/DenoiseGLTest.cpp against converged images.
    ("denoise-moved-instances-ignored", "engine/src/gl/DenoisePass.cpp",
     "  const bool anyMoved = moved.boxCount > 0 && (moved.areaLightCount > 0 || moved.lobes);",
     "  const bool anyMoved = false;",
     "tandem-gl-tests", "Denoise.NoGhost*"),
    ("denoise-moved-cone-as-wide-as-the-light", "shaders/denoise.frag",
     "boxInCone(instance, posR, areaLights[j], false);",
     "boxInCone(instance, posR, areaLights[j] * vec4(1.0, 1.0, 1.0, 4.0), false);",
     "tandem-gl-tests", "Denoise.ThingsMovingElsewhere*"),
    ("denoise-moved-cone-bounds-swapped", "shaders/denoise.frag",
     "    vec3 lower = max(mix(-none, tLo, plusLower), mix(-none, tHi, minusLower));",
     "    vec3 lower = max(mix(-none, tLo, plusUpper), mix(-none, tHi, minusUpper));",
     "tandem-gl-tests", "Denoise.NoGhost*"),
    ("denoise-moved-cone-only-its-axis", "shaders/denoise.frag",
     "boxInCone(instance, posR, areaLights[j], false);",
     "boxInCone(instance, posR, areaLights[j] * vec4(1.0, 1.0, 1.0, 0.0), false);",
     "tandem-gl-tests", "Denoise.NoGhost*"),
    # The light past the filter (mirrors', glass's and glossy lobes' hits, the probes) draws its own samples.
    ("denoise-past-filter-samples-ignored", "engine/include/tandem/Settings.h",
     "return denoise ? std::max(lightSamples, lightSamplesPastFilter) : lightSamples;", "return lightSamples;",
     "tandem-rt-tests", "RayPassWhitted.WithTheFilter*"),
    ("denoise-past-filter-below-light-samples", "engine/include/tandem/Settings.h",
     "return denoise ? std::max(lightSamples, lightSamplesPastFilter) : lightSamples;",
     "return denoise ? lightSamplesPastFilter : lightSamples;", "tandem-rt-tests", "RayPassWhitted.WithTheFilter*"),
    ("denoise-past-filter-at-the-primary-hits", "engine/src/rt/SurfaceShading.h",
     "return depth == 0 ? primaryLight : deeperLight;", "return deeperLight;", "tandem-rt-tests",
     "RayPassWhitted.WithTheFilter*"),
    ("denoise-past-filter-wavefront-depth-dropped", "engine/src/rt/Wavefront.cpp",
     "b_.area[h].data(), 1, 0, depth));", "b_.area[h].data(), 1, 0, 0));", "tandem-rt-tests",
     "RayPassWhitted.WithTheFilter*"),
    ("denoise-past-filter-recursion-depth-dropped", "engine/src/rt/Whitted.cpp",
     "lightMask(hit, counts, rec, &area, depth) : ~0u;", "lightMask(hit, counts, rec, &area, 0) : ~0u;",
     "tandem-rt-tests", "RayPassWhitted.WithTheFilter*"),
    ("denoise-past-filter-probes-ignored", "engine/src/render/SceneCaches.cpp",
     "    local.lightSamples = samples;", "",
     "tandem-gl-tests", "RasterEffectsGLTest.WithTheFilter*"),
    ("denoise-past-filter-probes-kept-when-it-changes", "engine/src/render/SceneCaches.cpp",
     "      ++lightSampleChanges_;\n", "", "tandem-gl-tests", "RasterEffectsGLTest.WithTheFilter*"),
    ("denoise-past-filter-in-debug-views", "engine/src/render/FramePlan.cpp",
     "p.denoise = p.raySettings.denoise = s.denoise", "p.denoise = s.denoise", "tandem-unit-tests",
     "FramePlan.TheLightPastTheFilter*"),
    ("denoise-past-filter-in-accumulated-samples", "engine/src/render/FramePlan.h",
     "void withoutFilter() { denoise = raySettings.denoise = false; }", "void withoutFilter() { denoise = false; }",
     "tandem-unit-tests", "FramePlan.TheLightPastTheFilter*"),
    ("denoise-past-filter-not-a-ray-input", "engine/src/render/FramePlan.cpp",
     "    s.lightSamplesPastFilter = s.unfilteredLightSamples();\n", "", "tandem-unit-tests",
     "FramePlan.TheLightPastTheFilter*"),
    # What a glossy lobe gathers: moved boxes in its cone, the lights the filter does not smooth.
    ("denoise-lobe-cone-ignored", "shaders/denoise.frag",
     "  for (int once = 0; once < (lobe != 0.0 ? 1 : 0); ++once) {", "  for (int once = 0; once < 0; ++once) {",
     "tandem-gl-tests", "Denoise.NoGhost*Glossy*"),
    ("denoise-lobe-cone-only-its-axis", "shaders/denoise.frag",
     "reach * (abs(tdLobeSpread(lobe)) + 0.03));", "0.0);", "tandem-gl-tests", "Denoise.AGlossyLobe*"),
    ("denoise-lobe-cone-from-the-camera", "shaders/denoise.frag",
     "    float reach = length(cameraPosR - posR) + movedReach;", "    float reach = movedReach;", "tandem-gl-tests",
     "Denoise.AGlossyLobe*"),
    ("denoise-lobe-transmission-as-reflection", "shaders/shading.glsl",
     "         : kt > 0.0f || coverage < 1.0f ? -1.0f", "         : coverage < 1.0f ? -1.0f", "tandem-rt-tests",
     "Glossy.TheFilters*"),
    ("denoise-lobe-blend-sees-nothing-behind", "shaders/shading.glsl",
     "         : kt > 0.0f || coverage < 1.0f ? -1.0f", "         : kt > 0.0f ? -1.0f", "tandem-rt-tests",
     "Glossy.TheFilters*"),
    ("denoise-lobe-cone-at-ninety-percent", "shaders/shading.glsl",
     "  float x = -4.6051702f / (e + 1.0f);", "  float x = -2.3025851f / (e + 1.0f);", "tandem-rt-tests",
     "Glossy.TheFilters*"),
    ("denoise-lobes-untested-without-area-lights", "engine/src/render/Motion.cpp",
     "  in.moved.lobes = std::any_of(scene.materials.begin(), scene.materials.end(), hasGlossyLobe);",
     "  in.moved.lobes = false;",
     "tandem-gl-tests", "Denoise.NoGhost*Glossy*"),
    ("denoise-lobes-outlive-a-point-light", "engine/src/gl/DenoisePass.cpp",
     "moved.lobesStale ? 1 : 0", "0", "tandem-gl-tests", "Denoise.NoGhost*Glossy*"),
    ("denoise-lens-said-every-frame", "engine/src/render/Denoise.cpp",
     "    denoiseLensWarned = true;\n", "", "tandem-gl-tests", "Denoise.ACamera*"),
    ("denoise-taa-keeps-a-dropped-history", "shaders/denoise.frag",
     "  bool fresh = !background && centre.a > 0.5;", "  bool fresh = false;", "tandem-gl-tests", "Denoise.NoGhost*"),
    ("denoise-dropped-lost-in-the-iterations", "shaders/denoise.frag",
     "centre.z, centre.w, dropped(centre));", "centre.z, centre.w, false);", "tandem-gl-tests", "Denoise.NoGhost*"),
    ("denoise-moved-boxes-in-slabs", "engine/src/render/Motion.cpp",
     "        const float growth = area(u) - area(moved[a].box) - area(moved[b].box);",
     "        const float growth = -(area(u) - area(moved[a].box) - area(moved[b].box));",
     "tandem-gl-tests", "Denoise.ThingsMovingElsewhere*"),
    ("denoise-moved-where-it-was-forgotten", "engine/src/render/Motion.cpp",
     "    for (const glm::dmat4* m : {&before.worldFromObject[i], &now.worldFromObject[i]}) {",
     "    for (const glm::dmat4* m : {&now.worldFromObject[i]}) {", "tandem-gl-tests", "Denoise.NoGhost*"),
    ("denoise-taa-sample-taken-for-the-centre", "shaders/denoise.frag",
     "  vec3 result = current + abs(jitterPx.x) * (nx - current) + abs(jitterPx.y) * (ny - current);",
     "  vec3 result = current;", "tandem-gl-tests", "Denoise.AFirstFrame*"),
    ("denoise-jitter-kept-in-motion", "engine/src/render/Accumulation.cpp",
     "  sample.jitterPx *= jitterScale;", "", "tandem-unit-tests", "Accumulation.*"),
    ("denoise-camera-motion-at-the-eye", "engine/src/render/Accumulation.cpp",
     "  float most = moved(now.targetW - before.posW, 0.5f * frame);", "  float most = moved(eyeMoved, 0.5f * frame);",
     "tandem-unit-tests", "Accumulation.*"),
    ("denoise-camera-motion-at-the-centre-only", "engine/src/render/Accumulation.cpp",
     "    most = std::max(most, moved(eyeMoved + fromNowEye, corner));", "    (void)fromNowEye;", "tandem-unit-tests",
     "Accumulation.*"),
    ("denoise-history-outlives-a-light", "engine/src/render/Motion.cpp",
     "  in.denoiseHistory = before.lights == now.lights && before.shading == now.shading;",
     "  in.denoiseHistory = true;", "tandem-gl-tests",
     "Denoise.NoGhost*"),
    ("denoise-luminance-weight-ignored", "shaders/denoise.frag",
     "  float lumScale = 1.4426950 / (4.0 * sqrt(max(v0, 0.0)) + 1e-6);", "  float lumScale = 0.0;", "tandem-gl-tests",
     "Denoise.*"),
    ("denoise-highlight-reprojected", "shaders/shade_local.glsl",
     "  areaLightsAsVisibility = kDenoiseGuides && !(surfaceRoughness > 0.0);",
     "  areaLightsAsVisibility = false;", "tandem-gl-tests", "Denoise.*"),
    ("denoise-statistical-test-off", "shaders/denoise.frag",
     "    if (any(greaterThan(abs(past - mean), box))) {", "    if (false) {", "tandem-gl-tests",
     "Denoise.TheStatisticalTest*"),
    ("denoise-statistical-box-doubled", "shaders/denoise.frag",
     "    vec3 box = 4.0 * sqrt(", "    vec3 box = 8.0 * sqrt(", "tandem-gl-tests", "Denoise.TheStatisticalTest*"),
    ("denoise-statistical-box-halved", "shaders/denoise.frag",
     "    vec3 box = 4.0 * sqrt(", "    vec3 box = 2.0 * sqrt(", "tandem-gl-tests", "Denoise.TheStatisticalTest*"),
    ("denoise-statistical-floor-dropped", "shaders/denoise.frag",
     "               vec3(0.02 * tdDenoiseLuminance(mean) + 1e-3);", "               vec3(1e-3);", "tandem-gl-tests",
     "Denoise.TheStatisticalTest*"),
    ("denoise-moved-point-mirrored", "shaders/denoise.frag",
     "  vec2 ndc = ndcOf(q);\n  vec3 across", "  vec2 ndc = -ndcOf(q);\n  vec3 across", "tandem-gl-tests",
     "Denoise.AGlossyLobe*"),
    ("denoise-history-depth-ignored", "shaders/denoise.frag",
     "abs(depthThen - m.z) <= 0.03 * m.z", "abs(depthThen - m.z) <= 1e9 * m.z", "tandem-gl-tests",
     "Denoise.AHistoryIsThePoints*"),
    ("denoise-history-normal-ignored", "shaders/denoise.frag",
     "dot(tdUnpackNormal(h.w), N) >= 0.9;", "dot(tdUnpackNormal(h.w), N) >= -2.0;",
     "tandem-gl-tests", "Denoise.AHistoryIsThePoints*"),
    ("denoise-history-kept-where-it-should-go", "shaders/denoise.frag",
     "    bool keep = holds && q == want", "    bool keep = q == want", "tandem-gl-tests",
     "Denoise.NoGhostFourFramesAfterAnObjectIsRemoved"),
    ("denoise-history-uncapped", "shaders/denoise.frag",
     "    len = min(floor(pastMoments.z + 0.5) + 1.0, maxHistory);", "    len = floor(pastMoments.z + 0.5) + 1.0;",
     "tandem-gl-tests", "Denoise.TheTemporalMean*"),
    ("denoise-variance-never-bootstrapped", "shaders/denoise.frag",
     "  float var = len >= 4.0 ? max(", "  float var = len >= 0.0 ? max(", "tandem-gl-tests", "Denoise.NoiseIsJudged*"),
    ("denoise-variance-of-one-frame", "shaders/denoise.frag",
     "  var /= len;\n", "", "tandem-gl-tests", "Denoise.NoiseIsJudged*"),
    ("denoise-settled-at-ten-percent", "shaders/denoise.frag",
     "return sqrt(var) <= 0.01 * tdDenoiseLuminance(illum)", "return sqrt(var) <= 0.1 * tdDenoiseLuminance(illum)",
     "tandem-gl-tests", "Denoise.NoiseIsJudged*"),
    ("denoise-plane-weight-ignored", "shaders/denoise.frag",
     "  float planeScale = 1.4426950 / (plane.footprint * spacing);", "  float planeScale = 0.0;", "tandem-gl-tests",
     "Denoise.TheSpatialFilterStops*"),
    ("denoise-variance-weights-not-squared", "shaders/denoise.frag",
     "      vsum += w * w * variance(t);", "      vsum += w * variance(t);", "tandem-gl-tests",
     "Denoise.NoiseIsJudged*"),
    ("denoise-atrous-across-instances", "shaders/denoise.frag",
     "      float valid = (q == want && tdInstanceTag(t.w) == tag) ? 1.0 : 0.0;\n      float w = kernel",
     "      float valid = q == want ? 1.0 : 0.0;\n      float w = kernel", "tandem-gl-tests", "Denoise.OnARayGrid*"),
    ("denoise-taa-unclamped", "shaders/denoise.frag",
     "    past = clamp(past, lo, hi);", "", "tandem-gl-tests", "Denoise.NoGhostFourFramesAfterAnObjectStepsAside*"),
    ("denoise-taa-history-bilinear", "shaders/denoise.frag",
     "    vec3 past = historyCatmullRom(vec2(p) + 0.5 - motion);",
     "    vec3 past = textureLod(taaHistoryTex, (vec2(p) + 0.5 - motion) / vec2(frameSize), 0.0).rgb;",
     "tandem-gl-tests", "Denoise.ABlendedFloors*"),
    ("denoise-taa-spline-middle-halfway", "shaders/denoise.frag",
     "middle = (i + 0.5 + wFar / wMiddle) / size", "middle = (i + 1.0) / size", "tandem-gl-tests",
     "Denoise.TheAntiAliasingsHistory*:Denoise.ABlendedFloors*"),
    ("denoise-taa-spline-not-renormalized", "shaders/denoise.frag",
     "  return sum / (wMiddle.x * (wMiddle.y + wBefore.y + wAfter.y) + wMiddle.y * (wBefore.x + wAfter.x));",
     "  return sum;", "tandem-gl-tests", "Denoise.TheAntiAliasingsHistory*"),
    ("denoise-taa-spline-before-weight-dropped", "shaders/denoise.frag",
     "  vec2 wBefore = f * (-0.5 + f * (1.0 - 0.5 * f));", "  vec2 wBefore = vec2(0.0);", "tandem-gl-tests",
     "Denoise.TheAntiAliasingsHistory*"),
    ("denoise-guide-glossy-not-demodulated", "shaders/shade.frag",
     "  vec3 modulation = glossy ? tdDemodulation(tdSurfaceColor(s.m, s.uv, s.pattern, s.tint))",
     "  vec3 modulation = glossy ? vec3(1.0)", "tandem-gl-tests", "Denoise.AGlossyFloors*"),
    ("denoise-guide-coverage-dropped", "shaders/shade.frag",
     ": clamp(s.coverage * areaLightUnshadowed, vec3(1e-4)", ": clamp(areaLightUnshadowed, vec3(1e-4)",
     "tandem-gl-tests", "Denoise.ABlendedFloors*"),
    ("denoise-taa-background-without-history", "shaders/denoise.frag",
     "  bool background = m.w < -0.5;", "  bool background = false;", "tandem-gl-tests", "Denoise.ASilhouette*"),
    ("denoise-shading-fault-kept", "shaders/denoise.frag",
     "  if (any(isnan(cur)) || any(isinf(cur))) cur = vec3(0.0);", "", "tandem-gl-tests", "Denoise.AShadingFault*"),
    ("denoise-moved-own-instance-blocks", "shaders/denoise.frag",
     "    bool own = lo.w >= 0.0 && uint(lo.w + 0.5) == instance;", "    bool own = false;", "tandem-gl-tests",
     "Denoise.TheMovedTestSkips*"),
    ("denoise-upsampling-fallback-black", "shaders/denoise.frag",
     "  return wsum > 1e-4 ? sum / wsum : nearest;", "  return sum / max(wsum, 1e-4);", "tandem-gl-tests",
     "Denoise.OnARayGridAThin*"),
    ("denoise-moments-not-accumulated", "shaders/denoise.frag",
     "      moments = mix(pastMoments.xy, moments, alpha);", "", "tandem-gl-tests", "Denoise.TheStatisticalTest*"),
    ("denoise-atrous-steps-all-one", "engine/src/gl/DenoisePass.cpp",
     "  draw(atrous_, t.scratchAFbo.id(), 4, &t.scratchB,", "  draw(atrous_, t.scratchAFbo.id(), 1, &t.scratchB,",
     "tandem-gl-tests", "Denoise.NoiseIsJudged*"),
    ("denoise-motion-keeps-the-jitter", "shaders/shade_debug.glsl",
     "  vec2 now = gl_FragCoord.xy + sampleOffset;", "  vec2 now = gl_FragCoord.xy;", "tandem-gl-tests",
     "Denoise.OneFilteredSample*"),
    ("denoise-motion-instances-still", "shaders/shade_debug.glsl",
     "  b.pointR = previousPoint(id, posR);", "  b.pointR = posR;", "tandem-gl-tests",
     "Denoise.NoGhostFourFramesAfterAnObjectStepsAside*"),
    ("denoise-motion-depth-from-this-camera", "shaders/shade_debug.glsl",
     "  float depthThen = dot(then.pointR - previousCameraPos, previousCameraForward);",
     "  float depthThen = dot(then.pointR - cameraPosW, previousCameraForward);", "tandem-gl-tests",
     "Denoise.OneFilteredSampleBeatsFourRawOnesWithTheCameraDollying"),
    ("denoise-motion-in-view-always", "shaders/shade_debug.glsl",
     "  b.inView = b.window.z > 0.0 && all(", "  b.inView = true || all(", "tandem-gl-tests",
     "MotionGLTest.TheFiltersMotion*"),
    ("denoise-guide-area-light-counted-twice", "shaders/shade.frag",
     "  outExact = vec4(local - area + (glossy", "  outExact = vec4(local + (glossy", "tandem-gl-tests",
     "Denoise.OneFilteredSampleBeatsFourRawOnesWithTheCameraMoving"),
    ("denoise-guide-visibility-ignored", "shaders/shade_local.glsl",
     "  float vis = rayShadowed ? rays.vis[j] : 1.0;\n  if (kShadowMaps && L.radiance.w > 0.5) vis = rasterShadow",
     "  float vis = 1.0;\n  if (kShadowMaps && L.radiance.w > 0.5) vis = rasterShadow", "tandem-gl-tests",
     "Denoise.OneFilteredSampleBeatsFourRawOnesWithTheCameraMoving"),
    ("denoise-taa-share-constant", "shaders/denoise.frag",
     "mix(0.15, 0.5, clamp((length(motion) - 1.5) / 1.5, 0.0, 1.0))", "0.15", "tandem-gl-tests",
     "Denoise.TheAntiAliasingsShare*"),
    ("denoise-taa-share-rises-late", "shaders/denoise.frag",
     "clamp((length(motion) - 1.5) / 1.5, 0.0, 1.0)", "clamp((length(motion) - 2.0) / 1.5, 0.0, 1.0)",
     "tandem-gl-tests", "Denoise.TheAntiAliasingsShare*"),
    ("denoise-grid-reprojects-in-frame-pixels", "shaders/denoise.frag",
     "  vec2 before = toGrid(vec2(at) + 0.5 - m.xy);", "  vec2 before = vec2(at) + 0.5 - m.xy;",
     "tandem-gl-tests", "Denoise.OnA*"),
    ("denoise-upsampling-across-instances", "shaders/denoise.frag",
     "    float valid = (q == want && tdInstanceTag(t.w) == tag) ? 1.0 : 0.0;\n    float w = bilinear",
     "    float valid = 1.0;\n    float w = bilinear", "tandem-gl-tests", "Denoise.OnA*"),
    ("denoise-grid-reads-a-blend", "shaders/denoise.frag",
     "  ivec2 top = min(ivec2(q.x, gridSize.y - 1 - q.y) * gridScale + gridScale / 2, frameSize - 1);",
     "  ivec2 top = min(ivec2(q.x, gridSize.y - 1 - q.y) * gridScale, frameSize - 1);", "tandem-gl-tests",
     "Denoise.OnA*"),
    ("denoise-samples-stand-still", "engine/src/render/Accumulation.cpp",
     "  return filteredSample(camera, frames_++, lastScale_);", "  return filteredSample(camera, 0, lastScale_);",
     "tandem-unit-tests", "Accumulation.TheFiltersOffsetScale*"),
    ("denoise-jitter-scale-from-the-first-frame", "engine/src/render/Accumulation.cpp",
     "  last_ = camera;\n  haveLast_ = true;", "  if (!haveLast_) last_ = camera;\n  haveLast_ = true;",
     "tandem-unit-tests", "Accumulation.TheFiltersOffsetScale*"),
    ("denoise-rect-light-reach-half-its-longer-side", "engine/src/core/Shading.cpp",
     "    case LightType::Rect: return 0.5f * (l.size.x + l.size.y);",
     "    case LightType::Rect: return 0.5f * std::max(l.size.x, l.size.y);", "tandem-unit-tests",
     "AreaLight.EveryPointOfTheLightIsWithinItsReach"),
    ("denoise-atrous-taps-at-half-their-distance", "shaders/denoise.frag",
     "  vec2 ndcStep = 2.0 * spacing / vec2(frameSize);", "  vec2 ndcStep = spacing / vec2(frameSize);",
     "tandem-gl-tests", "Denoise.TheATrousWeights*"),
    ("denoise-filtered-frame-summed", "engine/src/render/Renderer.cpp",
     "    if (single) accum.firstShown(plan.denoise);", "    if (single) accum.firstShown(false);",
     "tandem-gl-tests", "Denoise.AnAccumulation*"),
    ("denoise-toon-outline-faces-a-way", "shaders/shade.frag",
     "tdPackNormalInstance(outline ? vec3(0.0) : s.N, id.x)", "tdPackNormalInstance(s.N, id.x)", "tandem-gl-tests",
     "Denoise.Toon*"),
    ("denoise-stop-shows-the-raw-mean", "engine/src/render/Renderer.cpp",
     "    outputPass.uploadLinear(accum.shown());", "    outputPass.uploadLinear(accum.mean());",
     "tandem-gl-tests", "Denoise.WhenTheCameraStops*"),
    ("denoise-handover-never-ends", "engine/src/render/Accumulation.cpp",
     "  const int span = std::max(1, std::min(settings_.accumulate, 16) - 1);",
     "  const int span = std::max(1, std::min(settings_.accumulate, 16));", "tandem-unit-tests",
     "Accumulation.*"),
    ("proof-route-still-frame-is-a-change", "engine/src/render/FramePlan.h",
     "  void still() { changedBefore = false; }", "  void still() {}", "tandem-unit-tests", "FramePlan.*"),
    ("frame-budget-over-threshold", "engine/src/render/FrameBudget.cpp",
     "constexpr double kOver = 1.05;", "constexpr double kOver = 1.12;", "tandem-unit-tests", "FrameBudget*"),
    ("frame-budget-short-quiet-spell", "engine/src/render/FrameBudget.cpp",
     "constexpr int kQuietFrames = 10;", "constexpr int kQuietFrames = 3;", "tandem-unit-tests", "FrameBudget*"),
    ("frame-budget-first-frame-like-any", "engine/src/render/FrameBudget.cpp",
     "framesOnCurrent_ >= 2 ? meanMs > kOver * targetMs_ : meanMs > kFarOver * targetMs_",
     "meanMs > kOver * targetMs_", "tandem-unit-tests", "FrameBudget*"),
    ("frame-budget-first-frame-halved", "engine/src/render/FrameBudget.cpp",
     "c.work += c.framesRun == 0 ? delta : 0.5 * delta;", "c.work += 0.5 * delta;", "tandem-unit-tests", "FrameBudget*"),
    ("frame-budget-no-drift", "engine/src/render/FrameBudget.cpp",
     "logRho_ += 0.3 * (measured - logRho_ - c.work);", "logRho_ += 0.0 * (measured - logRho_ - c.work);",
     "tandem-unit-tests", "FrameBudget*"),
    ("frame-budget-never-offers-the-filter-for-light", "engine/src/render/FrameBudget.cpp",
     "  const bool lightSampled = offer && ", "  const bool lightSampled = false && ", "tandem-unit-tests", "FrameBudget*"),
    ("frame-budget-filters-through-a-lens", "engine/src/render/FrameBudget.cpp",
     "  const bool offer = !r.denoise && !facts.lensOrShutter;", "  const bool offer = !r.denoise;", "tandem-unit-tests",
     "FrameBudget*"),
    ("frame-budget-filters-probe-lobes", "engine/src/render/FrameBudget.cpp",
     "(glossSampled && (f.reflections == EffectMode::Ray || f.refraction == EffectMode::Ray))", "glossSampled",
     "tandem-unit-tests", "FrameBudget*"),
    ("frame-budget-raw-sets-priced-as-filtered", "engine/src/render/FrameBudget.cpp",
     "    if (!isFilteredSet(f)) raw = std::max(raw, fixedOffset_[f]);", "    raw = std::max(raw, fixedOffset_[f]);",
     "tandem-unit-tests", "FrameBudget*"),
    ("frame-budget-filter-before-the-request", "engine/src/render/FrameBudget.cpp",
     "    if (isRequest(a) != isRequest(b)) return isRequest(a);\n", "", "tandem-unit-tests", "FrameBudget*"),
    ("frame-budget-filter-shares-the-fixed-part", "engine/src/render/FrameBudget.h",
     "  int fixedSet() const { return filtered ? filteredSet(fallback, rayScale) : fallback; }",
     "  int fixedSet() const { return fallback; }", "tandem-unit-tests", "FrameBudget*"),
    ("frame-budget-filter-one-cost-on-every-grid", "engine/src/render/FrameBudget.h",
     "  int fixedSet() const { return filtered ? filteredSet(fallback, rayScale) : fallback; }",
     "  int fixedSet() const { return filtered ? filteredSet(fallback, 1) : fallback; }", "tandem-unit-tests",
     "FrameBudget*"),
    ("frame-budget-filter-added-from-any-grid", "engine/src/render/FrameBudget.cpp",
     "    const double added = sameGrid > kNone ? sameGrid : anyGrid;", "    const double added = anyGrid;",
     "tandem-unit-tests", "FrameBudget*"),
    ("frame-budget-filter-programs-dropped", "engine/src/render/Denoise.cpp",
     "  if (budget.offersFilter()) denoisePass->release();\n  else denoisePass.reset();", "  denoisePass.reset();",
     "tandem-gl-tests", "FrameBudgetGL.*"),
    ("frame-budget-filter-prior-not-carried", "engine/src/render/FrameBudget.cpp",
     "x.work = x.prior + (c.work - c.prior);", "x.work = x.prior;", "tandem-unit-tests", "FrameBudget*"),
    ("frame-budget-filter-keeps-the-samples", "engine/src/render/FrameBudget.cpp",
     "            c.settings.lightSamples = c.settings.glossSamples = 1;\n", "", "tandem-unit-tests", "FrameBudget*"),
    ("frame-budget-shown-frame-by-its-latency", "engine/src/render/FrameBudget.cpp",
     "  shown.totalMs = shown.stagesMs();\n", "", "tandem-unit-tests", "FrameBudget.ThroughputModeLearns*"),
    ("frame-budget-pipelined-call-learns-the-latency", "engine/src/render/PipelinedFrame.cpp",
     "  if (shown) budget.observeShown(result, sinceLastCall ? sinceLastCall->ms() : 0.0);",
     "  if (shown) budget.observe(result);", "tandem-gl-tests", "FrameBudgetGL.ThroughputModeLearnsNothing*"),
    ("frame-budget-calibration-inverted", "engine/src/render/FrameBudget.cpp",
     "std::clamp(meanMs / now, 0.5, 2.0)", "std::clamp(now / meanMs, 0.5, 2.0)", "tandem-unit-tests",
     "FrameBudget.AChoiceOverTheTarget*"),
    # The ids' read-back memory follows the frame's size (tests/gl/RendererGLTest.cpp).
    ("readback-buffer-never-grown", "engine/src/gl/PixelReadback.cpp",
     "  if (need > bytes_ || need < bytes_ / 4) {", "  if (bytes_ == 0) {", "tandem-gl-tests",
     "RendererGLTest.TheIdReadBack*"),
    # Contexts made and dropped on one thread (tests/gl/ContextGLTest.cpp).
    ("context-egl-rebind-skipped", "engine/src/gl/Context.cpp",
     "    if (tBound != this && eglGetCurrentContext() == context_)\n"
     "      eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);  // (tBound: EGL's record is stale)\n",
     "", "tandem-gl-tests", "ContextGLTest.ContextsMade*"),
    # glTF as its authors meant it (tests/corpus/GltfAuthorsIntentTest.cpp: a sample model's own markers).
    ("gltf-texture-rotation-as-the-readme-prints-it", "engine/src/io/GltfMaterials.cpp",
     "  const glm::mat3 R(std::cos(rot), -std::sin(rot), 0, std::sin(rot), std::cos(rot), 0, 0, 0, 1);",
     "  const glm::mat3 R(std::cos(rot), std::sin(rot), 0, -std::sin(rot), std::cos(rot), 0, 0, 0, 1);",
     "tandem-corpus-tests", "GltfAuthorsIntent.TextureTransforms*"),
    # Render space (tests/unit/CameraTest.cpp).
    ("render-space-anchor-at-origin", "engine/src/core/RenderSpace.cpp",
     "return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) ? p : glm::vec3(0.0f);",
     "return glm::vec3(0.0f);", "tandem-unit-tests", "RenderSpace*:Camera*"),
    ("render-space-anchor-at-the-target", "engine/src/core/RenderSpace.cpp",
     "const glm::vec3 p = scene.camera.posW;", "const glm::vec3 p = scene.camera.targetW;",
     "tandem-unit-tests", "RenderSpace*:Camera*"),
    # The floating origin (tests/unit/CameraTest.cpp, tests/rt/MotionBlurRayTest.cpp, tests/gl/FarFromOriginGLTest.cpp,
    # tests/pipeline/PipelineGLTest.cpp).
    ("render-space-view-from-points-rounded-apart", "engine/src/core/RenderSpace.cpp",
     "  c.targetW = glm::vec3(glm::dvec3(c.posW) + forward * scale);", "  c.targetW = toRenderSpace(camera.targetW, anchor);",
     "tandem-unit-tests", "RenderSpace*"),
    ("render-space-anchor-reach-ignored", "engine/src/core/RenderSpace.cpp",
     "  return glm::length(glm::dvec3(p) - glm::dvec3(anchor)) > anchorReach(camera);", "  return false;",
     "tandem-unit-tests", "RenderSpace*"),
    ("floating-origin-never-moves", "engine/src/render/SceneCaches.cpp",
     "  if (!anchorDue(camera)) return false;", "  if (!anchorDue(camera) || true) return false;",
     "tandem-gl-tests", "FarFromOrigin.ACameraFar*"),
    ("floating-origin-drops-the-motion-history", "engine/src/render/Motion.cpp",
     "  const bool history = before.held && before.sceneGeneration == now.sceneGeneration &&",
     "  const bool history = before.held && before.sceneGeneration == now.sceneGeneration && before.anchor == now.anchor &&",
     "tandem-gl-tests", "FarFromOrigin.TheMotion*"),
    ("floating-origin-embree-keeps-its-anchor", "engine/src/rt/EmbreeScene.cpp",
     "  if (anchor && *anchor != anchor_) anchor_ = *anchor, rereadAll_ = true;",
     "  if (anchor && *anchor != anchor_) rereadAll_ = true;", "tandem-rt-tests", "MotionBlurRays.ANewAnchor*"),
    ("floating-origin-gl-keeps-its-anchor", "engine/src/render/SceneCaches.cpp",
     "    gpu_.setAnchor(anchor_);\n", "", "tandem-gl-tests", "FarFromOrigin.ACameraFar*"),
    ("floating-origin-overlaps-the-frame-in-flight", "engine/src/render/PipelinedFrame.cpp",
     "!plan.glShadowProofs && !caches.anchorDue(camera);", "!plan.glShadowProofs;", "tandem-pipeline-tests",
     "Pipeline.ThroughputFrames*"),
    # Scene-file integers (tests/unit/SceneFileTest.cpp).
    ("scene-integer-refuses-dot-zero", "engine/src/io/SceneJson.h",
     "if (!j.is_number_integer() && d != std::floor(d)) fail(", "if (!j.is_number_integer()) fail(",
     "tandem-unit-tests", "SceneFile*"),
    ("scene-integer-range-open-above", "engine/src/io/SceneJson.h",
     "if (!(d >= lo && d <= hi))", "if (!(d >= lo && d < hi))", "tandem-unit-tests", "SceneFile*"),
    ("scene-integer-truncates", "engine/src/io/SceneJson.h",
     "if (!j.is_number_integer() && d != std::floor(d)) fail(",
     "if (!j.is_number_integer() && std::abs(d - std::floor(d)) > 0.5) fail(", "tandem-unit-tests", "SceneFile*"),
    # The raster frame: shadows on the ray grid, culled face draws, the probes' size.
    ("shadow-mask-second-layer-from-the-first", "shaders/shade_rays.glsl",
     "texelFetch(shadowMaskTex, ivec3(g, 1), 0)", "texelFetch(shadowMaskTex, ivec3(g, 0), 0)",
     "tandem-gl-tests", "ShadowMaskGL.*"),
    ("shadow-mask-at-the-grid-corner", "shaders/shade.frag",
     "  ivec2 pTop = gridPixelCentre(g);\n  ivec2 pix = ivec2(pTop.x, frameSize.y - 1 - pTop.y);\n  uvec2 id = texelFetch(idsTex, pix, 0).xy;\n  float vis[8]",
     "  ivec2 pTop = min(g * rayScale, frameSize - 1);\n  ivec2 pix = ivec2(pTop.x, frameSize.y - 1 - pTop.y);\n  uvec2 id = texelFetch(idsTex, pix, 0).xy;\n  float vis[8]",
     "tandem-gl-tests", "ShadowMaskGL.*"),
    ("culled-draw-one-per-run", "engine/src/gl/GpuScene.cpp",
     "drawRange(k, end - k, levelOf(k));", "drawRange(k, 1, levelOf(k));", "tandem-gl-tests", "RasterEffectsGLTest.Culled*"),
    ("cull-near-plane-flipped", "engine/src/gl/RasterEffects.cpp",
     "out[5] = out[5] && c.z > w;", "out[5] = out[5] && c.z < w;", "tandem-gl-tests", "RasterEffectsGLTest.Culled*"),
    ("probe-size-change-ignored", "engine/src/render/SceneCaches.cpp",
     "(probes_.probeCount() > 0 && probes_.faceSize() != plan.settings.probeSize) ||", "",
     "tandem-gl-tests", "RasterEffectsGLTest.ProbeSize*"),
    ("ray-tiles-forget-what-they-held", "engine/src/gl/ShadePass.cpp",
     "  resident.mayBeNonZero.assign(tiles.nonZero.begin(), tiles.nonZero.end());\n", "",
     "tandem-gl-tests", "RayUpload.*"),
    ("probe-lod-for-128-faces", "shaders/shade_probes.glsl",
     "float faceSize = float(textureSize(probes, 0).x);", "float faceSize = 128.0;",
     "tandem-gl-tests", "Glossy.RasterBlur*"),
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
    ("lean-primary-point-not-facing-the-viewer", "engine/src/rt/SurfaceShading.cpp",
     "  faceTheViewer(p, -ray.dir);\n  return p;", "  return p;",
     "tandem-rt-tests", "PrimaryPointTest.*"),
    ("lean-primary-point-for-mirrors", "engine/src/rt/SurfaceShading.cpp",
     "                                        !spawnsNoRay(frame.materials[inst.material].krKtIorModel, 1.0f));",
     "                                        false);",
     "tandem-rt-tests", "PrimaryPointTest.*:RayPassTest.*"),
    ("lean-primary-point-despite-a-normal-map", "engine/src/rt/SurfaceShading.cpp",
     "return mesh.exact || spawns || normalMapped || bumped;", "return mesh.exact || spawns || bumped;",
     "tandem-rt-tests", "PrimaryPointTest.*"),
    # Tile shafts: only a mesh in one axis plane may be passed over as its points' own; the shaft's planes
    # bound the hull of both boxes; the other instances' bounds are at the pass's time.
    ("shaft-own-instance-any-mesh", "engine/src/rt/TileShafts.cpp",
     "    if (planes[mesh] >= 0) {", "    if (true) {",
     "tandem-rt-tests", "TileShafts.*"),
    ("shaft-plane-through-the-wrong-corner", "engine/src/rt/TileShafts.cpp",
     "        p.d = ni * ai + nj * aj;", "        p.d = ni * bi + nj * aj;",
     "tandem-rt-tests", "TileShafts.*"),
    ("shaft-answers-other-lights", "engine/src/rt/Wavefront.cpp",
     "    if (((shaftLit >> j) & 1u) != 0) {", "    if (shaftLit != 0) {",
     "tandem-rt-tests", "TileShafts.*"),
    ("shaft-grazing-rays-answered", "engine/src/rt/Wavefront.cpp",
     "      if (rise >= 1.01 * TileShafts::kMinRise && ", "      if (rise >= -1.0 && ",
     "tandem-rt-tests", "TileShafts.*"),
    ("shaft-ill-conditioned-planes-join", "engine/src/rt/TileShafts.cpp",
     "      if (!(std::sqrt(f * g) <= kMaxCondition)) continue;", "      if (false) continue;",
     "tandem-rt-tests", "TileShafts.*"),
    ("shaft-plane-normal-not-transposed", "engine/src/rt/TileShafts.cpp",
     "      const glm::dvec3 normal = glm::transpose(inverse)[axis];", "      const glm::dvec3 normal = inverse[axis];",
     "tandem-rt-tests", "TileShafts.*"),
    ("shaft-bounds-at-mid-shutter", "engine/src/rt/TileShafts.cpp",
     "    const glm::mat4& m = embree.transformAt(i, timeU).worldFromObject;",
     "    const glm::mat4& m = embree.transform(i).worldFromObject;",
     "tandem-rt-tests", "TileShafts.*"),
    ("shaft-plane-normal-flipped", "engine/src/rt/TileShafts.cpp",
     "        if (ni < 0.0) ni = -ni, nj = -nj;", "        if (ni > 0.0) ni = -ni, nj = -nj;",
     "tandem-rt-tests", "TileShafts.*"),
    ("shaft-directional-rays-end-at-their-origins", "engine/src/rt/Wavefront.cpp",
     "        const glm::dvec3 along = shafts_->beyondScene(from, magnitude) / glm::length(toLight) * toLight;",
     "        const glm::dvec3 along = 1e-3 * toLight;",
     "tandem-rt-tests", "TileShafts.*"),
    # Throughput mode (docs/pipeline.md): the frame in flight composited with its own GL state and ids.
    ("pipeline-composites-with-the-next-frames-buffer", "engine/src/render/PipelinedFrame.cpp",
     "    shown = showLanded(*landed, *spareVisibility);",
     "    shown = showLanded(*landed, visibilityPass);",
     "tandem-pipeline-tests", "Pipeline.*"),
    ("pipeline-traces-the-last-frames-ids", "engine/src/render/PipelinedFrame.cpp",
     "    std::swap(visibility, stagedVisibility);\n", "\n",
     "tandem-pipeline-tests", "Pipeline.*"),
    ("pipeline-overlaps-a-new-scene", "engine/src/render/PipelinedFrame.cpp",
     "  bool overlap = inFlight && !changed.replaced && inFlight->plan.settings == s &&",
     "  bool overlap = inFlight && inFlight->plan.settings == s &&",
     "tandem-pipeline-tests", "Pipeline.*"),
    ("pipeline-overlaps-changed-settings", "engine/src/render/PipelinedFrame.cpp",
     "  bool overlap = inFlight && !changed.replaced && inFlight->plan.settings == s &&",
     "  bool overlap = inFlight && !changed.replaced &&",
     "tandem-pipeline-tests", "Pipeline.*"),
    ("pipeline-instances-into-the-in-flight-slot", "engine/src/render/PipelinedFrame.cpp",
     "caches.syncGpuInstances(scene, 1 - inFlight->slot);", "caches.syncGpuInstances(scene, inFlight->slot);",
     "tandem-pipeline-tests", "Pipeline.*"),
    ("pipeline-composites-with-the-next-frames-instances", "engine/src/render/PipelinedFrame.cpp",
     "    caches.gpu().setInstanceSlot(landed->slot);\n", "\n",
     "tandem-pipeline-tests", "Pipeline.*"),
    ("pipeline-proofs-from-the-last-embree-scene", "engine/src/render/PipelinedFrame.cpp",
     "    const bool proved = timed(sample.raysMs, [&] { return syncRayScene(camera); }) &&",
     "    const bool proved = true &&",
     "tandem-pipeline-tests", "Pipeline.*"),
    ("pipeline-ray-scene-keeps-old-lights", "engine/src/render/PipelinedFrame.cpp",
     "    if (rayPending.lights) rayScene.lights = scene.lights;\n", "\n",
     "tandem-pipeline-tests", "Pipeline.*"),
    # The environment (docs/environment.md).
    ("environment-glsl-ambient-left-out", "shaders/shade_local.glsl",
     "kUseEnvAmbient ? ambientIa + environmentAmbient(model == TD_MODEL_FLAT ? Ng : N)", "kUseEnvAmbient ? ambientIa",
     "tandem-gl-tests", "ShadingParityGLTest.*"),
    ("environment-glsl-background-constant", "shaders/shade.frag",
     "      sky = kUseEnvironment ? environmentRadiance(dir) : background;", "      sky = background;",
     "tandem-gl-tests", "ShadingParityGLTest.*"),
    ("environment-cpu-ambient-left-out", "engine/src/rt/SurfaceShading.cpp",
     "tdAmbient(m, frame.ambient + frame.environment.ambient(ambientN), hit.uv,", "tdAmbient(m, frame.ambient, hit.uv,",
     "tandem-rt-tests", "EnvironmentRays.*"),
    ("environment-wavefront-miss-is-the-background", "engine/src/rt/Wavefront.cpp",
     "n.local = frame.environment.radiance(n.dir);", "n.local = frame.environment.background();",
     "tandem-rt-tests", "EnvironmentRays.*"),
    ("environment-whitted-miss-is-the-background", "engine/src/rt/Whitted.cpp",
     "    return frame_.environment.radiance(dirW);", "    return frame_.environment.background();",
     "tandem-rt-tests", "EnvironmentRays.*"),
    ("environment-path-tracer-escapes-to-the-background", "engine/src/rt/PathTracer.cpp",
     "radiance += beta * frame.environment.radiance(dir);", "radiance += beta * frame.environment.background();",
     "tandem-rt-tests", "EnvironmentRays.*"),
    ("environment-turned-the-wrong-way", "shaders/shading.glsl",
     "return vec3(turn.x * dirW.x - turn.y * dirW.z, dirW.y, turn.y * dirW.x + turn.x * dirW.z);",
     "return vec3(turn.x * dirW.x + turn.y * dirW.z, dirW.y, -turn.y * dirW.x + turn.x * dirW.z);",
     "tandem-unit-tests", "Environment.*"),
    ("environment-equirect-mirrored", "shaders/shading.glsl",
     "return vec2(atan(d.x, -d.z) * 0.15915494f + 0.5f,", "return vec2(atan(-d.x, -d.z) * 0.15915494f + 0.5f,",
     "tandem-unit-tests", "Environment.*"),
    ("environment-sh-without-band-factors", "engine/src/core/Environment.cpp",
     "for (std::size_t i = 0; i < 9; ++i) out[i] = glm::vec3(sum[i] * kBand[i]);",
     "for (std::size_t i = 0; i < 9; ++i) out[i] = glm::vec3(sum[i]);",
     "tandem-unit-tests", "Environment.*"),
    ("environment-seam-clamped", "engine/src/core/Environment.cpp",
     "auto wrap = [w](long x) { return int(((x % w) + w) % w); };",
     "auto wrap = [w](long x) { return int(std::clamp(x, 0L, long(w - 1))); };",
     "tandem-unit-tests", "Environment.*"),
    ("hdr-cut-rows-read-past-the-end", "engine/src/core/Image.cpp",
     "        if (!byte(count)) return cut;\n", "        byte(count);\n",
     "tandem-unit-tests", "EnvironmentFile.*"),
    ("gltf-without-the-default-sky", "engine/src/io/GltfImport.cpp",
     "  s.environment.kind = Environment::Kind::Sky;\n", "\n",
     "tandem-unit-tests", "GltfImport.*"),
    # Reflection probes' cost (gl/GpuScene.h ensureProbeLod, gl/ReflectionProbes.h probeDetail).
    # The view behind see-through surfaces (gl/BehindView.h).
    ("see-through-reads-its-probe", "engine/src/render/SceneCaches.cpp",
     "        in.probeEffects |= gl::kProbeBehind;\n", "",
     "tandem-gl-tests", "RasterEffectsGLTest.SeeThrough*"),
    ("behind-view-not-peeled", "engine/src/gl/BehindView.cpp",
     "                    nullptr, &nearest_);", "                    nullptr, nullptr);",
     "tandem-gl-tests", "RasterEffectsGLTest.SeeThrough*"),
    ("behind-view-rough-stays-sharp", "shaders/shade_probes.glsl",
     "float behindLod = kt > 0.0 && spread > 0.0 ? max(log2(spread * pixelsPerRadian), 0.0) : 0.0;",
     "float behindLod = 0.0;",
     "tandem-gl-tests", "RasterEffectsGLTest.RoughSeeThrough*"),
    ("behind-blur-ignores-distance", "shaders/shade_probes.glsl",
     "float spread = alpha * max(behindDistance - here, 0.0) / max(behindDistance, 1e-6);", "float spread = alpha;",
     "tandem-corpus-tests", "GltfAuthorsIntent.TheLamps*"),
    ("behind-layers-without-distance", "engine/src/gl/BehindView.cpp",
     "  layer.distanceInAlpha = true;", "  layer.distanceInAlpha = false;",
     "tandem-corpus-tests", "GltfAuthorsIntent.TheLamps*"),
    ("probe-lod-ids-name-the-mesh-triangles", "shaders/visibility.frag",
     "uint(gl_PrimitiveID) + vPrimitiveBase);", "uint(gl_PrimitiveID));",
     "tandem-gl-tests", "ProbeDetailGLTest.*"),
    ("mesh-lod-keeps-turned-triangles", "engine/src/core/MeshLod.cpp",
     "normal(mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2])) <= 0.0f)",
     "normal(mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2])) < -1e30f)",
     "tandem-unit-tests", "MeshLod.*"),
    ("mesh-lod-keeps-repeats", "engine/src/core/MeshLod.cpp",
     "repeat[order[i]] = kept[order[i]] == kept[order[i - 1]];", "repeat[order[i]] = false;",
     "tandem-unit-tests", "MeshLod.*"),
    ("probe-lod-level-too-coarse", "engine/src/gl/GpuScene.cpp",
     "if (texels <= 2.0f * static_cast<float>(kProbeLodCells[l]))", "if (texels <= 8.0f * static_cast<float>(kProbeLodCells[l]))",
     "tandem-gl-tests", "ProbeDetail*"),
    ("probe-detail-ignores-glass", "engine/src/gl/ReflectionProbes.cpp",
     "if (m.kt <= 0.0f && m.alphaMode != AlphaMode::Blend && !view.orthographic) {",
     "if (m.alphaMode != AlphaMode::Blend && !view.orthographic) {",
     "tandem-gl-tests", "ProbeDetail.*"),
    ("probe-detail-never-stale", "engine/src/render/SceneCaches.cpp",
     "if (detail[slot] > 2.0f * probeDetailDrawn_[slot] && probeSlotVersions_[slot] != 0) {",
     "if (false && probeSlotVersions_[slot] != 0) {",
     "tandem-gl-tests", "ProbeDetailGLTest.*"),
    ("probes-budget-blanks-kept-probes", "engine/src/render/SceneCaches.cpp",
     "    if (all && !fresh && budget > 0) {", "    if (all && !fresh && budget > 0 && false) {",
     "tandem-gl-tests", "ProbeDetailGLTest.*"),
    ("probes-budget-only-for-moves", "engine/src/render/SceneCaches.cpp",
     "plan.settings.probeSize, budget, detail);", "plan.settings.probeSize, 0, detail);",
     "tandem-gl-tests", "ProbeDetailGLTest.*:RasterEffectsGLTest.ProbesPerFrame*"),
]


def run(cmd, cwd=None, timeout=None):
    return subprocess.run(cmd, cwd=cwd, timeout=timeout, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)


def sync_tree(root, src):
    """The scratch tree: the working tree as it is (uncommitted changes too), without build folders, .git and
    out/. A file is copied when its bytes differ, and gets the time of the copy: a copy that kept the working
    tree's older time would look older than objects the scratch build made since, and not be rebuilt. Files
    gone from the working tree go from the scratch tree too."""
    skip = {".git", "out", ".gpu"}
    wanted = set()
    for dirpath, dirnames, filenames in os.walk(root):
        rel_dir = os.path.relpath(dirpath, root)
        if rel_dir == ".":
            dirnames[:] = [d for d in dirnames if d not in skip and not d.startswith("build")]
        for f in filenames:
            rel = os.path.normpath(os.path.join(rel_dir, f))
            s, d = os.path.join(root, rel), os.path.join(src, rel)
            wanted.add(rel)
            if os.path.islink(s) or not os.path.isfile(s):
                continue
            if os.path.isfile(d) and os.path.getsize(d) == os.path.getsize(s) and filecmp.cmp(s, d, shallow=False):
                continue
            os.makedirs(os.path.dirname(d), exist_ok=True)
            shutil.copyfile(s, d)
            shutil.copymode(s, d)
    for dirpath, _, filenames in os.walk(src):
        for f in filenames:
            rel = os.path.normpath(os.path.relpath(os.path.join(dirpath, f), src))
            if rel not in wanted:
                os.remove(os.path.join(dirpath, f))


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(root, "build", "mutation"))
    ap.add_argument("--only", default="")
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--without-goldens", action="store_true",
                    help="leave the golden-image tests out: every mutation must be killed by an oracle")
    ap.add_argument("--check-texts", action="store_true")
    a = ap.parse_args()
    chosen = [m for m in MUTATIONS if not a.only or m[0] in a.only.split(",")]
    if a.check_texts:
        ids = [m[0] for m in MUTATIONS]
        bad = [f"{m}: listed {ids.count(m)} times" for m in sorted(set(ids)) if ids.count(m) > 1]
        for mid, rel, old, new, target, gfilter in chosen:
            n = open(os.path.join(root, rel)).read().count(old) if os.path.isfile(os.path.join(root, rel)) else -1
            if n != 1:
                bad.append(f"{mid}: {'no file ' + rel if n < 0 else f'{n} occurrences of its text in {rel}'}")
        # Each filter names some test (TEST, TEST_F or TEST_P as Suite.Name; a parameterized test's prefix and
        # suffix are not checked): a renamed test would leave its mutations with nothing to run.
        names = set()
        for folder, _, files in os.walk(os.path.join(root, "tests")):
            for f in files:
                if f.endswith(".cpp"):
                    text = open(os.path.join(folder, f), errors="replace").read()
                    found = re.findall(r"\bTEST(?:_F|_P)?\(\s*(\w+)\s*,\s*(\w+)\s*\)", text)
                    names.update(a + "." + b for a, b in found)
        for mid, rel, old, new, target, gfilter in chosen:
            patterns = [p for p in gfilter.split("-")[0].split(":") if p]
            if not any(fnmatch.fnmatchcase(n, p) for p in patterns for n in names):
                bad.append(f"{mid}: its filter {gfilter} names no test")
        for b in bad:
            print("mutate: STALE " + b)
        print(f"mutate: {len(chosen)} mutations, {len(bad)} stale")
        return 1 if bad else 0
    if a.list:
        for m in chosen:
            f = m[5] + ((":" if "-" in m[5] else "-") + "*Golden*" if a.without_goldens else "")
            print(f"{m[0]:45s} {m[1]:40s} {m[4]} --gtest_filter={f}")
        return 0
    if not chosen:
        print("mutate: no mutation by that id")
        return 1
    src, build = os.path.join(a.build, "src"), os.path.join(a.build, "build")
    os.makedirs(src, exist_ok=True)
    sync_tree(root, src)
    # ../shared beside the scratch tree, as beside the real one (tests look for ../shared/assets).
    shared = os.path.join(os.path.dirname(root), "shared")
    if os.path.isdir(shared) and not os.path.exists(os.path.join(a.build, "shared")):
        os.symlink(shared, os.path.join(a.build, "shared"))
    jobs = str(os.cpu_count() or 2)
    # Configured every run (seconds; the cache keeps its options): a test binary or source folder added since
    # the scratch build was made is then a target it knows.
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
            if a.without_goldens:
                gfilter = gfilter + (":" if "-" in gfilter else "-") + "*Golden*"
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
