# Checks that every path docs/architecture.md names exists in the tree:
#   - the first word of each line of its first code block (the tree, one folder per line,
#     paths relative to the repository root; continuation lines start with a space);
#   - every `code span` that looks like a repository path (contains a '/', no spaces, no
#     wildcard, placeholder or brace list, not a URL or an API route).
# Usage: cmake -DROOT=<repository root> -P cmake/CheckArchitecturePaths.cmake
if(NOT ROOT)
  message(FATAL_ERROR "CheckArchitecturePaths: pass -DROOT=<repository root>")
endif()
file(READ "${ROOT}/docs/architecture.md" doc)
set(missing "")
set(checked 0)

# The tree: the first fenced block.
string(FIND "${doc}" "```" open)
if(open LESS 0)
  message(FATAL_ERROR "docs/architecture.md: no code block with the tree")
endif()
math(EXPR body_start "${open} + 3")
string(SUBSTRING "${doc}" ${body_start} -1 rest)
string(FIND "${rest}" "```" close)
string(SUBSTRING "${rest}" 0 ${close} tree)
string(REPLACE "\n" ";" tree_lines "${tree}")
foreach(line IN LISTS tree_lines)
  if(line MATCHES "^([A-Za-z0-9_.][^ ]*)")
    set(p "${CMAKE_MATCH_1}")
    math(EXPR checked "${checked} + 1")
    if(NOT EXISTS "${ROOT}/${p}")
      list(APPEND missing "${p} (tree)")
    endif()
  endif()
endforeach()

# Code spans that name repository paths.
string(REGEX MATCHALL "`[^`\n]+`" spans "${doc}")
foreach(span IN LISTS spans)
  string(REGEX REPLACE "^`(.*)`$" "\\1" p "${span}")
  if(NOT p MATCHES "/" OR p MATCHES "[ *<>{}:]" OR p MATCHES "^/" OR p MATCHES "^[a-z]+://")
    continue()
  endif()
  if(NOT p MATCHES "^(engine|server|schema|web|tests|bench|scripts|docs|cmake)/")
    continue()
  endif()
  math(EXPR checked "${checked} + 1")
  if(NOT EXISTS "${ROOT}/${p}")
    list(APPEND missing "${p}")
  endif()
endforeach()

if(missing)
  list(JOIN missing "\n  " text)
  message(FATAL_ERROR "docs/architecture.md names paths that do not exist:\n  ${text}")
endif()
message(STATUS "docs/architecture.md: ${checked} paths, all exist")
