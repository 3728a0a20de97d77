#pragma once
// Files built to make a loader spend far more than their size: each takes a target size and writes the
// file (and whatever it refers to) into a folder. The resource tests load each in a child process and
// hold its peak memory and time to the contract in docs/gltf.md and docs/scene-format.md ("Resources").
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace tandem::test {

struct AdversarialCase {
  std::string name;
  std::string what;  // the amplification it tries
  /// Writes the files into `dir` for about `targetBytes` of input; returns the file to load.
  std::function<std::filesystem::path(const std::filesystem::path& dir, std::size_t targetBytes)> write;
};

/// Every case: glTF (.gltf and .glb), the JSON scene file, and a PNG.
const std::vector<AdversarialCase>& adversarialCases();

/// Bytes of every regular file under `dir` (the input a load may read).
std::uint64_t folderBytes(const std::filesystem::path& dir);

/// A PNG of w×h declared pixels whose zlib stream inflates to `inflatedBytes` (far more than w×h needs).
std::vector<std::uint8_t> pngBomb(int w, int h, std::size_t inflatedBytes);
/// A PNG header declaring w×h pixels, with a one-row IDAT: stb_image reads the size, never the pixels.
std::vector<std::uint8_t> pngHeaderOnly(int w, int h);
/// A real, flat-coloured w×h RGBA PNG (highly compressible): test::pngBytes.
std::vector<std::uint8_t> flatPng(int w, int h);

}  // namespace tandem::test
