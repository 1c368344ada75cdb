# The engine's dependencies, all Debian 12 packages; shared by the build and by the
# installed package's config so that consumers find the same targets.
include(CMakeFindDependencyMacro)
find_dependency(embree 3)
find_dependency(TBB)
find_dependency(ZLIB)  # gzip-encoded NRRD volumes (io/volume.hpp), compressed VTK arrays (io/vtk.hpp)
find_dependency(pugixml)  # VTK's XML formats (io/vtk.hpp)
find_dependency(tinyobjloader)  # Wavefront OBJ (io/obj.hpp); Debian's is a float build, version "2rc10"

if(NOT TARGET sciray::xsimd)
  # Header-only; Debian's xsimd CMake target links a non-existent "xtl" library, so use
  # the headers directly.
  find_path(SCIRAY_XSIMD_INCLUDE_DIR xsimd/xsimd.hpp REQUIRED)
  add_library(sciray::xsimd INTERFACE IMPORTED)
  set_target_properties(sciray::xsimd PROPERTIES INTERFACE_INCLUDE_DIRECTORIES ${SCIRAY_XSIMD_INCLUDE_DIR})
endif()

if(NOT TARGET sciray::stb)
  # Debian's libstb-dev ships the implementations compiled into libstb.so.
  find_path(SCIRAY_STB_INCLUDE_DIR stb/stb_image_write.h REQUIRED)
  find_library(SCIRAY_STB_LIBRARY stb REQUIRED)
  add_library(sciray::stb UNKNOWN IMPORTED)
  set_target_properties(sciray::stb PROPERTIES IMPORTED_LOCATION ${SCIRAY_STB_LIBRARY}
                                               INTERFACE_INCLUDE_DIRECTORIES ${SCIRAY_STB_INCLUDE_DIR})
endif()
