# Fails when a header under INCLUDE_DIR uses the heap, exceptions, RTTI, hosted-only headers or
# declares mutable static/inline/extern/thread_local data. Comments and string literals are
# ignored. Usage: cmake -DINCLUDE_DIR=<dir> -P include_purity.cmake
if(NOT INCLUDE_DIR)
  message(FATAL_ERROR "INCLUDE_DIR not set")
endif()
file(GLOB_RECURSE headers "${INCLUDE_DIR}/*.hpp" "${INCLUDE_DIR}/*.h")
if(NOT headers)
  message(FATAL_ERROR "no headers under ${INCLUDE_DIR}")
endif()

set(rules
  "heap allocation|(^|[^A-Za-z0-9_])(malloc|calloc|realloc|free|aligned_alloc)[ \t]*\\("
  "heap allocation|(^|[^A-Za-z0-9_.>])new[ \t]+[A-Za-z_(:]"
  "heap allocation|(^|[^A-Za-z0-9_])delete([ \t]*\\[\\])?[ \t]+[A-Za-z_(*]"
  "exceptions|(^|[^A-Za-z0-9_])(throw|try|catch)([^A-Za-z0-9_]|$)"
  "RTTI|(^|[^A-Za-z0-9_])(dynamic_cast|typeid)([^A-Za-z0-9_]|$)"
  "hosted-only header|#[ \t]*include[ \t]*<(iostream|istream|ostream|iosfwd|sstream|fstream|string|string_view|vector|list|deque|map|set|unordered_map|unordered_set|functional|memory|memory_resource|regex|thread|mutex|future|exception|stdexcept|typeinfo|any|cstdio|stdio\\.h|locale)>"
  "mutable global|^[ \t]*(static|inline|extern|thread_local)[ \t]+(static[ \t]+|inline[ \t]+)?(volatile[ \t]+)?([A-Za-z_][A-Za-z0-9_:<>, ]*)[ \t*&]+[A-Za-z_][A-Za-z0-9_]*[ \t]*(=|<semicolon>|\\{|\\[)"
)

set(failures 0)
foreach(header IN LISTS headers)
  file(READ "${header}" text)
  # Drop block comments, line comments and string/char literals before matching.
  string(REGEX REPLACE "/\\*([^*]|\\*+[^*/])*\\*+/" "" text "${text}")
  string(REGEX REPLACE "//[^\n]*" "" text "${text}")
  string(REGEX REPLACE "\"([^\"\\\\\n]|\\\\.)*\"" "\"\"" text "${text}")
  string(REGEX REPLACE "'([^'\\\\\n]|\\\\.)*'" "''" text "${text}")
  string(REPLACE ";" "<semicolon>" text "${text}")
  string(REPLACE "\n" ";" lines "${text}")
  set(lineno 0)
  foreach(line IN LISTS lines)
    math(EXPR lineno "${lineno} + 1")
    foreach(rule IN LISTS rules)
      string(FIND "${rule}" "|" bar)
      string(SUBSTRING "${rule}" 0 ${bar} what)
      math(EXPR start "${bar} + 1")
      string(SUBSTRING "${rule}" ${start} -1 pattern)
      if(line MATCHES "${pattern}")
        # const/constexpr data is read-only: not a mutable global
        if(what STREQUAL "mutable global" AND line MATCHES "(^|[^A-Za-z0-9_])(const|constexpr|consteval|constinit)[^A-Za-z0-9_]")
          continue()
        endif()
        if(what STREQUAL "mutable global" AND line MATCHES "(^|[ \t])(using|typedef|return|namespace|class|struct|enum|template|friend|operator)[ \t]")
          continue()
        endif()
        # the global placement form on a void pointer constructs in storage the caller owns
        # (the standard's non-allocating, non-replaceable operator new): not the heap
        if(what STREQUAL "heap allocation" AND line MATCHES "::new \\(static_cast<void\\*>\\(&[A-Za-z_][A-Za-z0-9_]*\\)\\)")
          string(REGEX REPLACE "::new \\(static_cast<void\\*>\\(&[A-Za-z_][A-Za-z0-9_]*\\)\\)" "" rest "${line}")
          if(NOT rest MATCHES "${pattern}")
            continue()
          endif()
        endif()
        message("${header}:${lineno}: ${what}: ${line}")
        math(EXPR failures "${failures} + 1")
      endif()
    endforeach()
  endforeach()
endforeach()
list(LENGTH headers count)
if(failures GREATER 0)
  message(FATAL_ERROR "${failures} violation(s) in ${count} header(s)")
endif()
message(STATUS "include purity: ${count} header(s) clean")
