# The layering check (ctest "layers"): a source file may include headers of its own folder and of
# the folders below it, never of one above. Run as
#   cmake -DROOT=<tree> -DLAYERS="solvers;continuation;..." -P CheckLayers.cmake
# with LAYERS lowest first (the top-level CMakeLists.txt's RUBCONT_LAYERS). Prints every violation
# as "<folder>/<file> includes <header>: <folder> is below <other>" and fails if there is one.
if(NOT ROOT OR NOT LAYERS)
  message(FATAL_ERROR "CheckLayers.cmake: pass -DROOT=<tree> -DLAYERS=<folders, lowest first>")
endif()
set(violations 0)
set(checked 0)
list(LENGTH LAYERS count)
foreach(layer IN LISTS LAYERS)
  list(FIND LAYERS ${layer} level)
  file(GLOB_RECURSE sources RELATIVE ${ROOT} ${ROOT}/${layer}/*.h ${ROOT}/${layer}/*.cpp
       ${ROOT}/${layer}/*.in)
  foreach(source IN LISTS sources)
    math(EXPR checked "${checked} + 1")
    file(STRINGS ${ROOT}/${source} includes REGEX "^[ \t]*#[ \t]*include[ \t]*\"[A-Za-z0-9_]+/")
    foreach(line IN LISTS includes)
      string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*\"([^\"]+)\".*$" "\\1" header "${line}")
      string(REGEX REPLACE "/.*$" "" folder "${header}")
      list(FIND LAYERS ${folder} other)
      if(other GREATER level)
        message(NOTICE "${source} includes ${header}: ${layer} is below ${folder}")
        math(EXPR violations "${violations} + 1")
      endif()
    endforeach()
  endforeach()
endforeach()
if(violations GREATER 0)
  message(FATAL_ERROR "${violations} include(s) go up the layers (${LAYERS})")
endif()
message(NOTICE "layers: ${checked} files in ${count} folders include only their own folder and those below (${LAYERS})")
