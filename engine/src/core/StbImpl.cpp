// The one translation unit that compiles stb_image and stb_image_write (Debian's libstb-dev ships
// headers only for these). Everything else includes the headers without the implementation macros.
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_NO_HDR
#define STBI_NO_LINEAR
#include <stb_image.h>
#include <stb_image_write.h>
