# Installs the navaid build in NAVAID_BINARY_DIR into WORK_DIR/prefix, then configures and builds
# the downstream project in SOURCE_DIR against it with find_package(navaid) (into WORK_DIR/build).
function(navaid_install_and_build SOURCE_DIR WHAT)
  file(REMOVE_RECURSE ${WORK_DIR})
  execute_process(COMMAND ${CMAKE_COMMAND} --install ${NAVAID_BINARY_DIR} --prefix ${WORK_DIR}/prefix
                  RESULT_VARIABLE rc OUTPUT_QUIET)
  if(rc)
    message(FATAL_ERROR "install of navaid failed: ${rc}")
  endif()
  execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${WORK_DIR}/build
                          -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_BUILD_TYPE=Release
                  RESULT_VARIABLE rc)
  if(rc)
    message(FATAL_ERROR "configuring ${WHAT} with find_package(navaid) failed: ${rc}")
  endif()
  execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK_DIR}/build RESULT_VARIABLE rc)
  if(rc)
    message(FATAL_ERROR "building ${WHAT} against the installed navaid failed: ${rc}")
  endif()
endfunction()
