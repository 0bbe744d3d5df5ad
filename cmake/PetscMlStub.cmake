# A stand-in for Trilinos ML, the library behind PETSc's `-pc_type ml`, which adamss never uses.
#
# Debian's libpetsc_real needs libtrilinos_ml, and loading that pulls in the Trilinos stack
# (Epetra, Teuchos, Ifpack, Amesos, AztecOO ...; 18 libraries bound at load time, ~36 000
# symbol relocations): 27-33 ms of every process's start-up on this machine, half of what PETSc
# costs to load (an empty program linked against libpetsc_real: 73 ms, 44 ms with the stand-in;
# bench/README.md). The stand-in is a small shared library with the same SONAME that defines the
# ML symbols libpetsc_real refers to; the dynamic loader maps it as a direct dependency of the
# executable and then takes it for libpetsc_real's dependency of that name, so the real ML and
# the libraries only it needs are never opened. Each stand-in function stops the process with a
# message naming the call; adamss refuses `-pc_type ml` itself before PETSc gets there
# (solver/time/petsc/petsc_env.cpp).
#
# The symbol list is read from the installed libraries at configure time (nm -D): the functions
# libpetsc_real leaves undefined that libtrilinos_ml defines. When PETSc does not need ML, when
# a symbol is versioned or not a function or plain data, or with -DADAMSS_PETSC_ML_STUB=OFF
# (which links the real ML and makes `-pc_type ml` work), nothing is replaced.
#
# Defines ADAMSS_PETSC_ML_STUB_TARGET (the target to link, empty when not used).

option(ADAMSS_PETSC_ML_STUB "Replace Trilinos ML (PETSc's -pc_type ml) by a stand-in: 30 ms faster start-up" ON)
set(ADAMSS_PETSC_ML_STUB_TARGET "")

function(adamss_petsc_ml_stub)
  if(NOT ADAMSS_PETSC_ML_STUB)
    return()
  endif()
  find_library(ADAMSS_PETSC_SHARED_LIBRARY NAMES petsc_real petsc HINTS ${PETSC_LIBRARY_DIRS} NO_DEFAULT_PATH)
  if(NOT ADAMSS_PETSC_SHARED_LIBRARY OR NOT CMAKE_NM OR NOT CMAKE_OBJDUMP)
    message(STATUS "PETSc ML stand-in: not used (libpetsc, nm or objdump not found)")
    return()
  endif()
  execute_process(COMMAND ${CMAKE_OBJDUMP} -p ${ADAMSS_PETSC_SHARED_LIBRARY} OUTPUT_VARIABLE dyn RESULT_VARIABLE rc)
  string(REGEX MATCH "NEEDED +(libtrilinos_ml\\.so[.0-9]*)" needed "${dyn}")
  if(NOT rc EQUAL 0 OR NOT needed)
    message(STATUS "PETSc ML stand-in: not used (libpetsc does not need Trilinos ML)")
    return()
  endif()
  set(soname ${CMAKE_MATCH_1})
  find_library(ADAMSS_TRILINOS_ML_LIBRARY NAMES ${soname} trilinos_ml)
  if(NOT ADAMSS_TRILINOS_ML_LIBRARY)
    message(STATUS "PETSc ML stand-in: not used (${soname} not found)")
    return()
  endif()
  execute_process(COMMAND ${CMAKE_NM} -D --undefined-only ${ADAMSS_PETSC_SHARED_LIBRARY} OUTPUT_VARIABLE undef)
  execute_process(COMMAND ${CMAKE_NM} -D -S --defined-only ${ADAMSS_TRILINOS_ML_LIBRARY} OUTPUT_VARIABLE def)
  # ML's exported symbols: name -> "type size" (nm -D -S: "address [size] type name[@version]")
  string(REGEX MATCHALL "[^\n]+" def_lines "${def}")
  set(def_names "")
  set(def_kinds "")
  foreach(line IN LISTS def_lines)
    if(line MATCHES "^[0-9a-f]+ ([0-9a-f]+ )?([A-Za-z]) ([^ @]+)(@.*)?$")
      list(APPEND def_names ${CMAKE_MATCH_3})
      string(STRIP "${CMAKE_MATCH_1}" size)
      if(CMAKE_MATCH_4)
        list(APPEND def_kinds "V:")  # versioned in ML: a stand-in could not match it
      else()
        list(APPEND def_kinds "${CMAKE_MATCH_2}:${size}")
      endif()
    endif()
  endforeach()
  string(REGEX MATCHALL "U [^\n]+" undef "${undef}")
  set(body "")
  set(count 0)
  foreach(u IN LISTS undef)
    string(SUBSTRING "${u}" 2 -1 sym)
    string(REGEX REPLACE "@.*" "" bare "${sym}")
    list(FIND def_names ${bare} at)
    if(at LESS 0)
      continue()
    endif()
    if(NOT sym STREQUAL bare)
      message(STATUS "PETSc ML stand-in: not used (${sym} is versioned)")
      return()
    endif()
    list(GET def_kinds ${at} kind)
    string(REGEX MATCH "^([A-Za-z]):(.*)$" kind "${kind}")
    set(type ${CMAKE_MATCH_1})
    set(size ${CMAKE_MATCH_2})
    if(type MATCHES "^[TW]$")
      string(APPEND body "ADAMSS_ML_STUB_FUNCTION(${sym})\n")
    elseif(type MATCHES "^[BD]$" AND size)
      string(APPEND body "ADAMSS_ML_STUB_DATA(${sym}, 0x${size})\n")
    else()
      message(STATUS "PETSc ML stand-in: not used (${sym} has symbol type ${type})")
      return()
    endif()
    math(EXPR count "${count} + 1")
  endforeach()
  if(count EQUAL 0)
    message(STATUS "PETSc ML stand-in: not used (libpetsc refers to no ML symbol)")
    return()
  endif()
  set(dir ${CMAKE_BINARY_DIR}/petsc_ml_stub)
  configure_file(${PROJECT_SOURCE_DIR}/cmake/petsc_ml_stub.cpp.in ${dir}/petsc_ml_stub.cpp @ONLY)
  file(WRITE ${dir}/petsc_ml_stub_symbols.inc "${body}")
  add_library(adamss_petsc_ml_stub SHARED ${dir}/petsc_ml_stub.cpp)
  target_include_directories(adamss_petsc_ml_stub PRIVATE ${dir})
  # The file name is the SONAME: the executables' RUNPATH finds it under that name.
  set_target_properties(adamss_petsc_ml_stub PROPERTIES PREFIX "" OUTPUT_NAME ${soname} SUFFIX "" NO_SONAME ON
                        LIBRARY_OUTPUT_DIRECTORY ${dir})
  target_link_options(adamss_petsc_ml_stub PRIVATE "LINKER:-soname,${soname}")
  message(STATUS "PETSc ML stand-in: ${soname} with ${count} symbols (-DADAMSS_PETSC_ML_STUB=OFF for the real one)")
  set(ADAMSS_PETSC_ML_STUB_TARGET adamss_petsc_ml_stub PARENT_SCOPE)
endfunction()

adamss_petsc_ml_stub()
