# Locate (or download once) the LAMMPS 4Feb2025 source and stage a build tree with PKG-GRIDDEM in it.
#
# LAMMPS's CMake only builds packages that sit in its own src/ folder and are named in its
# STANDARD_PACKAGES list, so the build stages a private copy of cmake/, src/ and lib/ under the build
# folder, links our package into src/GRIDDEM and adds GRIDDEM to that list. The user's source tree is
# never written to.

set(GRIDDEM_LAMMPS_TARBALL "lammps_20250204+dfsg.1.orig.tar.xz")
set(GRIDDEM_LAMMPS_SHA256 "3671165bd52fad36734e0a9136c5bc5ecb225e03988f8c89aa13366a8b53b1c7")
set(GRIDDEM_DOWNLOAD_DIR "${PROJECT_SOURCE_DIR}/.deps" CACHE PATH
  "Where the LAMMPS source tarball is downloaded to and unpacked (kept across configures)")
set(LAMMPS_SOURCE_DIR "" CACHE PATH
  "Top folder of an existing LAMMPS 4Feb2025 source tree (holds cmake/ and src/); empty: download it")

if(NOT LAMMPS_SOURCE_DIR)
  set(_tarball "${GRIDDEM_DOWNLOAD_DIR}/${GRIDDEM_LAMMPS_TARBALL}")
  set(_unpacked "${GRIDDEM_DOWNLOAD_DIR}/lammps-4Feb2025")
  if(NOT EXISTS "${_unpacked}/src/version.h")
    if(NOT EXISTS "${_tarball}")
      message(STATUS "Downloading the LAMMPS source package (Debian trixie lammps 20250204+dfsg.1)")
      execute_process(COMMAND "${PROJECT_SOURCE_DIR}/tools/fetch-lammps-source" "${GRIDDEM_DOWNLOAD_DIR}"
        RESULT_VARIABLE _rc)
      if(NOT _rc EQUAL 0 OR NOT EXISTS "${_tarball}")
        message(FATAL_ERROR "Could not download the LAMMPS source (see above). "
          "Point -DLAMMPS_SOURCE_DIR=<path> at a LAMMPS 4Feb2025 source tree instead.")
      endif()
    endif()
    file(SHA256 "${_tarball}" _sum)
    if(NOT _sum STREQUAL GRIDDEM_LAMMPS_SHA256)
      file(REMOVE "${_tarball}")
      message(FATAL_ERROR "${_tarball} has sha256 ${_sum}, expected ${GRIDDEM_LAMMPS_SHA256}; removed it, configure again to re-download")
    endif()
    message(STATUS "Unpacking ${_tarball}")
    file(ARCHIVE_EXTRACT INPUT "${_tarball}" DESTINATION "${GRIDDEM_DOWNLOAD_DIR}"
      PATTERNS "lammps-4Feb2025/cmake" "lammps-4Feb2025/src" "lammps-4Feb2025/lib"
               "lammps-4Feb2025/bench" "lammps-4Feb2025/potentials")
  endif()
  set(LAMMPS_SOURCE_DIR "${_unpacked}" CACHE PATH "" FORCE)
endif()

if(NOT EXISTS "${LAMMPS_SOURCE_DIR}/src/version.h" OR NOT EXISTS "${LAMMPS_SOURCE_DIR}/cmake/CMakeLists.txt")
  message(FATAL_ERROR "LAMMPS_SOURCE_DIR=${LAMMPS_SOURCE_DIR} is not a LAMMPS source tree (no src/version.h, cmake/CMakeLists.txt)")
endif()
file(STRINGS "${LAMMPS_SOURCE_DIR}/src/version.h" _version REGEX "LAMMPS_VERSION")
if(NOT _version MATCHES "4 Feb 2025")
  message(WARNING "GRIDDEM is developed against LAMMPS 4 Feb 2025; ${LAMMPS_SOURCE_DIR} has ${_version}")
endif()

# Stage: a copy of the LAMMPS tree, refreshed when the source folder or what is staged changes.
set(GRIDDEM_LAMMPS_TREE "${CMAKE_BINARY_DIR}/lammps-tree")
set(_stamp "${GRIDDEM_LAMMPS_TREE}/.griddem-staged-from")
set(_stage_key "${LAMMPS_SOURCE_DIR} (cmake src lib bench potentials doc/lammps.1)")
set(_staged_from "")
if(EXISTS "${_stamp}")
  file(READ "${_stamp}" _staged_from)
endif()
if(NOT _staged_from STREQUAL _stage_key)
  message(STATUS "Staging LAMMPS from ${LAMMPS_SOURCE_DIR} into ${GRIDDEM_LAMMPS_TREE}")
  file(REMOVE_RECURSE "${GRIDDEM_LAMMPS_TREE}")
  file(MAKE_DIRECTORY "${GRIDDEM_LAMMPS_TREE}")
  foreach(_dir cmake src lib)
    file(COPY "${LAMMPS_SOURCE_DIR}/${_dir}" DESTINATION "${GRIDDEM_LAMMPS_TREE}")
  endforeach()
  # what LAMMPS's install step copies under the prefix (bench/, potentials/, its man page)
  foreach(_dir bench potentials)
    if(EXISTS "${LAMMPS_SOURCE_DIR}/${_dir}")
      file(COPY "${LAMMPS_SOURCE_DIR}/${_dir}" DESTINATION "${GRIDDEM_LAMMPS_TREE}")
    else()
      file(MAKE_DIRECTORY "${GRIDDEM_LAMMPS_TREE}/${_dir}")
    endif()
  endforeach()
  if(EXISTS "${LAMMPS_SOURCE_DIR}/doc/lammps.1")
    file(COPY "${LAMMPS_SOURCE_DIR}/doc/lammps.1" DESTINATION "${GRIDDEM_LAMMPS_TREE}/doc")
  elseif(EXISTS "${GRIDDEM_DOWNLOAD_DIR}/${GRIDDEM_LAMMPS_TARBALL}")
    file(ARCHIVE_EXTRACT INPUT "${GRIDDEM_DOWNLOAD_DIR}/${GRIDDEM_LAMMPS_TARBALL}"
      DESTINATION "${CMAKE_BINARY_DIR}/lammps-man" PATTERNS "lammps-4Feb2025/doc/lammps.1")
    file(COPY "${CMAKE_BINARY_DIR}/lammps-man/lammps-4Feb2025/doc/lammps.1"
      DESTINATION "${GRIDDEM_LAMMPS_TREE}/doc")
    file(REMOVE_RECURSE "${CMAKE_BINARY_DIR}/lammps-man")
  else()
    message(WARNING "${LAMMPS_SOURCE_DIR} has no doc/lammps.1: cmake --install will stop at LAMMPS's man page")
  endif()
  file(READ "${GRIDDEM_LAMMPS_TREE}/cmake/CMakeLists.txt" _lists)
  string(REPLACE "set(STANDARD_PACKAGES\n" "set(STANDARD_PACKAGES\n  GRIDDEM\n" _lists "${_lists}")
  if(NOT _lists MATCHES "GRIDDEM")
    message(FATAL_ERROR "Could not add GRIDDEM to STANDARD_PACKAGES in ${LAMMPS_SOURCE_DIR}/cmake/CMakeLists.txt")
  endif()
  file(WRITE "${GRIDDEM_LAMMPS_TREE}/cmake/CMakeLists.txt" "${_lists}")
  file(WRITE "${_stamp}" "${_stage_key}")
endif()

# The package folder is a symbolic link, so editing src/PKG-GRIDDEM needs no re-staging.
file(CREATE_LINK "${PROJECT_SOURCE_DIR}/src/PKG-GRIDDEM" "${GRIDDEM_LAMMPS_TREE}/src/GRIDDEM" SYMBOLIC)

# Kokkos styles (src/PKG-GRIDDEM/kokkos/*_kokkos.{h,cpp}): with PKG_KOKKOS on, each file is linked
# into the staged src/KOKKOS, where LAMMPS's KOKKOS.cmake finds pair_<name>_kokkos.h next to the
# style pair_<name>.h of an enabled package (RegisterStylesExt) and compiles its .cpp. Without
# KOKKOS, links left by an earlier configure are removed so the staged tree matches the options.
file(GLOB _griddem_kk_staged LIST_DIRECTORIES false "${GRIDDEM_LAMMPS_TREE}/src/KOKKOS/*griddem*")
foreach(_f ${_griddem_kk_staged})
  if(IS_SYMLINK "${_f}")
    file(REMOVE "${_f}")
  endif()
endforeach()
if(PKG_KOKKOS)
  file(GLOB _griddem_kk_files CONFIGURE_DEPENDS
    "${PROJECT_SOURCE_DIR}/src/PKG-GRIDDEM/kokkos/*.h" "${PROJECT_SOURCE_DIR}/src/PKG-GRIDDEM/kokkos/*.cpp")
  foreach(_f ${_griddem_kk_files})
    get_filename_component(_name "${_f}" NAME)
    file(CREATE_LINK "${_f}" "${GRIDDEM_LAMMPS_TREE}/src/KOKKOS/${_name}" SYMBOLIC)
  endforeach()
endif()
