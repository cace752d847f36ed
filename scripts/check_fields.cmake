# The engine's own per-particle fields go by their typed handles (src/sphflume/core/fields.hpp):
# a string literal given to ParticleStore's string accessors in src/sphflume would be a field name
# no compiler checks. Usage: cmake -DSRC=<path of src/sphflume> -P scripts/check_fields.cmake
# (CTest fields_engine_uses_typed_handles); exits non-zero naming each file and line.
cmake_minimum_required(VERSION 3.20)
if(NOT SRC)
  message(FATAL_ERROR "check_fields: pass -DSRC=<path to src/sphflume>")
endif()
file(GLOB_RECURSE files "${SRC}/*.hpp" "${SRC}/*.cpp")
set(bad "")
foreach(f ${files})
  file(STRINGS "${f}" lines)
  set(n 0)
  foreach(line IN LISTS lines)
    math(EXPR n "${n} + 1")
    if(line MATCHES "\\.(scalar|vector|find_scalar|find_vector|has_scalar)\\(\"")
      file(RELATIVE_PATH rel "${SRC}/.." "${f}")
      string(APPEND bad "\n  ${rel}:${n}: a field named by a string literal: add a handle to core/fields.hpp and use it")
    endif()
  endforeach()
endforeach()
if(bad)
  message(FATAL_ERROR "check_fields: string-named engine fields:${bad}")
endif()
