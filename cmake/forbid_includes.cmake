# taskmatrix_forbid_includes(<what may be used> <include regex> [ALLOW <include regex>]): the
# layering enforced at configure time. Every .h and .cc under the calling folder is scanned; an
# #include whose path starts with a folder matched by <include regex> (e.g. "mujoco|ompl") stops
# the configure with the file, the include and what the folder may use instead. An include
# whose whole path matches the ALLOW regex is let through (a named exception, e.g. a header of
# plain data that has not moved out of a forbidden folder yet).
function(taskmatrix_forbid_includes allowed forbidden_folders)
  cmake_parse_arguments(PARSE_ARGV 2 arg "" "ALLOW" "")
  file(GLOB_RECURSE sources CONFIGURE_DEPENDS
       ${CMAKE_CURRENT_SOURCE_DIR}/*.h ${CMAKE_CURRENT_SOURCE_DIR}/*.cc)
  foreach(source ${sources})
    file(STRINGS ${source} forbidden
         REGEX "^[ \t]*#[ \t]*include[ \t]*[<\"](${forbidden_folders})/")
    if(forbidden AND arg_ALLOW)
      list(FILTER forbidden EXCLUDE REGEX "[<\"](${arg_ALLOW})[>\"]")
    endif()
    if(forbidden)
      message(FATAL_ERROR "${source}: ${forbidden}: ${allowed}")
    endif()
  endforeach()
endfunction()
