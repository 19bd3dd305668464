# Helpers in the spirit of colmap's: one call creates a target with its alias, include root,
# language level and warning flags. Flags are target-scoped only; CMAKE_CXX_FLAGS is never edited.

# --- Warnings: one INTERFACE target, linked PRIVATE to our own targets only. ------------------
add_library(mvtrack_warnings INTERFACE)
target_compile_options(mvtrack_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Woverloaded-virtual -Wconversion
  $<$<BOOL:${MVTRACK_WERROR}>:-Werror>)
# A unity build (the release preset) compiles each .cc as if it were a header of
# the batch's source, so GCC's -Wsubobject-linkage flags every class that holds a type of its
# file's anonymous namespace; that is safe in a .cc of its own, which is what every one is.
if(CMAKE_UNITY_BUILD)
  target_compile_options(mvtrack_warnings INTERFACE -Wno-subobject-linkage)
endif()

# --- Sanitizers (address+thread together is rejected, as ceres does). -----------------------
add_library(mvtrack_sanitizers INTERFACE)
if(MVTRACK_SANITIZE)
  if("address" IN_LIST MVTRACK_SANITIZE AND "thread" IN_LIST MVTRACK_SANITIZE)
    message(FATAL_ERROR "MVTRACK_SANITIZE: 'address' and 'thread' cannot be combined")
  endif()
  foreach(s IN LISTS MVTRACK_SANITIZE)
    if(NOT s MATCHES "^(address|undefined|thread|leak)$")
      message(FATAL_ERROR "MVTRACK_SANITIZE: unknown sanitizer '${s}'")
    endif()
  endforeach()
  string(REPLACE ";" "," _mvtrack_san "${MVTRACK_SANITIZE}")
  # GCC's flow analysis is known to report spurious -Wmaybe-uninitialized under -fsanitize (GCC
  # documents that sanitizers may produce false warnings): gcc 12 flags the fully initialized
  # tracker::WindowJob inside a std::variant at -O1. The normal builds keep the warning as an error.
  target_compile_options(mvtrack_sanitizers INTERFACE
    -fsanitize=${_mvtrack_san} -fno-omit-frame-pointer -fno-sanitize-recover=all
    $<$<CXX_COMPILER_ID:GNU>:-Wno-maybe-uninitialized>)
  # Debian's gcc links with --as-needed only without -fsanitize (its specs:
  # %{!fsanitize=*:--as-needed}); set it here so sanitizer binaries need the same shared libraries
  # as the shipped ones (package/deb checks mvtrackd's Depends: no OpenCV). The sanitizer runtimes
  # stay: gcc links them inside --push-state --no-as-needed.
  target_link_options(mvtrack_sanitizers INTERFACE -fsanitize=${_mvtrack_san} LINKER:--as-needed)
endif()

# mvtrack_add_library(NAME <module> SRCS ... DEPS ... [PRIVATE_DEPS ...])
#   creates mvtrack_<module> with alias mvtrack::<module>; lib/ is the include root.
function(mvtrack_add_library)
  cmake_parse_arguments(A "" "NAME" "SRCS;DEPS;PRIVATE_DEPS" ${ARGN})
  set(t mvtrack_${A_NAME})
  add_library(${t} STATIC ${A_SRCS})
  add_library(mvtrack::${A_NAME} ALIAS ${t})
  target_include_directories(${t} PUBLIC ${PROJECT_SOURCE_DIR}/lib)
  target_compile_features(${t} PUBLIC cxx_std_20)
  set_target_properties(${t} PROPERTIES CXX_EXTENSIONS OFF POSITION_INDEPENDENT_CODE ON)
  target_link_libraries(${t} PUBLIC ${A_DEPS} mvtrack_sanitizers PRIVATE ${A_PRIVATE_DEPS} mvtrack_warnings)
endfunction()

# mvtrack_add_executable(NAME <name> SRCS ... DEPS ...)
function(mvtrack_add_executable)
  cmake_parse_arguments(A "" "NAME" "SRCS;DEPS" ${ARGN})
  add_executable(${A_NAME} ${A_SRCS})
  target_compile_features(${A_NAME} PRIVATE cxx_std_20)
  set_target_properties(${A_NAME} PROPERTIES CXX_EXTENSIONS OFF)
  target_link_libraries(${A_NAME} PRIVATE ${A_DEPS} mvtrack_sanitizers mvtrack_warnings)
endfunction()

# mvtrack_add_test(NAME <module> SRCS ... DEPS ... [LABELS ...])
#   one test executable per module (mvtrack_<module>_tests); CTest names read "<module>/<case>"
#   and the Catch2 seed is pinned.
function(mvtrack_add_test)
  cmake_parse_arguments(A "" "NAME" "SRCS;DEPS;LABELS" ${ARGN})
  set(t mvtrack_${A_NAME}_tests)
  add_executable(${t} ${A_SRCS})
  target_compile_features(${t} PRIVATE cxx_std_20)
  set_target_properties(${t} PROPERTIES CXX_EXTENSIONS OFF)
  target_include_directories(${t} PRIVATE ${PROJECT_SOURCE_DIR}/tests)
  target_link_libraries(${t} PRIVATE ${A_DEPS} mvtrack_test_main mvtrack_sanitizers mvtrack_warnings)
  set(labels ${A_LABELS})
  if(NOT labels)
    set(labels unit)
  endif()
  # catch_discover_tests flattens PROPERTIES, so several labels must be passed as one
  # escaped list or only the first survives.
  string(REPLACE ";" "\\;" labels_joined "${labels}")
  catch_discover_tests(${t}
    TEST_PREFIX "${A_NAME}/"
    EXTRA_ARGS --rng-seed 12345
    PROPERTIES LABELS "${labels_joined}"
    DISCOVERY_TIMEOUT 60)
endfunction()
