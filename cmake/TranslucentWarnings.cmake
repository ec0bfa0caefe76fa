# SPDX-License-Identifier: GPL-3.0-or-later
# Warning flags for project code only, carried by an INTERFACE target so that
# third-party code (and system headers) are never compiled with -Werror.
include(GNUInstallDirs)
add_library(translucent_warnings INTERFACE)
add_library(translucent::warnings ALIAS translucent_warnings)
target_compile_options(translucent_warnings INTERFACE
  $<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
    -Wold-style-cast -Wcast-align -Woverloaded-virtual -Wnull-dereference
    -Wdouble-promotion -Wformat=2 -Wimplicit-fallthrough -Werror>)

add_library(translucent_sanitize INTERFACE)
add_library(translucent::sanitize ALIAS translucent_sanitize)
if(TRANSLUCENT_SANITIZE)
  target_compile_options(translucent_sanitize INTERFACE
    -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined
    # GCC 12's -Wmaybe-uninitialized misfires inside libstdc++ (std::regex's std::function
    # states) once the sanitizers instrument optimised code: a false positive of the
    # instrumentation, not of our code; the release build keeps the warning as an error.
    $<$<CXX_COMPILER_ID:GNU>:-Wno-maybe-uninitialized>)
  target_link_options(translucent_sanitize INTERFACE -fsanitize=address,undefined)
endif()

if(TRANSLUCENT_FUZZ)
  # fuzzer-no-link: coverage instrumentation for libFuzzer without its main (the fuzz targets
  # link -fsanitize=fuzzer); sanitizer findings abort so that libFuzzer records them.
  # -Wno-pass-failed: ASan's instrumentation keeps clang from vectorising the `#pragma omp simd`
  # loops (model_reference.cpp), which it reports as a warning about the optimiser, not the code.
  target_compile_options(translucent_sanitize INTERFACE
    -fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer
    -fno-sanitize-recover=undefined -Wno-pass-failed)
  target_link_options(translucent_sanitize INTERFACE -fsanitize=address,undefined)
endif()

# translucent_project_target(<target>): warnings (and sanitizers when enabled) for one of ours.
# A library of src/ is also part of the installed package: its headers are included as
# "translucent/<layer>/<file>.h" from src/ in the build tree and from <prefix>/include once
# installed, it is exported as Translucent::<name> (the target's name without "translucent_"),
# and src/CMakeLists.txt installs every such target (TRANSLUCENT_EXPORTED_TARGETS).
function(translucent_project_target target)
  target_link_libraries(${target} PRIVATE translucent::warnings translucent::sanitize)
  get_target_property(type ${target} TYPE)
  if(type STREQUAL "STATIC_LIBRARY" AND CMAKE_CURRENT_SOURCE_DIR MATCHES "^${PROJECT_SOURCE_DIR}/src/")
    target_include_directories(${target} PUBLIC
      $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/src> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
    string(REGEX REPLACE "^translucent_" "" name ${target})
    set_target_properties(${target} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME ${target})
    set_property(GLOBAL APPEND PROPERTY TRANSLUCENT_EXPORTED_TARGETS ${target})
  endif()
endfunction()
