# Where the model kernels come from.
#
# With Python 3 and the pinned sympy, the kernels are regenerated from derive/
# into the build tree (build/generated) whenever a file of derive/ changes, and
# the library is built from them.  Only what changed is derived
# (derive/generate.py): when derive/ has the digest that the committed
# generated/DIGESTS records, generated/ is copied and no sympy runs; else a
# model whose inputs are unchanged is taken from derive/.cache or generated/,
# and only the others are derived (one log line each, with its time).
# -DUSM_DERIVE_ALL=ON derives every model from scratch instead.  The test
# `generated_current` fails if the committed generated/ differs from the
# build's, `generated_in_sync` if it differs from a derivation from scratch.
# Without sympy the committed generated/ is compiled as it is.
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
  # Only the pinned sympy reproduces the committed generated/ byte for byte
  # (derive/generate.py, PINNED_SYMPY).
  if(_sympy_rc EQUAL 0 AND USM_SYMPY_VERSION VERSION_EQUAL 1.11.1)
    set(USM_HAVE_SYMPY ON)
  endif()
endif()
option(USM_REGENERATE "Regenerate the kernels from derive/ at build time" ${USM_HAVE_SYMPY})
if(USM_REGENERATE AND NOT USM_HAVE_SYMPY)
  message(FATAL_ERROR "USM_REGENERATE needs the pinned sympy 1.11.1 (Debian's /usr/bin/python3 "
                      "with python3-sympy); ${USM_PYTHON} has sympy '${USM_SYMPY_VERSION}'")
endif()

option(USM_DERIVE_ALL "Derive every model from scratch at build time (no cache, nothing from generated/)" OFF)

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
  # generate.py derives only the models whose inputs changed (nothing when
  # derive/ matches generated/DIGESTS) and rewrites only the files whose text
  # changed, so that only their objects are rebuilt; the stamp records the run.
  set(_stamp ${PROJECT_BINARY_DIR}/generated.stamp)
  set(_derive_all "")
  if(USM_DERIVE_ALL)
    set(_derive_all --no-cache --no-reuse)
  endif()
  # rewritten only when the option changes: turning it on derives again
  file(CONFIGURE OUTPUT ${PROJECT_BINARY_DIR}/generate_options.txt CONTENT "${_derive_all}\n")
  add_custom_command(
    OUTPUT ${_stamp}
    BYPRODUCTS ${_outs}
    COMMAND ${USM_PYTHON} ${USM_DERIVE_DIR}/generate.py --out ${USM_GENERATED_DIR}
            --committed ${USM_COMMITTED_GENERATED_DIR} ${_derive_all} --stamp ${_stamp}
    DEPENDS ${USM_DERIVE_INPUTS} ${USM_COMMITTED_GENERATED_DIR}/DIGESTS
            ${PROJECT_BINARY_DIR}/generate_options.txt
    COMMENT "Deriving the model kernels that changed (derive/ -> build/generated)"
    VERBATIM)
  add_custom_target(usm_kernels_generated DEPENDS ${_stamp})
  # The committed generated/ from the files the build derived (no second derivation).
  add_custom_target(generate
    COMMAND ${CMAKE_COMMAND} -E copy_if_different ${_outs} ${USM_COMMITTED_GENERATED_DIR}
    DEPENDS ${_stamp}
    COMMENT "Rewriting the committed generated/ from derive/ (the build's derived files)"
    VERBATIM)
else()
  message(STATUS "usm: building the committed kernels in generated/ (no sympy)")
  set(USM_GENERATED_DIR ${USM_COMMITTED_GENERATED_DIR})
endif()

# The equations documents (usm_equations.c) are not part of libusm: only the
# command links them (runtime/CMakeLists.txt, USM_EQUATIONS_SOURCES).
set(USM_GENERATED_SOURCES "")
set(USM_EQUATIONS_SOURCES "")
foreach(f IN LISTS USM_GENERATED_NAMES)
  if(f STREQUAL "usm_equations.c")
    list(APPEND USM_EQUATIONS_SOURCES ${USM_GENERATED_DIR}/${f})
  elseif(f MATCHES "\\.c$")
    list(APPEND USM_GENERATED_SOURCES ${USM_GENERATED_DIR}/${f})
  endif()
endforeach()
