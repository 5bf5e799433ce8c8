# griddemplugin.so: GRIDDEM as a LAMMPS plugin, for "plugin load" into a LAMMPS built without it
# (shared library or not, with the PLUGIN and GRANULAR packages).
#
# A plugin shares LAMMPS's classes, so it is compiled exactly as the package's files are compiled
# into this build's lmp: the same LAMMPS headers, definitions (LAMMPS_SIZES, MPI or STUBS, LMP_KOKKOS)
# and options (Kokkos's among them). It therefore loads into a LAMMPS 4Feb2025 configured with the
# same BUILD_MPI, LAMMPS_SIZES and, for the kk styles, KOKKOS settings as this build; the plugin
# refuses any other version, integer sizes or MPI when loaded.
#
# compute griddem/cg needs LAMMPS's parallel FFT (KSPACE's FFT3d and Remap), which a host without
# KSPACE lacks; the plugin carries its own copy, compiled from the LAMMPS source with the built-in
# KISS FFT in double precision, linked from a static library whose symbols are not exported
# (--exclude-libs), so it never clashes with a host's KSPACE whatever FFT library that one uses.

set(_pkg "${PROJECT_SOURCE_DIR}/src/PKG-GRIDDEM")
set(_lammps_src "${LAMMPS_SOURCE_DIR}/src")
set(_generated "${CMAKE_CURRENT_BINARY_DIR}/griddem-plugin")

# The package's style headers, as LAMMPS would collect them into style_*.h; a style of a kind the
# plugin does not register stops the configure instead of being left out silently.
file(GLOB _headers CONFIGURE_DEPENDS "${_pkg}/*.h")
file(GLOB _sources CONFIGURE_DEPENDS "${_pkg}/*.cpp")
if(PKG_KOKKOS)
  file(GLOB _kk_headers CONFIGURE_DEPENDS "${_pkg}/kokkos/*.h")
  file(GLOB _kk_sources CONFIGURE_DEPENDS "${_pkg}/kokkos/*.cpp")
  list(APPEND _headers ${_kk_headers})
  list(APPEND _sources ${_kk_sources})
endif()
set(_includes "")
foreach(_h ${_headers})
  file(STRINGS "${_h}" _declarations REGEX "^[A-Za-z]+Style\\(")
  foreach(_d ${_declarations})
    if(NOT _d MATCHES "^(Pair|Fix|Compute)Style\\(")
      message(FATAL_ERROR "${_h} declares '${_d}': griddemplugin registers pair, fix and compute styles only")
    endif()
  endforeach()
  if(_declarations)
    get_filename_component(_name "${_h}" NAME)
    string(APPEND _includes "#include \"${_name}\"\n")
  endif()
endforeach()
file(CONFIGURE OUTPUT "${_generated}/griddem_plugin_styles.h" CONTENT
  "// GRIDDEM headers that declare styles, written by cmake/GriddemPlugin.cmake (no include guard:\n// griddemplugin.cpp includes it once per style kind, as LAMMPS does style_*.h)\n${_includes}"
  @ONLY)

# LAMMPS's FFT for compute griddem/cg, from the LAMMPS source (see above)
set(_plugin_definitions "$<FILTER:$<TARGET_PROPERTY:lammps,COMPILE_DEFINITIONS>,EXCLUDE,^FFT_>" FFT_KISS)
add_library(griddem_plugin_fft STATIC "${_lammps_src}/KSPACE/fft3d.cpp"
  "${_lammps_src}/KSPACE/fft3d_wrap.cpp" "${_lammps_src}/KSPACE/remap.cpp"
  "${_lammps_src}/KSPACE/remap_wrap.cpp")

add_library(griddemplugin MODULE "${_pkg}/plugin/griddemplugin.cpp" ${_sources})
target_include_directories(griddemplugin PRIVATE "${_generated}" "${_pkg}")
if(PKG_KOKKOS)
  target_include_directories(griddemplugin PRIVATE "${_pkg}/kokkos")
endif()
get_target_property(_cxx_standard lammps CXX_STANDARD)
foreach(_target griddemplugin griddem_plugin_fft)
  target_include_directories(${_target} PRIVATE "${_lammps_src}/KSPACE" "${_lammps_src}"
    $<TARGET_PROPERTY:lammps,INCLUDE_DIRECTORIES>)
  target_compile_definitions(${_target} PRIVATE ${_plugin_definitions})
  target_compile_options(${_target} PRIVATE $<TARGET_PROPERTY:lammps,COMPILE_OPTIONS>)
  set_target_properties(${_target} PROPERTIES POSITION_INDEPENDENT_CODE ON
    CXX_STANDARD ${_cxx_standard} CXX_STANDARD_REQUIRED ON)
endforeach()
# LAMMPS's own symbols stay undefined here and are resolved from the host when it loads the plugin
target_link_libraries(griddemplugin PRIVATE griddem_core griddem_plugin_fft)
set_target_properties(griddemplugin PROPERTIES PREFIX "" SUFFIX ".so"
  LIBRARY_OUTPUT_DIRECTORY "${CMAKE_BINARY_DIR}")
target_link_options(griddemplugin PRIVATE "LINKER:--exclude-libs,ALL")

# LAMMPS auto-loads every *plugin.so in the folders named by LAMMPS_PLUGIN_PATH: the plugin goes to
# a folder of its own, lib/lammps/plugins, so that folder can be named without loading anything else
set(GRIDDEM_PLUGIN_INSTALL_DIR "${CMAKE_INSTALL_LIBDIR}/lammps/plugins")
install(TARGETS griddemplugin LIBRARY DESTINATION "${GRIDDEM_PLUGIN_INSTALL_DIR}")
set(GRIDDEM_PLUGIN "${CMAKE_BINARY_DIR}/griddemplugin.so")
