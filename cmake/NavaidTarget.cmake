# navaid_add_room(<room> [UNITY] PUBLIC_DEPS ... PRIVATE_DEPS ...)
# One library target per room: navaid_<room>, alias navaid::<room>, public headers under
# <room>/include, installed and exported. Warnings on (and errors) for our own code only.
function(navaid_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
    -Wold-style-cast -Woverloaded-virtual -Wnull-dereference)
  if(NAVAID_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# Unity builds (CMake UNITY_BUILD): the target's files compile in batches of NAVAID_UNITY_BATCH, so
# that the heavy headers they share (CLI11, Eigen, Ceres, gtest) are parsed once a batch, not once a
# file. A file's anonymous-namespace helpers and constants share the batch with the other files':
# they need names of their own (or a shared helper instead of a copy).
function(navaid_unity target)
  if(NAVAID_UNITY_BATCH GREATER 1)
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE ${NAVAID_UNITY_BATCH})
  endif()
endfunction()

# Sources are every src/**/*.cpp of the room (one concept per file; adding a file needs no edit here).
function(navaid_add_room room)
  cmake_parse_arguments(ARG "UNITY" "" "PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  set(target navaid_${room})
  file(GLOB_RECURSE sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/*.cpp)
  if(NOT sources)
    # A room whose code has not landed yet still exists as a target that carries the dependency
    # graph (DESIGN.md §2), so rooms can be linked and the graph checked from day one.
    add_library(${target} INTERFACE)
    add_library(navaid::${room} ALIAS ${target})
    set_target_properties(${target} PROPERTIES EXPORT_NAME ${room})
    target_link_libraries(${target} INTERFACE ${ARG_PUBLIC_DEPS})
    install(TARGETS ${target} EXPORT navaidTargets)
    return()
  endif()
  add_library(${target} ${sources})
  add_library(navaid::${room} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${room} POSITION_INDEPENDENT_CODE ON)
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(${target} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  target_compile_features(${target} PUBLIC cxx_std_17)
  navaid_warnings(${target})
  if(ARG_UNITY)
    navaid_unity(${target})
  endif()
  if(room IN_LIST NAVAID_FUZZED_ROOMS)
    navaid_fuzz_instrument(${target})
  endif()
  install(TARGETS ${target} EXPORT navaidTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()
