# SPDX-License-Identifier: MIT
# Fails when a page of the docs names a repository file or folder that does not exist, and
# lists each such name with its line. Run by ctest (docs_architecture_names_real_files, label
# docs), or by hand:
#   cmake -DSOURCE=. -DDOC=docs/architecture.md -P cmake/check_doc_paths.cmake
#
# What counts as a name, in the page's inline code spans (`...`; fenced blocks are skipped):
# - a span with a slash, made of letters, digits and . _ + - / only: a path from the repository
#   root (`core/src/world.cpp`); with a trailing slash it must be a folder (`gpu/src/exec/`);
#   an anchor (`docs/model.md#guards`) is dropped first;
# - a span without a slash that ends in a source or doc extension (`step.hpp`, `README.md`): a
#   file of that name at the root or anywhere under the repository's top-level folders.
# Spans such as `tumble::core`, `cmd_*.cpp` or `--pipeline cuda` are not names. Relative
# Markdown links ([x](model.md)) are checked too, from the page's folder.
cmake_minimum_required(VERSION 3.25)

if(NOT DEFINED SOURCE OR NOT DEFINED DOC)
  message(FATAL_ERROR "usage: cmake -DSOURCE=<repository root> -DDOC=<page, relative to it> -P check_doc_paths.cmake")
endif()
get_filename_component(SOURCE "${SOURCE}" ABSOLUTE)
set(_page "${SOURCE}/${DOC}")
if(NOT EXISTS "${_page}")
  message(FATAL_ERROR "${DOC}: no such page")
endif()
get_filename_component(_page_dir "${_page}" DIRECTORY)

# The page as a list of lines. Characters that CMake's lists treat specially (; [ ]) become
# spaces first: names never contain them, and a bracket would join lines.
file(READ "${_page}" _text)
string(REPLACE ";" " " _text "${_text}")
string(ASCII 1 _mark)  # marks "](" so that a link stays findable
string(REPLACE "](" "${_mark}(" _text "${_text}")
string(REPLACE "[" " " _text "${_text}")
string(REPLACE "]" " " _text "${_text}")
string(REPLACE "\n" ";" _lines "${_text}")

# Where a bare file name may live: the root and the top-level folders, build folders aside.
file(GLOB _top RELATIVE "${SOURCE}" "${SOURCE}/*" "${SOURCE}/.ci")
set(_roots "")
foreach(t IN LISTS _top)
  if(IS_DIRECTORY "${SOURCE}/${t}" AND NOT t MATCHES "^(build.*|\\.git)$")
    list(APPEND _roots "${t}")
  endif()
endforeach()

set(_path_re "^[A-Za-z0-9_.][A-Za-z0-9_.+-]*(/[A-Za-z0-9_.+-]+)*/?$")
set(_ext_re "\\.(cpp|hpp|h|cu|cuh|md|toml|sh|py|cmake|txt|in|stl)$")
set(_missing "")
set(_checked 0)
set(_fenced FALSE)
set(_n 0)
foreach(line IN LISTS _lines)
  math(EXPR _n "${_n} + 1")
  if(line MATCHES "^[ ]*```")
    if(_fenced)
      set(_fenced FALSE)
    else()
      set(_fenced TRUE)
    endif()
    continue()
  endif()
  if(_fenced)
    continue()
  endif()

  # Inline code spans.
  string(REGEX MATCHALL "`[^`]+`" _spans "${line}")
  foreach(span IN LISTS _spans)
    string(REGEX REPLACE "^`(.*)`$" "\\1" name "${span}")
    string(REGEX REPLACE "#[A-Za-z0-9_-]+$" "" name "${name}")
    if(NOT name MATCHES "${_path_re}")
      continue()
    endif()
    if(name MATCHES "/")
      math(EXPR _checked "${_checked} + 1")
      if(name MATCHES "/$")
        if(NOT IS_DIRECTORY "${SOURCE}/${name}")
          list(APPEND _missing "${DOC}:${_n}: ${name} (no such folder)")
        endif()
      elseif(NOT EXISTS "${SOURCE}/${name}")
        list(APPEND _missing "${DOC}:${_n}: ${name}")
      endif()
    elseif(name MATCHES "${_ext_re}")
      math(EXPR _checked "${_checked} + 1")
      set(_found FALSE)
      if(EXISTS "${SOURCE}/${name}" AND NOT IS_DIRECTORY "${SOURCE}/${name}")
        set(_found TRUE)
      else()
        foreach(r IN LISTS _roots)
          file(GLOB_RECURSE _hits "${SOURCE}/${r}/${name}")
          if(_hits)
            set(_found TRUE)
            break()
          endif()
        endforeach()
      endif()
      if(NOT _found)
        list(APPEND _missing "${DOC}:${_n}: ${name} (no file of that name in the repository)")
      endif()
    endif()
  endforeach()

  # Relative Markdown links, from the page's folder (web links and pure anchors aside).
  string(REGEX MATCHALL "${_mark}\\([^) ]+\\)" _links "${line}")
  foreach(link IN LISTS _links)
    string(REGEX REPLACE "^${_mark}\\((.*)\\)$" "\\1" target "${link}")
    string(REGEX REPLACE "#.*$" "" target "${target}")
    if(target STREQUAL "" OR target MATCHES "^[a-z]+:")
      continue()
    endif()
    math(EXPR _checked "${_checked} + 1")
    if(NOT EXISTS "${_page_dir}/${target}")
      list(APPEND _missing "${DOC}:${_n}: link ${target}")
    endif()
  endforeach()
endforeach()

if(_checked EQUAL 0)
  message(FATAL_ERROR "${DOC}: no repository name found: is this the right page?")
endif()
if(_missing)
  list(LENGTH _missing _count)
  string(REPLACE ";" "\n  " _list "${_missing}")
  message(FATAL_ERROR "${DOC} names ${_count} of ${_checked} paths that do not exist:\n  ${_list}\n"
                      "Fix the page (or restore the file).")
endif()
message(STATUS "${DOC}: all ${_checked} names exist")
