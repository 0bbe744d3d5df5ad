# Errors on several MPI ranks end every rank with a one-rank run's exit status and a message that
# names the rank (docs/parallel.md):
#   cmake -DADAMSS=... -DMPIEXEC=... -DSCENE=... -DOUT=... -P check_errors.cmake
# 1. An output "folder" that is a file: only rank 0 opens the folder, so only rank 0 fails (exit 4,
#    I/O error) while rank 1 is already running; the job must still end (ctest's TIMEOUT catches a
#    rank left waiting in a collective solve).
# 2. A missing scene file: every rank fails alike (exit 2).
# 3. A command other than run (serial only) refuses to start on several ranks (exit 2).
cmake_minimum_required(VERSION 3.20)
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})
file(WRITE ${OUT}/a-file "not a folder\n")

function(expect what code pattern)
  execute_process(COMMAND ${MPIEXEC} --oversubscribe -np 2 ${ADAMSS} ${ARGN}
                  RESULT_VARIABLE rc ERROR_VARIABLE err OUTPUT_VARIABLE out TIMEOUT 120)
  if(NOT rc EQUAL code)
    message(FATAL_ERROR "${what}: exit ${rc}, expected ${code}; stderr:\n${err}")
  endif()
  if(NOT err MATCHES "${pattern}")
    message(FATAL_ERROR "${what}: stderr does not match '${pattern}':\n${err}")
  endif()
  message(STATUS "${what}: exit ${rc} as expected")
endfunction()

expect("output folder is a file" 4 "I/O error \\(MPI rank 0 of 2\\): cannot create the output folder" run ${SCENE}
       -o ${OUT}/a-file -q)
expect("missing scene" 2 "error \\(MPI rank [01] of 2\\): cannot open scene file" run ${OUT}/missing.yaml -o
       ${OUT}/run -q)
expect("serial command" 2 "only 'adamss run' runs on several MPI ranks" info ${SCENE})
