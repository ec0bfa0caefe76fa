# SPDX-License-Identifier: GPL-3.0-or-later
# Plug-in modules (src/translucent/io/plugins.h): the code that needs OpenImageIO or OpenVDB,
# loaded with dlopen on first use, so that a process that reads and writes no image and no grid
# maps neither library nor their dependency closure. The modules are built into
# <build>/lib/translucent and installed into <prefix>/<libdir>/translucent: the same layout, so
# that a build-tree binary finds them as an installed one does (io::loadPlugin's lookup).
include(GNUInstallDirs)
set(TRANSLUCENT_PLUGIN_BUILD_DIR ${PROJECT_BINARY_DIR}/lib/translucent)
set(TRANSLUCENT_PLUGIN_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/translucent)

# translucent_plugin_module(<target> <output name> SOURCES ... [LIBS ...]): a module loaded by
# io::loadPlugin("<name>") as lib<output name>.so (output name translucent_<name>). Built with the
# project's flags (warnings, sanitizers, fuzzing coverage) like the binaries that load it, and
# with only header-only interfaces of ours (src/ on its include path), never one of our static
# libraries: a module linked with them would hold second copies of their state.
function(translucent_plugin_module target output)
  cmake_parse_arguments(M "" "" "SOURCES;LIBS" ${ARGN})
  add_library(${target} MODULE ${M_SOURCES})
  # Default symbol visibility, not hidden: OpenVDB's headers keep per-type static state (the tree
  # type names that openvdb::initialize() registers inside libopenvdb) that must resolve to the
  # library's own; a hidden module held private copies that were never initialised (a crash in
  # gridPtrCast). RTLD_LOCAL keeps the module's symbols from binding anything loaded later.
  set_target_properties(${target} PROPERTIES OUTPUT_NAME ${output}
    LIBRARY_OUTPUT_DIRECTORY ${TRANSLUCENT_PLUGIN_BUILD_DIR})
  target_include_directories(${target} PRIVATE ${PROJECT_SOURCE_DIR}/src)
  target_link_libraries(${target} PRIVATE ${M_LIBS})
  translucent_project_target(${target})
  # Every binary that links the io layer may load the module at run time: building any of them
  # (the CLI, the Python module, a test) builds the modules too, since a static library's
  # target-level dependencies reach the targets that link it.
  add_dependencies(translucent_io ${target})
  if(NOT TRANSLUCENT_FUZZ)
    install(TARGETS ${target} LIBRARY DESTINATION ${TRANSLUCENT_PLUGIN_INSTALL_DIR}
            COMPONENT runtime)
  endif()
endfunction()
