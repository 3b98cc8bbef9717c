# Included by ros2/*/CMakeLists.txt after their find_package calls (spcotmhp's own file).
# The message wheels' exported Python targets name the include folders of the machine that built them
# (/opt/python/cp311-cp311/...: Python's and NumPy's headers); CMake refuses a target naming a folder that does
# not exist. Every such folder is replaced by this Python's (or NumPy's) headers; an include folder that exists is
# kept as it is.
find_package(Python3 REQUIRED COMPONENTS Interpreter Development NumPy)
get_property(_imported DIRECTORY PROPERTY IMPORTED_TARGETS)
foreach(_target IN LISTS _imported)
  get_target_property(_dirs ${_target} INTERFACE_INCLUDE_DIRECTORIES)
  if(NOT _dirs)
    continue()
  endif()
  set(_kept "")
  foreach(_dir IN LISTS _dirs)
    if(EXISTS "${_dir}" OR _dir MATCHES "^\\$<")
      list(APPEND _kept "${_dir}")
    elseif(_dir MATCHES "numpy")
      list(APPEND _kept ${Python3_NumPy_INCLUDE_DIRS})
    elseif(_dir MATCHES "include/python3")
      list(APPEND _kept ${Python3_INCLUDE_DIRS})
    else()
      message(FATAL_ERROR "${_target} names the include folder ${_dir}, which does not exist here")
    endif()
  endforeach()
  set_target_properties(${_target} PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${_kept}")
endforeach()
