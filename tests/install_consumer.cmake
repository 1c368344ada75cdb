# Installs the build tree into a scratch prefix, then configures, builds and runs
# tests/consumer and tests/ospray_consumer against it with only CMAKE_PREFIX_PATH pointing there.
set(prefix ${BUILD_DIR}/install-test/prefix)
set(consumer_build ${BUILD_DIR}/install-test/consumer)
file(REMOVE_RECURSE ${BUILD_DIR}/install-test)

function(run)
  execute_process(COMMAND ${ARGV} RESULT_VARIABLE result)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "failed (${result}): ${ARGV}")
  endif()
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
message(STATUS "installed package builds and runs")
