# Every third-party package adamss links, found the way that works on Debian 12
# (see docs/architecture.md, "Dependencies"). scripts/install-deps installs them.

find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(CLI11 REQUIRED)
find_package(fmt REQUIRED)
find_package(ZLIB REQUIRED)
find_package(MPI REQUIRED COMPONENTS C CXX)
find_package(yaml-cpp REQUIRED)

# CGAL 5.5 (header-only; Mesh_3 on labelled images needs the ImageIO component).
find_package(CGAL REQUIRED COMPONENTS ImageIO)

# PETSc 3.18 (real, OpenMPI): pkg-config; petsc.pc has no MPI include path, so link MPI::MPI_C too.
find_package(PkgConfig REQUIRED)
pkg_check_modules(PETSC REQUIRED IMPORTED_TARGET petsc)
find_package(OpenMP REQUIRED COMPONENTS CXX)
include(${CMAKE_CURRENT_LIST_DIR}/PetscMlStub.cmake)  # a stand-in for Trilinos ML: faster start-up

# HDF5: the OpenMPI flavour, the same MPI PETSc uses.
set(HDF5_PREFER_PARALLEL TRUE)
find_package(HDF5 REQUIRED COMPONENTS C)

# VTK: always name the components, otherwise VTK 9.1 asks for Qt.
find_package(VTK REQUIRED COMPONENTS CommonCore CommonDataModel IOXML IOXMLParser)

# nifti_clib: Debian's FindNIFTI looks in the wrong folder, so build the target here.
# Only libnifti2 (reads NIfTI-1 and NIfTI-2); never libniftiio beside it.
find_path(NIFTI2_INCLUDE_DIR nifti2_io.h PATH_SUFFIXES nifti REQUIRED)
find_library(NIFTI2_LIBRARY nifti2 REQUIRED)
find_library(ZNZ_LIBRARY znz REQUIRED)
if(NOT TARGET adamss_nifti2)
  add_library(adamss_nifti2 INTERFACE)
  target_include_directories(adamss_nifti2 SYSTEM INTERFACE ${NIFTI2_INCLUDE_DIR})
  target_link_libraries(adamss_nifti2 INTERFACE ${NIFTI2_LIBRARY} ${ZNZ_LIBRARY} ZLIB::ZLIB m)
  add_library(adamss::nifti2 ALIAS adamss_nifti2)
endif()

# MUMPS's single-precision driver (libmumps-dev, which PETSc's double-precision MUMPS comes with):
# the direct solver's single-precision factorisation (solver/time/petsc/single_precision_factor.hpp).
find_path(SMUMPS_INCLUDE_DIR smumps_c.h REQUIRED)
find_library(SMUMPS_LIBRARY smumps REQUIRED)
find_library(MUMPS_COMMON_LIBRARY mumps_common REQUIRED)
if(NOT TARGET adamss_smumps)
  add_library(adamss_smumps INTERFACE)
  target_include_directories(adamss_smumps SYSTEM INTERFACE ${SMUMPS_INCLUDE_DIR})
  target_link_libraries(adamss_smumps INTERFACE ${SMUMPS_LIBRARY} ${MUMPS_COMMON_LIBRARY} MPI::MPI_C)
  add_library(adamss::smumps ALIAS adamss_smumps)
endif()

# METIS (libmetis-dev): nested-dissection pivot orders for the single-precision factorisation
# (solver/time/petsc/nested_dissection.hpp); Debian's MUMPS is built without it.
find_path(METIS_INCLUDE_DIR metis.h REQUIRED)
find_library(METIS_LIBRARY metis REQUIRED)

# LZ4 (liblz4-dev): the frames' optional LZ4 compression (solver/run/results.hpp).
find_path(LZ4_INCLUDE_DIR lz4.h REQUIRED)
find_library(LZ4_LIBRARY lz4 REQUIRED)

if(ADAMSS_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
