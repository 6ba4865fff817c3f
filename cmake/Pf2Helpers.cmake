# pf2_add_library(NAME SOURCES ... [PUBLIC_LIBS ...] [PRIVATE_LIBS ...])
# One library per stage folder; public headers live in <folder>/include/pf2/<stage>/. The library
# is also pf2::<folder> (pf2::core, pf2::slam, pf2::synth, ...), the name the rest of the build
# uses; NAME differs only where an app has the folder's name (pf2_slam, pf2_eval, pf2_synth).
function(pf2_add_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_LIBS;PRIVATE_LIBS" ${ARGN})
  add_library(${name} ${ARG_SOURCES})
  get_filename_component(folder ${CMAKE_CURRENT_SOURCE_DIR} NAME)
  add_library(pf2::${folder} ALIAS ${name})
  target_include_directories(${name} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
  target_link_libraries(${name} PUBLIC ${ARG_PUBLIC_LIBS} PRIVATE ${ARG_PRIVATE_LIBS})
endfunction()

# pf2_add_app(NAME LIBS ...): apps/NAME.cpp, skipped while the source or one of its libraries
# does not exist, so stages can land one at a time.
function(pf2_add_app name)
  cmake_parse_arguments(ARG "" "" "LIBS" ${ARGN})
  set(src ${CMAKE_CURRENT_SOURCE_DIR}/${name}.cpp)
  if(NOT EXISTS ${src})
    return()
  endif()
  foreach(lib ${ARG_LIBS})
    if(NOT TARGET ${lib})
      return()
    endif()
  endforeach()
  add_executable(${name} ${src})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS})
endfunction()

# pf2_add_test(NAME SOURCES ... LIBS ...): one GoogleTest executable, registered with ctest.
# Tests run from the build tree; PF2_SHARED_DATA points to the optional real data folder.
function(pf2_add_test name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} GTest::gtest GTest::gtest_main)
  target_compile_definitions(${name} PRIVATE
    PF2_SHARED_DATA="${PF2_SHARED_DATA_DIR}"
    PF2_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60 PROPERTIES TIMEOUT 600)
endfunction()
