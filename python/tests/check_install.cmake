# Installs the `python` component of the build BUILD_DIR into a fresh prefix PREFIX and
# imports dmbd from PREFIX/SITE with the interpreter PYTHON (cmake -P; CTest
# Python.ImportFromInstallPrefix).
file(REMOVE_RECURSE ${PREFIX})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${PREFIX} --component python
                RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "cmake --install --component python failed (${result})")
endif()
file(MAKE_DIRECTORY ${PREFIX}/empty)
execute_process(
  COMMAND ${CMAKE_COMMAND} -E env PYTHONPATH=${PREFIX}/${SITE} PYTHONDONTWRITEBYTECODE=1
          ${PYTHON} -c "import sys, dmbd; assert dmbd.__file__.startswith(sys.argv[1]), dmbd.__file__; print(dmbd.__file__, dmbd.__version__, dmbd.poles(dmbd.tf('1/(s+2)')))"
          ${PREFIX}/${SITE}/dmbd
  WORKING_DIRECTORY ${PREFIX}/empty
  RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "import dmbd from ${PREFIX}/${SITE} failed (${result})")
endif()
