# The runtime refuses to compile against kernels of another generator major
# version.  cmake -DCC=compiler -DKERNELS_H=.../usm_kernels.h -DRUNTIME=runtime/
#                 -DWORK=scratch-dir -P version_mismatch.cmake
# Compiles runtime/core/version.c against the real usm_kernels.h (must succeed) and
# against a copy whose USM_GENERATOR_VERSION_MAJOR is one more (must fail,
# saying to regenerate).
foreach(v CC KERNELS_H RUNTIME WORK)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "version_mismatch.cmake: -D${v}=... missing")
  endif()
endforeach()

get_filename_component(_kernels_dir ${KERNELS_H} DIRECTORY)
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})

execute_process(COMMAND ${CC} -std=c11 -c ${RUNTIME}/core/version.c -o ${WORK}/ok.o
                        -I${RUNTIME}/include/usm -I${_kernels_dir}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "version.c does not compile with the real kernels:\n${out}")
endif()

file(READ ${KERNELS_H} text)
if(NOT text MATCHES "#define USM_GENERATOR_VERSION_MAJOR ([0-9]+)")
  message(FATAL_ERROR "${KERNELS_H}: no USM_GENERATOR_VERSION_MAJOR")
endif()
math(EXPR other "${CMAKE_MATCH_1} + 1")
string(REGEX REPLACE "#define USM_GENERATOR_VERSION_MAJOR [0-9]+"
       "#define USM_GENERATOR_VERSION_MAJOR ${other}" text "${text}")
file(WRITE ${WORK}/other/usm_kernels.h "${text}")

execute_process(COMMAND ${CC} -std=c11 -c ${RUNTIME}/core/version.c -o ${WORK}/bad.o
                        -I${RUNTIME}/include/usm -I${WORK}/other
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(rc EQUAL 0)
  message(FATAL_ERROR "version.c compiled against kernels of generator major version ${other}")
endif()
if(NOT out MATCHES "regenerate")
  message(FATAL_ERROR "refused, but without saying to regenerate:\n${out}")
endif()
message(STATUS "kernels of generator major version ${other} refused:\n${out}")
file(REMOVE_RECURSE ${WORK})
