# plslam_add_module(NAME SOURCES ... DEPS <plslam modules> LIBS <external targets>)
#
# One shared library per module. Modules are linked with --no-undefined so a module
# that uses another module's symbols without declaring it fails to link, and the
# includes of every module are checked against its declared DEPS at configure time,
# so a wrong dependency fails the build rather than creeping in.
set(PLSLAM_MODULES "" CACHE INTERNAL "")

add_library(plslam_warnings INTERFACE)
target_compile_options(plslam_warnings INTERFACE -Wall -Wextra $<IF:$<CXX_COMPILER_ID:GNU>,-Wshadow=local,-Wshadow> -Wnon-virtual-dtor)
if(PLSLAM_WERROR)
  target_compile_options(plslam_warnings INTERFACE -Werror)
endif()

function(plslam_add_module name)
  cmake_parse_arguments(M "" "" "SOURCES;DEPS;LIBS" ${ARGN})
  add_library(plslam_${name} SHARED ${M_SOURCES})
  target_include_directories(plslam_${name} PUBLIC ${PROJECT_SOURCE_DIR}/src)
  set(deps "")
  foreach(d ${M_DEPS})
    list(APPEND deps plslam_${d})
  endforeach()
  target_link_libraries(plslam_${name} PUBLIC ${deps} ${M_LIBS} PRIVATE plslam_warnings)
  if(PLSLAM_NO_UNDEFINED OR NOT DEFINED PLSLAM_NO_UNDEFINED)
    target_link_options(plslam_${name} PRIVATE -Wl,--no-undefined)
  endif()
  set_target_properties(plslam_${name} PROPERTIES OUTPUT_NAME plslam_${name})

  # Include check: "module/header.h" may name only this module or a declared dependency
  # (transitively declared ones count).
  set(allowed ${name})
  foreach(d ${M_DEPS})
    list(APPEND allowed ${d})
    get_property(sub GLOBAL PROPERTY PLSLAM_ALLOWED_${d})
    list(APPEND allowed ${sub})
  endforeach()
  list(REMOVE_DUPLICATES allowed)
  set_property(GLOBAL PROPERTY PLSLAM_ALLOWED_${name} ${allowed})
  file(GLOB files ${CMAKE_CURRENT_SOURCE_DIR}/*.h ${CMAKE_CURRENT_SOURCE_DIR}/*.cpp)
  foreach(f ${files})
    file(STRINGS ${f} lines REGEX "^#include \"[a-z_]+/")
    foreach(line ${lines})
      string(REGEX REPLACE "^#include \"([a-z_]+)/.*" "\\1" inc "${line}")
      list(FIND allowed ${inc} found)
      if(found EQUAL -1)
        message(FATAL_ERROR "Module '${name}' includes '${inc}/' in ${f}, but '${inc}' is not among its dependencies (${allowed}).")
      endif()
    endforeach()
  endforeach()
  set(PLSLAM_MODULES ${PLSLAM_MODULES} ${name} CACHE INTERNAL "")
endfunction()
