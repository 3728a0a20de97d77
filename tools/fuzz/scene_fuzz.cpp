// libFuzzer target over the JSON scene file reader, which users write by hand: each input is scene.json
// in a fresh folder (FuzzFolder.h) beside model.gltf, buffer.bin and image.png, so glTF placements and
// glTF meshes ("gltf": "model.gltf") load real files. It must never crash, trip a sanitizer or exceed
// the RSS limit; a bad file gives an error.
//
//   tandem-scene-fuzz -dict=tests/fuzz/scene.dict corpus/ tests/fuzz/seeds/scene
#include <cstdint>

#include "FuzzFolder.h"
#include "tandem/Log.h"
#include "tandem/Scene.h"
#include "tandem/SceneFile.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  tandem::setLogSink([](tandem::LogLevel, std::string_view) {});
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  tandem::fuzz::Folder folder;
  const auto path = folder.write("scene.json", data, size);
  auto r = tandem::loadSceneFile(path.string());
  // A scene the reader accepts is one the renderer may take: it must pass the renderer's own contract.
  if (r && !tandem::validateScene(*r)) std::abort();
  return 0;
}
