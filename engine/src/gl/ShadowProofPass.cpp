#include "gl/ShadowProofPass.h"

#include <algorithm>
#include <cassert>
#include <cstring>

#include "gl/Bindings.h"
#include "gl/Program.h"
#include "gl/ShadePass.h"

namespace tandem::gl {

namespace {

// The uniform block of shadow_proof.frag (std140).
struct GpuProofMap {
  glm::vec4 originKind;
  glm::vec4 axes[18];
  glm::vec4 params;
  glm::vec4 params2;
  glm::vec4 toLight;
  glm::uvec4 ranges;
};
struct GpuProofBlock {
  GpuProofMap maps[TD_MAX_LIGHTS];
  glm::vec4 constants;
  glm::ivec4 lights;
};
static_assert(sizeof(GpuProofMap) == 23 * 16 && sizeof(GpuProofBlock) == TD_MAX_LIGHTS * 23 * 16 + 32,
              "GpuProofBlock: std140 layout of shadow_proof.frag's ProofBlock");

}  // namespace

Result<ShadowProofPass> ShadowProofPass::create() {
  auto program = buildProgram("shadow proofs", {{GL_VERTEX_SHADER, "shaders/fullscreen.vert"},
                                                {GL_FRAGMENT_SHADER, "shaders/shadow_proof.frag"}});
  if (!program) return program.error();
  ShadowProofPass pass;
  pass.program_ = std::move(*program);
  pass.emptyVao_ = createVertexArray("full-screen triangle (shadow proofs)");
  pass.block_ = createBuffer("shadow proofs: maps", sizeof(GpuProofBlock), nullptr);
  return pass;
}

void ShadowProofPass::upload(const ProofSource& source) {
  GLint maxTexels = 0;
  glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
  GpuProofBlock block{};
  // Records of every light whose map fits after the ones before it.
  std::size_t words = 0;
  std::vector<std::uint32_t> nearIds;
  const std::size_t lights = std::min<std::size_t>(source.maps.size(), TD_MAX_LIGHTS);
  std::vector<std::size_t> firstRecord(lights, 0);
  for (std::size_t j = 0; j < lights; ++j) {
    const ProofMapData& m = source.maps[j];
    GpuProofMap& g = block.maps[j];
    const std::size_t mapWords = m.texelCount * TD_PROOF_RECORD;
    if (m.kind == 0 || m.texelCount == 0 || words + mapWords > static_cast<std::size_t>(std::max(maxTexels, 0))) continue;
    firstRecord[j] = words / TD_PROOF_RECORD;
    words += mapWords;
    g.originKind = glm::vec4(m.origin, static_cast<float>(m.kind));
    for (int f = 0; f < 6; ++f)
      for (int k = 0; k < 3; ++k) g.axes[3 * f + k] = glm::vec4(m.axes[f][k], 0.0f);
    g.params = glm::vec4(m.extent, m.nearZ, m.top, m.depthEps);
    g.params2 = glm::vec4(m.centre, static_cast<float>(m.size), 0.0f);
    g.toLight = glm::vec4(m.toLight, 0.0f);
    g.ranges = glm::uvec4(static_cast<std::uint32_t>(firstRecord[j]), static_cast<std::uint32_t>(nearIds.size()),
                          static_cast<std::uint32_t>(m.nearLight.size()), 0u);
    nearIds.insert(nearIds.end(), m.nearLight.begin(), m.nearLight.end());
  }
  block.constants = source.constants;
  block.lights = glm::ivec4(static_cast<int>(lights), 0, 0, 0);
  texels_ = createBuffer("shadow proofs: texel records", words * sizeof(std::uint32_t), nullptr);
  for (std::size_t j = 0; j < lights; ++j) {
    const ProofMapData& m = source.maps[j];
    if (block.maps[j].originKind.w == 0.0f) continue;
    glNamedBufferSubData(texels_.id(), static_cast<GLintptr>(firstRecord[j] * TD_PROOF_RECORD * sizeof(std::uint32_t)),
                         static_cast<GLsizeiptr>(m.texelCount * TD_PROOF_RECORD * sizeof(std::uint32_t)), m.texels);
  }
  triangles_ = createBuffer("shadow proofs: triangles", source.triangles.size() * sizeof(glm::vec4), source.triangles.data());
  near_ = createBuffer("shadow proofs: near-light ids", nearIds.size() * sizeof(std::uint32_t), nearIds.data());
  instances_ = createBuffer("shadow proofs: instance bases", source.instanceBase.size() * sizeof(std::uint32_t),
                            source.instanceBase.data());
  texelsTex_ = createBufferTexture("shadow proofs: texel records", TD_FORMAT_PROOF_WORDS, texels_);
  trianglesTex_ = createBufferTexture("shadow proofs: triangles", TD_FORMAT_PROOF_TRIANGLES, triangles_);
  nearTex_ = createBufferTexture("shadow proofs: near-light ids", TD_FORMAT_PROOF_WORDS, near_);
  instancesTex_ = createBufferTexture("shadow proofs: instance bases", TD_FORMAT_PROOF_WORDS, instances_);
  glNamedBufferSubData(block_.id(), 0, sizeof(block), &block);
  generation_ = source.generation;
}

void ShadowProofPass::setInstanceFlags(std::span<const std::uint32_t> flags) {
  if (!flags_ || flags.size() != flagCount_) {
    flags_ = createBuffer("shadow proofs: instance flags", flags.size() * sizeof(std::uint32_t), flags.data());
    flagsTex_ = createBufferTexture("shadow proofs: instance flags", TD_FORMAT_PROOF_WORDS, flags_);
    flagCount_ = flags.size();
  } else if (!flags.empty()) {
    glNamedBufferSubData(flags_.id(), 0, static_cast<GLsizeiptr>(flags.size() * sizeof(std::uint32_t)), flags.data());
  }
}

void ShadowProofPass::release() {
  texels_.reset();
  triangles_.reset();
  near_.reset();
  instances_.reset();
  texelsTex_.reset();
  trianglesTex_.reset();
  nearTex_.reset();
  instancesTex_.reset();
  flags_.reset();
  flagsTex_.reset();
  flagCount_ = 0;
  fbo_.reset();
  target_.reset();
  width_ = height_ = 0;
  generation_ = 0;
}

Result<void> ShadowProofPass::prove(const GpuScene& scene, const Texture& ids, int width, int height,
                                    const Camera& camera, int rayScale) {
  assert(texelsTex_ && flagsTex_ && "ShadowProofPass::prove: upload the maps and the instance flags first");
  if (width != width_ || height != height_) {
    fbo_.reset();
    target_.reset();
    width_ = height_ = 0;
    auto target = tryCreateTexture2D("shadow proofs", kChannelShadowProofs.internal, width, height);
    if (!target) return target.error();
    Framebuffer fbo = createFramebuffer("shadow proofs");
    glNamedFramebufferTexture(fbo.id(), GL_COLOR_ATTACHMENT0, target->id(), 0);
    if (auto complete = checkFramebufferComplete(fbo, "shadow proofs"); !complete) return complete;
    target_ = std::move(*target);
    fbo_ = std::move(fbo);
    width_ = width;
    height_ = height;
  }
  const GLuint p = program_.id();
  setCameraUniforms(p, width, height, camera);
  glProgramUniform1i(p, TD_LOC_RAY_SCALE, std::max(rayScale, 1));
  scene.bindShading();
  glBindTextureUnit(kUnitIds, ids.id());
  glBindTextureUnit(kUnitExactHits, 0);
  glBindTextureUnit(kUnitProofTexels, texelsTex_.id());
  glBindTextureUnit(kUnitProofTriangles, trianglesTex_.id());
  glBindTextureUnit(kUnitProofNear, nearTex_.id());
  glBindTextureUnit(kUnitProofInstances, instancesTex_.id());
  glBindTextureUnit(kUnitProofFlags, flagsTex_.id());
  glBindBufferBase(GL_UNIFORM_BUFFER, kBlockProofMaps, block_.id());
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glViewport(0, 0, width, height);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glUseProgram(p);
  glBindVertexArray(emptyVao_.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return {};
}

void ShadowProofPass::read(std::vector<std::uint32_t>& out) const {
  readTopDown(fbo_, kChannelShadowProofs, width_, height_, out);
}

}  // namespace tandem::gl
