# Installs the navaid build into a scratch prefix, then configures, builds and runs a consumer
# project against it with find_package(navaid).
include(${CMAKE_CURRENT_LIST_DIR}/install_and_build.cmake)
navaid_install_and_build(${CONSUMER_SOURCE_DIR} "the consumer (navaid::core)")
execute_process(COMMAND ${WORK_DIR}/build/consumer RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "the consumer ran but failed: ${rc}")
endif()
message(STATUS "downstream find_package(navaid) consumer built and ran")
