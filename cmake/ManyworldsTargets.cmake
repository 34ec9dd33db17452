# Helpers shared by every layer's CMakeLists.txt.

# Warnings and code generation flags for a project target.
function(manyworlds_compile_options target)
  target_compile_options(${target} PRIVATE -Wall -Wextra)
  # GCC 12 reports a false -Wrestrict inside std::string concatenation at -O3
  # (GCC bug 105651); nothing in our code is involved.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
    target_compile_options(${target} PRIVATE -Wno-restrict)
  endif()
  # sqrt/exp without errno lets the compiler vectorise numeric loops.
  target_compile_options(${target} PRIVATE -fno-math-errno)
  if(MANYWORLDS_NATIVE)
    target_compile_options(${target} PRIVATE -march=native)
  endif()
endfunction()

# manyworlds_library(<layer> SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# Creates target manyworlds_<layer> (alias manyworlds::<layer>), with the
# include root src/, installs it and its headers.
function(manyworlds_library layer)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  set(target manyworlds_${layer})
  add_library(${target} ${ARG_SOURCES})
  add_library(manyworlds::${layer} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${layer})
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/src>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(${target} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  manyworlds_compile_options(${target})
  install(TARGETS ${target} EXPORT manyworldsTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/
    DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/manyworlds/${layer}
    FILES_MATCHING PATTERN "*.h")
endfunction()

# The non-test .cc files of the current directory and the given subfolders.
function(manyworlds_glob_sources out)
  set(patterns ${CMAKE_CURRENT_SOURCE_DIR}/*.cc)
  foreach(sub IN LISTS ARGN)
    list(APPEND patterns ${CMAKE_CURRENT_SOURCE_DIR}/${sub}/*.cc)
  endforeach()
  file(GLOB files CONFIGURE_DEPENDS ${patterns})
  list(FILTER files EXCLUDE REGEX "_test\\.cc$")
  set(${out} ${files} PARENT_SCOPE)
endfunction()

# manyworlds_tests(LIBS ... [DEFAULT_LABELS ...] [LABELS <file>=<label>,... ...]): one
# GoogleTest executable per *_test.cc, its tests labelled for `ctest -L`:
#   unit      fast checks of one piece (the default, unless DEFAULT_LABELS; the cli area's is cli)
#   cli       runs the built `manyworlds` program
#   learning  trains a learner to a threshold
#   fidelity  checks numbers against the official packages' recorded values
#   probe     a table of hostile inputs over every env option, config key or run directory
#   slow      takes more than about 20 s on two cores (left out of the quick suite)
# e.g. LABELS learning_test=learning,slow (a comma separates labels).
function(manyworlds_tests)
  cmake_parse_arguments(ARG "" "" "LIBS;LABELS;DEFAULT_LABELS" ${ARGN})
  get_filename_component(area ${CMAKE_CURRENT_SOURCE_DIR} NAME)
  if(ARG_DEFAULT_LABELS)
    set(default_labels ${ARG_DEFAULT_LABELS})
  elseif(area STREQUAL "cli")
    set(default_labels cli)
  else()
    set(default_labels unit)
  endif()
  file(GLOB tests CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*_test.cc)
  # a label for a file that is gone is a mistake, not a no-op
  foreach(entry IN LISTS ARG_LABELS)
    string(REGEX REPLACE "=.*$" "" labelled "${entry}")
    if(NOT EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/${labelled}.cc)
      message(FATAL_ERROR "manyworlds_tests LABELS: no ${labelled}.cc in ${CMAKE_CURRENT_SOURCE_DIR}")
    endif()
  endforeach()
  foreach(file IN LISTS tests)
    get_filename_component(name ${file} NAME_WE)
    set(target ${area}_${name})
    set(labels ${default_labels})
    foreach(entry IN LISTS ARG_LABELS)
      if(entry MATCHES "^${name}=(.+)$")
        string(REPLACE "," ";" labels "${CMAKE_MATCH_1}")
      endif()
    endforeach()
    add_executable(${target} ${file})
    target_link_libraries(${target} PRIVATE ${ARG_LIBS} GTest::gtest GTest::gtest_main)
    # Test helpers are included as "tests/<area>/<file>.h".
    target_include_directories(${target} PRIVATE ${PROJECT_SOURCE_DIR})
    manyworlds_compile_options(${target})
    # One OpenBLAS thread per test process: ctest -j runs one test per core,
    # and two processes with a BLAS thread on every core oversubscribe the
    # cores, whose spinning workers then wait for each other's time slices
    # (a PEARL update 13x slower beside any other busy process; docs/benchmarks.md).
    # Tests that need more threads set them (nn::SetThreads).
    gtest_discover_tests(${target} DISCOVERY_TIMEOUT 60
      PROPERTIES ENVIRONMENT "MANYWORLDS_SOURCE_DIR=${PROJECT_SOURCE_DIR}"
                 ENVIRONMENT_MODIFICATION "OPENBLAS_NUM_THREADS=set:1")
    # The labels are set by a script ctest reads after the discovered tests
    # (their names are known only then): gtest_discover_tests' PROPERTIES
    # cannot carry a list, so a second label would be lost there.
    # Slow tests start first (a high COST; ctest replaces it by measured times once it has
    # them): a long test started last would run alone while the other core idles.
    set(cost "")
    if("slow" IN_LIST labels)
      set(cost " COST 1000")
    endif()
    set(label_script ${CMAKE_CURRENT_BINARY_DIR}/${target}_labels.cmake)
    file(WRITE ${label_script}
         "if(${target}_TESTS)\n"
         "  set_tests_properties(\${${target}_TESTS} PROPERTIES LABELS \"${labels}\"${cost})\n"
         "endif()\n")
    set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES ${label_script})
  endforeach()
endfunction()

# manyworlds_includes_torch(<file> <out>): ON if <file> includes a libtorch
# header (torch/, ATen/, c10/), directly or through the project's own headers
# ("manyworlds/...", "apps/...", "tests/..."), found by reading #include lines
# at configure time. Used to keep the torch PCH out of sources that do not need
# it: a PCH-less source that includes torch textually would cost more, one
# that does not but gets the PCH pays ~10 s for loading it.
function(manyworlds_includes_torch file out)
  get_property(known GLOBAL PROPERTY "MANYWORLDS_TORCH:${file}" SET)
  if(known)
    get_property(result GLOBAL PROPERTY "MANYWORLDS_TORCH:${file}")
    set(${out} ${result} PARENT_SCOPE)
    return()
  endif()
  set_property(GLOBAL PROPERTY "MANYWORLDS_TORCH:${file}" OFF)  # guards include cycles
  set(result OFF)
  file(STRINGS ${file} lines REGEX "^[ \t]*#[ \t]*include")
  foreach(line IN LISTS lines)
    if(line MATCHES "<(torch|ATen|c10)/")
      set(result ON)
      break()
    elseif(line MATCHES "\"(manyworlds/[^\"]+)\"")
      set(header ${PROJECT_SOURCE_DIR}/src/${CMAKE_MATCH_1})
    elseif(line MATCHES "\"((apps|tests)/[^\"]+)\"")
      set(header ${PROJECT_SOURCE_DIR}/${CMAKE_MATCH_1})
    else()
      continue()
    endif()
    if(EXISTS ${header})
      manyworlds_includes_torch(${header} header_result)
      if(header_result)
        set(result ON)
        break()
      endif()
    endif()
  endforeach()
  set_property(GLOBAL PROPERTY "MANYWORLDS_TORCH:${file}" ${result})
  set(${out} ${result} PARENT_SCOPE)
endfunction()
