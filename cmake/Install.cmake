# `cmake --install` and `cpack -G DEB`: the public headers, the engine's static libraries and a CMake package
# exporting Tandem::tandem, which is all a game needs (README, "Using the engine in a game"):
#   <prefix>/include/tandem/*.h                      engine/include/tandem, the public API, nothing else
#   <prefix>/lib/libtandem_{core,scene,rt,glad,gl,engine}.a
#   <prefix>/lib/cmake/Tandem/TandemConfig.cmake     + TandemConfigVersion.cmake, TandemTargets*.cmake
# The libraries are static, so what they link privately a consumer links too: TandemConfig.cmake finds those
# Debian packages (find_dependency) and the .deb depends on their -dev packages. Embedded shaders and the
# default scene are compiled into libtandem_core.a: no data files.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)
set(TANDEM_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/Tandem)

# Tandem::tandem is the engine (the Renderer and every layer under it); the layers are exported too, as
# Tandem::core, Tandem::scene, ..., since the engine links them (a tool may link Tandem::scene alone).
set_target_properties(tandem_engine PROPERTIES EXPORT_NAME tandem)
foreach(layer core scene rt glad gl plan)
  set_target_properties(tandem_${layer} PROPERTIES EXPORT_NAME ${layer})
endforeach()
install(TARGETS tandem_core tandem_scene tandem_rt tandem_glad tandem_gl tandem_plan tandem_engine EXPORT TandemTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/engine/include/tandem DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT TandemTargets NAMESPACE Tandem:: DESTINATION ${TANDEM_CMAKE_DIR})

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/TandemConfig.cmake.in
  ${PROJECT_BINARY_DIR}/TandemConfig.cmake INSTALL_DESTINATION ${TANDEM_CMAKE_DIR})
# 0.x: a minor version may change the API, so only the same major.minor satisfies a request.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/TandemConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/TandemConfig.cmake ${PROJECT_BINARY_DIR}/TandemConfigVersion.cmake
        DESTINATION ${TANDEM_CMAKE_DIR})

# cpack -G DEB: libtandem-dev_<version>_<arch>.deb with the same files under /usr.
set(TANDEM_PACKAGE_MAINTAINER "Tandem developers <tandem@invalid>" CACHE STRING
    "Maintainer field of the .deb cpack builds (name <email>)")
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME libtandem-dev)
set(CPACK_PACKAGE_VENDOR Tandem)
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "Tandem hybrid rendering engine module: OpenGL 4.5 raster + Embree 3 ray pass (headers, static libraries, CMake package)")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${TANDEM_PACKAGE_MAINTAINER}")
set(CPACK_DEBIAN_PACKAGE_SECTION libdevel)
# The packages whose CMake packages TandemConfig.cmake finds (and whose libraries the static libraries need).
set(CPACK_DEBIAN_PACKAGE_DEPENDS
    "libglm-dev, libembree-dev (>= 3), libembree-dev (<< 4), libtbb-dev, libglfw3-dev (>= 3.3), libtinygltf-dev, libegl-dev")
# Rendering needs a GL 4.5 driver: Mesa's EGL and llvmpipe where there is no GPU, OSMesa as the last resort
# (opened at run time).
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "libegl-mesa0, libgl1-mesa-dri, libosmesa6")
include(CPack)
