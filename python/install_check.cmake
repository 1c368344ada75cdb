# Installs the build into a scratch prefix and imports sciray from there alone: the
# package and its extension land in PACKAGE_DIR and find libsciray_ospray by their RPATH.
set(prefix ${BUILD_DIR}/python_install_check)
file(REMOVE_RECURSE ${prefix})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix} OUTPUT_QUIET RESULT_VARIABLE installed)
if(NOT installed EQUAL 0)
  message(FATAL_ERROR "cmake --install failed")
endif()
execute_process(
  COMMAND ${CMAKE_COMMAND} -E env --unset=LD_LIBRARY_PATH PYTHONPATH=${prefix}/${PACKAGE_DIR} ${PYTHON} -c
          "import sciray; assert sciray.__file__.startswith('${prefix}'), sciray.__file__; print(sciray.render(sciray.builtin_scene(1000), size=(8, 8)).shape)"
  WORKING_DIRECTORY ${prefix} OUTPUT_VARIABLE out RESULT_VARIABLE imported)
if(NOT imported EQUAL 0 OR NOT out MATCHES "\\(8, 8, 4\\)")
  message(FATAL_ERROR "the installed module did not import and render: ${out}")
endif()
file(REMOVE_RECURSE ${prefix})
