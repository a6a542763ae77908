# Used by run_fuzzers.sh as CMAKE_PROJECT_svit_INCLUDE: reads
# tests/fuzz/CMakeLists.txt at the end of the top-level CMakeLists.txt unless
# a hook there (or in tests/CMakeLists.txt) already added it, so the fuzz
# build works with or without that one-line hook. (Deferred calls may not
# add_subdirectory(), hence include(); the file uses CMAKE_CURRENT_LIST_DIR
# so it reads the same either way.)
function(svit_attach_fuzz)
  if(NOT TARGET svit_fuzzers)
    include(${CMAKE_SOURCE_DIR}/tests/fuzz/CMakeLists.txt)
  endif()
endfunction()
cmake_language(DEFER DIRECTORY ${CMAKE_SOURCE_DIR} CALL svit_attach_fuzz)
