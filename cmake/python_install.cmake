# `cmake --install build` (scripts/install.sh): the pieces a user runs from a
# fresh shell without any environment variables of ours.
#   rodcore (the compiled pybind11 module) -> the system Python's site directory,
#     so that `import rodcore` gives the compiled module and never the source
#     folder rodcore/ (which has no __init__.py: a real module anywhere on
#     sys.path wins over a namespace folder);
#   rodsim -> ${CMAKE_INSTALL_PREFIX}/bin (default /usr/local/bin).
# The Python packages (mdbridge, dna_models, dnarod) are installed by pip from
# pyproject.toml, as an editable install of the checkout.
include(GNUInstallDirs)

# Debian's /usr/bin/python3 puts locally installed packages in
# /usr/local/lib/python3.X/dist-packages (its posix_local scheme), apart from
# the directories apt manages.
if(NOT DNAROD_PYTHON_INSTALL_DIR)
  execute_process(
    COMMAND ${Python_EXECUTABLE} -c "import sysconfig; print(sysconfig.get_path('platlib'))"
    OUTPUT_VARIABLE _dnarod_platlib OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE _dnarod_rc)
  if(NOT _dnarod_rc EQUAL 0 OR NOT _dnarod_platlib)
    message(FATAL_ERROR "could not ask ${Python_EXECUTABLE} for its site directory; "
                        "set -DDNAROD_PYTHON_INSTALL_DIR=DIR")
  endif()
  # Relative to the install prefix when it lies under it (the default /usr/local), so
  # that `cmake --install build --prefix DIR` keeps everything inside DIR.
  string(FIND "${_dnarod_platlib}" "${CMAKE_INSTALL_PREFIX}/" _dnarod_at)
  if(_dnarod_at EQUAL 0)
    file(RELATIVE_PATH _dnarod_platlib ${CMAKE_INSTALL_PREFIX} ${_dnarod_platlib})
  endif()
  set(DNAROD_PYTHON_INSTALL_DIR ${_dnarod_platlib} CACHE PATH
      "where `cmake --install` puts the compiled rodcore module (relative: to the prefix)")
endif()

# Both are linked with their install RPATH (which keeps the library directories
# outside the system's, such as HDF5's serial one), so `cmake --install` copies
# them unchanged and tests/python/test_install.py can compare the installed
# files with the built ones byte for byte.
foreach(_dnarod_target rodcore_py rodsim)
  if(TARGET ${_dnarod_target})
    set_target_properties(${_dnarod_target} PROPERTIES
      BUILD_WITH_INSTALL_RPATH ON INSTALL_RPATH_USE_LINK_PATH ON)
  endif()
endforeach()

if(TARGET rodcore_py)
  install(TARGETS rodcore_py LIBRARY DESTINATION ${DNAROD_PYTHON_INSTALL_DIR} COMPONENT python)
endif()
if(TARGET rodsim)
  install(TARGETS rodsim RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT python)
endif()
