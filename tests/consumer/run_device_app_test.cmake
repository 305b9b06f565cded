# Installs the navaid build into a scratch prefix, builds examples/device_app against it with
# find_package(navaid) and runs it on a short simulated corridor walk with the Smart Cane: it must
# print the steering wheel's cues as they come.
include(${CMAKE_CURRENT_LIST_DIR}/install_and_build.cmake)
navaid_install_and_build(${APP_SOURCE_DIR} "the device app (navaid::runtime)")
execute_process(COMMAND ${NAVAID} simulate --scenario corridor --seed 3 --set duration=5 --out ${WORK_DIR}/corridor
                RESULT_VARIABLE rc OUTPUT_QUIET)
if(rc)
  message(FATAL_ERROR "navaid simulate failed: ${rc}")
endif()
# The installed presets, as a user of the package finds them.
set(ENV{NAVAID_DEVICES_DIR} ${WORK_DIR}/prefix/share/navaid/devices)
# As fast as it goes (--speed 0: no frame dropped for being late; CI machines are shared).
execute_process(COMMAND ${WORK_DIR}/build/device_app ${WORK_DIR}/corridor smart-cane --speed 0
                        --set device.goal_start_frame_m=[8,0]
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message(STATUS "${out}")
if(rc)
  message(FATAL_ERROR "the device app failed (${rc}): ${err}")
endif()
if(NOT out MATCHES "smart-cane on .*corridor, as fast as it goes" OR NOT out MATCHES " s  [a-z-]+ [0-9]+:-?[0-9]+" OR NOT out MATCHES "cue events")
  message(FATAL_ERROR "the device app printed no steering cues")
endif()
message(STATUS "examples/device_app built from the installed package and guided a simulated walk")
