# Where the model kernels come from.
#
# With Python 3 and sympy, the kernels are regenerated from derive/ into the
# build tree whenever a file of derive/ changes, and the library is built from
# them; the test `generated_in_sync` then fails if the committed generated/
# differs.  Without sympy the committed generated/ is compiled as it is.
# `cmake --build build --target generate` rewrites the committed generated/.

set(USM_DERIVE_DIR ${PROJECT_SOURCE_DIR}/derive)
set(USM_COMMITTED_GENERATED_DIR ${PROJECT_SOURCE_DIR}/generated)
# Debian's interpreter first: its python3-sympy is the pinned generator.
find_program(USM_PYTHON NAMES python3 PATHS /usr/bin NO_DEFAULT_PATH)
if(NOT USM_PYTHON)
  find_program(USM_PYTHON NAMES python3)
endif()
set(USM_HAVE_SYMPY OFF)
if(USM_PYTHON)
  execute_process(COMMAND ${USM_PYTHON} -c "import sympy; print(sympy.__version__)"
                  OUTPUT_VARIABLE USM_SYMPY_VERSION RESULT_VARIABLE _sympy_rc
                  OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(_sympy_rc EQUAL 0)
    set(USM_HAVE_SYMPY ON)
  endif()
endif()
option(USM_REGENERATE "Regenerate the kernels from derive/ at build time" ${USM_HAVE_SYMPY})
if(USM_REGENERATE AND NOT USM_HAVE_SYMPY)
  message(FATAL_ERROR "USM_REGENERATE needs python3 with sympy (Debian: python3-sympy)")
endif()

file(GLOB_RECURSE USM_DERIVE_INPUTS CONFIGURE_DEPENDS ${USM_DERIVE_DIR}/*.py)
if(USM_REGENERATE)
  # The generator says which files it writes (a new variant adds some);
  # variants.py changing re-runs this configure step.
  execute_process(COMMAND ${USM_PYTHON} ${USM_DERIVE_DIR}/generate.py --list
                  OUTPUT_VARIABLE USM_GENERATED_NAMES OUTPUT_STRIP_TRAILING_WHITESPACE
                  RESULT_VARIABLE _list_rc)
  if(NOT _list_rc EQUAL 0)
    message(FATAL_ERROR "derive/generate.py --list failed")
  endif()
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${USM_DERIVE_DIR}/variants.py)
else()
  file(GLOB USM_GENERATED_NAMES CONFIGURE_DEPENDS RELATIVE ${USM_COMMITTED_GENERATED_DIR}
       ${USM_COMMITTED_GENERATED_DIR}/*.c ${USM_COMMITTED_GENERATED_DIR}/*.h
       ${USM_COMMITTED_GENERATED_DIR}/*.md ${USM_COMMITTED_GENERATED_DIR}/*.tex)
endif()
list(SORT USM_GENERATED_NAMES)

if(USM_REGENERATE)
  message(STATUS "usm: kernels regenerated from derive/ with sympy ${USM_SYMPY_VERSION} (${USM_PYTHON})")
  set(USM_GENERATED_DIR ${PROJECT_BINARY_DIR}/generated)
  set(_outs "")
  foreach(f IN LISTS USM_GENERATED_NAMES)
    list(APPEND _outs ${USM_GENERATED_DIR}/${f})
  endforeach()
  add_custom_command(
    OUTPUT ${_outs}
    COMMAND ${USM_PYTHON} ${USM_DERIVE_DIR}/generate.py --quiet --out ${USM_GENERATED_DIR}
    DEPENDS ${USM_DERIVE_INPUTS}
    COMMENT "Deriving the model kernels (derive/ -> build/generated)"
    VERBATIM)
  add_custom_target(usm_kernels_generated DEPENDS ${_outs})
  add_custom_target(generate
    COMMAND ${USM_PYTHON} ${USM_DERIVE_DIR}/generate.py --out ${USM_COMMITTED_GENERATED_DIR}
    COMMENT "Rewriting the committed generated/ from derive/"
    VERBATIM)
else()
  message(STATUS "usm: building the committed kernels in generated/ (no sympy)")
  set(USM_GENERATED_DIR ${USM_COMMITTED_GENERATED_DIR})
endif()

set(USM_GENERATED_SOURCES "")
foreach(f IN LISTS USM_GENERATED_NAMES)
  if(f MATCHES "\\.c$")
    list(APPEND USM_GENERATED_SOURCES ${USM_GENERATED_DIR}/${f})
  endif()
endforeach()
