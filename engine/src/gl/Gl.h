#pragma once
// The one way the GL layer includes OpenGL: glad's 4.5 core loader, generated into the build tree.
#include <glad/gl.h>

namespace tandem::gl {

/// Loads the GL entry points for the context about to be used. glad's pointers are process-wide, so a
/// context made current after one of another kind (OSMesa after EGL) loads them again; `owner`
/// identifies the loader so the same context does not reload on every makeCurrent.
using ProcLoader = GLADapiproc (*)(const char* name);
int loadGl(const void* owner, ProcLoader loader);
/// Called by a context's destructor, so a new context at the same address loads its own pointers.
void forgetGlLoader(const void* owner);

}  // namespace tandem::gl
