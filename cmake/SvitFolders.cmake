# svit_folder_sources(OUT ROOT FOLDER...): the .cpp and .h files of each
# FOLDER under ROOT, each folder a source group of its own, so that an IDE
# shows the library as the tree does (docs/architecture.md: one folder, one
# subsystem). Globbed: adding a file to a folder needs no edit here.
function(svit_folder_sources out root)
  set(files "")
  foreach(folder ${ARGN})
    file(GLOB sources CONFIGURE_DEPENDS ${root}/${folder}/*.cpp ${root}/${folder}/*.h)
    source_group(${folder} FILES ${sources})
    list(APPEND files ${sources})
  endforeach()
  set(${out} ${files} PARENT_SCOPE)
endfunction()
