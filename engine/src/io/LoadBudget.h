#pragma once
// The resource contract shared by the loaders (docs/gltf.md, docs/scene-format.md, "Resources"):
// whatever a file asks for, a load decodes, copies and keeps at most
//
//     limit = baseBytes + bytesPerInputByte × inputBytes
//
// where inputBytes counts the main file and every distinct file it reads, each once. Everything a load
// produces from its input (accessor reads, decoded texels, converted meshes, instances, repeated reads of a
// file already read) is charged here *before* it is allocated, so a small file that refers to the same
// data many times is refused with a message instead of growing memory by a product of two counts.
// Legitimate assets stay far below it: their output is a small multiple of their input.
#include <cstdint>
#include <string>

namespace tandem {

class LoadBudget {
 public:
  LoadBudget(std::uint64_t baseBytes, std::uint64_t bytesPerInputByte)
      : base_(baseBytes), perByte_(bytesPerInputByte) {}

  /// A file of `bytes` joined the input (the main file, or a buffer/image/glTF read for the first time).
  void addInput(std::uint64_t bytes) { input_ = bytes > ~std::uint64_t(0) - input_ ? ~std::uint64_t(0) : input_ + bytes; }

  /// Takes `bytes` from the budget; false (and nothing taken) when they do not fit.
  [[nodiscard]] bool charge(std::uint64_t bytes) {
    const std::uint64_t lim = limit();
    if (used_ > lim || bytes > lim - used_) return false;
    used_ += bytes;
    return true;
  }

  std::uint64_t limit() const {
    // Saturating: base + perByte·input never wraps.
    std::uint64_t scaled = 0;
    if (__builtin_mul_overflow(perByte_, input_, &scaled)) return ~std::uint64_t(0);
    return scaled > ~std::uint64_t(0) - base_ ? ~std::uint64_t(0) : base_ + scaled;
  }
  std::uint64_t used() const { return used_; }
  std::uint64_t inputBytes() const { return input_; }

  /// The message for a refused charge of `bytes` for `what`.
  std::string refusal(const std::string& what, std::uint64_t bytes) const {
    return what + " would take " + std::to_string(bytes) + " more bytes; the load has used " + std::to_string(used_) +
           " of its budget of " + std::to_string(limit()) + " bytes (" + std::to_string(base_) + " + " +
           std::to_string(perByte_) + " per input byte × " + std::to_string(input_) + " input bytes)";
  }

 private:
  std::uint64_t base_;
  std::uint64_t perByte_;
  std::uint64_t input_ = 0;
  std::uint64_t used_ = 0;
};

}  // namespace tandem
