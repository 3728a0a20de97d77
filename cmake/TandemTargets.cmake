# Warnings and sanitizers travel through interface targets, never through global flags.
add_library(tandem_warnings INTERFACE)
target_compile_options(tandem_warnings INTERFACE
  $<$<COMPILE_LANGUAGE:CXX>:-Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion
    -Wnon-virtual-dtor -Wold-style-cast -Wcast-align -Woverloaded-virtual -Wnull-dereference>
  $<$<BOOL:${TANDEM_WERROR}>:-Werror>)

add_library(tandem_sanitize INTERFACE)
if(TANDEM_SANITIZE)
  # -g1 (line tables with gcc and clang, clang's -gline-tables-only; after the build type's -g, so it wins): the
  # files, lines and inlined frames a sanitizer's report names, without the types and locals a debugger needs,
  # which made a file of the sanitizer builds up to 30 % longer to compile (clang 14 with ASan: RayTracer.cpp
  # 16.9 -> 20.0 s, DenoiseGLTest.cpp at -O1 19.9 -> 26.0 s). A Debug build keeps them: it is for a debugger.
  target_compile_options(tandem_sanitize INTERFACE -fsanitize=${TANDEM_SANITIZE} -fno-omit-frame-pointer
                                                   $<IF:$<CONFIG:Debug>,-g,-g1>)
  target_link_options(tandem_sanitize INTERFACE -fsanitize=${TANDEM_SANITIZE})
endif()

# Embed text files (shaders, the default scene) into a C++ source so binaries run from any directory.
# tandem_embed(OUT_CPP NAMESPACE_FN file...) produces a function returning {name, text} pairs.
function(tandem_embed out_cpp fn_name)
  set(inputs ${ARGN})
  add_custom_command(OUTPUT ${out_cpp}
    COMMAND ${CMAKE_COMMAND} -DOUT=${out_cpp} -DFN=${fn_name} -DROOT=${PROJECT_SOURCE_DIR}
            "-DINPUTS=${inputs}" -P ${PROJECT_SOURCE_DIR}/cmake/Embed.cmake
    DEPENDS ${inputs} ${PROJECT_SOURCE_DIR}/cmake/Embed.cmake
    COMMENT "Embedding ${fn_name}" VERBATIM)
endfunction()
