// Fuzz builds only (TANDEM_BUILD_FUZZ): tinygltf compiled from Debian's header with this tree's sanitizers
// and coverage, in place of Debian's libtinygltf.so, which has neither, so the fuzzer sees memory errors
// inside tinygltf and is guided by its branches. Its default image functions are compiled too (every
// translation unit that includes the header refers to them) but call the stb_image that tandem_core
// compiles, instrumented the same way; Tandem replaces the image loader, so they never run on input.
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
