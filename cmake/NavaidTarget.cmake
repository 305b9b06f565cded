# navaid_add_room(<room> PUBLIC_DEPS ... PRIVATE_DEPS ...)
# One library target per room: navaid_<room>, alias navaid::<room>, public headers under
# <room>/include, installed and exported. Warnings on (and errors) for our own code only.
function(navaid_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
    -Wold-style-cast -Woverloaded-virtual -Wnull-dereference)
  if(NAVAID_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# Sources are every src/**/*.cpp of the room (one concept per file; adding a file needs no edit here).
function(navaid_add_room room)
  cmake_parse_arguments(ARG "" "" "PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
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
  if(room IN_LIST NAVAID_FUZZED_ROOMS)
    navaid_fuzz_instrument(${target})
  endif()
  install(TARGETS ${target} EXPORT navaidTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()
