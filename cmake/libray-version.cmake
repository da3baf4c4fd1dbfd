# SPDX-License-Identifier: MIT
# libray-version.cmake -- libray's version for CMake, read from
# include/ray.h's RAY_VERSION_MAJOR, _MINOR and _PATCH, the one place it is
# set (the Makefile reads the same three lines).  Included by
# CMakeLists.txt; make version-test runs it as a script to compare:
#
#   cmake -DRAY_H=include/ray.h -P cmake/libray-version.cmake
#
# prints "libray-version: MAJOR.MINOR.PATCH".

function(libray_read_version header out)
  file(STRINGS "${header}" _lines
       REGEX "^#define RAY_VERSION_(MAJOR|MINOR|PATCH) +[0-9]+")
  set(_version "")
  foreach(_part MAJOR MINOR PATCH)
    set(_value "")
    foreach(_line IN LISTS _lines)
      if(_line MATCHES "^#define RAY_VERSION_${_part} +([0-9]+)")
        set(_value "${CMAKE_MATCH_1}")
      endif()
    endforeach()
    if(_value STREQUAL "")
      message(FATAL_ERROR "${header}: no #define RAY_VERSION_${_part}")
    endif()
    if(_version STREQUAL "")
      set(_version "${_value}")
    else()
      string(APPEND _version ".${_value}")
    endif()
  endforeach()
  set(${out} "${_version}" PARENT_SCOPE)
endfunction()

if(CMAKE_SCRIPT_MODE_FILE AND DEFINED RAY_H)
  libray_read_version("${RAY_H}" _v)
  message("libray-version: ${_v}")
endif()
