# `cmake --build build --target equations-pdf`: the derived equations of every
# model as PDF (build/equations/usm_<model>_equations.pdf), typeset by pdflatex
# (Debian: texlive-latex-base texlive-latex-recommended) from the LaTeX that
# derive/ emits next to the kernels.
find_program(USM_PDFLATEX pdflatex)
if(USM_PDFLATEX)
  set(_pdfs "")
  foreach(f IN LISTS USM_GENERATED_NAMES)
    if(f MATCHES "^(.*)\\.tex$")
      set(_pdf ${PROJECT_BINARY_DIR}/equations/${CMAKE_MATCH_1}.pdf)
      add_custom_command(
        OUTPUT ${_pdf}
        COMMAND ${CMAKE_COMMAND} -E make_directory ${PROJECT_BINARY_DIR}/equations
        COMMAND ${USM_PDFLATEX} -interaction=nonstopmode -halt-on-error
                -output-directory ${PROJECT_BINARY_DIR}/equations ${USM_GENERATED_DIR}/${f}
        DEPENDS ${USM_GENERATED_DIR}/${f}
        COMMENT "Typesetting ${CMAKE_MATCH_1}.pdf"
        VERBATIM)
      list(APPEND _pdfs ${_pdf})
    endif()
  endforeach()
  add_custom_target(equations-pdf DEPENDS ${_pdfs})
  if(USM_REGENERATE)  # the .tex files are byproducts of the derivation
    add_dependencies(equations-pdf usm_kernels_generated)
  endif()
else()
  add_custom_target(equations-pdf
    COMMAND ${CMAKE_COMMAND} -E echo "equations-pdf needs pdflatex: apt-get install texlive-latex-base texlive-latex-recommended"
    COMMAND ${CMAKE_COMMAND} -E false)
endif()

# The equations documents are installed with the other documentation.
set(_docs "")
foreach(f IN LISTS USM_GENERATED_NAMES)
  if(f MATCHES "_equations\\.(md|tex)$")
    list(APPEND _docs ${USM_GENERATED_DIR}/${f})
  endif()
endforeach()
include(GNUInstallDirs)
install(FILES ${_docs} DESTINATION ${CMAKE_INSTALL_DOCDIR}/equations)
