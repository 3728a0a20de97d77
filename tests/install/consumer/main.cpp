// A program out of the tree on the installed package: one headless frame of the embedded default scene through
// the public API, checked and written. Exit 0 only when the frame is drawn, has rays traced and content in it.
//   tandem-consumer OUT.png
#include <cstdio>
#include <set>
#include <string>
#include <utility>

#include "tandem/Context.h"
#include "tandem/Image.h"
#include "tandem/Renderer.h"
#include "tandem/SceneFile.h"
#include "tandem/Settings.h"

namespace {
int fail(const char* step, const std::string& why) {
  std::fprintf(stderr, "tandem-consumer: %s: %s\n", step, why.c_str());
  return 1;
}
}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) return fail("usage", "tandem-consumer OUT.png");
  auto context = tandem::createGlContext({.kind = tandem::ContextKind::Headless});
  if (!context) return fail("context", context.error().message);
  auto renderer = tandem::Renderer::create(**context);
  if (!renderer) return fail("renderer", renderer.error().message);
  // The default scene is compiled into the library (libtandem_core.a): no data files are installed.
  auto scene = tandem::loadDefaultScene();
  if (!scene) return fail("scene", scene.error().message);
  tandem::Camera camera = scene->camera;
  if (auto ok = (*renderer)->setScene(std::move(*scene)); !ok) return fail("setScene", ok.error().message);

  tandem::FrameSettings settings = *tandem::presetSettings("hybrid-full");
  settings.width = 64;
  settings.height = 36;
  tandem::FrameStats stats = (*renderer)->render(camera, settings);
  if (!stats.error.empty()) return fail("render", stats.error);
  // hybrid-full traces a shadow ray from every lit visible point of the default scene: none means the Embree
  // ray pass did not run.
  if (stats.rays.shadow == 0) return fail("render", "no shadow rays traced");

  tandem::Image frame = (*renderer)->readImage();
  if (frame.width != 64 || frame.height != 36) return fail("readImage", "not a 64x36 frame");
  // A frame that failed to draw is one colour (cleared or black); the default scene's floor, objects and
  // sky give many.
  std::set<unsigned> colours;
  for (int y = 0; y < frame.height; ++y)
    for (int x = 0; x < frame.width; ++x) {
      auto c = frame.at(x, y);
      colours.insert(unsigned(c.r) << 16 | unsigned(c.g) << 8 | unsigned(c.b));
    }
  if (colours.size() < 16) return fail("readImage", std::to_string(colours.size()) + " colours in the frame");
  if (auto ok = tandem::writeImage(argv[1], frame); !ok) return fail("writeImage", ok.error().message);
  std::printf("%s: %dx%d, %zu colours, %llu rays (%s)\n", argv[1], frame.width, frame.height, colours.size(),
              static_cast<unsigned long long>(stats.rays.total()), (*context)->describe().c_str());
  return 0;
}
