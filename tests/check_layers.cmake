# The layer rule (ARCHITECTURE.md, "Layers"): a file of host/ includes only files of its own folder and
# of the folders below it in PDMESH_LAYERS. Run by ctest (test `layer_order`):
#   cmake -DHOST_DIR=<repo>/host [-DPYTHON_DIR=<repo>/python/src] -P tests/check_layers.cmake
# A layer is a folder of host/ (`core`) or a subfolder (`app/config`): a folder split into layers has
# no files of its own, and a file of it, or an include of it, outside its subfolders is refused.
# With PYTHON_DIR, the binding's files are checked as a layer just above app/pipeline (they drive the
# pipeline, never the command line), except PYTHON_CLI_FILES, whose job is to run the command line.
# Fails naming every include against the order (file, line, included file, both layers), and every
# folder that has no place in the order (a new folder must be given one here).
cmake_minimum_required(VERSION 3.20)

# Lowest first. main is host/main.cpp.
set(PDMESH_LAYERS core geometry spacing nodes mesh layers io init motion cleanup sim render opencl
                  app/config app/pipeline app/bench app/cli main)
set(PYTHON_LAYER app/pipeline)   # the highest layer the binding may include
set(PYTHON_CLI_FILES bind_cli.cpp)

if(NOT HOST_DIR OR NOT IS_DIRECTORY "${HOST_DIR}")
  message(FATAL_ERROR "check_layers: HOST_DIR='${HOST_DIR}' is not a directory")
endif()
if(PYTHON_DIR AND NOT IS_DIRECTORY "${PYTHON_DIR}")
  message(FATAL_ERROR "check_layers: PYTHON_DIR='${PYTHON_DIR}' is not a directory")
endif()

# The folders split into layers (app).
set(split_folders "")
foreach(layer IN LISTS PDMESH_LAYERS)
  if(layer MATCHES "^([^/]+)/")
    list(APPEND split_folders "${CMAKE_MATCH_1}")
  endif()
endforeach()
list(REMOVE_DUPLICATES split_folders)

# The layer of a path under host/ ("app/config/case_file.hpp" -> app/config, "core/vec2.hpp" -> core):
# its subfolder when its folder is split, else its folder; "" when it has none, "-" for a file of a
# split folder outside its subfolders.
function(layer_of path out)
  set(layer "")
  if(path MATCHES "^([^/]+)/")
    set(folder "${CMAKE_MATCH_1}")
    if(folder IN_LIST split_folders)
      set(layer "-")
      if(path MATCHES "^([^/]+/[^/]+)/" AND CMAKE_MATCH_1 IN_LIST PDMESH_LAYERS)
        set(layer "${CMAKE_MATCH_1}")
      endif()
    else()
      set(layer "${folder}")
    endif()
  endif()
  set(${out} "${layer}" PARENT_SCOPE)
endfunction()

set(violations "")
set(checked 0)

# Checks the includes of `file` (shown as `shown`) against the layer `own` (a name in PDMESH_LAYERS).
macro(check_includes file shown own)
  list(FIND PDMESH_LAYERS "${own}" own_rank)
  file(STRINGS "${file}" lines)
  set(line_no 0)
  foreach(line IN LISTS lines)
    math(EXPR line_no "${line_no} + 1")
    if(NOT line MATCHES "^[ \t]*#[ \t]*include[ \t]*\"([^\"]+)\"")
      continue()
    endif()
    set(included "${CMAKE_MATCH_1}")
    math(EXPR checked "${checked} + 1")
    if(included MATCHES "^\\.\\./|/\\.\\./")
      string(APPEND violations "  ${shown}:${line_no}: includes \"${included}\": name a header by its folder under host/, not by '..'\n")
      continue()
    endif()
    layer_of("${included}" target)
    if(target STREQUAL "")
      continue()  # a file of the same folder
    endif()
    if(target STREQUAL "-")
      string(APPEND violations "  ${shown}:${line_no}: includes \"${included}\", which is in no layer of its folder\n")
      continue()
    endif()
    list(FIND PDMESH_LAYERS "${target}" target_rank)
    if(target_rank EQUAL -1)
      continue()  # not a folder of host/ (a library's header written with quotes)
    endif()
    if(target_rank GREATER own_rank)
      string(APPEND violations "  ${shown}:${line_no}: includes \"${included}\": ${own} may not include ${target} (above it)\n")
    endif()
  endforeach()
endmacro()

file(GLOB_RECURSE sources RELATIVE "${HOST_DIR}" "${HOST_DIR}/*.hpp" "${HOST_DIR}/*.cpp" "${HOST_DIR}/*.h")
list(SORT sources)
foreach(rel IN LISTS sources)
  layer_of("${rel}" own)
  if(own STREQUAL "")
    set(own main)
  elseif(own STREQUAL "-")
    string(REGEX MATCH "^[^/]+" folder "${rel}")
    string(APPEND violations "  ${rel}: a file of '${folder}' outside its layers (its subfolders in tests/check_layers.cmake)\n")
    continue()
  endif()
  if(NOT own IN_LIST PDMESH_LAYERS)
    string(APPEND violations "  ${rel}: folder '${own}' has no place in the layer order (tests/check_layers.cmake)\n")
    continue()
  endif()
  check_includes("${HOST_DIR}/${rel}" "${rel}" "${own}")
endforeach()
list(LENGTH sources files)

if(PYTHON_DIR)
  file(GLOB python_sources RELATIVE "${PYTHON_DIR}" "${PYTHON_DIR}/*.hpp" "${PYTHON_DIR}/*.cpp" "${PYTHON_DIR}/*.h")
  list(SORT python_sources)
  foreach(rel IN LISTS python_sources)
    if(rel IN_LIST PYTHON_CLI_FILES)
      set(own main)
    else()
      set(own ${PYTHON_LAYER})
    endif()
    check_includes("${PYTHON_DIR}/${rel}" "python/src/${rel}" "${own}")
  endforeach()
  list(LENGTH python_sources python_files)
  math(EXPR files "${files} + ${python_files}")
endif()

list(JOIN PDMESH_LAYERS " < " order)
if(violations)
  message(FATAL_ERROR "Includes against the layer order ${order}:\n${violations}")
endif()
message(STATUS "layer order ${order}: ${files} files, ${checked} includes, none against it")
