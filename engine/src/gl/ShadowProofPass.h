#pragma once
// Hybrid shadows' proofs in the GL (docs/shadows.md, "Proofs in the GL"): the light-space maps the CPU
// builds (rt/ShadowCertainty.h) copied into buffer textures, and a pass over the visibility buffer that
// marks, per pixel and direct light, the primary hit's shadow ray as certainly lit, certainly shadowed, or
// open (shaders/shadow_proof.frag). The ray pass reads the marks with the ids and traces only the open rays.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "gl/GlObjects.h"
#include "gl/GpuScene.h"
#include "tandem/Camera.h"
#include "tandem/Result.h"

namespace tandem::gl {

/// One light's map as plain data (the render layer fills it from rt::ShadowCertainty::Map).
struct ProofMapData {
  int kind = 0;  // 0: no map, 1: cube (point and spot lights), 2: orthographic (directional)
  int size = 0;  // texels a side
  glm::vec3 origin{0.0f};   // cube: the light
  glm::vec3 axes[6][3]{};   // per face S, T, A (orthographic: face 0)
  float extent = 1.0f, top = 0.0f, nearZ = 0.0f, depthEps = 0.0f;
  glm::vec2 centre{0.0f};
  glm::vec3 toLight{0.0f};  // directional: the CPU's shadow-ray direction, exactly
  const void* texels = nullptr;  // faces × size² records of TD_PROOF_RECORD 32-bit words
  std::size_t texelCount = 0;
  std::span<const std::uint32_t> nearLight;
};

/// All lights' maps and what their tests read.
struct ProofSource {
  std::uint64_t generation = 0;          // rt::ShadowCertainty::generation
  std::vector<ProofMapData> maps;        // light order
  std::vector<glm::vec4> triangles;      // 5 per global triangle: plane, three edges, (magnitude, valid, blocks, 0)
  std::vector<std::uint32_t> instanceBase;  // per instance: its first global triangle id; ~0: never proved
  glm::vec4 constants{0.0f};             // kQueryMargin, kDepthRel, kRelativeMargin, kShadowRayEnd
};

class ShadowProofPass {
 public:
  static Result<ShadowProofPass> create();

  /// The generation of the maps the GL holds (0: none).
  std::uint64_t generation() const { return generation_; }
  /// Copies the maps. A light whose records would not fit in one buffer texture (GL_MAX_TEXTURE_BUFFER_SIZE)
  /// gets no map: its rays stay open.
  void upload(const ProofSource& source);
  /// This frame's per-instance TD_PROOF_PLAIN / TD_PROOF_FLAT (they follow the materials and the shading
  /// override, not the maps).
  void setInstanceFlags(std::span<const std::uint32_t> flags);
  /// Drops the copy and the target.
  void release();

  /// Proves the pixels of `ids` (the visibility buffer, width × height) the ray pass reads into the proofs
  /// target: every one, or with `rayScale` > 1 each ray-grid pixel's stand-in (the rest 0); `camera` in render
  /// space, the GL copy's (the maps' render space must be the same). An error names what the GL refused (the
  /// target's storage).
  Result<void> prove(const GpuScene& scene, const Texture& ids, int width, int height, const Camera& camera,
                     int rayScale = 1);
  /// The proof words (bindings.glsl, TD_PROOF_*), row 0 = top (the ray pass's convention).
  void read(std::vector<std::uint32_t>& out) const;

 private:
  Program program_;
  VertexArray emptyVao_;
  Buffer texels_, triangles_, near_, instances_, flags_, block_;
  Texture texelsTex_, trianglesTex_, nearTex_, instancesTex_, flagsTex_;
  std::size_t flagCount_ = 0;
  Texture target_;
  Framebuffer fbo_;
  int width_ = 0, height_ = 0;
  std::uint64_t generation_ = 0;
};

}  // namespace tandem::gl
