# Installs the build tree into a scratch prefix, then configures, builds and runs
# tests/consumer and tests/ospray_consumer against it with only CMAKE_PREFIX_PATH pointing
# there; then runs the installed tool from that prefix and from a copy elsewhere, with no
# library path set.
set(prefix ${BUILD_DIR}/install-test/prefix)
set(consumer_build ${BUILD_DIR}/install-test/consumer)
file(REMOVE_RECURSE ${BUILD_DIR}/install-test)

# Runs a command in an environment without LD_LIBRARY_PATH (nor a preloaded library), so
# that a program finds its libraries only through its own RPATH or the system's paths.
function(run)
  execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=LD_LIBRARY_PATH --unset=LD_PRELOAD ${ARGV}
                  RESULT_VARIABLE result OUTPUT_VARIABLE output ERROR_VARIABLE output)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "failed (${result}): ${ARGV}\n${output}")
  endif()
  set(run_output "${output}" PARENT_SCOPE)
endfunction()

run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
foreach(expected bin/sciray include/sciray/sciray.hpp include/ospray/ospray.h include/ospray/ospray_util.h
                 include/ospray/ospray_cpp.h include/ospray/ospray_cpp/ext/glm.h
                 include/ospray/ospray_cpp/ext/rkcommon.h lib/cmake/sciray/sciray-config.cmake
                 lib/cmake/ospray/ospray-config.cmake)
  if(NOT EXISTS ${prefix}/${expected})
    message(FATAL_ERROR "the install lacks ${expected}")
  endif()
endforeach()
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/consumer -B ${consumer_build} -DCMAKE_BUILD_TYPE=Release
    -DCMAKE_PREFIX_PATH=${prefix})
run(${CMAKE_COMMAND} --build ${consumer_build})
run(${consumer_build}/header_only)
run(${consumer_build}/through_shim)

# OSPRay programs built with only find_package(ospray), run to write their images: the C
# tutorial, and the C++ one on the installed C++ wrapper (it checks its image itself).
set(ospray_build ${BUILD_DIR}/install-test/ospray_application)
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/ospray_consumer -B ${ospray_build} -DCMAKE_PREFIX_PATH=${prefix}
    -DTUTORIAL_SOURCE=${SOURCE_DIR}/examples/c/ospray_tutorial.c
    -DCPP_TUTORIAL_SOURCE=${SOURCE_DIR}/tests/cpp_wrapper/ospray_tutorial.cpp)
run(${CMAKE_COMMAND} --build ${ospray_build})
run(${ospray_build}/ospray_tutorial ${ospray_build}/tutorial.png)
run(${ospray_build}/ospray_tutorial_cpp ${ospray_build}/tutorial_cpp.ppm)
foreach(image tutorial.png tutorial_cpp.ppm)
  if(NOT EXISTS ${ospray_build}/${image})
    message(FATAL_ERROR "the OSPRay application wrote no ${image}")
  endif()
endforeach()

# The installed tool loads the installed shim wherever the prefix lies.
set(moved ${BUILD_DIR}/install-test/moved/prefix)
file(COPY ${prefix} DESTINATION ${BUILD_DIR}/install-test/moved)
foreach(root ${prefix} ${moved})
  run(${root}/bin/sciray info)
  if(NOT run_output MATCHES "chosen: ")
    message(FATAL_ERROR "${root}/bin/sciray info printed no chosen ISA:\n${run_output}")
  endif()
endforeach()
message(STATUS "installed package builds and runs")
