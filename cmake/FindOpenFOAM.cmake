# Finds Debian's OpenFOAM v1912 libraries and the include tree made by scripts/deps.sh from
# Debian's source package of the same version. Defines OpenFOAM::OpenFOAM (headers, flags, libs)
# and OpenFOAM_VERSION. The flags are the ones wmake uses for a double-precision, 32-bit-label
# linux64Gcc build, which is how Debian built the libraries.
set(OpenFOAM_HEADERS_DIR "$ENV{MIXLOAD_OPENFOAM_HEADERS}")
if(NOT OpenFOAM_HEADERS_DIR)
  set(OpenFOAM_HEADERS_DIR /opt/mixload/openfoam-headers)
endif()

find_file(OpenFOAM_VERSION_FILE .version PATHS ${OpenFOAM_HEADERS_DIR} NO_DEFAULT_PATH)
find_library(OpenFOAM_LIBRARY OpenFOAM PATHS /usr/lib NO_DEFAULT_PATH)
find_library(OpenFOAM_finiteVolume_LIBRARY finiteVolume PATHS /usr/lib NO_DEFAULT_PATH)
find_library(OpenFOAM_meshTools_LIBRARY meshTools PATHS /usr/lib NO_DEFAULT_PATH)
find_library(OpenFOAM_transport_LIBRARY incompressibleTransportModels PATHS /usr/lib NO_DEFAULT_PATH)
find_program(OpenFOAM_INTERFOAM interFoam)
# What interFoam links, to build mixload's own copy of the solver (fullcfd/solver).
set(_of_solver_libs fvOptions sampling dynamicFvMesh interfaceProperties
    immiscibleIncompressibleTwoPhaseMixture turbulenceModels incompressibleTurbulenceModels
    waveModels Pstream)
set(OpenFOAM_SOLVER_LIBRARIES "")
foreach(l IN LISTS _of_solver_libs)
  find_library(OpenFOAM_${l}_LIBRARY ${l} PATHS /usr/lib NO_DEFAULT_PATH)
  list(APPEND OpenFOAM_SOLVER_LIBRARIES ${OpenFOAM_${l}_LIBRARY})
endforeach()
find_file(OpenFOAM_INTERFOAM_SOURCE interFoam.C PATHS ${OpenFOAM_HEADERS_DIR}/solvers/interFoam
          NO_DEFAULT_PATH)

if(OpenFOAM_VERSION_FILE)
  file(READ ${OpenFOAM_VERSION_FILE} OpenFOAM_VERSION)
  string(STRIP "${OpenFOAM_VERSION}" OpenFOAM_VERSION)
endif()

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(OpenFOAM
  REQUIRED_VARS OpenFOAM_VERSION_FILE OpenFOAM_LIBRARY OpenFOAM_finiteVolume_LIBRARY
                OpenFOAM_meshTools_LIBRARY OpenFOAM_transport_LIBRARY OpenFOAM_INTERFOAM
                OpenFOAM_INTERFOAM_SOURCE OpenFOAM_Pstream_LIBRARY
  VERSION_VAR OpenFOAM_VERSION)

if(OpenFOAM_FOUND AND NOT TARGET OpenFOAM::OpenFOAM)
  set(_of_dirs OpenFOAM OSspecific/POSIX finiteVolume meshTools
               transportModels/incompressible transportModels/twoPhaseMixture)
  set(_of_includes "")
  foreach(d IN LISTS _of_dirs)
    list(APPEND _of_includes ${OpenFOAM_HEADERS_DIR}/${d})
  endforeach()
  add_library(OpenFOAM::OpenFOAM INTERFACE IMPORTED)
  set_target_properties(OpenFOAM::OpenFOAM PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${_of_includes}"
    INTERFACE_COMPILE_DEFINITIONS "OPENFOAM=1912;WM_DP;WM_LABEL_SIZE=32;NoRepository"
    # -O2 after the build type's -O3: compiled at -O3 by Debian's GCC 12, interFoam diverges on
    # meshes whose faces are not aligned with the axes (as Debian's own -O3 binary does), while
    # the same source at -O2 runs them. Everything compiled against OpenFOAM's templates
    # (solver, viscosity models, function objects) therefore builds at -O2.
    INTERFACE_COMPILE_OPTIONS "-O2;-m64;-ftemplate-depth-100;-Wno-old-style-cast;-Wno-unused-parameter"
    INTERFACE_LINK_LIBRARIES
      "${OpenFOAM_LIBRARY};${OpenFOAM_finiteVolume_LIBRARY};${OpenFOAM_meshTools_LIBRARY};${OpenFOAM_transport_LIBRARY}")
endif()
